"""Harmonic content of a periodic beat: the amplitudes of its 1st, 2nd, ... harmonics.

Small pure functions: numpy arrays in, numbers out. Conventions as in
:mod:`elastoactive.analysis.observables`: ``t`` (T,) strictly increasing times in tau, ``x`` (T,)
a scalar time series sampled at ``t`` (typically Theta(t) = theta_N - theta_1, or one mid-chain
angle ``theta[:, i]``: the caller passes the column), frequencies in cycles per tau, and
``transient`` the time in tau (from ``t[0]``) discarded at the start (``None``: the first half of
the record's duration).

Method (:func:`harmonic_fit`):

1. The fundamental f is first read off the upward crossings of the steady mean
   (:func:`observables.upward_crossings`, with hysteresis), as :func:`observables.frequency` does.
2. The steady part is cropped to the samples between the first and the last crossing: a whole
   number of periods, up to one sample at either end.
3. x is fitted by least squares with c + sum_k [a_k cos(2 pi k f t) + b_k sin(2 pi k f t)],
   k = 1 .. K, and f itself is refined by minimising the residual (first with the fundamental
   alone, then with all K harmonics, each time inside the main lobe of the previous estimate).

Why least squares and not a plain projection or an FFT: a projection (1/n) sum x e^{-2 pi i k f t}
is exact only when the window holds an exact whole number of periods on the sample grid; with
the window snapped to samples, each harmonic leaks into the others by about dt / window (1e-3
at 20 samples a period over 40 periods). An FFT has the same problem plus frequencies on a
grid, and windowing trades leakage for a bias that must then be interpolated away. Least
squares is exact for any window and any (even non-uniform) sampling when x is a sum of the
fitted harmonics; cropping to whole periods keeps the harmonics that are not fitted (above K)
nearly orthogonal to those that are, and K is twice the number reported (:data:`FIT_FACTOR`),
below the Nyquist frequency of the sampling, so that they barely leak in either.

When there is no fundamental (no oscillation, fewer than :data:`MIN_PERIODS` whole periods, or
a harmonic series that does not describe the signal) the amplitudes are NaN: never a number
that could be mistaken for a measurement.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import observables as obs

__all__ = ["MIN_AMPLITUDE", "MIN_PERIODS", "MIN_EXPLAINED", "FIT_FACTOR", "HarmonicFit", "harmonic_fit", "harmonics"]


MIN_AMPLITUDE = 1e-3
"""Units of x (rad for an angle): a steady part whose half peak-to-peak is at most this has no
fundamental (it is at rest; round-off or a last decaying wiggle is not a beat). The default of
``threshold``; the same level as :func:`observables.is_oscillating`."""
MIN_PERIODS = 2
"""Whole periods (between upward mean crossings) the steady part must hold for a fundamental."""
MIN_EXPLAINED = 0.9
"""Share of the variance of x (over the whole periods used) that the fitted harmonic series must
explain. Below it x is not one periodic beat (noise, chaos, a drifting period, a beat still growing
or decaying, or two incommensurate frequencies) and the amplitudes are NaN. A limit cycle with mild
noise explains more than 0.99. The default of ``min_explained``."""
FIT_FACTOR = 2
"""Harmonics fitted per harmonic reported (``count`` reported, ``FIT_FACTOR * count`` fitted,
fewer if the sampling cannot resolve them), so that unreported ones do not leak into reported ones."""


@dataclass(frozen=True)
class HarmonicFit:
    """A periodic series written as x(t) ~ offset + sum_k amplitudes[k-1] cos(2 pi k frequency t + phases[k-1]).

    Every field is NaN (arrays of NaN) when no fundamental was found; an amplitude or phase is NaN
    also for a harmonic at or above the Nyquist frequency of the sampling.
    """

    frequency: float
    """Fundamental f, cycles per tau (refined by least squares; NaN without a fundamental)."""
    offset: float
    """The mean c of the fitted series, units of x."""
    amplitudes: np.ndarray
    """(count,) amplitude A_k >= 0 of harmonic k = 1 .. count, units of x."""
    phases: np.ndarray
    """(count,) phase phi_k in (-pi, pi] of harmonic k, in the cosine form above, with the actual
    times t (not counted from the window's start)."""
    explained: float
    """Share of the variance of x over the fitted window that the series explains (1 - residual / variance)."""
    periods: float
    """Length of the fitted window in periods of the fundamental (a whole number, up to a sample)."""

    @property
    def relative(self) -> np.ndarray:
        """(count,) amplitudes relative to the fundamental: A_k / A_1 (element 0 is 1.0)."""
        return self.amplitudes / self.amplitudes[0]


def _nan_fit(count: int) -> HarmonicFit:
    nan = np.full(count, math.nan)
    return HarmonicFit(math.nan, math.nan, nan, nan.copy(), math.nan, math.nan)


def _lstsq(tc: np.ndarray, x: np.ndarray, f: float, k: int) -> tuple[np.ndarray, float]:
    """Least-squares coefficients [c, a_1, b_1, ..., a_k, b_k] at fundamental f, and the residual sum of squares."""
    # the basis [1, cos w, sin w, ..., cos kw, sin kw] by the recurrence e^{ijw} = e^{i(j-1)w} e^{iw}: one cos and
    # one sin per sample instead of 2k (the fit is evaluated ~50 times per run; rounding stays at 1e-15 x k)
    a = np.empty((tc.size, 2 * k + 1))
    a[:, 0] = 1.0
    z1 = np.exp(2j * math.pi * f * tc)
    z = z1
    for j in range(1, k + 1):
        a[:, 2 * j - 1] = z.real
        a[:, 2 * j] = z.imag
        if j < k:
            z = z * z1
    # normal equations: the Gram matrix of a Fourier basis over whole periods is nearly diagonal (well
    # conditioned), and 10x faster than an SVD for n >> k; one step of iterative refinement restores
    # the accuracy that squaring the condition number costs
    gram = a.T @ a
    coef = np.linalg.solve(gram, a.T @ x)
    r = x - a @ coef
    coef = coef + np.linalg.solve(gram, a.T @ r)
    r = x - a @ coef
    return coef, float(r @ r)


_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
BRACKET_TOL = 1e-3
"""Golden-section search narrows the fundamental to BRACKET_TOL x the half-width of its search interval ..."""
PARABOLA_STEPS = 4
"""... then at most this many steps of parabolic interpolation (the residual is quadratic near its minimum, so
one or two steps land on it to round-off)."""


def _refine(tc: np.ndarray, x: np.ndarray, f0: float, half_width: float, k: int) -> float:
    """The f in f0 +- half_width that minimises the residual of the k-harmonic fit: golden-section search (inside
    the main lobe the residual has one minimum), then parabolic interpolation. Written here rather than taken from
    scipy.optimize, whose import costs ~0.3 s in every process that measures a run."""
    rss = lambda f: _lstsq(tc, x, f, k)[1]  # noqa: E731
    lo, hi = max(f0 - half_width, 0.5 * f0), f0 + half_width
    a, b = lo + (1.0 - _GOLDEN) * (hi - lo), lo + _GOLDEN * (hi - lo)
    fa, fb = rss(a), rss(b)
    while hi - lo > BRACKET_TOL * half_width:
        if fa <= fb:
            hi, b, fb = b, a, fa
            a = lo + (1.0 - _GOLDEN) * (hi - lo)
            fa = rss(a)
        else:
            lo, a, fa = a, b, fb
            b = lo + _GOLDEN * (hi - lo)
            fb = rss(b)
    pts = sorted([(a, fa), (b, fb), (lo, rss(lo)), (hi, rss(hi))], key=lambda p: p[1])[:3]
    for _ in range(PARABOLA_STEPS):
        (x1, y1), (x2, y2), (x3, y3) = sorted(pts)
        den = (x2 - x1) * (y2 - y3) - (x2 - x3) * (y2 - y1)
        if den == 0.0:
            break
        step = x2 - 0.5 * ((x2 - x1) ** 2 * (y2 - y3) - (x2 - x3) ** 2 * (y2 - y1)) / den
        if not lo <= step <= hi or any(step == p[0] for p in pts):
            break
        pts = sorted(pts + [(step, rss(step))], key=lambda p: p[1])[:3]
    return float(min(pts, key=lambda p: p[1])[0])


def harmonic_fit(
    t,
    x,
    transient: float | None = None,
    count: int = 5,
    *,
    threshold: float = MIN_AMPLITUDE,
    min_explained: float = MIN_EXPLAINED,
    hysteresis: float = 0.1,
) -> HarmonicFit:
    """Fundamental frequency, offset, amplitudes and phases of harmonics 1 .. ``count`` of x after transients.

    See the module docstring for the method. x need not hold a whole number of periods, nor be
    uniformly sampled. A fit with no fundamental has NaN everywhere: when the steady part's half
    peak-to-peak is at most ``threshold`` (units of x), when it holds fewer than
    :data:`MIN_PERIODS` whole periods, or when the fitted series explains less than
    ``min_explained`` of its variance. ``hysteresis`` is that of :func:`observables.upward_crossings`.

    The fundamental is the mean-crossing frequency (refined): a series that crosses its mean
    upward several times per period, by more than the hysteresis band, is read at a multiple of
    its true fundamental.
    """
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise ValueError(f"count must be an integer >= 1; got {count!r}")
    count = int(count)
    threshold = float(threshold)
    if not math.isfinite(threshold) or threshold < 0.0:
        raise ValueError(f"threshold must be a finite amplitude >= 0; got {threshold}")
    min_explained = float(min_explained)
    if not (0.0 <= min_explained <= 1.0):
        raise ValueError(f"min_explained must be in [0, 1]; got {min_explained}")
    ts, xs = obs._steady(t, x, transient, min_samples=2)
    if 0.5 * (xs.max() - xs.min()) <= threshold:
        return _nan_fit(count)
    tcross = obs.upward_crossings(ts, xs, transient=0.0, hysteresis=hysteresis)
    if tcross.size < MIN_PERIODS + 1:
        return _nan_fit(count)
    f0 = (tcross.size - 1) / (tcross[-1] - tcross[0])
    m = (ts >= tcross[0]) & (ts < tcross[-1])
    tw, xw = ts[m], xs[m]
    # harmonics strictly below the Nyquist frequency of the coarsest sample spacing in the window
    k_nyquist = math.ceil(1.0 / (2.0 * f0 * np.max(np.diff(tw)))) - 1
    k_fit = min(FIT_FACTOR * count, k_nyquist)
    if k_fit < 1 or tw.size < 2 * k_fit + 3:
        return _nan_fit(count)
    centre = 0.5 * (tw[0] + tw[-1])
    tc = tw - centre  # centred times: a well-conditioned fit, phases converted back below
    span = tw[-1] - tw[0]
    f1 = _refine(tc, xw, f0, 0.5 / span, 1)  # inside the fundamental's main lobe (half-width 1/span)
    f = _refine(tc, xw, f1, 0.5 / (k_fit * span), k_fit) if k_fit > 1 else f1  # inside harmonic k_fit's lobe
    coef, rss = _lstsq(tc, xw, f, k_fit)
    variance = float(np.sum((xw - xw.mean()) ** 2))
    explained = 1.0 - rss / variance
    if explained < min_explained:
        return _nan_fit(count)
    a, b = coef[1::2], coef[2::2]
    k = np.arange(1, k_fit + 1)
    amps = np.hypot(a, b)
    # a cos(w) + b sin(w) = A cos(w - atan2(b, a)); w = 2 pi k f (t - centre)
    ph = np.angle(np.exp(1j * (-np.arctan2(b, a) - 2.0 * math.pi * k * f * centre)))
    amplitudes = np.full(count, math.nan)
    phases = np.full(count, math.nan)
    n = min(count, k_fit)
    amplitudes[:n], phases[:n] = amps[:n], ph[:n]
    return HarmonicFit(
        float(f), float(coef[0]), amplitudes, phases, float(explained), float(f * (tcross[-1] - tcross[0]))
    )


def harmonics(
    t,
    x,
    transient: float | None = None,
    count: int = 5,
    *,
    threshold: float = MIN_AMPLITUDE,
    min_explained: float = MIN_EXPLAINED,
) -> np.ndarray:
    """Amplitudes of harmonics 1 .. ``count`` of x after transients, relative to the fundamental.

    Returns a (count,) array A_k / A_1 (element 0 is 1.0), dimensionless. All NaN when x has no
    fundamental (at rest, fewer than :data:`MIN_PERIODS` periods, or not one periodic beat: see
    :func:`harmonic_fit` for the method, ``threshold`` and ``min_explained``); the entries of
    harmonics at or above the Nyquist frequency of the sampling are NaN too. For a chain's beat
    pass Theta (``observables.curvature(theta)``) or one column of theta.
    """
    return harmonic_fit(t, x, transient, count, threshold=threshold, min_explained=min_explained).relative

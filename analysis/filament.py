"""The chain as a discretised filament: precise beat measures of one chain, and their extrapolation in 1/N.

The clamped chain of N particles at sigma = S / N^3 is a discretisation of the clamped filament under a
distributed follower load S = f L^3 / B (analysis/continuum.py): with l = C = gamma = 1, B = C l, L = N l and
zeta = gamma / l, the filament's unit of time is zeta L^4 / B = N^4 tau. A chain's observables tend to the
filament's as powers of 1/N:

    omega(N) N^4  = omega_inf + a_1 / N + a_2 / N^2 + ...      (angular frequency, units B / (zeta L^4))
    Theta_amp(N)  = A_inf     + b_1 / N + ...                  (half peak-to-peak of theta_N - theta_1, rad)
    N^3 sigma_c(N) = S_c      + c_1 / N + ...                  (the onset)

`richardson` fits these expansions exactly through a ladder of N (Richardson extrapolation; a polynomial in 1/N
of degree len(ns) - 1) and estimates the error of the extrapolated value by its change when the coarsest rung
is dropped. `beat` measures one rung's period and amplitude to ~1e-9 (crossings and peaks interpolated, not
read off the samples), precise enough that the extrapolation, which amplifies the rungs' errors (by ~20 for
four rungs in halving steps), is limited by the expansion and not by the measures. `resample` carries a
chain's shape to another N, so that each rung starts next to its own limit cycle.

Pure functions: arrays in, numbers out.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Extrapolation", "Beat", "richardson", "beat", "resample"]


class Extrapolation(NamedTuple):
    """A value extrapolated to N -> infinity from a ladder of N."""

    value: float
    """The extrapolated value (polynomial of degree len(ns) - 1 in 1/N through every rung)."""
    error: float
    """Its estimated error: |value - the same extrapolation without the coarsest rung| (0 for one rung)."""
    ns: tuple[int, ...]
    values: tuple[float, ...]


class Beat(NamedTuple):
    """The steady beat of a scalar signal x(t) over whole periods."""

    period: float
    """Mean period between successive upward crossings of the mean (same units as t)."""
    amplitude: float
    """Half of (mean of the maxima - mean of the minima), each extremum refined by a parabola through its samples."""
    periods: int
    """Whole periods measured."""
    spread: float
    """Largest relative deviation of one period or one extremum from the means: how steady the beat is."""


def _polynomial_limit(ns: np.ndarray, values: np.ndarray) -> float:
    """The value at 1/N = 0 of the polynomial in 1/N through the points (exact interpolation)."""
    h = 1.0 / ns
    coeffs = np.polyfit(h, values, deg=h.size - 1)
    return float(coeffs[-1])


def richardson(ns, values) -> Extrapolation:
    """Extrapolate values(N) to N -> infinity through every rung (a polynomial of degree len(ns) - 1 in 1/N), with
    the error estimate of Extrapolation.error. ns: distinct positive N, any order."""
    ns = np.asarray(ns, dtype=float).reshape(-1)
    values = np.asarray(values, dtype=float).reshape(-1)
    if ns.size == 0 or ns.size != values.size:
        raise ValueError(
            f"richardson needs as many values as N (at least one), got {ns.size} N and {values.size} values"
        )
    if np.any(ns <= 0) or np.unique(ns).size != ns.size:
        raise ValueError(f"the ladder's N must be distinct and positive, got {ns.tolist()}")
    if not np.all(np.isfinite(values)):
        raise ValueError("richardson: every rung's value must be finite")
    order = np.argsort(ns)
    ns, values = ns[order], values[order]
    value = _polynomial_limit(ns, values)
    error = abs(value - _polynomial_limit(ns[1:], values[1:])) if ns.size > 1 else 0.0
    return Extrapolation(value, error, tuple(int(n) for n in ns), tuple(float(v) for v in values))


def _crossings(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Times of the upward crossings of 0 by x, each from the cubic through the four samples around it."""
    idx = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    idx = idx[(idx >= 1) & (idx + 2 < x.size)]
    times = np.empty(idx.size)
    for k, i in enumerate(idx):
        h = t[i + 1] - t[i]
        roots = np.roots(np.polyfit((t[i - 1 : i + 3] - t[i]) / h, x[i - 1 : i + 3], 3))
        roots = roots[np.abs(roots.imag) < 1e-9].real
        inside = roots[(roots >= 0.0) & (roots <= 1.0)]
        frac = inside[0] if inside.size else -x[i] / (x[i + 1] - x[i])
        times[k] = t[i] + frac * h
    return times


def _extremum(t: np.ndarray, x: np.ndarray, i: int) -> float:
    """The extreme value of x near its extreme sample i, from the quartic through the five samples around it
    (error ~ (h / period)^4 of the amplitude for a sample spacing h)."""
    lo, hi = max(0, i - 2), min(x.size, i + 3)
    h = t[min(i + 1, x.size - 1)] - t[max(i - 1, 0)]
    coeffs = np.polyfit((t[lo:hi] - t[i]) / h, x[lo:hi], hi - lo - 1)
    roots = np.roots(np.polyder(coeffs))
    roots = roots[(np.abs(roots.imag) < 1e-9) & (np.abs(roots.real) <= 0.5)].real
    candidates = np.concatenate([[x[i]], np.polyval(coeffs, roots)])
    return float(candidates.max() if x[i] >= np.mean(x[lo:hi]) else candidates.min())


def beat(t, x) -> Beat:
    """The period and amplitude of a steady periodic signal x sampled at t (at least ~20 samples a period), over the
    whole periods between its first and last upward crossing of its mean. Raises ValueError with fewer than two
    whole periods."""
    t = np.asarray(t, dtype=float).reshape(-1)
    x = np.asarray(x, dtype=float).reshape(-1)
    if t.size != x.size or t.size < 8:
        raise ValueError("beat needs t and x of the same length (at least 8 samples)")
    centred = x - 0.5 * (x.max() + x.min())
    up = _crossings(t, centred)
    if up.size < 3:
        raise ValueError(f"beat needs at least two whole periods, found {max(0, up.size - 1)}")
    periods = np.diff(up)
    highs, lows = [], []
    for a, b in zip(up[:-1], up[1:]):
        window = np.flatnonzero((t >= a) & (t <= b))
        if window.size < 5:
            raise ValueError("beat needs at least ~20 samples per period")
        highs.append(_extremum(t, x, int(window[np.argmax(x[window])])))
        lows.append(_extremum(t, x, int(window[np.argmin(x[window])])))
    highs, lows = np.array(highs), np.array(lows)
    period = float(periods.mean())
    amplitude = 0.5 * float(highs.mean() - lows.mean())
    spread = max(
        float(np.max(np.abs(periods / period - 1.0))),
        float(np.max(np.abs(np.concatenate([highs - highs.mean(), lows - lows.mean()])))) / amplitude,
    )
    return Beat(period, amplitude, int(periods.size), spread)


def resample(theta, n: int) -> np.ndarray:
    """A chain's absolute angles carried to n particles: theta_i sits at the middle of link i, s = (i - 1/2) / N of the
    length; the new angles are the piecewise linear interpolation of the old at the new links' middles (held
    constant beyond the first and last middles)."""
    theta = np.asarray(theta, dtype=float).reshape(-1)
    n_old = theta.size
    s_old = (np.arange(n_old) + 0.5) / n_old
    s_new = (np.arange(int(n)) + 0.5) / int(n)
    return np.interp(s_new, s_old, theta)

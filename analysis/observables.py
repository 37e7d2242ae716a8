"""Observables of elasto-active chains (docs/model.md, "Observables").

Small pure functions: numpy arrays in, numbers or arrays out. Conventions:

- ``t`` is a 1-D array of sample times in units of tau = gamma l^2 / C, strictly increasing.
- ``theta`` is a ``(T, N)`` array of absolute pendulum angles in radians (row = time,
  column = particle; column 0 is theta_1, the pendulum at the anchor).
- ``x`` is any 1-D scalar time series sampled at ``t`` (typically Theta(t), in radians).
- Frequencies are f*tau, i.e. cycles per tau (not angular frequencies).
- Every measure on a time series takes ``transient``: the time (in tau, counted from
  ``t[0]``) discarded at the start of the record. ``None`` discards the first half of the
  record's duration.

scipy.signal is imported inside _phase, the one measure that needs it (the Hilbert transform): it costs ~0.4 s,
which every run's measurement would otherwise pay.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "curvature",
    "polarisation",
    "limit_cycle",
    "steady_part",
    "amplitude",
    "frequency",
    "upward_crossings",
    "Cycles",
    "cycles",
    "cycle_amplitudes",
    "hilbert_phase",
    "phase_frequency",
    "frequency_mismatch",
    "snap_amplitude",
    "rotation_rate",
    "is_oscillating",
    "settling_time",
]


# --------------------------------------------------------------------------- validation


def _as_theta(theta) -> np.ndarray:
    a = np.asarray(theta, dtype=float)
    if a.ndim != 2:
        raise ValueError(f"theta must be a 2-D array of shape (T, N); got shape {a.shape}")
    if a.shape[0] < 1 or a.shape[1] < 1:
        raise ValueError(f"theta must have at least one sample and one particle; got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError("theta contains non-finite values (nan or inf)")
    return a


def _as_time(t) -> np.ndarray:
    a = np.asarray(t, dtype=float)
    if a.ndim != 1:
        raise ValueError(f"t must be a 1-D array of times; got shape {a.shape}")
    if a.size < 2:
        raise ValueError(f"t must have at least 2 samples; got {a.size}")
    if not np.all(np.isfinite(a)):
        raise ValueError("t contains non-finite values (nan or inf)")
    if np.any(np.diff(a) <= 0):
        raise ValueError("t must be strictly increasing")
    return a


def _as_series(t, x, name: str = "x", ndim: tuple[int, ...] = (1,)) -> tuple[np.ndarray, np.ndarray]:
    ta = _as_time(t)
    xa = np.asarray(x, dtype=float)
    if xa.ndim not in ndim:
        want = " or ".join(f"{d}-D" for d in ndim)
        raise ValueError(f"{name} must be {want}; got shape {xa.shape}")
    if xa.shape[0] != ta.size:
        raise ValueError(f"{name} has {xa.shape[0]} samples but t has {ta.size}; lengths must match")
    if not np.all(np.isfinite(xa)):
        raise ValueError(f"{name} contains non-finite values (nan or inf)")
    return ta, xa


def _steady_mask(t: np.ndarray, transient: float | None, fraction: float) -> np.ndarray:
    duration = t[-1] - t[0]
    if transient is None:
        if not (0.0 <= fraction < 1.0) or not math.isfinite(fraction):
            raise ValueError(f"fraction must be in [0, 1); got {fraction}")
        t_start = t[0] + fraction * duration
    else:
        transient = float(transient)
        if not math.isfinite(transient) or transient < 0.0:
            raise ValueError(f"transient must be a finite time >= 0 (in tau); got {transient}")
        if transient >= duration:
            raise ValueError(f"transient ({transient:g} tau) must be shorter than the record ({duration:g} tau)")
        t_start = t[0] + transient
    # small tolerance so that a transient landing exactly on a sample keeps it
    return t >= t_start - 1e-12 * max(1.0, abs(t_start))


def _steady(t, x, transient, *, name="x", ndim=(1,), min_samples=2):
    ta, xa = _as_series(t, x, name=name, ndim=ndim)
    m = _steady_mask(ta, transient, 0.5)
    ts, xs = ta[m], xa[m]
    if ts.size < min_samples:
        raise ValueError(f"only {ts.size} samples remain after discarding transients; need at least {min_samples}")
    return ts, xs


def _check_trim(trim: float) -> float:
    trim = float(trim)
    if not (0.0 <= trim < 0.5) or not math.isfinite(trim):
        raise ValueError(f"trim must be in [0, 0.5); got {trim}")
    return trim


def _check_uniform(t: np.ndarray, rtol: float = 1e-3) -> None:
    dt = np.diff(t)
    mean = dt.mean()
    if np.max(np.abs(dt - mean)) > rtol * mean:
        raise ValueError("the Hilbert transform needs uniformly sampled t (constant time step)")


def _trimmed_slope(t: np.ndarray, y: np.ndarray, trim: float) -> float:
    n = t.size
    k = int(math.floor(trim * n))
    ts, ys = t[k : n - k], y[k : n - k]
    if ts.size < 3:
        raise ValueError(f"only {ts.size} samples remain after trimming the ends; need at least 3")
    return float(np.polyfit(ts, ys, 1)[0])


# --------------------------------------------------------------------------- chain shape


def curvature(theta) -> np.ndarray:
    """Mean curvature Theta(t) = theta_N - theta_1 (the sum of the bends), in radians.

    theta: (T, N) absolute angles in radians. Returns an array of shape (T,).
    """
    a = _as_theta(theta)
    return a[:, -1] - a[:, 0]


def polarisation(theta) -> np.ndarray:
    """Mean polarisation Omega(t) = (1/N) sum_i theta_i, in radians.

    theta: (T, N) absolute angles in radians. Returns an array of shape (T,).
    """
    a = _as_theta(theta)
    return a.mean(axis=1)


def limit_cycle(theta) -> tuple[np.ndarray, np.ndarray]:
    """The (Omega(t), Theta(t)) curve in radians, each of shape (T,); closed on a limit cycle."""
    a = _as_theta(theta)
    return polarisation(a), curvature(a)


# --------------------------------------------------------------------------- time series


def steady_part(t, x, fraction: float = 0.5, transient: float | None = None):
    """The samples after transients: returns ``(t_steady, x_steady)``.

    t: (T,) times in tau. x: (T,) or (T, ...) samples (first axis is time).
    fraction: the fraction of the record's *duration* treated as transient and discarded
        (default 0.5: keep the last half). Ignored when ``transient`` is given.
    transient: time in tau (counted from t[0]) to discard instead of ``fraction``.
    """
    ta, xa = _as_series(t, x, ndim=tuple(range(1, 8)))
    m = _steady_mask(ta, transient, float(fraction))
    return ta[m], xa[m]


def amplitude(t, x, transient: float | None = None) -> float:
    """Half the peak-to-peak of x after transients, in the units of x (radians for Theta).

    Uses the raw samples: a sinusoid sampled at n points per period reads low by at most
    1 - cos(pi/n) (1.2 % at 20 points per period).
    """
    _, xs = _steady(t, x, transient, min_samples=2)
    return float(0.5 * (xs.max() - xs.min()))


def upward_crossings(t, x, transient: float | None = None, hysteresis: float = 0.1) -> np.ndarray:
    """Times (in tau) at which x crosses its steady mean upward, linearly interpolated.

    hysteresis: a crossing counts only if x has gone below ``mean - hysteresis * A`` since the
        previous counted crossing (A = half the peak-to-peak), so that noise or small wiggles
        near the mean are not counted as extra periods. 0 disables it.
    """
    ts, xs = _steady(t, x, transient, min_samples=2)
    hysteresis = float(hysteresis)
    if not math.isfinite(hysteresis) or hysteresis < 0.0:
        raise ValueError(f"hysteresis must be >= 0; got {hysteresis}")
    y = xs - xs.mean()
    amp = 0.5 * (y.max() - y.min())
    if amp == 0.0:
        return np.empty(0)
    idx = np.flatnonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))
    if idx.size == 0:
        return np.empty(0)
    if hysteresis > 0.0:
        below = np.flatnonzero(y < -hysteresis * amp)
        keep = []
        last = -1
        for i in idx:
            # is there a sample below the band in (last, i] ?
            j = np.searchsorted(below, last, side="right")
            if j < below.size and below[j] <= i:
                keep.append(i)
                last = i
        idx = np.asarray(keep, dtype=int)
        if idx.size == 0:
            return np.empty(0)
    y0, y1 = y[idx], y[idx + 1]
    t0, t1 = ts[idx], ts[idx + 1]
    return t0 - y0 * (t1 - t0) / (y1 - y0)


def frequency(t, x, transient: float | None = None, hysteresis: float = 0.1) -> float:
    """Oscillation frequency f*tau (cycles per tau) of x after transients.

    Counts upward crossings of the mean of the steady part (linear interpolation between
    samples; see :func:`upward_crossings` for ``hysteresis``) and averages over whole
    periods: f = (n_crossings - 1) / (t_last - t_first). Insensitive to a nonzero mean and
    to non-sinusoidal wave forms that cross their mean once per period. Returns 0.0 when
    there are fewer than 2 crossings (no oscillation).
    """
    tc = upward_crossings(t, x, transient=transient, hysteresis=hysteresis)
    if tc.size < 2:
        return 0.0
    return float((tc.size - 1) / (tc[-1] - tc[0]))


@dataclass(frozen=True)
class Cycles:
    """Cycle-by-cycle statistics of an oscillation (see :func:`cycles`)."""

    count: int
    """Whole periods between the first and the last upward crossing of the steady part."""
    period_spread: float
    """Standard deviation over mean of the cycle periods (NaN with fewer than 2 cycles)."""
    amplitude_spread: float
    """Standard deviation over mean of each cycle's half peak-to-peak (NaN with fewer than 2 cycles)."""


def cycles(t, x, transient: float | None = None, hysteresis: float = 0.1) -> Cycles:
    """How regular an oscillation is: the spread of its cycle periods and of its cycle amplitudes.

    Cycles run between consecutive upward crossings of the steady mean (:func:`upward_crossings`).
    A limit cycle gives spreads near zero (1e-5 for the paper's beat sampled at 0.05 tau); noise,
    chaos, or a beat still growing or decaying in the window give larger ones.
    """
    ts, xs = _steady(t, x, transient, min_samples=2)
    tc = upward_crossings(ts, xs, transient=0.0, hysteresis=hysteresis)
    count = max(tc.size - 1, 0)
    if count < 2:
        return Cycles(count, math.nan, math.nan)
    periods = np.diff(tc)
    amps = _cycle_amplitudes(ts, xs, tc)
    amp_spread = float(amps.std() / amps.mean()) if amps.size >= 2 and amps.mean() > 0 else math.nan
    return Cycles(count, float(periods.std() / periods.mean()), amp_spread)


def _cycle_amplitudes(ts: np.ndarray, xs: np.ndarray, crossings: np.ndarray) -> np.ndarray:
    edges = np.searchsorted(ts, crossings)
    return np.array([0.5 * np.ptp(xs[a:b]) for a, b in zip(edges[:-1], edges[1:]) if b - a >= 2])


def cycle_amplitudes(t, x, transient: float | None = None, hysteresis: float = 0.1) -> np.ndarray:
    """Half peak-to-peak of each whole cycle of x after transients, in time order (cycles as in :func:`cycles`;
    empty with fewer than one)."""
    ts, xs = _steady(t, x, transient, min_samples=2)
    return _cycle_amplitudes(ts, xs, upward_crossings(ts, xs, transient=0.0, hysteresis=hysteresis))


def _whole_period_window(ts: np.ndarray, xs: np.ndarray, hysteresis: float = 0.1) -> slice:
    """Samples from the first to the last upward mean crossing (a whole number of periods)."""
    tc = upward_crossings(ts, xs, transient=0.0, hysteresis=hysteresis)
    if tc.size < 2:
        return slice(0, ts.size)
    i0 = int(np.argmin(np.abs(ts - tc[0])))
    i1 = int(np.argmin(np.abs(ts - tc[-1])))
    if i1 - i0 < 4:
        return slice(0, ts.size)
    return slice(i0, i1)  # i1 excluded: its sample is the start of the next period


def whole_period_mean(t, x, transient: float | None = None) -> float:
    """The mean of x over a whole number of its periods after transients (from its first to its last upward mean
    crossing), so that a window's ragged ends do not bias the mean of an oscillating signal; the plain mean where x
    has fewer than two crossings."""
    ts, xs = _steady(t, x, transient, min_samples=2)
    return float(np.mean(xs[_whole_period_window(ts, xs)]))


def _phase(ts: np.ndarray, xs: np.ndarray, whole_periods: bool) -> tuple[np.ndarray, np.ndarray]:
    from scipy.signal import hilbert  # start-up time: scipy.signal costs ~0.4 s to import

    _check_uniform(ts)
    w = _whole_period_window(ts, xs) if whole_periods else slice(0, ts.size)
    tw, xw = ts[w], xs[w]
    return tw, np.unwrap(np.angle(hilbert(xw - xw.mean())))


def hilbert_phase(
    t,
    x,
    transient: float | None = None,
    *,
    whole_periods: bool = False,
    return_time: bool = False,
):
    """Unwrapped instantaneous phase (radians) of the analytic signal of x after transients.

    The mean of the steady part is subtracted before scipy.signal.hilbert. By default the
    result has one value per steady sample, aligned with
    ``steady_part(t, x, transient=transient)[0]`` (``transient=None``: the last half of the
    record). The phase increases by 2 pi per cycle. Needs uniformly sampled t.

    Edge effects: the FFT-based transform treats the window as periodic, so the phase is
    distorted within about a period of either end. ``whole_periods=True`` first crops the
    steady part to a whole number of periods (first to last upward mean crossing), which
    makes that distortion much smaller; the output is then shorter, so pass
    ``return_time=True`` to get ``(t_used, phase)``.
    """
    ts, xs = _steady(t, x, transient, min_samples=4)
    tw, phi = _phase(ts, xs, whole_periods)
    return (tw, phi) if return_time else phi


def phase_frequency(t, x, transient: float | None = None, trim: float = 0.1) -> float:
    """Frequency f*tau (cycles per tau) from the slope of the Hilbert phase / (2 pi).

    The steady part is cropped to whole periods (see :func:`hilbert_phase`), a fraction
    ``trim`` of the samples is dropped at each end (Hilbert edge effects), and the unwrapped
    phase is fitted by a straight line against time.
    """
    trim = _check_trim(trim)
    tw, phi = hilbert_phase(t, x, transient, whole_periods=True, return_time=True)
    return _trimmed_slope(tw, phi, trim) / (2.0 * math.pi)


def frequency_mismatch(t, x1, x2, transient: float | None = None, trim: float = 0.1, absolute: bool = False) -> float:
    """Frequency mismatch of a pair, in cycles per tau: slope of Psi = Phi_2 - Phi_1, / (2 pi).

    Phi_k is the unwrapped Hilbert phase of x_k (typically Theta of chain k), each computed
    on its own whole-period crop of the steady part (see :func:`hilbert_phase`) and compared
    on the common time window. Psi is fitted by a straight line against time, a fraction
    ``trim`` of the window dropped at each end. Signed (f_2 - f_1) unless ``absolute`` is
    True. Zero when the two chains are frequency-locked, whatever their phase lag.
    """
    trim = _check_trim(trim)
    _as_series(t, x1, name="x1")
    _as_series(t, x2, name="x2")
    t1, p1 = hilbert_phase(t, x1, transient, whole_periods=True, return_time=True)
    t2, p2 = hilbert_phase(t, x2, transient, whole_periods=True, return_time=True)
    lo, hi = max(t1[0], t2[0]), min(t1[-1], t2[-1])
    m = (t1 >= lo) & (t1 <= hi)
    if np.count_nonzero(m) < 4:
        raise ValueError("the two signals' phase windows barely overlap; use a longer record")
    tc = t1[m]
    psi = np.interp(tc, t2, p2) - p1[m]
    slope = _trimmed_slope(tc, psi, trim) / (2.0 * math.pi)
    return abs(slope) if absolute else slope


# --------------------------------------------------------------------------- scene-specific


def snap_amplitude(theta, t=None, transient: float | None = None, particle: int = 3) -> float:
    """Self-snapping amplitude: standard deviation (radians, ddof=0) of theta_particle.

    theta: (T, N) absolute angles in radians; ``particle`` is 1-based (default 3, i.e.
    column 2). Transients are discarded as elsewhere when ``t`` (in tau) is given; without
    ``t`` the last half of the samples is kept and ``transient`` must be None.
    """
    a = _as_theta(theta)
    n = a.shape[1]
    if isinstance(particle, bool) or not isinstance(particle, (int, np.integer)):
        raise ValueError(f"particle must be an integer 1-based index; got {particle!r}")
    if not 1 <= particle <= n:
        raise ValueError(f"particle must be in 1..{n} (1-based) for a chain of {n}; got {particle}")
    col = a[:, particle - 1]
    if t is None:
        if transient is not None:
            raise ValueError("transient is a time in tau: pass t as well")
        xs = col[col.size // 2 :]
    else:
        _, xs = _steady(t, col, transient, name="theta", min_samples=2)
    if xs.size < 2:
        raise ValueError(f"need at least 2 steady samples; got {xs.size}")
    return float(np.std(xs))


def rotation_rate(t, theta, transient: float | None = None, unwrap: bool = False) -> float:
    """Mean rotation rate d theta_1/dt in rad per tau after transients (freely rotating pin).

    Slope of a least-squares line through theta_1(t) = theta[:, 0]. theta: (T, N) or (T,)
    absolute angles in radians, continuous in time (not wrapped); pass ``unwrap=True`` if
    they are wrapped to an interval of length 2 pi.
    """
    ta, a = _as_series(t, theta, name="theta", ndim=(1, 2))
    if a.ndim == 2:
        if a.shape[1] < 1:
            raise ValueError(f"theta must have at least one particle; got shape {a.shape}")
        a = a[:, 0]
    if unwrap:
        a = np.unwrap(a)
    ts, xs = _steady(ta, a, transient, name="theta", min_samples=2)
    return float(np.polyfit(ts, xs, 1)[0])


def is_oscillating(
    t,
    x,
    threshold: float = 1e-3,
    transient: float | None = None,
    max_decay: float | None = None,
) -> bool:
    """Whether x sustains an oscillation after transients.

    True when the amplitude (half peak-to-peak, units of x, e.g. radians) exceeds
    ``threshold`` and x crosses its mean upward at least twice. If ``max_decay`` is given,
    also requires that the amplitude over the second half of the steady part be at least
    (1 - max_decay) times that over its first half (rejects slowly decaying transients).
    """
    threshold = float(threshold)
    if not math.isfinite(threshold) or threshold < 0.0:
        raise ValueError(f"threshold must be >= 0; got {threshold}")
    ts, xs = _steady(t, x, transient, min_samples=4)
    if 0.5 * (xs.max() - xs.min()) <= threshold:
        return False
    if frequency(ts, xs, transient=0.0) == 0.0:
        return False
    if max_decay is not None:
        max_decay = float(max_decay)
        if not (0.0 <= max_decay <= 1.0):
            raise ValueError(f"max_decay must be in [0, 1]; got {max_decay}")
        half = xs.size // 2
        a1 = 0.5 * (xs[:half].max() - xs[:half].min())
        a2 = 0.5 * (xs[half:].max() - xs[half:].min())
        if a2 < (1.0 - max_decay) * a1:
            return False
    return True


def settling_time(t, x, level: float = 0.9, transient: float | None = None) -> float:
    """Time (tau, from t[0]) at which |x - x_0| first reaches `level` of its steady-state size.

    The steady-state size is max |x - x_0| over the steady part (after `transient`); x_0 = x[0].
    For a self-oscillation growing from a small kick this is the end of the growth phase; for a
    chain settling into steady rotation, the time its bend takes to form.
    """
    tt, xx = _as_series(t, x)
    if not 0 < level <= 1:
        raise ValueError(f"level must lie in (0, 1], got {level}")
    mask = _steady_mask(tt, transient, 0.5)
    excursion = np.abs(xx - xx[0])
    target = level * excursion[mask].max()
    reached = np.flatnonzero(np.maximum.accumulate(excursion) >= target)
    return float(tt[reached[0]] - tt[0]) if reached.size else float(tt[-1] - tt[0])

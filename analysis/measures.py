"""Observables the studies need beyond `analysis.observables` (same conventions).

Small pure functions: numpy arrays in, numbers or arrays out. ``t`` in tau (strictly increasing),
``theta`` a (T, N) array of absolute angles in radians, ``x`` a 1-D series sampled at ``t``,
frequencies in cycles per tau, rates in 1/tau. ``transient`` is the time (tau, from t[0]) discarded
first; ``None`` discards the first half of the record, as in `analysis.observables`.
"""

from __future__ import annotations

import math

import numpy as np

from . import observables as obs

__all__ = [
    "landau_variable",
    "envelope",
    "growth_rate",
    "phase_difference",
    "phase_slips",
    "is_locked",
    "steady_shape",
    "rotation_uniformity",
    "period_variability",
    "amplitude_variability",
    "chain_positions",
]


def landau_variable(theta, mu: float) -> np.ndarray:
    """z = theta_1 + i sqrt((1 + mu)/(1 - mu)) theta_2 of an N = 2 chain, mu = sigma - 3 (|mu| < 1).

    The supplement's variable that turns the linear part of Eqs. (1)-(2) into (i + mu) z; on the
    limit cycle near onset |z|^2 -> mu / (-Re c) with c the Landau-Stuart cubic coefficient.
    """
    a = np.asarray(theta, dtype=float)
    if a.ndim != 2 or a.shape[1] != 2:
        raise ValueError(f"theta must have shape (T, 2) (an N = 2 chain); got {a.shape}")
    if not -1.0 < mu < 1.0:
        raise ValueError(f"mu = sigma - 3 must lie in (-1, 1); got {mu}")
    return a[:, 0] + 1j * math.sqrt((1.0 + mu) / (1.0 - mu)) * a[:, 1]


def envelope(t, x, transient: float | None = 0.0, center: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Instantaneous amplitude |analytic signal| of x after transients: (t, env).

    center: remove the mean first (an oscillation about an offset); use False for a growing or
    decaying oscillation about 0, whose window mean is not its centre. Needs uniform sampling;
    distorted within about a period of either end of the window. Default transient 0: the whole record.
    """
    ts, xs = obs.steady_part(t, x, transient=transient)
    dt = np.diff(ts)
    if np.max(np.abs(dt - dt.mean())) > 1e-3 * dt.mean():
        raise ValueError("envelope needs uniformly sampled t")
    from scipy.signal import hilbert  # scipy's heavy part (~0.4 s of import): the scenes' registry loads this module

    return ts, np.abs(hilbert(xs - xs.mean() if center else xs))


def growth_rate(t, x, transient: float | None = 0.0, trim: float = 0.15) -> float:
    """Exponential growth (> 0) or decay (< 0) rate, 1/tau, of an oscillation x(t) ~ e^{g t} cos(w t).

    Slope of log(envelope) against time, a fraction ``trim`` dropped at each end (Hilbert edge
    effects). x must oscillate about 0. Needs a few periods in the window; returns the real part
    of the dominant eigenvalue when one complex pair dominates.
    """
    if not 0.0 <= trim < 0.5:
        raise ValueError(f"trim must be in [0, 0.5); got {trim}")
    ts, env = envelope(t, x, transient, center=False)
    k = int(trim * ts.size)
    ts, env = ts[k : ts.size - k], env[k : env.size - k]
    if ts.size < 3 or np.any(env <= 0):
        raise ValueError("too few samples (or a zero envelope) to fit a growth rate")
    return float(np.polyfit(ts, np.log(env), 1)[0])


def phase_difference(t, x1, x2, transient: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Psi(t) = Phi_2 - Phi_1 (radians, unwrapped) of two oscillations after transients: (t, psi).

    Phases are the Hilbert phases of `analysis.observables.hilbert_phase` on whole periods; Psi is
    evaluated on chain 1's times within the common window.
    """
    t1, p1 = obs.hilbert_phase(t, x1, transient, whole_periods=True, return_time=True)
    t2, p2 = obs.hilbert_phase(t, x2, transient, whole_periods=True, return_time=True)
    lo, hi = max(t1[0], t2[0]), min(t1[-1], t2[-1])
    m = (t1 >= lo) & (t1 <= hi)
    if np.count_nonzero(m) < 4:
        raise ValueError("the two signals' phase windows barely overlap; use a longer record")
    return t1[m], np.interp(t1[m], t2, p2) - p1[m]


def phase_slips(t, x1, x2, transient: float | None = None) -> float:
    """Net number of 2 pi slips of Psi over the window (|Psi_end - Psi_start| / 2 pi, ends smoothed).

    The ends are averaged over 10% of the window each, so that the bounded wobble of a locked
    (non-isochronous) pair does not count.
    """
    ts, psi = phase_difference(t, x1, x2, transient)
    k = max(1, psi.size // 10)
    return float(abs(psi[-k:].mean() - psi[:k].mean()) / (2.0 * math.pi))


def is_locked(t, x1, x2, transient: float | None = None, max_slips: float = 0.5) -> bool:
    """Whether the two oscillations are frequency-locked over the window: fewer than
    ``max_slips`` net phase slips. Exactness near the threshold depends on the window: a
    slip period longer than the window reads as locked."""
    return phase_slips(t, x1, x2, transient) < max_slips


def steady_shape(theta, t=None, transient: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Shape in the frame turning with pendulum 1: mean and std over the steady part of
    theta_i - theta_1 (radians, shape (N,) each). A rigidly rotating chain has std ~ 0."""
    a = np.asarray(theta, dtype=float)
    if a.ndim != 2:
        raise ValueError(f"theta must be (T, N); got shape {a.shape}")
    rel = a - a[:, :1]
    if t is None:
        if transient is not None:
            raise ValueError("transient is a time in tau: pass t as well")
        part = rel[rel.shape[0] // 2 :]
    else:
        _, part = obs.steady_part(t, rel, transient=transient)
    return part.mean(axis=0), part.std(axis=0)


def rotation_uniformity(t, theta, transient: float | None = None) -> float:
    """Relative spread std(w) / |mean(w)| of the instantaneous rotation rate w = d theta_1/dt
    over the steady part (0 for rotation at constant speed; inf if the chain does not turn)."""
    ta, a = obs._as_series(t, theta, name="theta", ndim=(1, 2))
    a = a[:, 0] if a.ndim == 2 else a
    ts, xs = obs.steady_part(ta, a, transient=transient)
    w = np.gradient(xs, ts)
    mean = abs(w.mean())
    return float(w.std() / mean) if mean > 0 else float("inf")


def _cycles(t, x, transient):
    tc = obs.upward_crossings(t, x, transient=transient)
    if tc.size < 3:
        raise ValueError(f"need at least 3 upward crossings (2 whole cycles); got {tc.size}")
    return tc


def period_variability(t, x, transient: float | None = None) -> float:
    """Coefficient of variation (std / mean) of the periods between upward mean crossings:
    0 on a limit cycle, growing as noise makes the cycle irregular."""
    tc = _cycles(t, x, transient)
    periods = np.diff(tc)
    return float(periods.std() / periods.mean())


def amplitude_variability(t, x, transient: float | None = None) -> float:
    """Coefficient of variation of the per-cycle half peak-to-peak of x (cycles between
    successive upward mean crossings)."""
    tc = _cycles(t, x, transient)
    ts, xs = obs.steady_part(t, x, transient=transient)
    amps = []
    for a, b in zip(tc[:-1], tc[1:]):
        m = (ts >= a) & (ts < b)
        if np.count_nonzero(m) >= 2:
            amps.append(0.5 * np.ptp(xs[m]))
    amps = np.asarray(amps)
    return float(amps.std() / amps.mean())


def chain_positions(theta) -> tuple[np.ndarray, np.ndarray]:
    """Particle positions (x, y) in units of l from absolute angles: r_i = sum_{j<=i} e_j.

    theta: (N,) or (T, N). Returns arrays of the same shape, the clamp at the origin excluded.
    """
    a = np.asarray(theta, dtype=float)
    return np.cumsum(np.cos(a), axis=-1), np.cumsum(np.sin(a), axis=-1)

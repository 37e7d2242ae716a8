"""Synchrony of a star's arms (the star scene): Hilbert phases of every arm's beat, the Kuramoto order parameters,
the mean phase differences, how firmly they are locked, and the state they make. Arrays in, numbers out.

For k arms with phases psi_j(t) (the Hilbert phase of arm j's Theta_j = theta_{j,N} - theta_{j,1}):

  R_m          = time mean of |(1/k) sum_j exp(i m psi_j)|: R_1 = 1 in phase, R_1 = 0 and R_k = 1 in a k-fold splay
                 state (psi_j = psi + 2 pi j s / k, s coprime to k; for k = 2 antiphase)
  differences  circular means of psi_j - psi_1 over the window, wrapped to (-pi, pi], j = 2 .. k
  locking      the smallest phase-locking value |<exp(i (psi_j - psi_1))>_t| over the arms: 1 when every phase
               difference is constant, ~0 when they drift through every value
"""

from __future__ import annotations

import math

import numpy as np

from .observables import hilbert_phase

__all__ = [
    "LOCKED",
    "ORDERED",
    "SYNC_STATES",
    "arm_phases",
    "order_parameter",
    "phase_differences",
    "phase_locking",
    "sync_state",
]

LOCKED = 0.9
"""Phase-locking value from which the arms count as locked (their phase differences steady)."""
ORDERED = 0.9
"""R_1 (in phase) or R_k (splay) from which a locked state is named by it; below 1 - ORDERED R_1 counts as zero."""
SYNC_STATES = ("rest", "unlocked", "in-phase", "antiphase", "splay", "locked", "uncoupled")
"""What sync_state returns: at rest (no arm beats), unlocked (phase differences drift), in phase, in antiphase
(k = 2), a k-fold splay state (k >= 3), locked in another pattern, or uncoupled: arms that share nothing (a clamped
hub), whose phase differences keep what their start gave them, so that no pattern is selected and none is named."""


def arm_phases(t, signals, transient: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(times, phases (k, T)): the unwrapped Hilbert phase of each arm's signal (rows of `signals`, shape (k, len(t)),
    typically Theta_j) after the transient, on their common whole-period window, a tenth of it cut at each end
    (the transform's edge effects)."""
    signals = np.asarray(signals, dtype=float)
    if signals.ndim != 2 or signals.shape[0] < 2:
        raise ValueError(f"signals must hold at least two arms' series, shape (k, T); got {signals.shape}")
    pieces = [hilbert_phase(t, x, transient, whole_periods=True, return_time=True) for x in signals]
    lo = max(tw[0] for tw, _ in pieces)
    hi = min(tw[-1] for tw, _ in pieces)
    cut = 0.1 * (hi - lo)
    t0, phi0 = pieces[0]
    keep = (t0 >= lo + cut) & (t0 <= hi - cut)
    if np.count_nonzero(keep) < 4:
        raise ValueError("the arms' phase windows barely overlap; use a longer record")
    tc = t0[keep]
    return tc, np.stack([np.interp(tc, tw, p) for tw, p in pieces])


def order_parameter(phases, m: int = 1) -> float:
    """R_m: the time mean of |(1/k) sum_j exp(i m psi_j(t))| for phases of shape (k, T)."""
    phases = np.asarray(phases, dtype=float)
    return float(np.mean(np.abs(np.mean(np.exp(1j * m * phases), axis=0))))


def phase_differences(phases) -> np.ndarray:
    """Circular means of psi_j - psi_1 over time (radians in (-pi, pi]), j = 2 .. k."""
    phases = np.asarray(phases, dtype=float)
    mean = np.angle(np.mean(np.exp(1j * (phases[1:] - phases[0])), axis=1))
    return np.where(mean <= -math.pi, mean + 2.0 * math.pi, mean)


def phase_locking(phases) -> float:
    """The smallest phase-locking value |<exp(i (psi_j - psi_1))>_t| over j = 2 .. k (1: every difference constant)."""
    phases = np.asarray(phases, dtype=float)
    return float(np.min(np.abs(np.mean(np.exp(1j * (phases[1:] - phases[0])), axis=1))))


def sync_state(phases, coupled: bool = True) -> str:
    """The arms' state (SYNC_STATES) from their phases (k, T): "uncoupled" for arms that share nothing (coupled False:
    identical independent arms keep steady phase differences, which are their start's, not a locked state); else
    unlocked below LOCKED; else in-phase (R_1 >= ORDERED), antiphase (k = 2, R_1 <= 1 - ORDERED), splay (k >= 3, R_1 ..
    R_{k-1} <= 1 - ORDERED and R_k >= ORDERED: no clusters), or locked (another steady pattern, e.g. two clusters).
    ("rest" is the caller's: no phases without a beat.)"""
    phases = np.asarray(phases, dtype=float)
    if not coupled:
        return "uncoupled"
    k = phases.shape[0]
    if phase_locking(phases) < LOCKED:
        return "unlocked"
    r1 = order_parameter(phases, 1)
    if r1 >= ORDERED:
        return "in-phase"
    if r1 <= 1.0 - ORDERED:
        if k == 2:
            return "antiphase"
        spread = all(order_parameter(phases, m) <= 1.0 - ORDERED for m in range(2, k))  # no clusters
        if spread and order_parameter(phases, k) >= ORDERED:
            return "splay"
    return "locked"

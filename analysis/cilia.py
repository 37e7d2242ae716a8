r"""What cilia on a wall do together: their tips' signals, a pair's phase lag and locked state, a row's metachronal
wave, and the volume flux they pump. Pure functions: arrays in, numbers and typed records out.

Signals. Each cilium's tip moves across the wall's normal in the wall's (x, y) plane; `tip_signals` projects every
tip's displacement (about its mean) on one axis, the major axis of the first cilium's tip path, so that the cilia's
phases compare whether they beat (in a common plane) or whirl. Phases are the Hilbert phases of these signals
(analysis.measures.phase_difference, on whole periods).

A pair (`pair_locking`): the phase lag Psi = Phi_2 - Phi_1 over the steady window, its circular mean `lag` in
(-pi, pi] and spread (analysis.locking.phase_spread). Locked when the spread is below LOCK_SPREAD and fewer than half
a slip of 2 pi accrues (analysis.measures.phase_slips); then 'in-phase' for |lag| <= LAG_TOLERANCE, 'anti-phase' for
|lag| >= pi - LAG_TOLERANCE, 'lag' between; 'none' when not locked (or not both beating).

A row (`metachronal_wave`): the lags between neighbours, dPsi_m = Phi_{m+1} - Phi_m (circular means); locked when
each neighbour pair is. A wave Phi(x, t) = omega t - k x has neighbours' lag -k d, so the wave number is
k = -<dPsi> / d (rad / l, signed along x: k > 0 a wave travelling toward +x); its direction '+x', '-x',
'synchronous' (|<dPsi>| <= LAG_TOLERANCE) or 'none' (not locked).

The flux (`blake_flux`). A point force F parallel to a no-slip wall at height h drives the flow of Blake's image
system (Blake 1971), whose far field is, to leading order in 1 / r,

    u_a = (3 h / (2 pi mu)) F_b x_a x_b z / r^5   (a, b along the wall; r measured from the force's foot on the wall).

The flux through the half-plane x = X (all y, z > 0), with y = rho cos phi, z = rho sin phi:
Q = (3 h F_x / (2 pi mu)) X^2 int_0^pi sin phi dphi int_0^inf rho^2 d rho / (X^2 + rho^2)^(5/2)
= (3 h F_x / (2 pi mu)) X^2 (2) (1 / (3 X^2)) = F_x h / (pi mu), whatever X (the flow is incompressible and its far
field carries no net flux elsewhere), and the forces' fluxes add (Stokes flow is linear). A force normal to the wall
pumps nothing along it (its far field is odd in x). In the units gamma = 6 pi mu a = 1 (a = bead_radius l), 1 / (pi mu)
= 6 a, so beads that push the fluid with forces F_i at heights h_i pump

    Q = 6 a sum_i F_x,i h_i   (l^3 / tau),

instantaneously; its time mean is the net flux. The finite-size corrections of the Rotne-Prager-Blake mobility decay
faster than 1 / r^2 and carry no flux (tests/analysis/test_cilia.py integrates the mobility's flow through a
half-plane far from the forces and finds the formula).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from . import measures
from . import observables as obs
from .locking import phase_spread
from .motion3d import REST_AMPLITUDE

__all__ = [
    "LAG_TOLERANCE",
    "LOCK_SPREAD",
    "LOCK_STATES",
    "WAVE_DIRECTIONS",
    "PairLocking",
    "Wave",
    "blake_flux",
    "circular_mean",
    "metachronal_wave",
    "pair_locking",
    "tip_signals",
]

LOCK_SPREAD = 0.3
"""Largest circular spread (rad) of a locked pair's phase lag over the window."""
LAG_TOLERANCE = math.pi / 8
"""A locked lag within this of 0 is in phase, within this of pi anti-phase (rad)."""
LOCK_STATES = ("in-phase", "anti-phase", "lag", "none")
WAVE_DIRECTIONS = ("+x", "-x", "synchronous", "none")


class PairLocking(NamedTuple):
    """Two oscillations' phase relation over a window."""

    lag: float
    """Circular mean of Phi_2 - Phi_1 (rad, in (-pi, pi]); NaN where the phases are not measured."""
    spread: float
    """Circular spread of the lag (rad)."""
    slips: float
    """Net 2 pi slips of the lag over the window."""
    state: str
    """One of LOCK_STATES."""


class Wave(NamedTuple):
    """A row's metachronal wave."""

    wave_number: float
    """k = -<Phi_{m+1} - Phi_m> / d (rad / l, signed along x); NaN unless locked."""
    direction: str
    """One of WAVE_DIRECTIONS."""
    lags: np.ndarray
    """The neighbours' lags <Phi_{m+1} - Phi_m> (rad), M - 1 of them."""


def tip_signals(positions: np.ndarray) -> np.ndarray:
    """(C, T): every cilium's tip displacement in the wall's plane, about its mean, along the major axis of the first
    cilium's tip path (positions (T, C, N, 3), the wall's normal z)."""
    tips = np.asarray(positions, dtype=float)[:, :, -1, :2]
    lateral = tips - tips.mean(axis=0)
    spread = np.cov(lateral[:, 0].T) if len(tips) > 1 else np.eye(2)
    _, axes = np.linalg.eigh(spread)
    return np.moveaxis(lateral @ axes[:, 1], 0, -1)


def circular_mean(angles: np.ndarray) -> float:
    """The mean direction of angles (rad), in (-pi, pi]."""
    return float(np.angle(np.mean(np.exp(1j * np.asarray(angles, dtype=float)))))


def _lock_state(lag: float, spread: float, slips: float) -> str:
    if not (spread < LOCK_SPREAD and slips < 0.5):
        return "none"
    if abs(lag) <= LAG_TOLERANCE:
        return "in-phase"
    if abs(lag) >= math.pi - LAG_TOLERANCE:
        return "anti-phase"
    return "lag"


def pair_locking(t, x1, x2, transient: float | None = None) -> PairLocking:
    """The phase relation of signals x1, x2 sampled at uniform t, after the transient (module docstring); 'none' with
    NaN lag where either is at rest (amplitude at most motion3d.REST_AMPLITUDE) or has too few periods for its
    phase."""
    if min(obs.amplitude(t, x, transient) for x in (x1, x2)) <= REST_AMPLITUDE:
        return PairLocking(math.nan, math.nan, math.nan, "none")
    try:
        _, psi = measures.phase_difference(t, x1, x2, transient)
    except ValueError:
        return PairLocking(math.nan, math.nan, math.nan, "none")
    k = max(1, psi.size // 10)
    slips = float(abs(psi[-k:].mean() - psi[:k].mean()) / (2.0 * math.pi))
    lag, spread = circular_mean(psi), phase_spread(psi)
    return PairLocking(lag, spread, slips, _lock_state(lag, spread, slips))


def metachronal_wave(t, signals: np.ndarray, spacing: float, transient: float | None = None) -> Wave:
    """The wave of a row of cilia at `spacing` (l) along x whose signals (M, T) are sampled at uniform t."""
    pairs = [pair_locking(t, a, b, transient) for a, b in zip(signals[:-1], signals[1:], strict=True)]
    lags = np.array([p.lag for p in pairs])
    if any(p.state == "none" for p in pairs):
        return Wave(math.nan, "none", lags)
    mean = circular_mean(lags)
    if abs(mean) <= LAG_TOLERANCE:
        return Wave(-mean / spacing, "synchronous", lags)
    return Wave(-mean / spacing, "+x" if mean < 0 else "-x", lags)


def blake_flux(force_x, heights, radius: float) -> np.ndarray:
    """Q(t) = 6 a sum_i F_x,i h_i (l^3 / tau): the flux along +x that forces F_x,i (C1 / l) on the fluid at heights
    h_i (l) above a no-slip wall pump, beads of radius a = `radius` (l) setting the viscosity (6 pi mu a = 1). The
    first axis of force_x and heights is time, the others the beads (summed), e.g. (T, C, N) -> (T,)."""
    f = np.asarray(force_x, dtype=float)
    h = np.asarray(heights, dtype=float)
    return 6.0 * radius * (f * h).reshape(len(f), -1).sum(axis=1)

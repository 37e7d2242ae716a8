"""Locking of a beat to a periodic drive, and the Adler width of the locking range from a phase response.

Pure functions: arrays in, numbers and typed records out.

A beat of frequency f_0 under a weak drive of frequency f is 1:1 locked when its phase follows the drive's,
psi = Phi_beat - 2 pi f t bounded. Measures (drive_locking): the frequency ratio f_beat / f (1 when locked) and the
circular spread of psi over the window, sqrt(-2 ln |<exp(i psi)>|) (0 for a constant psi, large when psi drifts).

Adler's estimate: with the beat's phase response Z(phi) to a unit perturbation of a drive coordinate y (the
phase advance per unit kick of y, at phase phi), a drive y(t) = A sin(Omega t) acts through y' = A Omega
cos(Omega t) and averages to psi' = (omega_0 - Omega) + A H(psi) with the coupling function
H(psi) = Omega <Z(psi + s) cos s>_s; the beat locks while |Omega - omega_0| <= A max|H| (adler_half_width):
for a Z with first Fourier coefficients a_1 cos + b_1 sin, max|H| = Omega sqrt(a_1^2 + b_1^2) / 2.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from . import measures
from . import observables as obs

__all__ = [
    "Locking",
    "drive_locking",
    "phase_spread",
    "coupling_amplitude",
    "adler_half_width",
    "asymptotic_phase_shift",
]


class Locking(NamedTuple):
    """A beat against a drive of frequency f over a window."""

    frequency_ratio: float
    """f_beat / f_drive (nan when the beat has no frequency in the window)."""
    phase_spread: float
    """Circular spread of Phi_beat - 2 pi f t (rad; nan as above)."""


def phase_spread(psi: np.ndarray) -> float:
    """sqrt(-2 ln R), R = |mean exp(i psi)|: the circular standard deviation of psi (rad)."""
    r = min(1.0, float(abs(np.mean(np.exp(1j * np.asarray(psi, dtype=float))))))  # rounding can pass 1
    return math.sqrt(-2.0 * math.log(r)) if r > 0 else math.inf


def drive_locking(t: np.ndarray, theta: np.ndarray, drive_frequency: float, transient: float) -> Locking:
    """The beat of one chain's angles theta (T, N) (its curvature Theta = theta_N - theta_1) against the drive
    sin(2 pi f t), after `transient` (tau from the first sample)."""
    t = np.asarray(t, dtype=float)
    keep = t >= t[0] + transient
    ts, x = t[keep], obs.curvature(np.asarray(theta)[keep])
    beat = obs.frequency(ts, x)
    if not (math.isfinite(beat) and beat > 0):
        return Locking(math.nan, math.nan)
    try:
        _, psi = measures.phase_difference(ts, np.sin(2.0 * math.pi * drive_frequency * ts), x)
    except ValueError:  # too few whole periods in the window for the phases
        return Locking(float(beat / drive_frequency), math.nan)
    return Locking(float(beat / drive_frequency), phase_spread(psi))


def coupling_amplitude(phases: np.ndarray, response: np.ndarray) -> float:
    """sqrt(a_1^2 + b_1^2) / 2 for a phase response Z(phi) sampled at phases spread evenly over one period
    (least squares fit of Z by a_0 + a_1 cos phi + b_1 sin phi): max|H| / Omega."""
    phases, response = np.asarray(phases, dtype=float), np.asarray(response, dtype=float)
    if phases.size < 3:
        raise ValueError("the phase response needs at least 3 phases")
    basis = np.column_stack([np.ones_like(phases), np.cos(phases), np.sin(phases)])
    coef, *_ = np.linalg.lstsq(basis, response, rcond=None)
    return float(math.hypot(coef[1], coef[2]) / 2.0)


def adler_half_width(amplitude: float, drive_omega: float, coupling: float) -> float:
    """Adler's locking half width A max|H| = A Omega coupling (rad / tau) for a drive A sin(Omega t) of the
    coordinate whose phase response has coupling_amplitude `coupling`."""
    return abs(amplitude) * drive_omega * coupling


def asymptotic_phase_shift(
    t: np.ndarray, x_free: np.ndarray, x_kicked: np.ndarray, omega: float, last: int = 4
) -> float:
    """Phase advance (rad) of a kicked beat over the free one, omega (t_free - t_kicked) averaged over the `last`
    upward mean crossings of both signals (sampled at the same times t, after the kick has relaxed)."""
    up_free = obs.upward_crossings(t, x_free, transient=0.0)
    up_kick = obs.upward_crossings(t, x_kicked, transient=0.0)
    k = min(last, up_free.size, up_kick.size)
    if k < 1:
        raise ValueError("no upward crossing in the window: run the kicked beats longer")
    # pair each crossing of the kicked beat with the nearest of the free one
    free = up_free[-k:]
    kicked = np.array([up_kick[np.argmin(np.abs(up_kick - c))] for c in free])
    return float(omega * np.mean(free - kicked))

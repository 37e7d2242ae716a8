"""The locking threshold of two coupled oscillators: the critical coupling read off a grid of
locked / slipping runs, and the near-onset N = 2 theory (a sqrt(mu |1 - rho|) law and the phase
equation it is meant to come from). Arrays in, numbers out.
"""

from __future__ import annotations

import numpy as np

__all__ = ["locking_threshold", "kappa_c_sqrt_law", "kappa_c_phase_equation"]


def locking_threshold(kappa, locked) -> tuple[float, float]:
    """(kappa_lo, kappa_hi): the largest unlocked kappa below the smallest kappa from which every
    larger kappa of the (sorted) grid is locked. (kappa_max, inf) if the largest is not locked;
    (nan, kappa_min) if every kappa is."""
    kappa = np.asarray(kappa, float)
    locked = np.asarray(locked, bool)
    order = np.argsort(kappa)
    kappa, locked = kappa[order], locked[order]
    if not locked[-1]:
        return float(kappa[-1]), float("inf")
    i = kappa.size - 1
    while i > 0 and locked[i - 1]:
        i -= 1
    return (float(kappa[i - 1]) if i > 0 else float("nan")), float(kappa[i])


def kappa_c_sqrt_law(mu, rho, prefactor: float):
    """kappa_c = prefactor sqrt(mu |1 - rho|) (mu = sigma - 3: distance from the N = 2 onset;
    rho = C2 / C1)."""
    return prefactor * np.sqrt(np.asarray(mu) * np.abs(1.0 - np.asarray(rho)))


def kappa_c_phase_equation(mu, rho, detuning: float):
    """kappa_c from the phase equation d Psi/dt = d nu + eps / cos Psi_0 sin(Psi - Psi_0), i.e.
    |d nu| = |eps / cos Psi_0|, with d nu = detuning (rho - 1),
    eps = kappa (2 mu - 3 (rho - 1)) / (2 sqrt(mu (mu - 3 (rho - 1)))) and
    tan Psi_0 = 3 (rho - 1) / (2 mu - 3 (rho - 1)). For |rho - 1| << mu it tends to detuning |1 - rho|."""
    mu, r = np.asarray(mu, float), np.asarray(rho, float) - 1.0
    per_kappa = np.sqrt((2 * mu - 3 * r) ** 2 + 9 * r**2) / (2 * np.sqrt(mu * (mu - 3 * r)))
    return detuning * np.abs(r) / per_kappa

"""The N = 2 chain near its Hopf onset as a Landau-Stuart oscillator, dz/dt = (i + mu) z + c |z|^2 z
(mu = sigma - 3): what a given cubic coefficient c predicts for the limit cycle, and what a simulated
limit cycle measures. Arrays in, numbers out; l = C = gamma = 1 (tau = 1).
"""

from __future__ import annotations

import numpy as np

from .measures import landau_variable

__all__ = ["landau_limit_cycle", "limit_cycle_moments"]


def landau_limit_cycle(mu, c_at_onset: complex, c_slope: complex = 0j) -> tuple[np.ndarray, np.ndarray]:
    """(<|z|^2>, omega) on the limit cycle of the Landau-Stuart form with c(mu) = c_at_onset + c_slope mu:
    |z|^2 = mu / (-Re c) and omega = 1 + Im c |z|^2."""
    mu = np.asarray(mu, dtype=float)
    re = c_at_onset.real + c_slope.real * mu
    im = c_at_onset.imag + c_slope.imag * mu
    z2 = mu / -re
    return z2, 1.0 + im * z2


def limit_cycle_moments(t, theta, mu: float, transient: float) -> tuple[float, float]:
    """(<|z|^2>, omega) of a simulated N = 2 record after `transient`: the mean of |z|^2 of the
    supplement's variable z (measures.landau_variable) and the slope of its unwrapped phase."""
    t = np.asarray(t, dtype=float)
    m = t >= transient
    z = landau_variable(np.asarray(theta)[m], mu)
    omega = abs(np.polyfit(t[m], np.unwrap(np.angle(z)), 1)[0])
    return float(np.mean(np.abs(z) ** 2)), float(omega)

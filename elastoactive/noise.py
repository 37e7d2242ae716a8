"""Counter-based Gaussian white noise shared by the MuJoCo callback and the reduced model.

The noise on particle p during step k depends only on (seed, k, p): no generator state, so
runs are reproducible, threads need no coordination, and the C callback in
`controllers/follower.c` draws exactly the numbers this module draws (a test checks it).

Draw: key = splitmix64(splitmix64(seed) ^ k); u1, u2 from splitmix64(key + 2p), splitmix64(key + 2p + 1)
(top 53 bits); xi = sqrt(-2 ln(1 - u1)) cos(2 pi u2) (Box-Muller). Over a step of length dt the
white noise eta of amplitude a is the constant a xi / sqrt(dt), so sum(eta dt) has variance a^2 t
(Ito, Euler-Maruyama).
"""

from __future__ import annotations

import numpy as np

_MASK = np.uint64(0xFFFFFFFFFFFFFFFF)


def splitmix64(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.uint64)
    with np.errstate(over="ignore"):
        z = x + np.uint64(0x9E3779B97F4A7C15)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def standard_normal(seed: int, step: int | np.ndarray, n_particles: int) -> np.ndarray:
    """xi[k, p] for the given step(s) and particles 0..n_particles-1; shape (len(step), n_particles)."""
    steps = np.atleast_1d(np.asarray(step, dtype=np.uint64))
    key = splitmix64(splitmix64(np.uint64(seed)) ^ steps)[:, None]
    p = np.arange(n_particles, dtype=np.uint64)[None, :]
    with np.errstate(over="ignore"):
        h1 = splitmix64(key + np.uint64(2) * p)
        h2 = splitmix64(key + np.uint64(2) * p + np.uint64(1))
    u1 = (h1 >> np.uint64(11)).astype(np.float64) * 2.0**-53
    u2 = (h2 >> np.uint64(11)).astype(np.float64) * 2.0**-53
    return np.sqrt(-2.0 * np.log1p(-u1)) * np.cos(2.0 * np.pi * u2)


def force_factor(seed: int, step: int | np.ndarray, n_particles: int, amplitude: float, dt: float) -> np.ndarray:
    """1 + eta over each step: the factor multiplying F_a on each particle."""
    if amplitude == 0:
        return np.ones((np.atleast_1d(step).size, n_particles))
    return 1.0 + amplitude / np.sqrt(dt) * standard_normal(seed, step, n_particles)

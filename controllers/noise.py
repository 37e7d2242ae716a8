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

import math

import numpy as np


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


# ----------------------------------------------------------------------------------------------
# coloured noise: an Ornstein-Uhlenbeck process per particle
# ----------------------------------------------------------------------------------------------
INITIAL_STEP = 0xFFFFFFFFFFFFFFFF
"""The counter of the stationary draw of eta_0 (a step index no run reaches), so that eta_0 has its own draws."""


def ou_constants(amplitude: float, tau_c: float, dt: float) -> tuple[float, float, float]:
    """(stationary standard deviation, decay e = exp(-dt / tau_c), innovation scale sqrt(var (1 - e^2))) of the
    coloured noise of amplitude a and correlation time tau_c: var = a^2 / (2 tau_c), so that
    <eta(t) eta(t')> = a^2 / (2 tau_c) exp(-|t - t'| / tau_c) -> a^2 delta(t - t') as tau_c -> 0 (the white
    noise of the same amplitude). Scalar libm arithmetic (math.exp, math.sqrt), as follower.c computes them."""
    var = amplitude * amplitude / (2.0 * tau_c)
    decay = math.exp(-dt / tau_c)
    return math.sqrt(var), decay, math.sqrt(var * (1.0 - decay * decay))


class ColouredNoise:
    """The coloured noise eta[k, p] of one run: an Ornstein-Uhlenbeck process per particle, constant over each
    step (the value at the step's start), updated once per step by the exact OU discretisation

        eta_0 = sqrt(var) xi(seed, INITIAL_STEP, p)                        (the stationary law)
        eta_{k+1} = e eta_k + sqrt(var (1 - e^2)) xi(seed, k, p)           (e = exp(-dt / tau_c))

    with the counter-based xi of standard_normal. eta_k is a function of (seed, k) alone; follower.c computes the
    same numbers, in the same order, keeping eta_k in mjData.userdata. `eta(steps)` is fastest for consecutive
    calls on consecutive steps (it resumes where it stopped; other steps replay from step 0)."""

    def __init__(self, seed: int, n_particles: int, amplitude: float, tau_c: float, dt: float):
        if not tau_c > 0:
            raise ValueError(f"the correlation time tau_c must be > 0, got {tau_c}")
        self.seed, self.n = int(seed), int(n_particles)
        self.std, self.decay, self.kick = ou_constants(amplitude, tau_c, dt)
        self._start()

    def _start(self) -> None:
        self.step = 0
        self.value = self.std * standard_normal(self.seed, INITIAL_STEP, self.n)[0]

    def advance(self, step: int) -> np.ndarray:
        """eta at `step` (the held state moves there)."""
        if step < self.step:
            self._start()
        if step > self.step:
            xi = standard_normal(self.seed, np.arange(self.step, step), self.n)
            value = self.value
            for row in xi:
                value = self.decay * value + self.kick * row
            self.value, self.step = value, step
        return self.value

    def eta(self, steps) -> np.ndarray:
        """eta[k, p] for the given (non-decreasing) step indices; shape (len(steps), n_particles)."""
        steps = np.atleast_1d(np.asarray(steps, dtype=np.int64))
        out = np.empty((steps.size, self.n))
        if steps.size and steps[0] < self.step:
            self._start()
        if steps.size > 1 and np.all(np.diff(steps) == 1):  # the common case: one draw call for the block
            first = int(steps[0])
            self.advance(first)
            xi = standard_normal(self.seed, np.arange(first, int(steps[-1])), self.n)
            value = self.value
            out[0] = value
            for r in range(xi.shape[0]):
                value = self.decay * value + self.kick * xi[r]
                out[r + 1] = value
            self.value, self.step = value, int(steps[-1])
            return out
        for r, k in enumerate(steps):
            out[r] = self.advance(int(k))
        return out

    def force_factor(self, steps) -> np.ndarray:
        """1 + eta over each step: the factor multiplying F_a on each particle."""
        return 1.0 + self.eta(steps)

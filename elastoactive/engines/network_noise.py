"""Noise on a network's units in MuJoCo: the Euler-Maruyama kicks of elastoactive.terms.unit_noise after each step.

`NoisySteps` replaces mj_step(model, data, nstep) in a noisy network run: one step at a time, each followed by
qpos += sqrt(2 D_t dt) xi[:2F] (the free nodes' slide joints, in the reduced state's order) and
act[units] += sqrt(2 D_r dt) xi[2F:] (the polarities, node order), xi = controllers.noise.standard_normal(seed, k,
2F + A) over step k counted from the run's start: the reduced engine's draws (reduced.network.solve_noisy), so the two
engines integrate the same realisation. The velocities are left alone: a unit turns toward its node's drift, as in
the reduced model. A step's Python costs a few microseconds beside MuJoCo's (the noiseless run stays in C).
"""

from __future__ import annotations

import mujoco
import numpy as np

from ..controllers.noise import standard_normal
from ..terms.unit_noise import UnitNoise


class NoisySteps:
    """Callable (model, data, nstep): nstep MuJoCo steps, each followed by the unit noise's kicks."""

    def __init__(self, noise: UnitNoise, dt: float, n_coordinates: int, units: np.ndarray):
        self.seed = int(noise.seed)
        self.units = np.asarray(units, dtype=int)
        self.f2 = int(n_coordinates)
        self.size = self.f2 + self.units.size
        self.translational = float(np.sqrt(2.0 * noise.translational * dt))
        self.rotational = float(np.sqrt(2.0 * noise.rotational * dt))
        self.step = 0

    def __call__(self, model: mujoco.MjModel, data: mujoco.MjData, nstep: int) -> None:
        for _ in range(int(nstep)):
            mujoco.mj_step(model, data)
            xi = standard_normal(self.seed, self.step, self.size)[0]
            if self.translational:
                data.qpos[: self.f2] += self.translational * xi[: self.f2]
            if self.rotational:
                data.act[self.units] += self.rotational * xi[self.f2 :]
            self.step += 1

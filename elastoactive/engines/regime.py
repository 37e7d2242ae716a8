"""Which physics a mass ratio gives: the one criterion both engines and the pre-flight check use.

Inside the overdamped limit, mass_ratio x (fastest overdamped rate at the scene's base state) <= INERTIA_RESOLUTION
(0.1), both engines model the paper's overdamped chain (MuJoCo approximates it with a small mass); outside it, both
model the inertial chain with that mass. A light module (the reduced model's numpy functions, no compiled solver),
so that elastoactive.engines.timestep classifies a MuJoCo run without loading the reduced engine;
elastoactive.engines.reduced runs the model this chooses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import reduced as _math
from ..core.params import Numerics, Physics
from ..reduced import INERTIA_RESOLUTION

EXACT_RATE_ANGLES = 50
"""From this many angles on, regime tries the cheap upper bound of the rate before its eigenvalues (which cost ~1 s
at N = 400)."""


def base_state(physics: Physics) -> np.ndarray:
    """The scene's base state (its initial state without the seeded push): the straight chain(s), or the
    two-pinned chain's arch (MuJoCo's keyframe)."""
    return np.asarray(physics.scene_def.initial_angles(physics, Numerics(perturbation=0.0)), dtype=float)


@dataclass(frozen=True)
class Regime:
    """Which physics a mass ratio gives (see the module docstring).

    model           "overdamped" or "inertial"
    mass_ratio      the particle mass m / (gamma tau)
    rate            fastest overdamped rate at the base state, 1/tau (analysis.reduced.overdamped_rate); for
                    systems of EXACT_RATE_ANGLES angles or more, its upper bound (analysis.reduced.rate_bound)
                    when that already places the mass inside the limit (rate_is_bound)
    inertia_number  mass_ratio x rate: the inertial time over the fastest overdamped time
    """

    model: str
    mass_ratio: float
    rate: float
    inertia_number: float
    rate_is_bound: bool = False

    @property
    def inertial(self) -> bool:
        return self.model == "inertial"

    @property
    def mass_limit(self) -> float:
        """Largest mass ratio inside the overdamped limit (INERTIA_RESOLUTION / rate)."""
        return INERTIA_RESOLUTION / self.rate if self.rate > 0 else np.inf

    def describe(self) -> str:
        where = "outside" if self.inertial else "inside"
        return (
            f"mass_ratio = {self.mass_ratio:g} is {where} the overdamped limit (m x fastest overdamped rate = "
            f"{self.mass_ratio:g} x {self.rate:.3g} = {self.inertia_number:.2g}, limit {INERTIA_RESOLUTION:g}): "
            f"both engines model the {self.model} chain"
        )


def regime(physics: Physics, numerics: Numerics) -> Regime:
    """The one criterion: inertial iff numerics.mass_ratio x (fastest overdamped rate at the base state)
    > INERTIA_RESOLUTION (analysis.reduced.regime)."""
    m = float(numerics.mass_ratio)
    system, theta = physics.scene_def.reduced_system(physics), base_state(physics)
    if system.n_angles >= EXACT_RATE_ANGLES:  # a cheap bound decides first
        bound = _math.rate_bound(system, theta)
        if not _math.outside_overdamped_limit(m, bound):
            return Regime("overdamped", m, bound, m * bound, rate_is_bound=True)
    rate = _math.overdamped_rate(system, theta)
    return Regime("inertial" if _math.outside_overdamped_limit(m, rate) else "overdamped", m, rate, m * rate)

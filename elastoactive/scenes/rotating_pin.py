"""A freely rotating pin: no spring at the clamp, so the whole bent chain turns at constant speed.

Paper, appendix: at sigma = 0.33 (N = 7) the chain settles into a fixed bent shape that rotates
about the pin; the sense of rotation is chosen spontaneously. Observable: rotation_rate, the mean
d theta_1 / dt in rad per tau (validated instead of the beat's amplitude and frequency).
"""

from __future__ import annotations

import math

from ..analysis import observables as obs
from ..core.observables import Observable
from ..core.params import Physics
from ..core.trajectory import Trajectory
from .base import Onset, ValidationCase
from .chain_kind import ChainScene

ROTATION_RATE = Observable("rotation_rate", "rad/tau", "mean d theta_1 / dt", floor=1e-6)
"""A chain's rigid turning rate (every scene whose chain turns as a whole reports it: the ring, the dish)."""


class RotatingPin(ChainScene):
    name = "rotating-pin"
    paper = True
    summary = "first hinge free (no clamp spring): steady rotation about the pin"
    base_file = "rotating-pin.xml"
    clamped = False
    observables = (ROTATION_RATE,)
    compared = ("rotation_rate",)
    no_linear_operator = ""

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        return {"rotation_rate": obs.rotation_rate(traj.t, traj.theta, transient)}

    def onset(self, physics: Physics) -> Onset:
        from ..analysis import stability  # start-up time: scipy

        return Onset(stability.rotation_threshold(physics.n), 0.0, "steady rotation (a real eigenvalue crosses 0)")

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        import numpy as np  # the eigenvalues' array

        from ..analysis import stability  # start-up time: scipy

        lam = np.linalg.eigvals(stability.rotating_operator(physics.n, sigma))
        return complex(lam[np.argmax(lam.real)])

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (ValidationCase(self.physics(n=7, sigma=0.8), 300.0),)

    def extreme_cases(self, quick: bool = False) -> tuple[Physics, ...]:
        if quick:
            return ()
        return tuple(self.physics(n=7, sigma=s) for s in (0.8, 100.0)) + (self.physics(n=100, sigma=0.8),)

    def video_period(self, traj: Trajectory) -> float | None:
        """One turn per second of video."""
        omega = abs(obs.rotation_rate(traj.t, traj.theta))
        return 2.0 * math.pi / omega if omega > 1e-3 else None


SCENE = RotatingPin()

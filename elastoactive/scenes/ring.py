"""A ring: the chain closes on itself, one particle held at a free pin.

Beyond the paper (its outlook's "more intricate geometrical connections"): N particles on N rigid links, a
torsional spring C1 at every joint including the one that closes the ring (between the last link and the first),
the follower force on every particle. The first link starts at a free pin at the origin and the last particle is
held there, so the ring can turn about that point. At rest it is the regular N-gon, every joint bent by 2 pi / N.
The follower forces sum to zero round a closed ring but not their torque: the ring turns about the pin.

MuJoCo: the last particle is held at the pin by a connect equality (as the two-pinned chain's end, nearly hard),
and the closing spring is a fixed tendon hinge_1 + ... + hinge_{N-1} with rest length 2 pi. The reduced model: the
two-pinned chain's constraints with the pin at the pivot (delta = 1) and the closing spring (ChainSystem.closed).
Observables: rotation_rate (mean d theta_1 / dt: the ring's turning), with the beat of Theta = theta_N - theta_1
where its shape oscillates.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import observables as obs
from ..analysis.reduced.constraints import project_on_pins
from ..analysis.reduced.system import ChainSystem
from ..errors import ParameterError
from ..initial import pushed_chains
from ..params import Numerics, Physics
from ..trajectory import Trajectory
from .base import Scene, ValidationCase
from .two_pinned import PIN_SOLIMP

CLOSED = 1.0
"""The reduced model's compression delta that puts the last particle on the pivot: (N (1 - delta), 0) = (0, 0)."""


def polygon(n: int) -> np.ndarray:
    """Absolute angles of the regular N-gon, first link along +x, turning counterclockwise."""
    return 2.0 * math.pi * np.arange(n) / n


class Ring(Scene):
    name = "ring"
    summary = "the chain closed on itself, one particle on a free pin: the ring turns about it"
    base_file = "ring.xml"
    min_n = 3
    clamped = False
    pinned = True
    observables = ("rotation_rate",)
    compared = ("rotation_rate",)
    no_linear_operator = "the ring turns about its pin at any sigma > 0: its steady state is a rotation, not a rest"

    def check(self, physics: Physics) -> None:
        super().check(physics)
        if physics.contact:  # the reduced model's contact path has no closing spring (ChainSystem.typed refuses it)
            raise ParameterError("contact: self-contact is not built for the ring (the reduced model that checks its "
                                 "numerics and cross-validates it has no closing spring with contact)")

    def build(self, spec, physics: Physics, numerics: Numerics) -> None:
        import mujoco  # start-up time: mujoco is needed only to build a model

        spec.add_equality(
            name="pin", type=mujoco.mjtEq.mjEQ_CONNECT, objtype=mujoco.mjtObj.mjOBJ_SITE,
            name1=f"particle_{physics.n - 1}", name2="pin", solref=[2.0 * numerics.dt, 1.0], solimp=list(PIN_SOLIMP),
        )
        closure = spec.add_tendon(name="closure", stiffness=[1.0, 0, 0], springlength=[2.0 * math.pi, 2.0 * math.pi])
        for i in range(1, physics.n):
            closure.wrap_joint(f"hinge_{i}", 1.0)
        spec.add_key(name="ring", qpos=np.diff(polygon(physics.n), prepend=0.0).tolist())

    def reduced_system(self, physics: Physics) -> ChainSystem:
        return super().reduced_system(physics)._replace(delta=CLOSED, closed=True)

    def initial_angles(self, physics: Physics, numerics: Numerics) -> np.ndarray:
        """The regular N-gon, pushed like the other scenes and projected back onto the pin."""
        kick = pushed_chains(physics.n, 1, numerics.perturbation, numerics.seed)
        return project_on_pins(polygon(physics.n) + kick, CLOSED)

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        return {"rotation_rate": obs.rotation_rate(traj.t, traj.theta, transient)}

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (ValidationCase(self.physics(n=7, sigma=0.8), 300.0),)

    def extent_points(self, physics: Physics) -> np.ndarray:
        return np.zeros((1, 2))


SCENE = Ring()

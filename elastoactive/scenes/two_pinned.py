"""Both ends pinned: the compressed chain buckles into an arch and, above a threshold, snaps.

The last particle is held at (N (1 - delta), 0). In MuJoCo the pin is a soft `connect` equality
to a world site, nearly hard (solimp close to 1) with MuJoCo's shortest time constant 2 dt; its
hold scales with mass_ratio / dt^2 (docs/mujoco.md). In the reduced model it is a pair of
holonomic constraints g(theta) = (sum cos theta_i - N (1 - delta), sum sin theta_i) = 0, solved
as a Baumgarte-stabilised saddle-point system. Observable: snap_amplitude (std of theta_3).
"""

from __future__ import annotations

import numpy as np

from ..analysis import observables as obs
from ..core.observables import Observable
from ..core.parameters import Parameter
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory
from ..reduced.initial import buckled_arch, project_on_pins, pushed_chains
from ..reduced.system import ChainSystem
from .base import ValidationCase
from .chain_kind import ChainScene

# The pin is a soft constraint; its time constant is MuJoCo's floor 2 dt (set explicitly, since
# MuJoCo would raise a smaller one silently) and its impedance is close to 1 (nearly hard). With
# the particles' tiny mass the default solimp lets the pin drift by ~1e-2 l (docs/mujoco.md).
PIN_SOLIMP = (0.9999, 0.999999, 0.001, 0.5, 2.0)


SNAP_AMPLITUDE = Observable("snap_amplitude", "rad", "standard deviation of theta_3 (self-snapping; NaN for n < 3)")
"""The snap-through's size: analysis.observables.snap_amplitude of theta_3 over the measured window."""


class TwoPinned(ChainScene):
    name = "two-pinned"
    paper = True
    summary = "last particle also pinned at (N l (1-delta), 0): self-snapping"
    base_file = "two-pinned.xml"
    parameters = (
        Parameter(
            "delta",
            0.1,
            "compression of the two-pinned chain, in [0, 1)",
            low=0.0,
            high=1.0,
            high_open=True,
            title="compression",
            symbol="δ",
        ),
    )
    min_n = 2
    pinned = True
    no_linear_operator = "its base state, the buckled arch, is held by the pins and moves with the load"
    observables = (SNAP_AMPLITUDE,)

    def pin_position(self, physics: Physics) -> tuple[float, float]:
        return physics.n * (1.0 - physics.delta), 0.0

    def build(self, spec, physics: Physics, numerics: Numerics) -> None:
        import mujoco  # start-up time: mujoco is needed only to build a model

        end = [*self.pin_position(physics), 0.0]
        spec.site("pin").pos = end
        spec.geom("pin_marker").pos = end
        spec.add_equality(
            name="pin",
            type=mujoco.mjtEq.mjEQ_CONNECT,
            objtype=mujoco.mjtObj.mjOBJ_SITE,
            name1=f"particle_{physics.n - 1}",
            name2="pin",
            solref=[2.0 * numerics.dt, 1.0],
            solimp=list(PIN_SOLIMP),
        )
        arch = buckled_arch(physics.n, physics.delta)
        spec.add_key(name="buckled", qpos=np.diff(arch, prepend=0.0).tolist())

    def reduced_system(self, physics: Physics) -> ChainSystem:
        return super().reduced_system(physics)._replace(delta=physics.delta)

    def initial_angles(self, physics: Physics, numerics: Numerics) -> np.ndarray:
        """A single arch at the compression, pushed like the other scenes and projected back onto the pins."""
        kick = pushed_chains(physics.n, 1, numerics.perturbation, numerics.seed)
        return project_on_pins(buckled_arch(physics.n, physics.delta) + kick, physics.delta)

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        if traj.physics.n < 3:  # theta_3 does not exist
            return {}
        return {"snap_amplitude": obs.snap_amplitude(traj.theta, traj.t, transient)}

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (ValidationCase(self.physics(n=7, sigma=0.8, delta=0.1), 300.0),)

    def extreme_cases(self, quick: bool = False) -> tuple[Physics, ...]:
        if quick:
            return (self.physics(n=7, sigma=0.8, delta=0.5),)
        cases = tuple(self.physics(n=7, sigma=s, delta=d) for d in (0.1, 0.5) for s in (0.8, 10.0))
        return cases + (self.physics(n=30, sigma=0.8, delta=0.5),)

    def extent_points(self, physics: Physics) -> np.ndarray:
        return np.array([self.pin_position(physics)])


SCENE = TwoPinned()

"""A free chain in a paraboloid dish: the supplement's satellite-dish experiment (sigma = 0.30).

The rotating-pin chain whose pin also slides: the head point, the pivot of the first pendulum, has two
more coordinates (x_h, y_h). It is the chain's front piece: it carries one particle's drag (gamma_L
along the first pendulum, gamma_T across) and one particle's mass, and no active force. Without drag
there the drag matrix is singular: the first pendulum could swing about particle 1 for free, its
pivot moving at no cost. The dish enters in its small-slope limit, a harmonic trap: every particle
and the head feel -k r, with r measured from the dish's centre and trap = k l^2 / C1 (the units of
kappa). In MuJoCo each of them hangs on a spatial tendon of rest length 0 from the centre, whose
spring is exactly -k r; in the reduced model the head adds two coordinates after the angles.

Observables (elastoactive.analysis.dish): rotation_rate (mean d theta_1 / dt, the body's rotation),
orbit_rate (mean angular velocity of the centre of mass about the dish's centre; the centre of mass of the
N particles, the head left out, as the issue's sanity figures count it), orbit_radius, and
curvature (the chain's mean curvature), and dish_state: "rest", "spin", "orbit", "crawl", "beat" or "irregular"
(STATE_MEANING). The supplement: the chain "tends to rotate around the center of the
paraboloid, but ... also crawls in circles at the same time".
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import dish
from ..analysis import observables as obs
from ..core.observables import Observable
from ..core.parameters import Parameter
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory
from ..core.units import NETWORK, Worded
from ..reduced.system import ChainSystem
from .base import ValidationCase
from .chain_kind import ChainScene
from .rotating_pin import ROTATION_RATE

HEAD_COORDINATES = 2
"""The head's position (x_h, y_h): MuJoCo's two slide joints before the first hinge; in the reduced model
the last two state variables."""
STATE_MEANING = {
    "rest": "the chain sits still",
    "spin": "the chain turns in place near the dish's centre",
    "orbit": "the chain goes round the centre as a rigid body: body rotation = orbit rate",
    "crawl": "the chain orbits the centre while its body turns at another rate: it crawls in circles",
    "beat": "the chain beats in place (the flagellar beat, its head held by the dish), without turning",
    "irregular": "no steady pattern: the rates drift over the measured window",
}
"""What each state of analysis.dish.dish_state means (docs, the phase diagram's legend)."""
DISH_RINGS = 3
"""Rings of equal height drawn on the dish."""


ORBIT_RATE = Observable(
    "orbit_rate",
    "rad/tau",
    "mean angular velocity of the N particles' centre of mass about the dish's centre",
    floor=1e-6,
    worded=(Worded(NETWORK.name, "mean angular velocity of the unit about the trap's centre"),),
)
ORBIT_RADIUS = Observable(
    "orbit_radius",
    "l",
    "mean distance of the N particles' centre of mass from the dish's centre",
    floor=1e-3,
    worded=(Worded(NETWORK.name, "mean distance of the unit from the trap's centre"),),
)
CURVATURE = Observable(
    "curvature", "1/l", "mean curvature of the chain (theta_{i+1} - theta_i per l, signed)", floor=1e-4, min_n=2
)
DISH_STATE = Observable(
    "dish_state", "1", "state of the chain in the dish (analysis.dish.dish_state)", error="none", categories=dish.STATES
)
"""The dish's observables (analysis.dish); the orbit's two are the trapped unit's too."""


class Paraboloid(ChainScene):
    name = "paraboloid"
    summary = "free chain in a dish: sliding head, harmonic trap -k r (the supplement's satellite dish)"
    base_file = "paraboloid.xml"
    parameters = (
        Parameter(
            "trap",
            0.1,
            "stiffness k l^2 / C1 of the harmonic trap -k r (the dish's on every particle "
            "and the head; the trapped unit's k_t / k on its node)",
            low=0.0,
            low_open=True,
            title="harmonic trap stiffness; without it the active bodies swim away",
            worded=(Worded(NETWORK.name, "stiffness k_t / k of the harmonic trap -k_t x holding the unit"),),
        ),
    )
    clamped = False
    head_coordinates = HEAD_COORDINATES
    observables = (ROTATION_RATE, ORBIT_RATE, ORBIT_RADIUS, CURVATURE, DISH_STATE)
    no_linear_operator = "a free chain in a dish has no fixed base state (it drifts and turns as a whole)"
    compared = ("rotation_rate", "orbit_rate")

    def label(self, physics: Physics) -> str:
        return f"{self.name} N={physics.n} sigma={physics.sigma:g} trap={physics.trap:.4g}"

    # ------------------------------------------------------------------ MJCF
    def build(self, spec, physics: Physics, numerics: Numerics) -> None:
        from ..mjcf.chain import add_sliding_head  # start-up time: elastoactive.mjcf.chain imports mujoco

        add_sliding_head(spec, physics, numerics)  # qpos = (x_h, y_h, hinge angles)
        trap = spec.find_default("trap")
        for site, name in [("head", "trap_head")] + [(f"particle_{i}", f"trap_{i}") for i in range(physics.n)]:
            tendon = spec.add_tendon(name=name, default=trap, stiffness=[physics.trap, 0, 0], springlength=[0, 0])
            tendon.wrap_site("dish_centre")
            tendon.wrap_site(site)
        for k, radius in enumerate(self.ring_radii(physics), start=1):
            spec.geom(f"dish_{k}").size = [radius, 0.01, 0]

    def ring_radii(self, physics: Physics) -> tuple[float, ...]:
        """Radii of the rings drawn on the dish: equal steps in height up to the chain's length."""
        length = physics.n + 1.0
        return tuple(length * math.sqrt(k / DISH_RINGS) for k in range(DISH_RINGS, 0, -1))

    # ------------------------------------------------------------------ reduced model
    def reduced_system(self, physics: Physics) -> ChainSystem:
        return super().reduced_system(physics)._replace(head_free=True, trap=physics.trap)

    # ------------------------------------------------------------------ observables
    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        head = traj.head
        return {
            "rotation_rate": obs.rotation_rate(traj.t, traj.theta, transient),
            "orbit_rate": dish.orbit_rate(traj.t, traj.theta, head, transient, include_head=False),
            "orbit_radius": dish.orbit_radius(traj.t, traj.theta, head, transient, include_head=False),
            "curvature": dish.mean_curvature(traj.theta, traj.t, transient),
            "dish_state": dish.dish_state(traj.t, traj.theta, traj.head, transient),
        }

    # ------------------------------------------------------------------ validation
    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (ValidationCase(self.physics(n=7, sigma=0.3, trap=0.1), 600.0),)

    def extreme_cases(self, quick: bool = False) -> tuple[Physics, ...]:
        if quick:
            return ()
        return (self.physics(n=7, sigma=0.3, trap=30.0), self.physics(n=7, sigma=30.0, trap=0.1))

    # ------------------------------------------------------------------ drawing
    def extent_points(self, physics: Physics) -> np.ndarray:
        r = self.ring_radii(physics)[-1]
        return np.array([[-r, -r], [r, r]])

    def video_period(self, traj: Trajectory) -> float | None:
        """One orbit (or one turn of the body) per second of video."""
        rates = (
            obs.rotation_rate(traj.t, traj.theta),
            dish.orbit_rate(traj.t, traj.theta, traj.head, include_head=False),
        )
        omega = max((abs(r) for r in rates if not math.isnan(r)), default=0.0)  # the orbit rate: NaN at the centre
        return 2.0 * math.pi / omega if omega > 1e-3 else None


SCENE = Paraboloid()

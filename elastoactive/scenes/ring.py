"""A ring: the chain closes on itself, one particle held at a free pin.

Beyond the paper (its outlook's "more intricate geometrical connections"): N particles on N rigid links, a
torsional spring C1 at every joint including the one that closes the ring (between the last link and the first),
the follower force on every particle. The first link starts at a free pin at the origin and the last particle is
held there, so the ring can turn about that point. At rest it is the regular N-gon, every joint bent by 2 pi / N.
The follower forces sum to zero round a closed ring but not their torque: the ring turns about the pin.

pin = free: no pin. The first pendulum's pivot (the root) slides in the plane as the paraboloid's head does, carrying
one particle's drag and mass and no active force, and the last particle is held on it: the ring may translate and
turn. MuJoCo: the root's two slide joints before the first hinge, the closure a connect equality between the last
particle and the root's site. The reduced model: the paraboloid's free head (ChainSystem.head_free, the head's two
coordinates after the angles) with the ring's closure (closed, pinned with delta = 1: the last particle on the moving
pivot). Observables then add centre_drift (the speed of the ring's centre of drag: its particles and the root).

MuJoCo: the last particle is held at the pin by a connect equality (as the two-pinned chain's end, nearly hard),
and the closing spring is a fixed tendon hinge_1 + ... + hinge_{N-1} with rest length 2 pi. The reduced model: the
two-pinned chain's constraints with the pin at the pivot (delta = 1) and the closing spring (ChainSystem.closed).
Observables: rotation_rate (mean d theta_1 / dt: the ring's turning), with the beat of Theta = theta_N - theta_1
where its shape oscillates.

Linear stability (pin = pinned; analysis/ring_stability.py, docs/outlook.md): the steady state is a rigid rotation,
theta(t) = theta* + Omega t (every angle shifted alike: a relative equilibrium), theta* a polygon the follower forces
deform. The Jacobian of the reduced model's right-hand side at theta*, on the closure's tangent space less the
rotation's zero, decides its stability. `onset` follows the rigid rotation from the regular polygon (sigma -> 0) up
to SCAN_MAX: N <= 14 stays stable; from N = 15 on it loses stability in a Hopf bifurcation (the shape beats while it
turns; N = 24: sigma_c = 0.4377, omega_c = 0.1063) and does not regain it. The rigid rotations a long ring reaches at
large sigma (N = 24 at sigma = 8) are other branches (analysis.ring_stability.restabilisation). The free ring has no
linear operator written (its rotation also moves its root).
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import observables as obs
from ..core.errors import ParameterError
from ..core.observables import Observable
from ..core.parameters import Parameter
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory
from ..reduced.constraints import project_on_pins
from ..reduced.initial import pushed_chains
from ..reduced.system import ChainSystem
from .base import Onset, ValidationCase
from .chain_kind import ChainScene
from .rotating_pin import ROTATION_RATE
from .two_pinned import PIN_SOLIMP

CLOSED = 1.0
"""The reduced model's compression delta that puts the last particle on the pivot: (N (1 - delta), 0) = (0, 0)."""


PINNED = "pinned"
FREE = "free"
PIN = Parameter(
    "pin",
    PINNED,
    "the ring's root: on a free pin at the origin (pinned: it turns about it), or free in "
    "the plane (free: it may translate and turn; the root carries one particle's drag)",
    kind=str,
    choices=(PINNED, FREE),
    title="the ring's root",
    quiet_default=True,
)
SCAN_MAX = 100.0
"""sigma up to which onset follows the pinned ring's rigid rotation from the polygon (the rings study goes to 80)."""
HEAD_COORDINATES = 2
"""The free ring's root position (x_h, y_h): MuJoCo's two slide joints, the reduced model's last two state variables."""


def centre_drift(t: np.ndarray, theta: np.ndarray, head: np.ndarray, transient: float | None = None) -> float:
    """Mean speed (l / tau) of the free ring's centre after the transient (default: half the record): the distance
    it moved over the window, over the window's length. The centre is the mean of the N particles and the root's bead
    (the N + 1 points that carry drag): with isotropic drag the total force on the ring is zero (the follower forces
    sum to zero round the closed ring), so the drag's sum over these points, their mean velocity, vanishes."""
    t = np.asarray(t, dtype=float)
    start = t[0] + 0.5 * (t[-1] - t[0]) if transient is None else transient
    keep = t >= start
    if np.count_nonzero(keep) < 2:
        return math.nan
    th = np.asarray(theta, dtype=float)[keep]
    h = np.asarray(head, dtype=float)[keep]
    n = th.shape[1]
    cx = h[:, 0] + np.cumsum(np.cos(th), axis=1).sum(axis=1) / (n + 1)
    cy = h[:, 1] + np.cumsum(np.sin(th), axis=1).sum(axis=1) / (n + 1)
    tw = t[keep]
    return float(math.hypot(cx[-1] - cx[0], cy[-1] - cy[0]) / (tw[-1] - tw[0]))


def polygon(n: int) -> np.ndarray:
    """Absolute angles of the regular N-gon, first link along +x, turning counterclockwise."""
    return 2.0 * math.pi * np.arange(n) / n


CENTRE_DRIFT = Observable(
    "centre_drift",
    "l/tau",
    "mean speed of the free ring's centre (the mean of its particles) over the measured window",
    error="absolute",
    floor=0.0,
)
"""The free ring's drift (pin = free only)."""


class Ring(ChainScene):
    name = "ring"
    summary = "the chain closed on itself, one particle on a free pin: the ring turns about it"
    base_file = "ring.xml"
    parameters = (PIN,)
    min_n = 3
    clamped = False
    pinned = True
    observables = (ROTATION_RATE,)
    occasional_observables = (CENTRE_DRIFT,)
    compared = ("rotation_rate",)
    no_linear_operator = ""  # the pinned ring's: its rigid rotation's (the free ring refuses in onset)

    def check(self, physics: Physics) -> None:
        super().check(physics)
        if physics.contact:  # the reduced model's contact path has no closing spring (ChainSystem.typed refuses it)
            raise ParameterError(
                "contact: self-contact is not built for the ring (the reduced model that checks its "
                "numerics and cross-validates it has no closing spring with contact)"
            )

    @staticmethod
    def free(physics: Physics) -> bool:
        return physics.pin == FREE

    def inertial_model(self, physics: Physics) -> bool:
        return not self.free(physics)  # the free root's inertial model is not written (the engine refuses a mass)

    def head_count(self, physics: Physics) -> int:
        return HEAD_COORDINATES if self.free(physics) else 0

    def label(self, physics: Physics) -> str:
        return f"{self.name} N={physics.n} sigma={physics.sigma:g}" + (" free" if self.free(physics) else "")

    def caption(self, physics: Physics) -> list[str]:
        return ["free ring"] if self.free(physics) else []

    def build(self, spec, physics: Physics, numerics: Numerics) -> None:
        import mujoco  # start-up time: mujoco is needed only to build a model

        from ..mjcf.chain import add_sliding_head  # start-up time: elastoactive.mjcf.chain imports mujoco

        anchor = "pin"
        if self.free(physics):  # the root slides: qpos = (x_h, y_h, hinge angles), as the paraboloid's head
            add_sliding_head(spec, physics, numerics)
            spec.delete(spec.geom("pin_marker"))
            anchor = "head"
        spec.add_equality(
            name="pin",
            type=mujoco.mjtEq.mjEQ_CONNECT,
            objtype=mujoco.mjtObj.mjOBJ_SITE,
            name1=f"particle_{physics.n - 1}",
            name2=anchor,
            solref=[2.0 * numerics.dt, 1.0],
            solimp=list(PIN_SOLIMP),
        )
        closure = spec.add_tendon(name="closure", stiffness=[1.0, 0, 0], springlength=[2.0 * math.pi, 2.0 * math.pi])
        for i in range(1, physics.n):
            closure.wrap_joint(f"hinge_{i}", 1.0)
        head = [0.0] * self.head_count(physics)
        spec.add_key(name="ring", qpos=head + np.diff(polygon(physics.n), prepend=0.0).tolist())

    def reduced_system(self, physics: Physics) -> ChainSystem:
        system = super().reduced_system(physics)._replace(delta=CLOSED, closed=True)
        return system._replace(head_free=True) if self.free(physics) else system

    def initial_angles(self, physics: Physics, numerics: Numerics) -> np.ndarray:
        """The regular N-gon, pushed like the other scenes and projected back onto the pin."""
        kick = pushed_chains(physics.n, 1, numerics.perturbation, numerics.seed)
        return project_on_pins(polygon(physics.n) + kick, CLOSED)

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        values = {"rotation_rate": obs.rotation_rate(traj.t, traj.theta, transient)}
        if self.free(traj.physics) and traj.head is not None:
            values["centre_drift"] = centre_drift(traj.t, traj.theta, traj.head, transient)
        return values

    # ------------------------------------------------------------------ linear stability (analysis.ring_stability)
    def _shape_modes(self, physics: Physics) -> float:
        """The longitudinal drag of the pinned ring whose shape modes are asked for; refuses the free ring and the
        triangle."""
        if self.free(physics):
            raise ParameterError(
                "stability: the free ring (pin = free) has no linear operator here: its steady "
                "turning carries its root round the centre of drag, a relative equilibrium of the "
                "plane's rotations and translations that is not written (the pinned ring's is)"
            )
        if physics.n < 4:
            raise ParameterError(
                f"stability: a ring of N = {physics.n} links is rigid (N - 3 = 0 shape modes): it "
                "turns without deforming at every sigma"
            )
        return self.reduced_system(physics).gamma_l

    def onset(self, physics: Physics) -> Onset:
        """Where the rigid rotation followed from the regular polygon first loses stability (sigma up to SCAN_MAX),
        how, and the shape's angular frequency there; sigma_c = inf when it stays stable over the scan."""
        from ..analysis import ring_stability  # start-up time: scipy and the compiled kernels

        gamma_l = self._shape_modes(physics)
        sigma_c, omega_c, branch = ring_stability.onset(physics.n, SCAN_MAX, gamma_l)
        if not branch.crossings:
            return Onset(
                math.inf,
                math.nan,
                f"none: the rigid rotation, followed from the regular polygon, stays "
                f"linearly stable up to sigma = {SCAN_MAX:g} (the scan's end)",
            )
        first = branch.crossings[0]
        how = {
            "Hopf": "Hopf: the turning ring's shape beats",
            "fold": "fold: the rigid rotation ceases to exist",
            "real": "a real eigenvalue: the turning ring's shape buckles",
        }[first.kind]
        last = float(branch.sigma[-1])
        if len(branch.crossings) > 1:
            after = f"stable again from sigma = {branch.crossings[1].sigma:.6g} along the branch"
        else:
            after = f"unstable from there up to sigma = {last:.6g}, " + (
                "the scan's end" if last >= SCAN_MAX else "where the continuation stopped"
            )
        return Onset(sigma_c, omega_c, f"{how} ({after})")

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        """The least stable shape eigenvalue of the rigid rotation at sigma, on its branch followed from the regular
        polygon (the rotation's zero removed)."""
        from ..analysis import ring_stability  # start-up time: scipy and the compiled kernels

        return ring_stability.linearise(physics.n, sigma, gamma_l=self._shape_modes(physics)).leading

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (
            ValidationCase(self.physics(n=7, sigma=0.8), 300.0),
            ValidationCase(self.physics(n=7, sigma=0.8, pin=FREE), 300.0, convergence=False),
        )

    def extent_points(self, physics: Physics) -> np.ndarray:
        return np.empty((0, 2)) if self.free(physics) else np.zeros((1, 2))


SCENE = Ring()

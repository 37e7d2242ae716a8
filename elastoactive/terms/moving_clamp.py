"""A moving clamp: chain 1's clamp follows a prescribed motion (the paper's outlook: "alternative boundary
conditions --- pinned or moving clamping points").

clamp_motion (with clamp_amplitude A > 0 and clamp_frequency f, omega = 2 pi f):
  transverse     the clamp point moves across the straight chain, y_c(t) = A sin(omega t) (lab y, A in l)
  longitudinal   along it, x_c(t) = A sin(omega t) (lab x, A in l)
  angle          the clamp turns about its point, phi_c(t) = A sin(omega t) (A in rad): the clamp spring acts as
                 C1 (theta_1 - phi_c(t)); |A| < pi/2, or the clamp would turn the chain's root into the wall it
                 is mounted on
  rotating       the clamp turns steadily about its point, phi_c(t) = 2 pi f t (counterclockwise): it needs
                 clamp_frequency alone (clamp_amplitude has no meaning and is refused); the chain is dragged round

The physics (docs/clamp.md): in the overdamped chain the lab-frame drag acts on the particles' lab velocities
u(t) + J_k theta', so a clamp moving with velocity u adds -Gamma_k(theta) u to every particle's force (both drag
coefficients: drag_ratio), D(theta) theta' = f(theta) - sum_k J_k^T Gamma_k u; the angle enters through the clamp
spring alone. The reduced engine adds these through elastoactive.engines.node_forces (Term.clamp_motion).

MuJoCo moves the clamp physically, so its lab-frame drag sees the motion: chain 1's root body gets two slide joints
(clamp_x, clamp_y) before its hinge, held on the prescribed path by a servo: a damping -B v of the clamp point (two
velocity actuators on its site, integrated implicitly) and, from the compiled passive callback (controllers/follower.c,
clamp_servo), the force B u(t) + K (x_c(t) - q) with K = SERVO_RATE B / dt. The angle drive is exact there: the
callback adds C1 phi_c(t) to the clamp hinge's generalised force. Trajectory.head holds the clamp point's position
(x_c, y_c) when the point moves (MuJoCo: the slides' measured position; reduced: the prescribed one); drawings put
the clamp's box there. A rotating clamp: the callback adds C1 Omega t (the numeric's eighth entry Omega = 2 pi f).

Observables (analysis.locking): clamp_frequency_ratio (the beat's frequency over the drive's) and
clamp_phase_spread (the circular spread of the beat's phase against the drive's over the steady window: 0 locked,
large unlocked); a rotating clamp adds clamp_lag (rad: the time mean of phi_c - arg(r_N), how far the tip particle
trails the clamp's direction as seen from the clamp point, followed along the chain so that it may exceed pi).

mujoco (in `start` and `build`) and analysis.locking (scipy, in `measure`) are imported inside the hooks that use them,
the engine's and the analysis's boundary: the command line imports the terms for their parameters.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.cases import ValidationCase
from ..core.errors import ParameterError
from ..core.observables import Observable
from ..core.parameters import Parameter
from .base import ClampMotion, Term

ROTATING = "rotating"
MOTIONS = ("transverse", "longitudinal", "angle", ROTATING)
DIRECTIONS = {"transverse": (0.0, 1.0), "longitudinal": (1.0, 0.0)}
ANGLE_LIMIT = math.pi / 2
"""Largest clamp-angle amplitude (excluded): at pi/2 the clamp turns the chain's first pendulum along the wall the
clamp is mounted on, and beyond it into the wall."""
SERVO_DAMPING = 1.0e4
"""MuJoCo: the clamp point's damping B (units of gamma; two velocity actuators on its site, which the implicit
integrators treat implicitly, so it costs no stability): the clamp's velocity lags the prescribed one by
(force on the clamp) / B before the position gain corrects it."""
SERVO_RATE = 0.1
"""MuJoCo: the servo's position gain K = SERVO_RATE B / dt: the clamp's position error relaxes within dt /
SERVO_RATE (explicit in K, stable for K dt / B < 1); a steady force R on the clamp leaves an error R / K."""
CLAMP_JOINTS = ("clamp_x", "clamp_y")
CLAMP_SITE = "clamp"
"""The site at the clamp point (on chain 1's first body, at its pivot) whose two velocity actuators damp the
clamp's slides."""
HINGE_TEXT = "elastoactive_clamp_hinge"
"""The custom text naming chain 1's clamp hinge (the callback's angle drive acts on it)."""

CLAMP_AMPLITUDE = Parameter(
    "clamp_amplitude",
    0.0,
    "amplitude A of the clamp's motion: l for a transverse or "
    "longitudinal clamp point, rad for the clamp angle (0: a fixed clamp)",
    low=0.0,
    title="clamp amplitude",
    units="l or rad",
    quiet_default=True,
)
"""(clamp_motion rotating needs no amplitude: the term's switch is then the motion itself, CLAMP_FREQUENCY.or_needs)"""
CLAMP_FREQUENCY = Parameter(
    "clamp_frequency",
    0.01,
    "frequency f tau of the clamp's motion A sin(2 pi f t), or of a "
    "rotating clamp's turns (cycles per tau; with --clamp-amplitude or --clamp-motion rotating)",
    low=0.0,
    low_open=True,
    title="clamp frequency f tau",
    units="1/tau",
    needs="clamp_amplitude",
    or_needs="clamp_motion",
    or_needs_value=ROTATING,
    quiet_default=True,
)
CLAMP_MOTION = Parameter(
    "clamp_motion",
    "transverse",
    "what moves: the clamp point across the chain (transverse, lab "
    "y) or along it (longitudinal, lab x), or the clamp's angle (angle) (with --clamp-amplitude); "
    "or the clamp turns steadily at --clamp-frequency (rotating, no amplitude)",
    kind=str,
    choices=MOTIONS,
    title="clamp motion",
    needs="clamp_amplitude",
    or_needs="clamp_motion",
    or_needs_value=ROTATING,
    quiet_default=True,
)


def clamp_path(amplitude: float, frequency: float, motion: str) -> ClampMotion:
    """The prescribed motion A sin(omega t) of the clamp point along `motion`'s direction, or of its angle."""
    omega = 2.0 * math.pi * frequency
    if motion == ROTATING:
        zero2 = np.zeros(2)
        return ClampMotion(
            displacement=lambda t: zero2,
            velocity=lambda t: zero2,
            angle=lambda t: omega * np.asarray(t, dtype=float),
            translates=False,
        )
    if motion == "angle":
        zero2 = np.zeros(2)
        return ClampMotion(
            displacement=lambda t: zero2,
            velocity=lambda t: zero2,
            angle=lambda t: amplitude * np.sin(omega * t),
            translates=False,
        )
    along = np.array(DIRECTIONS[motion]) * amplitude

    def displacement(t):
        return np.multiply.outer(np.sin(omega * np.asarray(t, dtype=float)), along)

    def velocity(t):
        return np.multiply.outer(omega * np.cos(omega * np.asarray(t, dtype=float)), along)

    return ClampMotion(displacement=displacement, velocity=velocity, angle=lambda t: 0.0, translates=True)


def tip_lag(t, theta, frequency: float, transient: float) -> float:
    """How far (rad) the tip particle trails a clamp rotating at `frequency` (phi_c = 2 pi f t) after the transient:
    the time mean of phi_c - arg(r_N), r_N = sum_i e(theta_i) the tip's position from the clamp point (positive:
    behind the clamp). arg(r_N) is followed particle by particle from arg(r_1) = theta_1 (each step below pi), so a
    chain curled round the clamp by more than half a turn lags by more than pi."""
    t = np.asarray(t, dtype=float)
    keep = t >= transient
    th = np.asarray(theta, dtype=float)[keep]
    points = np.cumsum(np.exp(1j * th), axis=1)
    steps = np.angle(points[:, 1:] / points[:, :-1]).sum(axis=1)
    return float(np.mean(2.0 * math.pi * frequency * t[keep] - th[:, 0] - steps))


def check_scene(physics) -> None:
    """Refuse, in one line, a scene whose clamp this term cannot move."""
    scene = physics.scene_def
    if not scene.clamped:
        raise ParameterError(
            f"moving clamp: scene {physics.scene} has no clamp (its first pendulum turns freely "
            "on a pin); a moving clamp needs a chain that hangs from one (one-pinned, or the angle "
            "of coupled-pair's)"
        )
    if scene.pinned:
        raise ParameterError(
            f"moving clamp: scene {physics.scene} pins its chain's far end to the lab, and the "
            "reduced engine's pinned model has no moving clamp; use one-pinned"
        )
    if scene.head_coordinates:
        raise ParameterError(
            f"moving clamp: scene {physics.scene} holds its chains' roots on a coordinate of its own "
            "(a sliding head, or the star's hub), which a prescribed clamp motion would override; use "
            "one-pinned, or the angle of coupled-pair's clamp"
        )
    if scene.n_chains > 1 and physics.clamp_motion not in ("angle", ROTATING):
        raise ParameterError(
            f"clamp_motion {physics.clamp_motion} on scene {physics.scene}: moving chain 1's clamp "
            "point would stretch the coupling spring, which the reduced model holds between fixed "
            "clamps; move its angle (clamp_motion angle), or use one-pinned"
        )


CLAMP_FREQUENCY_RATIO = Observable(
    "clamp_frequency_ratio", "1", "the beat's frequency over the clamp's drive frequency (NaN without a beat)"
)
CLAMP_PHASE_SPREAD = Observable(
    "clamp_phase_spread",
    "rad",
    "circular spread of the beat's phase against the drive's (0: locked; NaN without a beat)",
    error="none",
)
CLAMP_LAG = Observable(
    "clamp_lag", "rad", "time mean of how far the tip particle trails a rotating clamp's direction (rotating only)"
)
"""The chain's locking to the clamp's motion (analysis.locking) and a rotating clamp's lag (tip_lag)."""


class MovingClamp(Term):
    name = "moving-clamp"
    summary = (
        "chain 1's clamp moves: its point across or along the chain, or its angle, as A sin(2 pi f t); or it "
        "turns steadily at f"
    )
    parameters = (CLAMP_AMPLITUDE, CLAMP_FREQUENCY, CLAMP_MOTION)
    observables = (CLAMP_FREQUENCY_RATIO, CLAMP_PHASE_SPREAD, CLAMP_LAG)
    measured_at_rest = False  # its observables describe the term acting

    def prepare(self, values: dict) -> None:
        if values.get("clamp_motion") == ROTATING and values.get("clamp_amplitude", 0.0) != 0:
            raise ParameterError(
                f"clamp_amplitude has no effect with clamp_motion {ROTATING} (the clamp turns steadily "
                "at clamp_frequency, 2 pi f t); leave clamp_amplitude out"
            )
        if values.get("clamp_motion") == "angle" and values.get("clamp_amplitude", 0.0) >= ANGLE_LIMIT:
            raise ParameterError(
                f"clamp_amplitude (clamp amplitude) must be < pi/2 = {ANGLE_LIMIT:.6g} rad for "
                f"clamp_motion angle, got {values['clamp_amplitude']}: at pi/2 the clamp turns the "
                "chain's first pendulum along the wall it is mounted on, beyond it into the wall"
            )

    def active(self, physics) -> bool:
        return physics.clamp_amplitude > 0 or physics.clamp_motion == ROTATING

    def check(self, physics) -> None:
        check_scene(physics)

    def clamp_motion(self, physics) -> ClampMotion:
        check_scene(physics)
        return clamp_path(physics.clamp_amplitude, physics.clamp_frequency, physics.clamp_motion)

    def rate(self, physics) -> float:
        """The clamp's angular frequency 2 pi f: the servo's path and the drag it drags are stepped at dt."""
        return 2.0 * math.pi * physics.clamp_frequency

    def slower(self, physics, rate: float) -> str:
        return f"clamp_frequency <= {rate / (2.0 * math.pi):.2g}"

    def start(self, physics, model, data) -> None:
        """A translating clamp starts at its path's velocity u(0) = A omega (the chain with it, at rest in the clamp's
        frame, as the reduced model starts): the servo's B (u - q') is then small from the first step, where a clamp
        at rest would take the whole jump B u(0) on the bodies' tiny mass (MuJoCo diverged beyond A f ~ 0.1 l/tau)."""
        import mujoco  # start-up time: mujoco is needed only to run a model

        motion = self.clamp_motion(physics)
        if not motion.translates:
            return
        velocity = np.asarray(motion.velocity(0.0), dtype=float)
        for axis, name in enumerate(CLAMP_JOINTS):
            data.qvel[model.jnt_dofadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)]] = velocity[axis]

    def build(self, spec, physics, numerics):
        """A translating clamp: slides clamp_x, clamp_y (damping B) before chain 1's first hinge, and the numeric
        elastoactive_clamp = (A, omega, a_x, a_y, A_phi, K, B) the callback's servo reads; an angle: the same numeric
        and the text naming the clamp hinge."""
        import mujoco  # start-up time: mujoco is needed only to build a model

        check_scene(physics)
        prefix = physics.scene_def.chain_prefixes()[0]
        motion, amplitude = physics.clamp_motion, physics.clamp_amplitude
        d_x, d_y = DIRECTIONS.get(motion, (0.0, 0.0))
        angle = amplitude if motion == "angle" else 0.0
        rate = 2.0 * math.pi * physics.clamp_frequency if motion == ROTATING else 0.0
        if motion not in ("angle", ROTATING):
            first = spec.body(f"{prefix}segment_0")
            hinge = spec.joint(f"{prefix}hinge_0")
            stiffness = list(hinge.stiffness)
            spec.delete(hinge)  # the slides go first: qpos = (x_c, y_c, hinge angles), as the paraboloid's head
            for axis, name in enumerate(CLAMP_JOINTS):
                direction = [0.0, 0.0, 0.0]
                direction[axis] = 1.0
                first.add_joint(name=name, type=mujoco.mjtJoint.mjJNT_SLIDE, axis=direction, stiffness=[0, 0, 0])
            first.add_joint(name=f"{prefix}hinge_0", default=spec.find_default("segment"), stiffness=stiffness)
            first.add_site(name=CLAMP_SITE, default=spec.find_default("segment"), pos=[0, 0, 0], userdata=[0.0])
            for axis in range(2):  # isotropic damping -B v of the clamp point (its site turns with theta_1)
                gear = [0.0] * 6
                gear[axis] = 1.0
                spec.add_actuator(
                    name=f"clamp_servo_{'xy'[axis]}",
                    default=spec.find_default("drag"),
                    target=CLAMP_SITE,
                    trntype=mujoco.mjtTrn.mjTRN_SITE,
                    gear=gear,
                    gainprm=[SERVO_DAMPING] + [0] * 9,
                    biasprm=[0, 0, -SERVO_DAMPING] + [0] * 7,
                )
        spec.add_text(name=HINGE_TEXT, data=f"{prefix}hinge_0")
        marker = spec.add_numeric(name="elastoactive_clamp")
        marker.data = [
            amplitude,
            2.0 * math.pi * physics.clamp_frequency,
            d_x * amplitude,
            d_y * amplitude,
            angle,
            SERVO_RATE * SERVO_DAMPING / numerics.dt,
            SERVO_DAMPING,
            rate,
        ]

    def validation_cases(self, physics):
        """N = 3 at 1.1 sigma_c (f tau ~ 0.072) with the clamp moving across the chain near the beat's frequency,
        its angle turning, and the clamp rotating steadily at f tau = 0.05."""
        base = dict(n=3, sigma=1.28, clamp_amplitude=0.1, clamp_frequency=0.07)
        return (
            ValidationCase(physics(**base), 300.0, convergence=False),
            ValidationCase(
                physics(**{**base, "clamp_amplitude": 0.2, "clamp_motion": "angle"}), 300.0, convergence=False
            ),
            ValidationCase(
                physics(n=3, sigma=1.28, clamp_motion=ROTATING, clamp_frequency=0.05), 300.0, convergence=False
            ),
        )

    def reported(self, physics) -> tuple[str, ...]:
        """clamp_lag only for the rotating clamp (a lag behind a turning clamp; the other motions have no such
        angle)."""
        names = self.observable_names()
        return names if physics.clamp_motion == ROTATING else tuple(n for n in names if n != CLAMP_LAG.name)

    def measure(self, traj, transient):
        """clamp_frequency_ratio and clamp_phase_spread of Theta = theta_N - theta_1 against the drive, over the steady
        window; null when the beat has no frequency there."""
        from ..analysis import locking  # start-up time: scipy (the CLI imports the terms)

        physics = traj.physics
        lock = locking.drive_locking(traj.t, traj.theta[:, : physics.n], physics.clamp_frequency, transient)
        values = {"clamp_frequency_ratio": lock.frequency_ratio, "clamp_phase_spread": lock.phase_spread}
        if physics.clamp_motion == ROTATING:
            values["clamp_lag"] = tip_lag(traj.t, traj.theta[:, : physics.n], physics.clamp_frequency, transient)
        return values


TERM = MovingClamp()

"""Beyond the paper: a star of k one-pinned arms on one hub at the origin (docs/star.md).

Arm j (j = 1 .. k) is the paper's one-pinned chain of N particles, its clamp pointing at alpha_j = 2 pi (j - 1) / k
from the hub. The hub is either clamped (the arms then share nothing: k independent one-pinned chains, turned by
alpha_j) or turning about the origin: its angle phi obeys

    hub_drag phi' = -hub_stiffness phi + sum_j C1 (theta_{j,1} - alpha_j - phi),

the arms' clamp springs C1 (theta_{j,1} - alpha_j - phi) acting between the hub and each first link. The hub has no
particle: the arms' drag does not turn it, only its own rotational drag hub_drag (units gamma l^2), which must be
> 0 so that phi is a state with a finite rate. As hub_drag -> 0 the hub follows the arms at once,
phi = sum_j (theta_{j,1} - alpha_j) / (hub_stiffness + k): eliminating it leaves every arm clamped by a spring
hub_stiffness / (hub_stiffness + k) and every pair of arms joined by a spring 1 / (hub_stiffness + k) between their
first links (all-to-all; the coupled pair's kappa at k = 2), and the hub's rate (hub_stiffness + k) / hub_drag
diverges (a stiff system: the explicit method's steps and MuJoCo's dt shrink with hub_drag).

Parameters: arms (k, 2 .. 6), hub ("turning" or "clamped": a clamped hub is its own choice, not a stiffness value),
hub_stiffness (C1) and hub_drag (gamma l^2), both acting only with a turning hub.

MuJoCo: the hub a body on a hinge (stiffness hub_stiffness, a velocity actuator for hub_drag), each arm's first
hinge joined to it by a fixed tendon theta_{j,1} - phi of stiffness C1 and rest length alpha_j; with a clamped hub the
arm's own first hinge carries the clamp spring (spring reference alpha_j) and the hub's hinge, coupled to nothing,
stays at 0. qpos = (phi, the arms' hinge angles); the arms' first hinges read absolute angles (their bodies turned by
alpha_j, the hinge's ref at alpha_j). Trajectory.head holds phi (Scene.head_coordinates = 1; zeros with a clamped
hub). Reduced model: ChainSystem.star (and hub_free with a turning hub: phi the last state variable).

Observables: per-arm amplitude and frequency (as for the pair), sync_order R_1 and splay_order R_k (Kuramoto order
parameters of the arms' Hilbert phases), phase_locking, phase_lag (each arm's mean phase behind arm 1),
sync_state (analysis.star: in-phase, antiphase, splay, locked, unlocked, rest; uncoupled on a clamped hub, whose
phase_locking is NaN: its arms share nothing, so their steady phase differences are their start's), hub_amplitude
and hub_rate (a star spinning as a whole: with a free hub, hub_stiffness = 0, three or more arms turn rigidly with it).
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import observables as obs
from ..analysis import star as sync
from ..core.constants import BEAD_INERTIA_FACTOR
from ..core.errors import ParameterError
from ..core.observables import Observable
from ..core.parameters import Parameter
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory
from ..reduced.system import ChainSystem
from .base import Onset, ValidationCase
from .chain_kind import ChainScene

MAX_ARMS = 6
"""The most arms a star has (mjcf/star.xml holds this many template arms)."""
HUB_TURNING = "turning"
HUB_CLAMPED = "clamped"
BEATING = 1e-2
"""rad: an arm whose Theta swings less than this (half peak-to-peak) does not beat (no phase to compare)."""
HUB_RADIUS = 0.3
"""l: the hub's disc in mjcf/star.xml (the camera keeps it in view)."""


def clamp_angles(k: int) -> np.ndarray:
    """alpha_j = 2 pi (j - 1) / k: where each arm's clamp points from the hub (j = 1 .. k)."""
    return 2.0 * math.pi * np.arange(k) / k


def effective_coupling(hub_stiffness: float, k: int) -> tuple[float, float]:
    """(clamp stiffness, pairwise coupling) of the arms when the hub follows them at once (hub_drag -> 0): eliminating
    phi from sum_j (theta_j - phi)^2 / 2 + hub_stiffness phi^2 / 2 leaves hub_stiffness / (hub_stiffness + k) on each
    arm's first link and 1 / (hub_stiffness + k) between every pair of them (units C1)."""
    return hub_stiffness / (hub_stiffness + k), 1.0 / (hub_stiffness + k)


SYNC_ORDER = Observable(
    "sync_order",
    "1",
    "the star's Kuramoto order parameter R_1 of the arms' beat phases (1: in phase; NaN unless every arm beats)",
    error="absolute",
)
SPLAY_ORDER = Observable(
    "splay_order", "1", "R_k of the star's arms' phases (1 with R_1 = 0: a k-fold splay state)", error="absolute"
)
PHASE_LOCKING = Observable(
    "phase_locking",
    "1",
    "smallest phase-locking value of the star's arms against arm 1 (1: steady "
    "phase differences; NaN for uncoupled arms on a clamped hub)",
    error="absolute",
)
PHASE_LAG = Observable(
    "phase_lag", "rad", "mean phase of each of the star's arms behind arm 1, in (-pi, pi]", per_chain=True, error="none"
)
SYNC_STATE = Observable(
    "sync_state", "1", "state of the star's arms (analysis.star.sync_state)", error="none", categories=sync.SYNC_STATES
)
HUB_AMPLITUDE = Observable(
    "hub_amplitude", "rad", "half peak-to-peak of the star's hub angle phi (0 for a clamped hub)"
)
HUB_RATE = Observable(
    "hub_rate", "rad/tau", "mean d phi / dt of the star's hub (a star spinning as a whole)", floor=1e-6
)
"""The star's observables: its arms' synchronisation (analysis.star) and its hub's motion."""


class Star(ChainScene):
    name = "star"
    summary = "beyond the paper: k one-pinned arms on one hub (clamped, or turning on a spring): arm synchrony"
    base_file = "star.xml"
    parameters = (
        Parameter(
            "arms",
            3,
            f"number of arms k on the hub (2 .. {MAX_ARMS}), clamped at 2 pi j / k",
            kind=int,
            low=2,
            high=MAX_ARMS,
            title="number of arms k",
            symbol="k",
        ),
        Parameter(
            "hub",
            HUB_TURNING,
            "the hub: turning about the origin on a spring (hub_stiffness, hub_drag), or "
            "clamped (the arms are then k independent one-pinned chains)",
            kind=str,
            choices=(HUB_TURNING, HUB_CLAMPED),
            title="the hub",
        ),
        Parameter(
            "hub_stiffness",
            1.0,
            "the turning hub's torsional spring to the lab, in C1",
            low=0.0,
            title="hub stiffness (C1)",
            symbol="K_h",
            needs="hub",
            needs_value=HUB_TURNING,
        ),
        Parameter(
            "hub_drag",
            1.0,
            "the turning hub's rotational drag, in gamma l^2 (> 0: the hub's angle has a finite rate)",
            low=0.0,
            low_open=True,
            title="hub drag (gamma l^2)",
            symbol="γ_h",
            needs="hub",
            needs_value=HUB_TURNING,
        ),
    )
    n_chains = MAX_ARMS
    observables = (SYNC_ORDER, SPLAY_ORDER, PHASE_LOCKING, PHASE_LAG, SYNC_STATE, HUB_AMPLITUDE, HUB_RATE)
    compared = ("amplitude", "frequency", "hub_amplitude")
    head_coordinates = 1
    no_linear_operator = ""

    # ------------------------------------------------------------------ parameters
    def check(self, physics: Physics) -> None:
        super().check(physics)
        if physics.contact:
            raise ParameterError(
                "contact: the star's arms meet at the hub, and self-contact between arms is not "
                "modelled; run the star without --contact"
            )

    def chain_count(self, physics: Physics) -> int:
        return physics.arms

    def base_physics(self) -> Physics:
        """mjcf/star.xml holds the most arms."""
        return self.physics(n=7, sigma=0.8, arms=MAX_ARMS)

    def chain_offset(self, physics: Physics, k: int) -> float:
        return 0.0  # every arm starts at the hub

    def label(self, physics: Physics) -> str:
        hub = (
            f"hub K_h={physics.hub_stiffness:.4g} drag={physics.hub_drag:.4g}"
            if self.turning(physics)
            else "hub clamped"
        )
        return f"{self.name} k={physics.arms} N={physics.n} sigma={physics.sigma:g} {hub}"

    @staticmethod
    def turning(physics: Physics) -> bool:
        return physics.hub == HUB_TURNING

    # ------------------------------------------------------------------ MJCF
    def build(self, spec, physics: Physics, numerics: Numerics) -> None:
        import mujoco  # start-up time: mujoco is needed only to build a model

        turning = self.turning(physics)
        hub = spec.body("hub")
        hub.mass = numerics.mass_ratio  # a bead's mass and rotational inertia: only its inertia acts
        hub.inertia = [numerics.mass_ratio * BEAD_INERTIA_FACTOR] * 3
        spec.joint("hub_hinge").stiffness = [physics.hub_stiffness if turning else 0.0, 0.0, 0.0]
        gamma = physics.hub_drag if turning else 1.0  # a clamped hub's idle hinge: no force ever turns it
        spec.add_actuator(
            name="hub_drag",
            default=spec.find_default("drag"),
            target="hub_hinge",
            trntype=mujoco.mjtTrn.mjTRN_JOINT,
            gainprm=[gamma] + [0] * 9,
            biasprm=[0, 0, -gamma] + [0] * 7,
        )
        for j, (prefix, alpha) in enumerate(zip(self.chain_prefixes(), clamp_angles(physics.arms))):
            spec.body(f"{prefix}segment_0").quat = [math.cos(alpha / 2), 0.0, 0.0, math.sin(alpha / 2)]
            hinge = spec.joint(f"{prefix}hinge_0")
            hinge.ref = alpha  # qpos reads the absolute angle
            if turning:  # the clamp spring between the hub and the arm's first link
                hinge.stiffness = [0.0, 0.0, 0.0]
                tendon = spec.add_tendon(name=f"clamp{j + 1}", stiffness=[1.0, 0, 0], springlength=[alpha, alpha])
                tendon.wrap_joint(f"{prefix}hinge_0", 1.0)
                tendon.wrap_joint("hub_hinge", -1.0)
            else:
                hinge.springref = alpha

    # ------------------------------------------------------------------ reduced model
    def reduced_system(self, physics: Physics) -> ChainSystem:
        system = super().reduced_system(physics)._replace(star=True)
        if self.turning(physics):
            system = system._replace(hub_free=True, hub_stiffness=physics.hub_stiffness, hub_drag=physics.hub_drag)
        return system

    # ------------------------------------------------------------------ initial state
    def initial_angles(self, physics: Physics, numerics: Numerics) -> np.ndarray:
        """Each arm's static shape under its own seeded pushes (pushed_chains draws arm by arm, so no two arms start
        alike and no synchrony is imposed), turned to its clamp direction; the hub at phi = 0."""
        theta = super().initial_angles(physics, numerics)
        return theta + np.repeat(clamp_angles(physics.arms), physics.n)

    # ------------------------------------------------------------------ observables
    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float | str | tuple[float, ...]]:
        physics = traj.physics
        t = traj.t
        head = traj.head if traj.head is not None else np.zeros((t.size, 1))
        hub = obs.amplitude(t, head[:, 0], transient)
        rate = obs.rotation_rate(t, head[:, :1], transient)
        curvatures = np.stack([obs.curvature(traj.chain(j)) for j in range(physics.arms)])
        nan = math.nan
        if min(obs.amplitude(t, x, transient) for x in curvatures) <= BEATING:
            return {
                "sync_order": nan,
                "splay_order": nan,
                "phase_locking": nan,
                "phase_lag": (nan,) * physics.arms,
                "sync_state": "rest",
                "hub_amplitude": hub,
                "hub_rate": rate,
            }
        _, phases = sync.arm_phases(t, curvatures, transient)
        lags = (0.0, *(float(-d) for d in sync.phase_differences(phases)))
        coupled = self.turning(physics)  # a clamped hub couples nothing: no locking to measure, no state to name
        return {
            "sync_order": sync.order_parameter(phases, 1),
            "splay_order": sync.order_parameter(phases, physics.arms),
            "phase_locking": sync.phase_locking(phases) if coupled else nan,
            "phase_lag": lags,
            "sync_state": sync.sync_state(phases, coupled),
            "hub_amplitude": hub,
            "hub_rate": rate,
        }

    # ------------------------------------------------------------------ linear stability
    def _hub(self, physics: Physics) -> tuple[float | None, float | None]:
        return (physics.hub_stiffness, physics.hub_drag) if self.turning(physics) else (None, None)

    def onset(self, physics: Physics) -> Onset:
        """The first of the star's modes to lose stability about the straight state (analysis.star_stability): the
        in-phase mode (the hub turns), or the hub-free ones (antiphase, splay) at the one-pinned chain's onset."""
        from ..analysis import star_stability  # start-up time: scipy

        sigma_c, omega_c, mode = star_stability.star_onset(physics.n, physics.arms, *self._hub(physics))
        kind = "flutter (Hopf)" if omega_c > 1e-6 else "divergence (the star starts turning)"
        return Onset(sigma_c, omega_c, f"{kind}, {mode} mode")

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        from ..analysis import star_stability  # start-up time: scipy

        return star_stability.leading_eigenvalue(physics.n, physics.arms, sigma, *self._hub(physics))

    # ------------------------------------------------------------------ validation
    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (
            ValidationCase(self.physics(n=7, sigma=0.8, arms=3, hub_stiffness=1.0, hub_drag=1.0), 600.0),
            ValidationCase(self.physics(n=7, sigma=0.8, arms=2, hub=HUB_CLAMPED), 300.0, convergence=False),
        )

    # ------------------------------------------------------------------ drawing
    def caption(self, physics: Physics) -> list[str]:
        parts = [f"k = {physics.arms}"]
        if self.turning(physics):
            parts.append(f"K_h = {physics.hub_stiffness:.3g} γ_h = {physics.hub_drag:.3g}")
        else:
            parts.append("hub clamped")
        return parts

    def extent_points(self, physics: Physics) -> np.ndarray:
        return np.array([[-HUB_RADIUS, -HUB_RADIUS], [HUB_RADIUS, HUB_RADIUS]])


SCENE = Star()

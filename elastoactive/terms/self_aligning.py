"""Self-aligning active units: the active force's direction turns toward its particle's velocity.

Each loaded particle i carries a unit whose force sigma n_i (C1 / l, the follower force's magnitude) points along
its own polarity n_i = (cos psi_i, sin psi_i), free to turn (a Hexbug in a rotating holder: Baconnier et al.,
Nature Physics 18, 1234 (2022)), with

    dpsi_i/dt = (1 / l_a) (dx_i/dt) . n_i_perp,      n_perp = (-sin psi, cos psi),

so psi_i turns toward the particle's velocity at a rate set by the alignment length l_a (`alignment_length`, in
units of l). The follower force is the opposite limit, a unit fixed to its link. At t = 0 every polarity points
along the follower direction of the initial shape, so the two laws start with the same force.

Its parameters: `active` (the law: follower, the default, or self-aligning) and `alignment_length` (l_a; acts
only with active = self-aligning). The polarity angles (absolute, lab frame) are state in both engines.

mujoco is imported inside the hooks that build or step a MuJoCo model, the engine's boundary: the command line
imports the terms for their parameters, and a reduced-engine run never loads MuJoCo.
"""

from __future__ import annotations

import math

import numpy as np

from ..core import registry
from ..core.cases import ValidationCase
from ..core.errors import ParameterError
from ..core.parameters import Parameter
from ..core.units import NETWORK, Worded
from .base import Term

FOLLOWER = "follower"
SELF_ALIGNING = "self-aligning"
LAWS = (FOLLOWER, SELF_ALIGNING)

ACTIVE = Parameter(
    "active",
    FOLLOWER,
    "direction law of the active force: follower (along each link, toward the "
    "clamp) or self-aligning (a polarity that turns toward its particle's velocity over the alignment "
    "length)",
    kind=str,
    choices=LAWS,
    title="active force's direction law",
    quiet_default=True,
    worded=(Worded(NETWORK.name, "direction law of the units' active force"),),
)
ALIGNMENT_LENGTH = Parameter(
    "alignment_length",
    1.0,
    "alignment length l_a / l of self-aligning units (with --active self-aligning)",
    low=0.0,
    low_open=True,
    title="alignment length l_a / l",
    symbol="l_a",
    units="l",
    needs="active",
    needs_value=SELF_ALIGNING,
    worded=(Worded(NETWORK.name, "alignment length l_a / a of the self-aligning units"),),
)


MAX_REDUCED_TURNS = 2e5
"""Largest duration x turning_rate the reduced engine integrates with self-aligning units. A short alignment length
makes the polarities stiff (they turn at up to sigma / l_a): the explicit DOP853 then needs steps in proportion to
duration x sigma / l_a; at this bound a chain of N = 7 takes about 35 s and a network less (measured: 14 s for 8e4
on the chain, 1.5 s on the trapped unit). Beyond it the run is refused in one line naming alignment_length, rather
than left to hang."""


def turning_rate(physics) -> float:
    """The fastest rate at which self-aligning units turn, sigma / l_a (1 / tau on a chain, k / gamma on a network): a
    unit pushed by its own force moves at up to sigma (a length per unit time) and its polarity turns at that speed
    over l_a. 0 without self-aligning units."""
    return float(physics.sigma) / float(physics.alignment_length) if physics.active == SELF_ALIGNING else 0.0


def check_reduced_span(physics, duration: float) -> None:
    """Refuse, in one line naming alignment_length, a reduced run whose units are too stiff for its length
    (duration x turning_rate > MAX_REDUCED_TURNS)."""
    rate = turning_rate(physics)
    if duration * rate > MAX_REDUCED_TURNS:
        raise ParameterError(
            f"alignment_length = {physics.alignment_length:g} is too short for the reduced engine over a duration of "
            f"{duration:g}: the self-aligning units turn at up to sigma / l_a = {rate:.3g} per unit time, so its "
            f"explicit solver would need steps in proportion to duration x sigma / l_a = {duration * rate:.2g} (at "
            f"most {MAX_REDUCED_TURNS:.0e}); use "
            f"alignment_length >= {float(physics.sigma) * duration / MAX_REDUCED_TURNS:.3g} or a duration <= "
            f"{MAX_REDUCED_TURNS / rate:.3g}"
        )


POLARITY_SUFFIX = "_polarity"
"""A unit's actuator in MuJoCo is named after its site: '<site name>_polarity' (controllers/follower.c)."""


def add_unit(spec, site: str, alignment_length: float, slide: str | None = None) -> None:
    """Mark the site `site` (which carries a force magnitude in its first user value) as a self-aligning unit: an
    actuator with user dynamics, l_a in dynprm[0], no gain or bias; its activation is the polarity psi
    (controllers/follower.c). Generic over sites: a chain's particle or a lattice node. The actuator's transmission is
    the site, or, for a site on a body that slides, `slide`, one of that body's slide joints: the same unit (the
    callback finds the site from the joint's body), but MuJoCo computes a joint transmission in O(1) where a site's
    costs a Jacobian every step (the unit has no gain: its transmission moves nothing)."""
    import mujoco  # start-up time: the CLI imports the terms

    target, transmission = (site, mujoco.mjtTrn.mjTRN_SITE) if slide is None else (slide, mujoco.mjtTrn.mjTRN_JOINT)
    spec.add_actuator(
        name=site + POLARITY_SUFFIX,
        target=target,
        trntype=transmission,
        dyntype=mujoco.mjtDyn.mjDYN_USER,
        gaintype=mujoco.mjtGain.mjGAIN_FIXED,
        biastype=mujoco.mjtBias.mjBIAS_NONE,
        gainprm=[0.0] * 10,
        dynprm=[float(alignment_length)] + [0.0] * 9,
        actdim=1,
    )


def unit_actuators(model) -> np.ndarray:
    """Indices of the actuators that mark self-aligning units (follower.c's rule: on a site, or on a slide joint),
    in model order."""
    import mujoco  # start-up time: the CLI imports the terms

    trn = model.actuator_trntype
    target = model.actuator_trnid[:, 0]
    on_slide = (trn == mujoco.mjtTrn.mjTRN_JOINT) & (target >= 0)
    on_slide[on_slide] = model.jnt_type[target[on_slide]] == mujoco.mjtJoint.mjJNT_SLIDE
    return np.flatnonzero(
        (model.actuator_dyntype == mujoco.mjtDyn.mjDYN_USER)
        & ((trn == mujoco.mjtTrn.mjTRN_SITE) | on_slide)
        & (target >= 0)
        & (model.actuator_dynprm[:, 0] > 0)
        & (model.actuator_actadr >= 0)
    )


def polarity_addresses(model) -> np.ndarray:
    """Where each unit's polarity lives in mjData.act (units in model order: chain 1's particles, then chain 2's)."""
    return model.actuator_actadr[unit_actuators(model)].astype(int)


def align_with_sites(model, data) -> None:
    """Set every unit's polarity along the follower direction of its site, -x_site (after mj_forward: site_xmat):
    at t = 0 the two laws exert the same force. Chain units only (their transmission is the site)."""
    import mujoco  # start-up time: the CLI imports the terms

    for a in unit_actuators(model):
        if model.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_SITE:
            continue
        R = data.site_xmat[model.actuator_trnid[a, 0]]
        data.act[model.actuator_actadr[a]] = math.atan2(-R[3], -R[0])


def initial_polarity(theta: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """The polarity of the loaded particles of chains with absolute angles theta: the follower direction, toward
    the clamp, -(cos theta, sin theta), as an angle in (-pi, pi] (the one align_with_sites gives MuJoCo's units);
    mask: the load mask over theta's columns."""
    theta = np.asarray(theta, dtype=float)[np.asarray(mask, dtype=bool)]
    return np.arctan2(-np.sin(theta), -np.cos(theta))


def free_pin():
    """The first registered scene of a single chain whose first pendulum turns freely on a fixed pin (the rotating
    pin): found by what it is, through the scene registry (a term module imports no scene)."""
    return next(
        s
        for s in registry.scenes()
        if getattr(s, "n_chains", 0) == 1 and not (getattr(s, "clamped", True) or s.pinned or s.head_coordinates)
    )


class SelfAligning(Term):
    name = "self-aligning"
    summary = "self-aligning active units: the force's direction turns toward the particle's velocity"
    parameters = (ACTIVE, ALIGNMENT_LENGTH)

    def active(self, physics) -> bool:
        return physics.active == SELF_ALIGNING

    def validation_cases(self, physics):
        """The chain on a freely rotating pin (N = 7, sigma = 0.8) with units of l_a = 0.5: the straight chain
        buckles and settles into a steady rigid rotation at -0.219 rad/tau (engines within 0.004%). The one-pinned
        chain with self-aligning units winds irregularly at these parameters (no periodic beat to hold to 1%; its
        Theta amplitude agrees to 0.02% over 100 tau at l_a = 2: docs/terms.md)."""
        return (
            ValidationCase(
                physics(scene=free_pin().name, n=7, sigma=0.8, active=SELF_ALIGNING, alignment_length=0.5),
                100.0,
                convergence=False,
            ),
        )

    def rate(self, physics) -> float:
        return turning_rate(physics)

    def slower(self, physics, rate: float) -> str:
        return f"alignment_length >= {float(physics.sigma) / rate:.2g}"

    def inertial_model(self, physics) -> bool:
        """The units' reduced model (engines.polarity) is overdamped only."""
        return False

    polarity_switch = (ACTIVE.name, SELF_ALIGNING)

    def turning_rate(self, physics) -> float:
        return turning_rate(physics)

    def check_reduced_span(self, physics, duration: float) -> None:
        check_reduced_span(physics, duration)

    def add_unit(self, spec, site: str, physics, slide: str | None = None) -> None:
        add_unit(spec, site, physics.alignment_length, slide=slide)

    def polarity_addresses(self, model) -> np.ndarray:
        return polarity_addresses(model)

    def align_polarity(self, model, data) -> None:
        align_with_sites(model, data)

    def initial_polarity(self, theta: np.ndarray, mask: np.ndarray) -> np.ndarray:
        return initial_polarity(theta, mask)

    def build(self, spec, physics, numerics):
        """One unit actuator per loaded particle (add_unit), chain by chain (the chains this physics has: a star's
        arms)."""
        mask = physics.load_mask()
        for prefix in physics.scene_def.chain_prefixes()[: physics.n_chains]:
            for i in np.flatnonzero(mask):
                add_unit(spec, f"{prefix}particle_{i}", physics.alignment_length)


TERM = SelfAligning()

"""Self-contact: a capsule on each link that collides with the non-adjacent links of its own chain.

MuJoCo (`build`): a capsule geom on each link, radius contact_radius, length CONTACT_LENGTH centred on the link;
chain k collides only with itself (contype = conaffinity = 2^k), parent-child filtering keeps neighbours apart;
frictionless (condim 1) or condim 3 with contact_friction; near-hard contact made for the overdamped limit
(contact_solref); the contact, constraint and parent-filter flags the scenes switch off (mjcf/common.xml) switched
on. The reduced model: a steep penalty of stiffness CONTACT_STIFFNESS between the capsules' cores (its record's
contact_radius and contact_stiffness; analysis.reduced.contact), frictionless. Observables: contact_fraction and
min_clearance, from the trajectory's geometry the same way for both engines.

mujoco is imported inside `build`, the MuJoCo engine's boundary: the command line imports the terms for their
parameters, and a reduced-engine run never loads MuJoCo.
"""

from __future__ import annotations

import numpy as np

from ..core.constants import CONTACT_LENGTH, CONTACT_STIFFNESS
from ..core.observables import Observable
from ..core.parameters import Parameter
from ..reduced.contact import capsule_clearance, core_span
from .base import Term

CONTACT = Parameter(
    "contact",
    False,
    "self-contact: the links' capsules collide with non-adjacent links of the same chain",
    kind=bool,
    quiet_default=True,
)
CONTACT_RADIUS = Parameter(
    "contact_radius",
    0.1,
    f"radius of each link's capsule, in l (with --contact; the capsule is {CONTACT_LENGTH:g} l long)",
    low=0.0,
    high=CONTACT_LENGTH / 2,
    low_open=True,
    high_open=True,
    units="l",
    needs="contact",
    title=f"capsule radius, in l; the capsule is {CONTACT_LENGTH:g} l long",
)
CONTACT_FRICTION = Parameter(
    "contact_friction",
    0.0,
    "friction coefficient between capsules (with --contact; 0: frictionless)",
    low=0.0,
    title="friction coefficient",
    needs="contact",
)


CONTACT_IMPEDANCE = 0.99
"""MuJoCo's constraint impedance d of a self-contact (solimp d0 = d_width = d): the share of the pushing force
the contact cancels within the step; the rest, (1 - d), is left to the contact's reference spring."""
CONTACT_RATE = 0.25
"""Contact spring K_c in units of gamma / dt: the overlap relaxes by about this fraction of itself per step."""


def contact_solref(numerics) -> list[float]:
    """solref (-stiffness, -damping) of a self-contact, made for the overdamped limit.

    MuJoCo's soft constraints ask for a reference acceleration a_ref = -b v - k r and produce a force of the
    contact's effective mass times it; with implicit drag that force is then divided by (m + dt gamma), so a
    standard solref (time constant, damping ratio) holds a particle of mass m -> 0 with a force ~ m / dt^2:
    at mass_ratio 1e-4 and dt 0.0025 the capsules pass through each other (overlap ~ 2R, measured). Scaled
    by 1/m, b = gamma / m and k = K_c / m with K_c = CONTACT_RATE gamma / dt, the normal motion of an
    overdamped particle in contact obeys gamma v = (1 - d) F_n - d K_c r: the contact cancels a share d of
    the force pushing in and pulls the overlap r back at rate ~ d K_c / gamma, independently of the mass.
    The overlap then falls like dt (a hard contact in the limit): N = 17, sigma = 0.8, largest overlap
    0.0027 l at dt 0.0025, 0.0010 l at dt 0.00125, the same at mass ratio 1e-4 and 1e-5 (docs/mujoco.md)."""
    mass = numerics.mass_ratio
    return [-CONTACT_RATE / numerics.dt / mass, -1.0 / mass]


CONTACT_FRACTION = Observable(
    "contact_fraction",
    "1",
    "share of recorded samples with at least one self-contact (overlapping capsules of non-adjacent links)",
    error="absolute",
    floor=0.0,
)
MIN_CLEARANCE = Observable(
    "min_clearance",
    "l",
    "smallest clearance between capsules of non-adjacent links over the measured window (negative: overlap)",
    error="none",
)
"""Self-contact's observables, measured on the trajectory's geometry (the same way for both engines)."""


class Contact(Term):
    name = "contact"
    summary = "self-contact between the capsules of non-adjacent links"
    labelled = False
    parameters = (CONTACT, CONTACT_RADIUS, CONTACT_FRICTION)
    observables = (CONTACT_FRACTION, MIN_CLEARANCE)
    measured_at_rest = False  # its observables describe the term acting
    agreement = 0.03  # MuJoCo's soft contact against the reduced model's penalty: 1.7% at N = 10, sigma 2, over 10 tau

    def active(self, physics) -> bool:
        return physics.contact

    def short_case(self, physics):
        """A chain that folds onto itself within a few tau (N = 10 at sigma 2: its links touch by t = 10)."""
        return physics(n=10, sigma=2.0, contact=True)

    def reduced_system(self, system, physics):
        # MuJoCo's near-hard contact becomes a steep penalty (docs/model.md, "Self-contact")
        return system._replace(contact_radius=physics.contact_radius, contact_stiffness=CONTACT_STIFFNESS)

    def build(self, spec, physics, numerics):
        import mujoco  # start-up time: the CLI imports the terms for their parameters, not the engine

        for flag in (
            mujoco.mjtDisableBit.mjDSBL_CONTACT,
            mujoco.mjtDisableBit.mjDSBL_FILTERPARENT,
            mujoco.mjtDisableBit.mjDSBL_CONSTRAINT,
        ):
            spec.option.disableflags &= ~int(flag)
        start, end = core_span(physics.contact_radius)  # the reduced model's capsule: CONTACT_LENGTH long, centred
        d, friction = CONTACT_IMPEDANCE, physics.contact_friction
        for chain, prefix in enumerate(physics.scene_def.chain_prefixes()):
            bits = 1 << chain
            for i in range(physics.n):
                spec.body(f"{prefix}segment_{i}").add_geom(
                    name=f"{prefix}capsule_{i}",
                    default=spec.find_default("capsule"),
                    fromto=[start, 0, 0, end, 0, 0],
                    size=[physics.contact_radius, 0, 0],
                    contype=bits,
                    conaffinity=bits,
                    condim=3 if friction > 0 else 1,
                    friction=[friction, 0.005, 0.0001],
                    solref=contact_solref(numerics),
                    solimp=[d, d, 0.001, 0.5, 2],
                )

    def measure(self, traj, transient):
        """contact_fraction and min_clearance, from the capsules' geometry (every chain) over the steady window."""
        steady = traj.t - traj.t[0] >= transient
        head = None if traj.head is None else traj.head[steady]
        clearance = np.min(
            [
                capsule_clearance(traj.chain(k)[steady], traj.physics.contact_radius, head)
                for k in range(traj.physics.n_chains)
            ],
            axis=0,
        )
        return {"contact_fraction": float(np.mean(clearance < 0.0)), "min_clearance": float(np.min(clearance))}


TERM = Contact()

"""Self-contact: a capsule on each link that collides with the non-adjacent links of its own chain.

MuJoCo: capsules of radius contact_radius and length CONTACT_LENGTH (elastoactive.model), one collision bit per
chain, near-hard contact made for the overdamped limit (model.contact_solref); friction contact_friction. The
reduced model: a steep penalty of stiffness CONTACT_STIFFNESS between the capsules' cores (its record's
contact_radius and contact_stiffness; analysis.reduced.contact), frictionless.
"""

from __future__ import annotations

import numpy as np

from ..analysis.reduced.contact import capsule_clearance
from ..constants import CONTACT_LENGTH, CONTACT_STIFFNESS
from ..parameters import Parameter
from .base import Term

CONTACT = Parameter("contact", False, "self-contact: the links' capsules collide with non-adjacent links of the same "
                    "chain", kind=bool, quiet_default=True)
CONTACT_RADIUS = Parameter(
    "contact_radius", 0.1, f"radius of each link's capsule, in l (with --contact; the capsule is {CONTACT_LENGTH:g} l "
    "long)", low=0.0, high=CONTACT_LENGTH / 2, low_open=True, high_open=True, units="l", needs="contact",
    title=f"capsule radius, in l; the capsule is {CONTACT_LENGTH:g} l long")
CONTACT_FRICTION = Parameter("contact_friction", 0.0, "friction coefficient between capsules (with --contact; 0: "
                             "frictionless)", low=0.0, title="friction coefficient", needs="contact")


class Contact(Term):
    name = "contact"
    summary = "self-contact between the capsules of non-adjacent links"
    labelled = False
    parameters = (CONTACT, CONTACT_RADIUS, CONTACT_FRICTION)
    observables = ("contact_fraction", "min_clearance")

    def active(self, physics) -> bool:
        return physics.contact

    def reduced_system(self, system, physics):
        # MuJoCo's near-hard contact becomes a steep penalty (docs/model.md, "Self-contact")
        return system._replace(contact_radius=physics.contact_radius, contact_stiffness=CONTACT_STIFFNESS)

    def measure(self, traj, transient):
        """contact_fraction and min_clearance, from the capsules' geometry (every chain) over the steady window."""
        steady = traj.t - traj.t[0] >= transient
        head = None if traj.head is None else traj.head[steady]
        clearance = np.min([capsule_clearance(traj.chain(k)[steady], traj.physics.contact_radius, head)
                            for k in range(traj.physics.n_chains)], axis=0)
        return {"contact_fraction": float(np.mean(clearance < 0.0)), "min_clearance": float(np.min(clearance))}


TERM = Contact()

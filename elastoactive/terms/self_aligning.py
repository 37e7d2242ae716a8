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
"""

from __future__ import annotations

from ..parameters import Parameter
from .base import Term

FOLLOWER = "follower"
SELF_ALIGNING = "self-aligning"
LAWS = (FOLLOWER, SELF_ALIGNING)

ACTIVE = Parameter("active", FOLLOWER, "direction law of the active force: follower (along each link, toward the "
                   "clamp) or self-aligning (a polarity that turns toward its particle's velocity over the alignment "
                   "length)", kind=str, choices=LAWS, title="active force's direction law", quiet_default=True)
ALIGNMENT_LENGTH = Parameter("alignment_length", 1.0, "alignment length l_a / l of self-aligning units (with "
                             "--active self-aligning)", low=0.0, low_open=True, title="alignment length l_a / l",
                             symbol="l_a", units="l", needs="active", needs_value=SELF_ALIGNING)


class SelfAligning(Term):
    name = "self-aligning"
    summary = "self-aligning active units: the force's direction turns toward the particle's velocity"
    parameters = (ACTIVE, ALIGNMENT_LENGTH)

    def active(self, physics) -> bool:
        return physics.active == SELF_ALIGNING


TERM = SelfAligning()

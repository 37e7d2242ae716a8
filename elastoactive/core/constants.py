"""Fixed physical constants of the models: one place for each, read by both engines and the reduced model.

A leaf module (it imports nothing), so that the reduced model (elastoactive.reduced), the MJCF builder
(elastoactive.mjcf.chain), the parameter specs and the terms all read the same number.
"""

BEAD_RADIUS = 0.14
"""Radius of the massive sphere (the bead) on each particle of the MuJoCo chains, in l (mjcf/common.xml's particle
geom has this size; elastoactive.mjcf.chain sets it from here)."""
BEAD_INERTIA_FACTOR = 0.4 * BEAD_RADIUS**2
"""I / m of a bead, a solid sphere of radius BEAD_RADIUS: (2/5) r^2 = 0.00784. The inertial reduced model gives each
particle this rotational inertia, as MuJoCo's bead has."""

CONTACT_LENGTH = 0.7
"""Length of each link's contact capsule, caps included, in units of the link length l: a Hexbug Nano is about
5 cm long on a link pitch of about 7 cm (N = 7 over L = 500 mm), so 5 / 7 ~ 0.7. The capsule of link i is
centred on the link; its core (the segment whose points within the radius R make the capsule) runs over the
fractions s in [(1 - CONTACT_LENGTH) / 2 + R, (1 + CONTACT_LENGTH) / 2 - R] of the link
(elastoactive.reduced.contact)."""
CONTACT_STIFFNESS = 1.0e3
"""The reduced model's self-contact penalty K (force K x overlap, units C1 / l^2): overlaps ~ force / K ~ 1e-3 l.
MuJoCo's contact is nearly hard instead (elastoactive.terms.contact.contact_solref); the two agree as K grows and dt
shrinks (docs/model.md, "Self-contact")."""

MAX_PARTICLES = 1000
"""Most particles per chain a Physics accepts."""

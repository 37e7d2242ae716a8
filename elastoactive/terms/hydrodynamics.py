"""Hydrodynamic interactions: the lab-frame drag of every particle replaced by a mobility among all of them.

With bead_radius a / l > 0 each particle is a sphere of radius a whose drag gamma = 6 pi mu a is the unit of drag
(an isolated bead moves as under the lab-frame drag at drag_ratio 1), and every bead's force moves every other bead
through the fluid: the Rotne-Prager-Yamakawa mobility in free space, the Rotne-Prager-Blake mobility above a no-slip
wall where the scene has one (elastoactive.hydro; the reduced equations: elastoactive.reduced.fluid,
docs/hydrodynamics.md). At bead_radius 0 (the default) the term rests and every run is the lab-frame drag's, bit for
bit.

Scenes: the ones that name bead_radius in their term_parameters (the 3D chains clamped-3d and rotating-pin-3d in
free space, the cilia on a wall: cilium, cilia-pair, cilia-row). The others refuse it as having no effect on them
(Physics; `named_only`: the paper's planar chains too, which take every other chain term): their engines, the planar
kernels and planar MuJoCo models, carry no mobility among the beads (docs/hydrodynamics.md, "Which scenes take the
term"). The beads are spheres, so a drag_ratio other than 1 is refused while the term acts (`check`).

Engines: both. The reduced engine solves the constrained mobility problem (elastoactive.reduced.fluid); MuJoCo carries
the coupling as a background flow on the beads' drag actuators, explicit from the step before, the self-drag implicit
(elastoactive.controllers.hydro, elastoactive.mjcf.cilia; docs/hydrodynamics.md).
"""

from __future__ import annotations

from ..core.errors import ParameterError
from ..core.parameters import Parameter
from .base import Term

MAX_BEAD_RADIUS = 0.5
"""The largest bead radius a / l: neighbouring beads of a chain (one link, l, apart) touch at a = l / 2."""

BEAD_RADIUS = Parameter(
    "bead_radius",
    0.0,
    "radius a / l of each bead for the hydrodynamic interactions (0: none, the lab-frame drag; "
    f"(0, {MAX_BEAD_RADIUS:g}]: the RPY / RPB mobility among all beads)",
    low=0.0,
    high=MAX_BEAD_RADIUS,
    units="l",
    title="bead radius a / l",
    symbol="a",
    quiet_default=True,
)


class Hydrodynamics(Term):
    name = "hydrodynamics"
    summary = "hydrodynamic interactions among all beads (RPY in free space, RPB above a wall), bead radius a / l"
    parameters = (BEAD_RADIUS,)
    named_only = True  # the planar chains' engines carry no mobility among the beads

    def active(self, physics) -> bool:
        return physics.bead_radius > 0

    def check(self, physics) -> None:
        if physics.drag_ratio != 1.0:
            raise ParameterError(
                f"drag_ratio = {physics.drag_ratio:g} with bead_radius = {physics.bead_radius:g}: the beads are "
                "spheres, their drag is isotropic (drag_ratio 1)"
            )


TERM = Hydrodynamics()

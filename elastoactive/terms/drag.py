"""Lab-frame drag: gamma_T across each link, gamma_L = drag_ratio gamma_T along it (the paper's overdamped limit).

MuJoCo carries it as velocity actuators on each particle's site (elastoactive.mjcf.chain.add_drag, implicit in
implicitfast); the reduced model as the drag matrix D(theta) of its record's gamma_l and gamma_t.
"""

from __future__ import annotations

from ..core.parameters import Parameter
from .base import Term

DRAG_RATIO = Parameter(
    "drag_ratio",
    1.0,
    "anisotropy gamma_L / gamma_T of the drag (1: isotropic)",
    low=0.0,
    low_open=True,
    title="gamma_L/gamma_T",
)


class Drag(Term):
    name = "drag"
    summary = "lab-frame drag, transverse gamma_T = 1 and longitudinal gamma_L = drag_ratio"
    labelled = False
    parameters = (DRAG_RATIO,)

    def active(self, physics) -> bool:
        return True  # every chain has drag

    def reduced_system(self, system, physics):
        return system._replace(gamma_l=physics.drag_ratio, gamma_t=1.0)


TERM = Drag()

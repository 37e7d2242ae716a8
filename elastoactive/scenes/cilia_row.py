"""A row of M cilia on a wall at spacing d along x (scenes.cilium), coupled only through the fluid (the hydrodynamics
term, bead_radius > 0).

Observables, beyond the first cilium's motion and the pumped flux: wave_number, the metachronal wave number
k = -<Phi_{m+1} - Phi_m> / d (rad / l, signed along x) and wave_direction (+x, -x, synchronous, none)
(analysis.cilia.metachronal_wave).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..analysis import cilia as cilia_analysis
from ..core.observables import Observable, names_of
from ..core.parameters import Parameter
from ..core.trajectory import Trajectory
from .base import ValidationCase
from .cilium import Cilium

if TYPE_CHECKING:  # typing only: params imports the registry that holds scenes
    from ..core.params import Physics

MAX_CILIA = 1024
"""The most cilia of a row (the dense mobility of M N beads costs (M N)^2 memory and (M N)^3 / 3 per evaluation)."""
CILIA = Parameter(
    "cilia",
    4,
    "number M of cilia in the row",
    kind=int,
    low=2,
    high=MAX_CILIA,
    title="number of cilia",
    symbol="M",
)
WAVE_NUMBER = Observable(
    "wave_number",
    "rad/l",
    "metachronal wave number k = -<Phi_{m+1} - Phi_m> / d, signed along x (NaN unless every neighbour pair locks)",
    error="absolute",
)
WAVE_DIRECTION = Observable(
    "wave_direction",
    "1",
    "the metachronal wave's direction along x (analysis.cilia.metachronal_wave)",
    error="none",
    categories=cilia_analysis.WAVE_DIRECTIONS,
)


class CiliaRow(Cilium):
    name = "cilia-row"
    summary = "a row of M cilia on a wall at spacing d, coupled through the fluid (bead_radius): metachronal waves"
    parameters = ("base_height", "spacing", CILIA)
    observables = (*names_of(Cilium.observables), WAVE_NUMBER, WAVE_DIRECTION)

    def cilia(self, physics: Physics) -> int:
        return physics.cilia

    def spacing(self, physics: Physics) -> float:
        return physics.spacing

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float | str]:
        values = super().measure_extra(traj, transient)
        wave = cilia_analysis.metachronal_wave(traj.t, np.asarray(self.beat_signals(traj)), traj.physics.spacing,
                                               transient=transient)  # fmt: skip
        values["wave_number"] = wave.wave_number
        values["wave_direction"] = wave.direction
        return values

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        """Three independent clamped-3d chains (no fluid): the engines agree as for one."""
        return (ValidationCase(self.physics(n=5, sigma=0.6, cilia=3), 300.0),)


SCENE = CiliaRow()

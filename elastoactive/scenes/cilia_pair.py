"""Two cilia on a wall at separation d along x (scenes.cilium), coupled only through the fluid (the hydrodynamics
term, bead_radius > 0), or also, or instead, by a spring between their tips (tip_coupling K: energy
K/2 |r_tip,1 - r_tip,2 - (b_1 - b_2)|^2, relaxed when both stand straight; the planar coupled pair's spring joins
the first pendula instead, which is why this is a parameter of its own).

Observables, beyond the first cilium's motion and the pumped flux: phase_difference, the circular mean of
Phi_2 - Phi_1 of the two tips' signals along one axis (analysis.cilia.pair_locking), and lock_state (in-phase,
anti-phase, lag, none).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..analysis import cilia as cilia_analysis
from ..core.observables import Observable, names_of
from ..core.parameters import Parameter
from ..core.trajectory import Trajectory
from .base import ValidationCase
from .cilium import Cilium

if TYPE_CHECKING:  # typing only: params imports the registry that holds scenes
    from ..core.params import Physics

SPACING = Parameter(
    "spacing",
    3.0,
    "distance d between neighbouring cilia's bases along x, in l",
    low=0.0,
    low_open=True,
    units="l",
    title="spacing of the cilia",
    symbol="d",
)
TIP_COUPLING = Parameter(
    "tip_coupling",
    0.0,
    "stiffness K l^2 / C1 of a spring between the two cilia's tips (0: coupled only through the fluid)",
    low=0.0,
    title="tips' spring stiffness",
    symbol="K",
)
PHASE_DIFFERENCE = Observable(
    "phase_difference",
    "rad",
    "circular mean of the tips' phase difference Phi_2 - Phi_1, in (-pi, pi] (NaN unless both beat)",
    error="absolute",
)
LOCK_STATE = Observable(
    "lock_state",
    "1",
    "the pair's phase locking (analysis.cilia.pair_locking)",
    error="none",
    categories=cilia_analysis.LOCK_STATES,
)


class CiliaPair(Cilium):
    name = "cilia-pair"
    summary = "two cilia on a wall, d apart, coupled through the fluid (bead_radius) or a spring between their tips"
    parameters = ("base_height", SPACING, TIP_COUPLING)
    observables = (*names_of(Cilium.observables), PHASE_DIFFERENCE, LOCK_STATE)

    def cilia(self, physics: Physics) -> int:
        return 2

    def spacing(self, physics: Physics) -> float:
        return physics.spacing

    def tip_coupling(self, physics: Physics) -> float:
        return physics.tip_coupling

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float | str]:
        values = super().measure_extra(traj, transient)
        first, second = self.beat_signals(traj)
        locking = cilia_analysis.pair_locking(traj.t, first, second, transient=transient)
        values["phase_difference"] = locking.lag
        values["lock_state"] = locking.state
        return values

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        """Two independent clamped-3d chains (no fluid, no spring): the engines agree as for one."""
        return (ValidationCase(self.physics(n=7, sigma=0.4), 300.0),)


SCENE = CiliaPair()

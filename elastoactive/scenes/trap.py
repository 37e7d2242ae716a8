"""The scene `trapped-unit`: a single self-aligning active unit in a harmonic trap, the network's smallest member
(named apart from its parameter `trap`, the paraboloid dish's, which it shares).

Beyond the paper: one node of drag gamma carrying a unit of force F_a n (sigma), its polarity turning toward the
node's velocity over the alignment length l_a, held by an isotropic trap of stiffness k_t (`trap`, the paraboloid
dish's parameter: a harmonic trap's stiffness in the scene's units, here k = 1 for the spring of a network):

    dx/dt = sigma n - trap x,        dpsi/dt = (1 / l_a) (dx/dt) . n_perp

With l_e = sigma / trap the elasto-active length and Pi = l_e / l_a: for Pi < 1 the unit comes to rest at distance
l_e from the centre, pointing outward; for Pi > 1 it goes round a circle of radius sqrt(l_e l_a) at the angular
frequency trap sqrt(Pi - 1) (docs/network.md derives both). Observables: orbit_radius and orbit_rate (about the
trap's centre), and the network scenes' (elastoactive.scenes.lattice.ActiveNetwork).
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.network import Network, trap_unit
from ..core.params import Physics
from ..core.trajectory import Trajectory
from ..core.units import Signal
from .base import Onset, ValidationCase
from .lattice import ActiveNetwork
from .paraboloid import ORBIT_RADIUS, ORBIT_RATE


def orbit(sigma: float, trap: float, alignment_length: float) -> tuple[float, float]:
    """(radius, angular frequency) of the trapped unit's steady state: (l_e, 0) at rest for Pi <= 1, else
    (sqrt(l_e l_a), trap sqrt(Pi - 1)) with l_e = sigma / trap, Pi = l_e / l_a."""
    elastic = sigma / trap
    coupling = elastic / alignment_length
    if coupling <= 1.0:
        return elastic, 0.0
    return math.sqrt(elastic * alignment_length), trap * math.sqrt(coupling - 1.0)


class Trap(ActiveNetwork):
    name = "trapped-unit"
    summary = "a single self-aligning active unit in a harmonic trap: at rest below Pi = l_e / l_a = 1, orbiting above"
    parameters = ("trap",)
    observables = ActiveNetwork.observables + (ORBIT_RADIUS, ORBIT_RATE)
    compared = ("orbit_radius", "orbit_rate")
    no_linear_operator = ""

    coupling_formula = "σ / (k_t l_a)"

    def coupling(self, physics: Physics, sigma: float | None = None) -> float:
        """Pi = l_e / l_a with l_e = sigma / trap: the trap is the unit's only spring."""
        return (physics.sigma if sigma is None else sigma) / (physics.trap * physics.alignment_length)

    def network(self, physics: Physics) -> Network:
        return trap_unit(physics.trap)

    def beat_signal(self, physics: Physics) -> Signal:
        return Signal("x", "x = the unit's position along x", "a")

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        """The unit's x (units a)."""
        return [traj.nodes[:, 0, 0]]

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        out = super().measure_extra(traj, transient)
        keep = traj.t - traj.t[0] >= transient
        x = traj.nodes[keep, 0, :]
        angle = np.unwrap(np.arctan2(x[:, 1], x[:, 0]))
        t = traj.t[keep]
        radius = float(np.linalg.norm(x, axis=1).mean())
        rate = float((angle[-1] - angle[0]) / (t[-1] - t[0]))
        return {"orbit_rate": rate, "orbit_radius": radius, **out}  # the orbit first, as summary.json lists it

    def onset(self, physics: Physics) -> Onset:
        """sigma_c = trap l_a (Pi = 1), where the rest state's one non-zero eigenvalue trap (Pi - 1) crosses zero."""
        return Onset(
            sigma_c=physics.trap * physics.alignment_length,
            omega_c=0.0,
            kind="real eigenvalue trap (Pi - 1) through zero; the circular orbit grows from radius l_a",
        )

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        return complex(physics.trap * (sigma / (physics.trap * physics.alignment_length) - 1.0))

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (
            ValidationCase(self.physics(sigma=0.8, trap=0.1, alignment_length=1.0), 300.0),
            ValidationCase(self.physics(sigma=0.2, trap=1.0, alignment_length=0.1), 100.0, convergence=False),
        )


SCENE = Trap()

"""Noise on a network's active units: rotational diffusion of the polarities, translational diffusion of the nodes.

The Ito SDE of every free node i and unit u (units k = gamma = a = 1; pinned nodes stay at rest):

    dx_i   = v_i dt + sqrt(2 D_t) dW_i                  (D_t: translational_diffusion, a^2 per gamma / k)
    dpsi_u = psi_u' dt + sqrt(2 D_r) dW_u               (D_r: rotational_diffusion, rad^2 per gamma / k)

with v and psi' the deterministic model's (elastoactive.reduced.network): a polarity turns toward its node's drift
velocity, not toward the noise's kicks. A free node with no force diffuses with <|x(t) - x(0)|^2> = 4 D_t t (2 D_t t
per axis), a free polarity with <(psi(t) - psi(0))^2> = 2 D_r t.

Both engines step the same Euler-Maruyama increments amplitude_i xi(seed, k, i) over step k of length dt, with the
counter-based normal xi of elastoactive.controllers.noise, i indexing the reduced state (the free nodes' x and y, then
the units' psi, node order), the seed the run's numerics.seed (recorded with it): the reduced engine
(reduced.network.solve_noisy) adds them after its explicit step, MuJoCo (engines.network_mujoco) to qpos and the
polarities after each mj_step, so a run is reproducible from its seed and the two engines draw the same realisation.

The parameters act on the network scenes only (they list them among the terms' parameters that act on a network,
Scene.term_parameters); they are registered here, not as a term every chain scene would take.
"""

from __future__ import annotations

from typing import NamedTuple

from ..core import parameters as _parameters
from ..core.parameters import Parameter

ROTATIONAL = Parameter(
    "rotational_diffusion",
    0.0,
    "rotational diffusion D_r of a network's unit polarities (Ito; <dpsi^2> = 2 D_r t)",
    low=0.0,
    title="D_r of the polarities",
    units="1/tau",
    quiet_default=True,
    stochastic=True,
)
TRANSLATIONAL = Parameter(
    "translational_diffusion",
    0.0,
    "translational diffusion D_t of a network's free nodes (Ito; <dx^2> = 2 D_t t per axis)",
    low=0.0,
    title="D_t of the nodes",
    units="l^2/tau",
    quiet_default=True,
    stochastic=True,
)
PARAMETERS = (ROTATIONAL, TRANSLATIONAL)
NAMES = tuple(p.name for p in PARAMETERS)
"""The parameters a network scene lists among those acting on it."""

for _spec in PARAMETERS:
    _parameters.register(_spec, "the network units' noise")


class UnitNoise(NamedTuple):
    """A run's noise on its units: diffusion constants and the seed of its counter-based draws."""

    translational: float  # D_t, a^2 per gamma / k
    rotational: float  # D_r, rad^2 per gamma / k
    seed: int

    @property
    def active(self) -> bool:
        return self.translational > 0 or self.rotational > 0


def unit_noise(physics, numerics) -> UnitNoise:
    """The noise of a network run at these parameters, seeded by numerics.seed."""
    return UnitNoise(float(physics.translational_diffusion), float(physics.rotational_diffusion), int(numerics.seed))

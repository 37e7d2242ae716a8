"""Multiplicative noise on the active force: F_a (1 + eta), white or coloured (Ornstein-Uhlenbeck).

Both engines draw the same counter-based realisation (elastoactive.controllers.noise); MuJoCo's callback applies
it (`build` gives it the amplitude, seed and correlation time), the reduced engine integrates the SDE (Euler-Maruyama,
Heun for Stratonovich) or the random ODE of coloured noise. Its correlation time and calculus act only when the
amplitude is > 0.
"""

from __future__ import annotations

from ..core.errors import ParameterError
from ..core.parameters import Parameter
from .base import Term

NOISE_CALCULI = ("ito", "stratonovich")
NOISE = Parameter(
    "noise", 0.0, "amplitude a of multiplicative white noise on F_a", low=0.0, title="amplitude a", stochastic=True
)
NOISE_CORRELATION = Parameter(
    "noise_correlation",
    0.0,
    "correlation time tau_c of the noise, in tau (0: white; > 0: Ornstein-Uhlenbeck of variance a^2 / (2 tau_c))",
    low=0.0,
    title="tau_c, 0: white",
    units="tau",
    needs="noise",
)
NOISE_CALCULUS = Parameter(
    "noise_calculus",
    "ito",
    "reading of white noise (reduced engine; MuJoCo: ito, or stratonovich as small tau_c)",
    kind=str,
    choices=NOISE_CALCULI,
    needs="noise",
    unless="noise_correlation",
    unless_why="coloured noise is a smooth random force, read alike in either calculus",
)


class Noise(Term):
    name = "noise"
    summary = "multiplicative noise on the active force, white (Ito or Stratonovich) or coloured"
    labelled = False
    parameters = (NOISE, NOISE_CORRELATION, NOISE_CALCULUS)

    def active(self, physics) -> bool:
        return physics.noise > 0

    def build(self, spec, physics, numerics):
        """The callback's marker carries (a, seed, tau_c); coloured noise keeps its state in mjData.userdata: the
        held step + 1 and eta of each particle (controllers/follower.c)."""
        if physics.noise_correlation == 0 and physics.noise_calculus != "ito":
            raise ParameterError(
                "MuJoCo applies white noise in the Ito reading only (constant over each step); for the Stratonovich "
                "reading give the noise a short correlation time (--noise-correlation, its Wong-Zakai limit), or "
                "use the reduced engine"
            )
        spec.numeric("elastoactive_follower").data = [physics.noise, float(numerics.seed), physics.noise_correlation]
        if physics.noise_correlation > 0:
            spec.nuserdata = 1 + physics.n_angles


TERM = Noise()

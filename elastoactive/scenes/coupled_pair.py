"""Two chains coupled by a spring between their first pendula: frequency entrainment.

Chain 1 has joint stiffness C1, chain 2 C2 = rho C1 (so chain 2's elasto-active number is
sigma / rho and it relaxes rho times faster). The coupling energy is kappa/2 (theta_1 - phi_1)^2:
in MuJoCo a fixed tendon hinge_0(chain 1) - hinge_0(chain 2) with stiffness kappa and spring
length 0. The chains lock above kappa_c = 0.078 at the paper's sigma = 0.8, rho = 4/3 (the paper
says ~1.1; see docs/errata.md). Observables: per-chain amplitude and frequency, and
frequency_mismatch f_2 - f_1 from the Hilbert phases.
"""

from __future__ import annotations

from ..analysis import observables as obs
from ..core.observables import Observable
from ..core.parameters import Parameter
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory
from ..reduced.system import ChainSystem
from .base import Onset, ValidationCase
from .chain_kind import ChainScene

FREQUENCY_MISMATCH = Observable(
    "frequency_mismatch", "1/tau", "f_2 - f_1 from the Hilbert phases (NaN unless both oscillate)", error="absolute"
)
"""How far the two chains are from a common frequency (analysis.observables.frequency_mismatch)."""


class CoupledPair(ChainScene):
    name = "coupled-pair"
    paper = True
    summary = (
        "two chains (stiffness C1, C2 = rho C1) joined by a spring kappa between their first\n"
        "                pendula: frequency entrainment above kappa_c = 0.078 (sigma 0.8, rho 4/3) [paper: ~1.1]"
    )
    base_file = "coupled-pair.xml"
    parameters = (
        Parameter(
            "kappa",
            1.0,
            "coupling stiffness K l^2 / C1 of the pair's first pendula",
            low=0.0,
            title="coupling stiffness",
            symbol="κ",
        ),
        Parameter(
            "rho",
            4.0 / 3.0,
            "stiffness ratio C2 / C1 of the pair; chain 2 has sigma/rho",
            low=0.0,
            low_open=True,
            title="stiffness ratio C2/C1",
            symbol="ρ",
        ),
    )
    n_chains = 2
    observables = (FREQUENCY_MISMATCH,)
    no_linear_operator = ""

    def stiffness(self, physics: Physics) -> tuple[float, ...]:
        return (1.0, physics.rho)

    def build(self, spec, physics: Physics, numerics: Numerics) -> None:
        first, second = (f"{prefix}hinge_0" for prefix in self.chain_prefixes())
        spec.geom("clamp2").pos = [-0.15, self.chain_offset(physics, 1), 0.0]
        tendon = spec.add_tendon(name="coupling", stiffness=[physics.kappa, 0, 0], springlength=[0.0, 0.0])
        tendon.wrap_joint(first, 1.0)
        tendon.wrap_joint(second, -1.0)

    def reduced_system(self, physics: Physics) -> ChainSystem:
        return super().reduced_system(physics)._replace(kappa=physics.kappa, rho=physics.rho)

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        t = traj.t
        curvatures = [obs.curvature(traj.chain(k)) for k in range(self.n_chains)]
        oscillating = all(obs.amplitude(t, x, transient) > 1e-3 for x in curvatures)
        mismatch = obs.frequency_mismatch(t, *curvatures, transient) if oscillating else float("nan")
        return {"frequency_mismatch": mismatch}

    def onset(self, physics: Physics) -> Onset:
        from ..analysis import stability  # start-up time: scipy

        return Onset(*stability.pair_onset(physics.n, physics.kappa, physics.rho), "flutter (Hopf) of the pair")

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        import numpy as np  # the eigenvalues' array

        from ..analysis import stability  # start-up time: scipy

        lam = stability.pair_eigenvalues(physics.n, sigma, physics.kappa, physics.rho)
        return complex(lam[np.argmax(lam.real)])

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (
            ValidationCase(self.physics(n=7, sigma=0.8, rho=4 / 3, kappa=0.5), 600.0, convergence=False),
            ValidationCase(self.physics(n=7, sigma=0.8, rho=4 / 3, kappa=2.0), 600.0),
        )

    def extreme_cases(self, quick: bool = False) -> tuple[Physics, ...]:
        if quick:
            return ()
        cases = tuple(self.physics(n=7, sigma=0.8, kappa=k) for k in (0.5, 100.0, 1000.0))
        return cases + (self.physics(n=7, sigma=10.0, kappa=1000.0),)

    def decorate(self, frame) -> None:
        """The coupling spring, a zigzag between the two chains' first particles."""
        frame.spring(0, 0, 1, 0)


SCENE = CoupledPair()

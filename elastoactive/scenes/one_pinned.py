"""One pinned end: a chain clamped at one end beats like a flagellum above the Hopf onset sigma_c.

The paper's main scene (its Fig. 2-3): pendulum 1 hangs from a clamp through a hinge spring, the
other end is free. sigma_c = 0.1575 for N = 7 from the linear stability of the reduced model
(the paper quotes 0.15), falling as N^-3. Everything here is the base Scene's single clamped chain.
"""

from __future__ import annotations

import numpy as np

from ..core.params import Physics
from .base import Onset, ValidationCase
from .chain_kind import ChainScene

DENSE_GROWTH_MAX = 400
"""Up to this many angles the growth rate at a given sigma comes from every eigenvalue (dense); beyond, from the
slowest modes (analysis.stability.slow_eigenvalues), which hold the least stable one near the onset."""
SLOW_GROWTH_MODES = 16
"""Slowest modes searched for the least stable one beyond DENSE_GROWTH_MAX."""


def loaded_mask(physics: Physics) -> np.ndarray | None:
    """The particles the follower force acts on (Physics.load_mask), None when it acts on every one."""
    return None if physics.all_loaded else physics.load_mask()


class OnePinned(ChainScene):
    name = "one-pinned"
    paper = True
    summary = "chain clamped at one end: flagellar beating above sigma_c (N=7: 0.1575 [paper: 0.15])"
    base_file = "one-pinned.xml"
    no_linear_operator = ""
    filament = True

    def onset(self, physics: Physics) -> Onset:
        """The straight chain's flutter with the follower force on the particles `loaded` carries it on (every one:
        O(N) per sigma, banded operator and slowest modes; some: dense, analysis.stability.onset)."""
        from ..analysis import stability  # start-up time: scipy

        sigma_c, omega_c = stability.onset(physics.n, loaded_mask(physics))
        return Onset(sigma_c, omega_c, "flutter (Hopf)" + ("" if physics.all_loaded else f", loaded {physics.loaded}"))

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        from ..analysis import stability  # start-up time: scipy

        n, loaded = physics.n, loaded_mask(physics)
        lam = (
            stability.eigenvalues(n, sigma, loaded)
            if n <= DENSE_GROWTH_MAX or loaded is not None  # a partial load's unstable mode need not be slow
            else stability.slow_eigenvalues(n, sigma, SLOW_GROWTH_MODES)
        )
        return complex(lam[np.argmax(lam.real)])

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (ValidationCase(self.physics(n=7, sigma=0.8), 300.0),)

    def extreme_cases(self, quick: bool = False) -> tuple[Physics, ...]:
        if quick:
            return (self.physics(n=7, sigma=0.8),)
        return tuple(self.physics(n=n, sigma=s) for n in (7, 30, 100) for s in (0.8, 10.0, 100.0))


SCENE = OnePinned()

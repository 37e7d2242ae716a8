"""The reduced model's description of a system of chains: a typed record, built by each scene.

The compiled kernels read it by field name (numba compiles NamedTuples as typed records). A
scene turns its `Physics` into a `ChainSystem` (Scene.reduced_system); the solver needs nothing
else, so it knows no scene by name.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...errors import ParameterError

BEAD_INERTIA_FACTOR = 0.4 * 0.14**2
"""I / m of the MuJoCo scenes' bead, a solid sphere of radius 0.14 l on each particle: (2/5) r^2 = 0.00784
(the same number as analysis.flutter.BEAD_INERTIA_FACTOR, which imports scipy; this package must not)."""


class ChainSystem(NamedTuple):
    """One chain, or two chains coupled at their first pendula, in units l = C1 = gamma_T = 1.

    n         particles per chain N
    n_chains  1, or 2 for a coupled pair (state: theta of chain 1, then phi of chain 2)
    clamped   a spring (stiffness c) holds the first pendulum at angle 0; False: a free pin
    pinned    the last particle of chain 1 is held at (N (1 - delta), 0) (two constraints)
    sigma     follower force F_a l / C1 on every particle (the same on both chains)
    gamma_l   longitudinal drag, along each pendulum
    gamma_t   transverse drag, across it (1 in these units)
    kappa     coupling spring kappa/2 (theta_1 - phi_1)^2 between the chains' first pendula
    rho       joint stiffness of chain 2 over chain 1 (chain 1: 1)
    delta     compression of a pinned chain
    mass_ratio      particle mass m / (gamma_T tau); 0: the overdamped model (D th' = f, state th), > 0: the
                    inertial model (M th'' + c + D th' = f, state (th, th'); equations.py)
    inertia_factor  rotational inertia of each particle's body about the vertical axis, over its mass
                    (default: the MuJoCo bead's (2/5) 0.14^2); used only when mass_ratio > 0
    """

    n: int
    n_chains: int = 1
    clamped: bool = True
    pinned: bool = False
    sigma: float = 0.0
    gamma_l: float = 1.0
    gamma_t: float = 1.0
    kappa: float = 0.0
    rho: float = 1.0
    delta: float = 0.0
    mass_ratio: float = 0.0
    inertia_factor: float = BEAD_INERTIA_FACTOR

    @property
    def n_angles(self) -> int:
        return self.n * self.n_chains

    @property
    def inertial(self) -> bool:
        """Whether this is the inertial model (mass_ratio > 0): its state is (theta, omega), 2 n_angles numbers."""
        return self.mass_ratio > 0

    @property
    def state_size(self) -> int:
        """Numbers in the integrated state: n_angles (overdamped), 2 n_angles (inertial: angles, then rates)."""
        return 2 * self.n_angles if self.mass_ratio > 0 else self.n_angles

    def stiffness(self, chain: int) -> float:
        """Joint stiffness of chain `chain` (0 or 1) in units of C1."""
        return 1.0 if chain == 0 else self.rho

    def typed(self) -> "ChainSystem":
        """This record with the field types the compiled kernels are compiled for (int n and n_chains,
        bool clamped and pinned, float the rest), so that a numpy integer or an integer sigma does not
        compile a second specialisation. The solvers call it on every record they are given."""
        if int(self.n) != self.n or self.n < 1:
            raise ParameterError(f"n (particles per chain) must be an integer >= 1, got {self.n!r}")
        if self.n_chains not in (1, 2):
            raise ParameterError(f"n_chains must be 1 or 2, got {self.n_chains!r}")
        if self.pinned and self.n_chains != 1:
            raise ParameterError("pinned: only a single chain can be held at both ends")
        if not (self.mass_ratio >= 0 and np.isfinite(self.mass_ratio)):
            raise ParameterError(f"mass_ratio must be finite and >= 0 (0: overdamped), got {self.mass_ratio!r}")
        if not (self.inertia_factor >= 0 and np.isfinite(self.inertia_factor)):
            raise ParameterError(f"inertia_factor must be finite and >= 0, got {self.inertia_factor!r}")
        return ChainSystem(
            n=int(self.n), n_chains=int(self.n_chains), clamped=bool(self.clamped), pinned=bool(self.pinned),
            sigma=float(self.sigma), gamma_l=float(self.gamma_l), gamma_t=float(self.gamma_t),
            kappa=float(self.kappa), rho=float(self.rho), delta=float(self.delta),
            mass_ratio=float(self.mass_ratio), inertia_factor=float(self.inertia_factor),
        )

    def force_factors(self, factor=None) -> np.ndarray:
        """Per-particle force factors (1 + eta_i) as a float array of n_angles entries (default: ones)."""
        if factor is None:
            return np.ones(self.n_angles)
        fac = np.ascontiguousarray(factor, dtype=float).reshape(-1)
        if fac.size != self.n_angles:
            raise ParameterError(f"factor must have {self.n_angles} entries (one per particle), got {fac.size}")
        return fac

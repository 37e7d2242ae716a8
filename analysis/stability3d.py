r"""Linear stability of the straight clamped chain in three dimensions (reduced 3D model, l = C = gamma_T = 1).

About the straight chain t_k = e_x, a small shape is t_k = e_x + y_k e_y + z_k e_z (the basis of the reduced 3D model,
elastoactive.reduced.chain3d, is (a_k, b_k) = (e_y, e_z) there), and the linear dynamics of q = (y_1..y_N, z_1..z_N) is

    q' = A3 q,    A3 = [[A, 0], [0, A]],    A = -D0^-1 (K - sigma S)   (the planar operator, analysis.stability)

because every matrix of the model is isotropic across the axis at the straight state: the drag tensor of a particle
moving across its link is gamma_T (gamma_L does not enter at linear order, as in the plane), the bending energy
C/2 phi^2 is C/2 (|dy|^2 + |dz|^2) to second order, and the follower forces' transverse part is -sigma times the
transverse tangent, the same for y and z. So the spectrum is the planar one twice: an in-plane branch (the y block) and
an out-of-plane branch (the z block), degenerate eigenvalue for eigenvalue, and the onset is the planar onset sigma_c(N)
with the same frequency; at onset two complex pairs cross together, whose combinations are a beat in any plane through
the axis and a whirl either way (which one the chain takes is decided beyond linear order: docs/model3d.md, section 6).

`linear_operator3d` does not assume this: it differentiates the reduced 3D right-hand side numerically (central
differences) at the straight chain, for any drag ratio, and `branches` splits its spectrum into the two blocks and
reports the coupling between them; `onset3d` finds the onset from the whole 2N x 2N operator. Pure functions.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from contextvars import ContextVar
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..reduced.chain3d import Chain3D, rhs
from . import stability

__all__ = ["Branches", "STEP", "branches", "exact_operator3d", "linear_operator3d", "onset3d"]

STEP = 1e-6
"""Central-difference step of linear_operator3d (its error ~ STEP^2 x the third derivative + round-off / STEP: ~1e-10
relative)."""


def linear_operator3d(n: int, sigma: float, gamma_l: float = 1.0, clamped: bool = True) -> np.ndarray:
    """A3 (2N x 2N) with q' = A3 q about the straight chain, q = (y_1..y_N, z_1..z_N): the central-difference
    Jacobian of the reduced 3D right-hand side (elastoactive.reduced.chain3d.rhs) in the tangents' transverse parts."""
    n = int(n)
    chain = Chain3D(n=n, sigma=float(sigma), gamma_l=float(gamma_l), clamped=bool(clamped)).checked()
    straight = np.tile([1.0, 0.0, 0.0], (n, 1))
    operator = np.empty((2 * n, 2 * n))
    for block, axis in enumerate((1, 2)):
        for k in range(n):
            columns = []
            for sign in (1.0, -1.0):
                t = straight.copy()
                t[k, axis] = sign * STEP
                t[k] /= np.linalg.norm(t[k])
                v = rhs(t, chain)
                columns.append(np.concatenate([v[:, 1], v[:, 2]]))
            operator[:, block * n + k] = (columns[0] - columns[1]) / (2.0 * STEP)
    return operator


def exact_operator3d(n: int, sigma: float) -> np.ndarray:
    """The analytic A3 = diag(A, A), A the planar operator (analysis.stability.linear_operator)."""
    a = stability.linear_operator(n, sigma)
    zero = np.zeros_like(a)
    return np.block([[a, zero], [zero, a]])


@dataclass(frozen=True)
class Branches:
    """The spectrum of A3 split by block, each sorted by decreasing real part."""

    in_plane: np.ndarray
    """Eigenvalues of the y block (motion in the plane of e_x and e_y)."""
    out_of_plane: np.ndarray
    """Eigenvalues of the z block."""
    coupling: float
    """Largest entry of the off-diagonal blocks over the largest entry of A3: 0 when the branches are independent."""

    @property
    def splitting(self) -> float:
        """Largest |in-plane - out-of-plane| eigenvalue difference over the largest |eigenvalue|: 0 when degenerate."""
        return float(np.max(np.abs(self.in_plane - self.out_of_plane)) / np.max(np.abs(self.in_plane)))


def _sorted(lam: np.ndarray) -> np.ndarray:
    return lam[np.lexsort((-lam.imag, -lam.real))]


def branches(n: int, sigma: float, gamma_l: float = 1.0, clamped: bool = True) -> Branches:
    """The in-plane and out-of-plane branches of the straight chain's spectrum (linear_operator3d)."""
    a3 = linear_operator3d(n, sigma, gamma_l, clamped)
    n = int(n)
    coupling = max(np.abs(a3[:n, n:]).max(), np.abs(a3[n:, :n]).max()) / np.abs(a3).max()
    return Branches(_sorted(np.linalg.eigvals(a3[:n, :n])), _sorted(np.linalg.eigvals(a3[n:, n:])), float(coupling))


ONSET_EVALUATIONS = 14
"""About how many operators (linear_operator3d, then its eigenvalues) onset3d's search builds: the bracket's two ends,
brentq's ~10 iterations to xtol 1e-14, the last."""
ON_COST: ContextVar[Callable[[str, float], None] | None] = ContextVar("onset cost", default=None)
"""Told (what, estimated seconds) by onset3d once its first operator is timed (a caller's announcement of the search's
cost: elastoactive stability); None: nobody asks."""


def onset3d(n: int, gamma_l: float = 1.0) -> tuple[float, float]:
    """(sigma_c, omega_c) where the largest real part of the whole A3 crosses zero (brentq, bracketed around the planar
    onset: the 3D onset is found, not assumed), and |Im lambda| there. ON_COST, when set, is told the search's
    estimated wall time (ONSET_EVALUATIONS times its first operator's) before the rest of it runs."""
    n = int(n)
    planar, _ = stability.critical_sigma(n)

    def growth(sigma: float) -> float:
        return float(np.max(np.linalg.eigvals(linear_operator3d(n, sigma, gamma_l)).real))

    lo, hi = 0.8 * planar, 1.25 * planar
    start = time.perf_counter()
    low = growth(lo)
    told = ON_COST.get()
    if told is not None:
        told(f"the 3D onset of N = {n}", ONSET_EVALUATIONS * (time.perf_counter() - start))
    if not (low < 0 < growth(hi)):
        raise RuntimeError(f"3D onset of N = {n} not bracketed by [{lo:g}, {hi:g}]")
    sigma_c = brentq(growth, lo, hi, xtol=1e-14, rtol=1e-12)
    lam = np.linalg.eigvals(linear_operator3d(n, sigma_c, gamma_l))
    return float(sigma_c), float(abs(lam[np.argmax(lam.real)].imag))

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

On a free ball pivot (no clamp spring) K_11 = 1 instead of 2, so each block is A + D0^-1 e_1 e_1^T, and
D0^-1 e_1 = e_1 - e_2 (D0 = B^T B, B the lower triangular matrix of ones): the planar rotating pin's operator, whose
rigid turn (eigenvalue 0) analysis.stability.rotating_operator factors out.

So the analysis costs what the planar one does: linear_operator3d is built from the planar block (planar_operator),
onset3d is the planar onset (analysis.stability.onset: O(N) per sigma), fastest_rate3d the planar block's. The
degeneracy is checked, not only assumed: numerical_operator3d differentiates the reduced 3D right-hand side
numerically (central differences, 2N evaluations) at the straight chain, for any drag ratio, `branches` splits its
spectrum into the two blocks and reports the coupling between them, and searched_onset3d finds the onset from the whole
numerical 2N x 2N operator (tests/analysis/test_stability3d.py holds them against the planar ones at small N). Pure
functions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from . import stability

__all__ = [
    "Branches",
    "STEP",
    "branches",
    "fastest_rate3d",
    "linear_operator3d",
    "numerical_operator3d",
    "onset3d",
    "planar_operator",
    "searched_onset3d",
]

STEP = 1e-6
"""Central-difference step of numerical_operator3d (its error ~ STEP^2 x the third derivative + round-off / STEP:
~1e-10 relative)."""


def planar_operator(n: int, sigma: float, clamped: bool = True) -> np.ndarray:
    """A (N x N), one block of A3: the planar clamped chain's operator (analysis.stability.linear_operator), or on a
    free ball pivot (clamped False) the same without the clamp spring, A + (e_1 - e_2) e_1^T (the module docstring)."""
    a = stability.linear_operator(n, sigma)
    if not clamped:
        a[0, 0] += 1.0
        if a.shape[0] > 1:
            a[1, 0] -= 1.0
    return a


def linear_operator3d(n: int, sigma: float, gamma_l: float = 1.0, clamped: bool = True) -> np.ndarray:
    """A3 (2N x 2N) with q' = A3 q about the straight chain, q = (y_1..y_N, z_1..z_N): diag(A, A), A = planar_operator.
    The drag ratio gamma_l does not enter at linear order (numerical_operator3d shows it for any)."""
    a = planar_operator(n, sigma, clamped)
    zero = np.zeros_like(a)
    return np.block([[a, zero], [zero, a]])


def numerical_operator3d(n: int, sigma: float, gamma_l: float = 1.0, clamped: bool = True) -> np.ndarray:
    """A3 (2N x 2N) as the central-difference Jacobian of the reduced 3D right-hand side
    (elastoactive.reduced.chain3d.rhs) in the tangents' transverse parts: 2N evaluations, each O(N^3); the
    independent check of linear_operator3d."""
    from ..reduced.chain3d import Chain3D, rhs  # engine boundary: the compiled 3D model (numba)

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
    """The in-plane and out-of-plane branches of the straight chain's spectrum, from numerical_operator3d (the check
    that they are the planar block's twice)."""
    a3 = numerical_operator3d(n, sigma, gamma_l, clamped)
    n = int(n)
    coupling = max(np.abs(a3[:n, n:]).max(), np.abs(a3[n:, :n]).max()) / np.abs(a3).max()
    return Branches(_sorted(np.linalg.eigvals(a3[:n, :n])), _sorted(np.linalg.eigvals(a3[n:, n:])), float(coupling))


def onset3d(n: int, gamma_l: float = 1.0) -> tuple[float, float]:
    """(sigma_c, omega_c) of the straight clamped 3D chain: the planar onset (analysis.stability.onset, O(N) per
    sigma), where the in-plane and out-of-plane pairs cross together; the drag ratio gamma_l does not enter
    (searched_onset3d finds it again from the numerical 3D operator)."""
    return stability.onset(int(n))


def searched_onset3d(n: int, gamma_l: float = 1.0) -> tuple[float, float]:
    """(sigma_c, omega_c) where the largest real part of the whole numerical A3 (numerical_operator3d) crosses zero
    (brentq, bracketed around the planar onset: the 3D onset found, not assumed), and |Im lambda| there. About 14
    numerical operators of 2N right-hand sides each, O(N^4) in all: for small N (a second at N = 60)."""
    n = int(n)
    planar, _ = stability.critical_sigma(n)

    def growth(sigma: float) -> float:
        return float(np.max(np.linalg.eigvals(numerical_operator3d(n, sigma, gamma_l)).real))

    lo, hi = 0.8 * planar, 1.25 * planar
    if not (growth(lo) < 0 < growth(hi)):
        raise RuntimeError(f"3D onset of N = {n} not bracketed by [{lo:g}, {hi:g}]")
    sigma_c = brentq(growth, lo, hi, xtol=1e-14, rtol=1e-12)
    lam = np.linalg.eigvals(numerical_operator3d(n, sigma_c, gamma_l))
    return float(sigma_c), float(abs(lam[np.argmax(lam.real)].imag))


def fastest_rate3d(n: int, sigma: float, clamped: bool = True) -> float:
    """The largest |eigenvalue| of A3, 1/tau: the planar block's (each of its eigenvalues is A3's twice)."""
    return float(np.abs(np.linalg.eigvals(planar_operator(n, sigma, clamped))).max())

r"""Linear stability of straight chains coupled through the fluid (elastoactive.reduced.fluid; l = C = gamma = 1).

About straight chains (every tangent t_ck = e_x in its chain's frame), a small shape is t_ck = e_x + y_ck e_y +
z_ck e_z, and the reduced equations J^T M^-1 J q' = r, r = J^T F - dU/dq, linearise to

    q' = L(sigma) q,    L(sigma) = -G (H - sigma S),    G = (J^T M^-1 J)^-1 at the straight chains,

q ordered (y of every chain's links, chain by chain, then z likewise): r vanishes at the straight state (the follower
forces lie along the links, the bending and the tips' springs are relaxed), so only G at the straight state enters,
and r's linear part is the local drag's, -(K - sigma S) on each chain and in each plane (analysis.stability's K, the
bending with the clamp spring, and S, the follower forces), plus the tips' springs, whose energy K_t/2 |tip_c -
tip_c+1|^2 adds K_t 1 1^T blocks (the tip's displacement is the sum of its chain's y, or z). H - sigma S is
block-diagonal; all the fluid does is G, the mobility of the links' transverse motions, which does not depend on sigma
(nor on the chains' state but through the straight geometry): one G per scene, then each sigma costs one eigenvalue
problem of the 2CN x 2CN operator.

Symmetry. For one straight chain in free space the RPY mobility of collinear beads is a(r) 1 + b(r) e e^T with e the
axis, so G has no coupling between the y and z planes and the same block in each: the in-plane / out-of-plane
degeneracy of the 3D chain survives exactly. Above a wall with the chain along the normal, the wall's image system is
invariant under rotations about the normal through the beads, so the same holds there. Chains side by side (a pair, a
row along the lab's x) keep only the mirror symmetry across their common plane: the planes still decouple (the lab's
y -> -y flips the out-of-plane motion alone), but their blocks differ, and the onset is the first block's.

`mobility_operator` builds G from reduced.fluid.mobility_matrix (the compiled mobilities); `numerical_operator`
differentiates the compiled right-hand side (reduced.fluid.rhs) by central differences, the independent check (the
tests hold them equal); `onset_fluid` finds where the largest real part of L crosses zero (a scan up from below the
local drag's onset, then brentq), `branches_fluid` splits the spectrum by plane. With the local drag (mobility
"local" or "identity") L is analysis.stability3d.linear_operator3d's, and as a / l -> 0 the RPY and RPB operators
tend to it (the interactions fall like a / r, the wall's like a / h): the clamped 3D chain's onset.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..core.errors import ParameterError
from . import stability, stability3d
from .flutter import follower_matrix

__all__ = [
    "FluidBranches",
    "STEP",
    "branches_fluid",
    "leading_eigenvalue_fluid",
    "linear_operator_fluid",
    "mobility_operator",
    "numerical_operator",
    "onset_fluid",
    "straight",
]

STEP = 1e-6
"""Central-difference step of numerical_operator (error ~ STEP^2 x the third derivative + round-off / STEP)."""


def straight(beds) -> np.ndarray:
    """The straight chains' tangents (C, N, 3): every link along its chain's clamp axis e_x."""
    t = np.zeros((beds.chains, beds.n, 3))
    t[..., 0] = 1.0
    return t


def _index(beds) -> np.ndarray:
    """Positions in q (axis, chain, link) of the kernel's link coordinates (chain, link, axis), flattened."""
    c, n = beds.chains, beds.n
    return np.arange(2 * c * n).reshape(2, c, n).transpose(1, 2, 0).ravel()


def mobility_operator(beds) -> np.ndarray:
    """G (2CN x 2CN): (J^T M^-1 J)^-1 at the straight chains, q ordered as the module docstring's (the basis of each
    straight link is (e_y, e_z) of its chain's frame, reduced.chain3d.basis_of)."""
    from ..reduced.fluid import lab_positions, mobility_matrix  # engine boundary: the compiled mobilities (numba)

    beds = beds.checked()
    c, n = beds.chains, beds.n
    t = straight(beds)
    rot = np.asarray(beds.rotation, dtype=float)
    positions = lab_positions(t, beds).reshape(-1, 3)
    m = mobility_matrix(positions, t.reshape(-1, 3) @ rot.T, beds)
    frame = rot[:, 1:]  # lab images of the chain frame's e_y, e_z
    jac = np.zeros((3 * c * n, 2 * c * n))
    for chain in range(c):
        for k in range(n):
            for i in range(k, n):
                row, col = 3 * (chain * n + i), 2 * (chain * n + k)
                jac[row : row + 3, col : col + 2] = frame
    resistance = jac.T @ np.linalg.solve(m, jac)
    g = np.linalg.inv(resistance)
    g = 0.5 * (g + g.T)  # symmetric by construction: round-off removed
    order = _index(beds)
    out = np.empty_like(g)
    out[np.ix_(order, order)] = g
    return out


def _stiffness(beds, sigma: float) -> np.ndarray:
    """H - sigma S (2CN x 2CN) of the module docstring: the local drag's K - sigma S on each chain in each plane
    (D0 times the planar operator, analysis.stability3d.planar_operator), the tips' springs added."""
    c, n = beds.chains, beds.n
    idx = np.arange(1, n + 1)
    d0 = (n - np.maximum(idx[:, None], idx[None, :]) + 1).astype(float)  # B^T B: the local drag of the links
    block = -d0 @ stability3d.planar_operator(n, sigma, beds.clamped)
    h = np.kron(np.eye(2 * c), block)
    if beds.tip_coupling:
        ones = np.ones((n, n)) * beds.tip_coupling
        for axis in range(2):
            for chain in range(c - 1):
                a = slice((axis * c + chain) * n, (axis * c + chain + 1) * n)
                b = slice((axis * c + chain + 1) * n, (axis * c + chain + 2) * n)
                h[a, a] += ones
                h[b, b] += ones
                h[a, b] -= ones
                h[b, a] -= ones
    return h


def linear_operator_fluid(beds, sigma: float, mobility: np.ndarray | None = None) -> np.ndarray:
    """L(sigma) (2CN x 2CN) with q' = L q about the straight chains: -G (H - sigma S); mobility: G when already
    built (mobility_operator(beds): it does not depend on sigma)."""
    g = mobility_operator(beds) if mobility is None else mobility
    return -g @ _stiffness(beds, float(sigma))


def numerical_operator(beds, sigma: float | None = None) -> np.ndarray:
    """L (2CN x 2CN) as the central-difference Jacobian of the compiled right-hand side (reduced.fluid.rhs) in the
    tangents' transverse parts, at beds.sigma (or `sigma`): 4CN evaluations; the independent check of
    linear_operator_fluid."""
    from ..reduced.fluid import rhs  # engine boundary: the compiled model (numba)

    beds = beds.checked() if sigma is None else beds._replace(sigma=float(sigma)).checked()
    c, n = beds.chains, beds.n
    base = straight(beds)
    operator = np.empty((2 * c * n, 2 * c * n))
    for axis in (1, 2):
        for chain in range(c):
            for k in range(n):
                columns = []
                for sign in (1.0, -1.0):
                    t = base.copy()
                    t[chain, k, axis] = sign * STEP
                    t[chain, k] /= np.linalg.norm(t[chain, k])
                    v = rhs(t, beds)
                    columns.append(np.concatenate([v[..., 1].ravel(), v[..., 2].ravel()]))
                operator[:, ((axis - 1) * c + chain) * n + k] = (columns[0] - columns[1]) / (2.0 * STEP)
    return operator


def _sorted(lam: np.ndarray) -> np.ndarray:
    return lam[np.lexsort((-lam.imag, -lam.real))]


@dataclass(frozen=True)
class FluidBranches:
    """The spectrum of L split by plane (the chain frame's y block and z block), each sorted by decreasing real
    part."""

    in_plane: np.ndarray
    """Eigenvalues of the y block (motion in the plane of the clamp axis and e_y: the lab's xz plane for cilia)."""
    out_of_plane: np.ndarray
    """Eigenvalues of the z block."""
    coupling: float
    """Largest entry of L's off-diagonal blocks over its largest entry: 0 when the planes are independent."""

    @property
    def splitting(self) -> float:
        """Largest |in-plane - out-of-plane| eigenvalue difference over the largest |eigenvalue|: 0 when degenerate."""
        return float(np.max(np.abs(self.in_plane - self.out_of_plane)) / np.max(np.abs(self.in_plane)))


def branches_fluid(operator: np.ndarray) -> FluidBranches:
    """The planes' branches of an operator L (linear_operator_fluid's or numerical_operator's)."""
    half = operator.shape[0] // 2
    coupling = max(np.abs(operator[:half, half:]).max(), np.abs(operator[half:, :half]).max()) / np.abs(operator).max()
    return FluidBranches(
        _sorted(np.linalg.eigvals(operator[:half, :half])),
        _sorted(np.linalg.eigvals(operator[half:, half:])),
        float(coupling),
    )


def leading_eigenvalue_fluid(beds, sigma: float, mobility: np.ndarray | None = None) -> complex:
    """The eigenvalue of L(sigma) with the largest real part (the larger imaginary part of a pair)."""
    return complex(_sorted(np.linalg.eigvals(linear_operator_fluid(beds, sigma, mobility)))[0])


def onset_fluid(beds, tol: float = 1e-12) -> tuple[float, float]:
    """(sigma_c, omega_c): the first sigma where the largest real part of L(sigma) crosses zero, and |Im lambda| there.

    G is built once; the bracket is a geometric scan upward from a quarter of the local drag's onset (the planar
    chain's, analysis.stability.onset), then brentq. Raises ParameterError when the chains are stable up to 1e4 times
    that onset (no follower force exerts a torque: N = 1)."""
    beds = beds.checked()
    n = beds.n
    if n < 2 or not np.any(follower_matrix(n)):
        raise ParameterError(f"n = {n}: a chain of one link has no flutter onset")
    g = mobility_operator(beds)

    def growth(sigma: float) -> float:
        return float(np.max(np.linalg.eigvals(linear_operator_fluid(beds, sigma, g)).real))

    local = stability.onset(n)[0]
    lo = 0.25 * local
    while growth(lo) >= 0:
        lo /= 4.0
    hi = lo
    while growth(hi) < 0:
        lo, hi = hi, 1.25 * hi
        if hi > 1e4 * local:
            raise ParameterError(f"the chains (N = {n}) are stable up to sigma = {hi:.3g}: no onset")
    sigma_c = brentq(growth, lo, hi, xtol=1e-300, rtol=tol, maxiter=200)
    return float(sigma_c), float(abs(leading_eigenvalue_fluid(beds, sigma_c, g).imag))

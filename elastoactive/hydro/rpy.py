"""The free-space Rotne-Prager-Yamakawa mobility of n beads, with the overlap correction.

Units are the paper's: lengths in l (the link length), forces in units whose drag of one bead gamma = 6 pi mu a is 1,
so a mobility is dimensionless and an isolated bead's self-mobility is the identity. The bead radius `radius` = a / l
is the one parameter. For beads i != j at separation r = x_i - x_j (|r| = r, rhat = r / r):

    r >= 2a:  M_ij = (3a / 4r) [ (1 + 2a^2 / 3r^2) I + (1 - 2a^2 / r^2) rhat rhat^T ]
    r <  2a:  M_ij = (1 - 9r / 32a) I + (3r / 32a) rhat rhat^T
    M_ii = I

(Rotne and Prager 1969; Yamakawa 1970; the overlap form as in Wajnryb, Mizerski, Zuk and Szymczak, J. Fluid Mech.
2013). The two forms meet at r = 2a (both 7/16 I + 3/16 rhat rhat^T) and M_ij -> I as r -> 0. The 3n x 3n matrix
is symmetric and positive definite for every configuration of distinct beads, overlapping or not: it is the average
of the Oseen tensor over two spheres' surfaces, a Gram matrix. Two beads at one point make it singular (equal and
opposite forces on them move nothing), never indefinite. The matrix's row block i, column block j (rows 3i..3i+2,
columns 3j..3j+2) is M_ij: the velocity of bead i is sum_j M_ij F_j.

`rpy` is the readable reference (numpy, whole arrays); `rpy_into` the compiled twin that writes into a preallocated
array, built for the solver's right-hand side; the tests hold them equal.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..core.errors import ParameterError


def check_positions(positions, name: str = "positions") -> np.ndarray:
    """`positions` as a float64 array of shape (n, 3), n >= 1, all finite; ParameterError naming it otherwise."""
    p = np.asarray(positions, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3 or p.shape[0] < 1:
        raise ParameterError(f"{name} must have shape (n, 3) with n >= 1, got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ParameterError(f"{name} must be finite")
    return np.ascontiguousarray(p)


def check_radius(radius) -> float:
    """The bead radius a / l as a float, finite and > 0; ParameterError naming `radius` otherwise."""
    a = float(radius)
    if not (np.isfinite(a) and a > 0.0):
        raise ParameterError(f"radius (the bead radius a / l) must be finite and > 0, got {radius!r}")
    return a


def check_out(out, n: int) -> None:
    """`out` must be a C-contiguous float64 array of shape (3n, 3n) to be written into."""
    if not (
        isinstance(out, np.ndarray)
        and out.dtype == np.float64
        and out.shape == (3 * n, 3 * n)
        and out.flags.c_contiguous
        and out.flags.writeable
    ):
        raise ParameterError(f"out must be a writeable C-contiguous float64 array of shape ({3 * n}, {3 * n})")


def pair_coefficients(r: np.ndarray, a: float) -> tuple[np.ndarray, np.ndarray]:
    """(c_I, c_rr) with M_ij = c_I I + c_rr rhat rhat^T at separations r > 0 (arrays), radius a."""
    r = np.asarray(r, dtype=float)
    far = r >= 2.0 * a
    with np.errstate(divide="ignore", invalid="ignore"):
        c_i = np.where(far, 0.75 * a / r * (1.0 + 2.0 * a**2 / (3.0 * r**2)), 1.0 - 9.0 * r / (32.0 * a))
        c_rr = np.where(far, 0.75 * a / r * (1.0 - 2.0 * a**2 / r**2), 3.0 * r / (32.0 * a))
    return c_i, c_rr


def rpy(positions, radius) -> np.ndarray:
    """The free-space RPY mobility (3n, 3n) of beads at `positions` (n, 3), radius a / l = `radius`; the reference."""
    x = check_positions(positions)
    a = check_radius(radius)
    n = len(x)
    d = x[:, None, :] - x[None, :, :]  # d[i, j] = x_i - x_j
    r = np.linalg.norm(d, axis=-1)
    off = ~np.eye(n, dtype=bool)
    c_i, c_rr = np.ones((n, n)), np.zeros((n, n))
    c_i[off], c_rr[off] = pair_coefficients(r[off], a)
    c_rr[~(r > 0.0)] = 0.0
    apart = r > 0.0  # coincident beads (r = 0) have the self block, I: no direction
    rhat = np.zeros_like(d)
    rhat[apart] = d[apart] / r[apart][:, None]
    blocks = c_i[:, :, None, None] * np.eye(3) + c_rr[:, :, None, None] * rhat[..., :, None] * rhat[..., None, :]
    return blocks.transpose(0, 2, 1, 3).reshape(3 * n, 3 * n)


@njit(cache=True)
def rpy_pair(dx, dy, dz, a, block):
    """The RPY pair block M_ij for separation (dx, dy, dz) = x_i - x_j, written into block (3, 3); at zero separation
    the self block, the identity (the overlap form's limit)."""
    r2 = dx * dx + dy * dy + dz * dz
    if r2 == 0.0:
        for p in range(3):
            for q in range(3):
                block[p, q] = 1.0 if p == q else 0.0
        return
    r = np.sqrt(r2)
    if r >= 2.0 * a:
        s = 0.75 * a / r
        c_i = s * (1.0 + 2.0 * a * a / (3.0 * r2))
        c_rr = s * (1.0 - 2.0 * a * a / r2) / r2
    else:
        c_i = 1.0 - 9.0 * r / (32.0 * a)
        c_rr = 3.0 / (32.0 * a * r)
    block[0, 0] = c_i + c_rr * dx * dx
    block[1, 1] = c_i + c_rr * dy * dy
    block[2, 2] = c_i + c_rr * dz * dz
    block[0, 1] = block[1, 0] = c_rr * dx * dy
    block[0, 2] = block[2, 0] = c_rr * dx * dz
    block[1, 2] = block[2, 1] = c_rr * dy * dz


@njit(cache=True)
def rpy_kernel(x, a, out):
    """Fill out (3n, 3n) with the RPY mobility of positions x (n, 3); pairs at zero separation get the self block."""
    n = x.shape[0]
    block = np.empty((3, 3))
    for i in range(n):
        for p in range(3):
            for q in range(3):
                out[3 * i + p, 3 * i + q] = 1.0 if p == q else 0.0
        for j in range(i + 1, n):
            dx = x[i, 0] - x[j, 0]
            dy = x[i, 1] - x[j, 1]
            dz = x[i, 2] - x[j, 2]
            rpy_pair(dx, dy, dz, a, block)
            for p in range(3):
                for q in range(3):
                    out[3 * i + p, 3 * j + q] = block[p, q]
                    out[3 * j + q, 3 * i + p] = block[p, q]


@njit(cache=True)
def rpy_cross_kernel(x, y, a, out):
    """Fill out (3n, 3m) with the blocks M_ij between beads x (n, 3) and other beads y (m, 3): rpy_kernel's
    off-diagonal blocks for the beads x then y, for kernels that build the mobility in pieces."""
    block = np.empty((3, 3))
    for i in range(x.shape[0]):
        for j in range(y.shape[0]):
            dx = x[i, 0] - y[j, 0]
            dy = x[i, 1] - y[j, 1]
            dz = x[i, 2] - y[j, 2]
            rpy_pair(dx, dy, dz, a, block)
            for p in range(3):
                for q in range(3):
                    out[3 * i + p, 3 * j + q] = block[p, q]


def rpy_into(positions, radius, out: np.ndarray) -> np.ndarray:
    """Write the free-space RPY mobility of `positions` (n, 3) into `out` (3n, 3n, float64, C-contiguous); returns
    out. The compiled twin of `rpy`, for calls at every right-hand-side evaluation."""
    x = check_positions(positions)
    a = check_radius(radius)
    check_out(out, len(x))
    rpy_kernel(x, a, out)
    return out

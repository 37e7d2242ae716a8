"""The Rotne-Prager-Blake mobility of n beads above a no-slip plane wall at z = 0 (the fluid fills z > 0).

Units as elastoactive.hydro.rpy: lengths in l, the drag of one bead 6 pi mu a = 1, the bead radius a / l = `radius`.
M = M_RPY + M_wall, the free-space RPY mobility (with its overlap correction) plus the wall's part, Blake's image
system (Blake 1971) with the finite-size corrections of Swan and Brady (Phys. Fluids 19, 113306, 2007). In units of
a, for the velocity of bead i under a force on bead j (i != j) with R = (x_i - x_j, y_i - y_j, z_i + z_j) / a (the
separation from j's mirror image), rho = |R|, e = R / rho, c = e_z and hh = z_j / (z_i + z_j):

    M_wall_ij = A I + B e e^T + C e zhat^T + D zhat e^T + E zhat zhat^T
    A = -[3 (1 + 2 hh (1 - hh) c^2) / rho + 2 (1 - 3 c^2) / rho^3 - 2 (1 - 5 c^2) / rho^5] / 4
    B = -[3 (1 - 6 hh (1 - hh) c^2) / rho - 6 (1 - 5 c^2) / rho^3 + 10 (1 - 7 c^2) / rho^5] / 4
    C = c [3 hh (1 - 6 (1 - hh) c^2) / rho - 6 (1 - 5 c^2) / rho^3 + 10 (2 - 7 c^2) / rho^5] / 2
    D = c [3 hh / rho - 10 / rho^5] / 2
    E = -[3 hh^2 c^2 / rho + 3 c^2 / rho^3 + (2 - 15 c^2) / rho^5]

and for one bead at height h (H = h / a), the limit of the above as bead j reaches bead i:

    M_wall_ii = -(9 / 16H - 1 / 8H^3 + 1 / 16H^5) (I - zhat zhat^T) - (9 / 8H - 1 / 2H^3 + 1 / 8H^5) zhat zhat^T

so the self-mobility is the parallel series 1 - 9/16 (a/h) + 1/8 (a/h)^3 - 1/16 (a/h)^5 (Faxen's, without its
-45/256 (a/h)^4 term) and the perpendicular 1 - 9/8 (a/h) + 1/2 (a/h)^3 - 1/8 (a/h)^5 (Lorentz's leading term; 19%
above Brenner's exact value at h = 1.54a, 0.9% at 3a). The matrix is symmetric (M_ij = M_ji^T).

Validity. The tensor is positive definite for beads that overlap neither the wall (every height h >= a) nor each
other (every separation >= 2a). For beads overlapping each other at heights >= a no counterexample was found
(tests/hydro/test_blake.py and the searches docs/hydrodynamics.md lists), but that is not a theorem. A bead that
overlaps the wall (0 < h < a) is taken as in Swan and Brady's successors' codes (RigidMultiblobsWall, libMobility):
the mobility is evaluated at the effective height max(h, a) and scaled by b = min(h / a, 1) on both sides,
M = B M(h_eff) B with B = diag(b_i), which keeps it symmetric positive definite and makes it vanish as the bead
reaches the wall (no slip); the series alone turn negative below h = 0.64a. A bead at or below the wall (h <= 0)
is refused.

`rpb` is the readable reference (numpy); `rpb_into` the compiled twin writing into a preallocated array; the tests
hold them equal.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..core.errors import ParameterError
from .rpy import check_out, check_positions, check_radius, rpy, rpy_pair


def check_above_wall(x: np.ndarray) -> None:
    """Every bead centre above the wall (z > 0); ParameterError naming the first that is not."""
    below = np.flatnonzero(~(x[:, 2] > 0.0))
    if below.size:
        i = int(below[0])
        raise ParameterError(
            f"positions: bead {i} has height z = {x[i, 2]:g} <= 0; the wall is z = 0 and the fluid z > 0"
        )


def wall_self(h, a):
    """(parallel, perpendicular) wall corrections of one bead's self-mobility at height h (array or float)."""
    s = a / np.asarray(h, dtype=float)
    parallel = -(9.0 / 16.0 * s - 1.0 / 8.0 * s**3 + 1.0 / 16.0 * s**5)
    perpendicular = -(9.0 / 8.0 * s - 1.0 / 2.0 * s**3 + 1.0 / 8.0 * s**5)
    return parallel, perpendicular


def wall_pair(xi: np.ndarray, xj: np.ndarray, a: float) -> np.ndarray:
    """The wall's part (3, 3) of the velocity of bead i under a force on bead j != i (Swan and Brady's form)."""
    big_r = np.array([xi[0] - xj[0], xi[1] - xj[1], xi[2] + xj[2]]) / a
    rho = np.linalg.norm(big_r)
    e = big_r / rho
    c = e[2]
    hh = xj[2] / (xi[2] + xj[2])
    r1, r3, r5 = 1.0 / rho, 1.0 / rho**3, 1.0 / rho**5
    coef_a = -(3 * (1 + 2 * hh * (1 - hh) * c**2) * r1 + 2 * (1 - 3 * c**2) * r3 - 2 * (1 - 5 * c**2) * r5) / 4
    coef_b = -(3 * (1 - 6 * hh * (1 - hh) * c**2) * r1 - 6 * (1 - 5 * c**2) * r3 + 10 * (1 - 7 * c**2) * r5) / 4
    coef_c = c * (3 * hh * (1 - 6 * (1 - hh) * c**2) * r1 - 6 * (1 - 5 * c**2) * r3 + 10 * (2 - 7 * c**2) * r5) / 2
    coef_d = c * (3 * hh * r1 - 10 * r5) / 2
    coef_e = -(3 * hh**2 * c**2 * r1 + 3 * c**2 * r3 + (2 - 15 * c**2) * r5)
    z = np.array([0.0, 0.0, 1.0])
    return (
        coef_a * np.eye(3)
        + coef_b * np.outer(e, e)
        + coef_c * np.outer(e, z)
        + coef_d * np.outer(z, e)
        + coef_e * np.outer(z, z)
    )


def rpb(positions, radius) -> np.ndarray:
    """The Rotne-Prager-Blake mobility (3n, 3n) above the wall z = 0 of beads at `positions` (n, 3), z > 0, radius
    a / l = `radius`; the reference."""
    x = check_positions(positions)
    a = check_radius(radius)
    check_above_wall(x)
    scale = np.minimum(x[:, 2] / a, 1.0)  # b_i: 1 for a bead clear of the wall, h / a for one overlapping it
    x_eff = x.copy()
    x_eff[:, 2] = np.maximum(x[:, 2], a)
    m = rpy(x_eff, a)
    n = len(x)
    parallel, perpendicular = wall_self(x_eff[:, 2], a)
    for i in range(n):
        m[3 * i : 3 * i + 3, 3 * i : 3 * i + 3] += np.diag([parallel[i], parallel[i], perpendicular[i]])
        for j in range(n):
            if j != i:
                m[3 * i : 3 * i + 3, 3 * j : 3 * j + 3] += wall_pair(x_eff[i], x_eff[j], a)
    b = np.repeat(scale, 3)
    return b[:, None] * m * b[None, :]


@njit(cache=True)
def wall_pair_into(xi0, xi1, xi2, xj0, xj1, xj2, a, block):
    """Add the wall's part of M_ij (bead i's velocity under bead j's force, i != j) to block (3, 3)."""
    rx = (xi0 - xj0) / a
    ry = (xi1 - xj1) / a
    rz = (xi2 + xj2) / a
    rho = np.sqrt(rx * rx + ry * ry + rz * rz)
    r1 = 1.0 / rho
    r3 = r1 * r1 * r1
    r5 = r3 * r1 * r1
    ex = rx * r1
    ey = ry * r1
    c = rz * r1
    c2 = c * c
    hh = xj2 / (xi2 + xj2)
    k = hh * (1.0 - hh) * c2
    ca = -(3.0 * (1.0 + 2.0 * k) * r1 + 2.0 * (1.0 - 3.0 * c2) * r3 - 2.0 * (1.0 - 5.0 * c2) * r5) * 0.25
    cb = -(3.0 * (1.0 - 6.0 * k) * r1 - 6.0 * (1.0 - 5.0 * c2) * r3 + 10.0 * (1.0 - 7.0 * c2) * r5) * 0.25
    cc = c * (
        3.0 * hh * (1.0 - 6.0 * (1.0 - hh) * c2) * r1 - 6.0 * (1.0 - 5.0 * c2) * r3 + 10.0 * (2.0 - 7.0 * c2) * r5
    )
    cc *= 0.5
    cd = c * (3.0 * hh * r1 - 10.0 * r5) * 0.5
    ce = -(3.0 * hh * hh * c2 * r1 + 3.0 * c2 * r3 + (2.0 - 15.0 * c2) * r5)
    block[0, 0] += ca + cb * ex * ex
    block[1, 1] += ca + cb * ey * ey
    block[2, 2] += ca + cb * c2 + (cc + cd) * c + ce
    block[0, 1] += cb * ex * ey
    block[1, 0] += cb * ex * ey
    block[0, 2] += cb * ex * c + cc * ex
    block[2, 0] += cb * ex * c + cd * ex
    block[1, 2] += cb * ey * c + cc * ey
    block[2, 1] += cb * ey * c + cd * ey


@njit(cache=True)
def self_mobility(a, h):
    """(parallel, perpendicular): the self-mobility of a bead of radius a at height h above the wall, the Faxen /
    Lorentz series 1 - 9/16 s + 1/8 s^3 - 1/16 s^5 and 1 - 9/8 s + 1/2 s^3 - 1/8 s^5, s = a / h: 1 + wall_self's
    corrections, for the compiled kernels' self blocks."""
    s = a / h
    s3 = s * s * s
    s5 = s3 * s * s
    parallel = 1.0 - (9.0 / 16.0 * s - 1.0 / 8.0 * s3 + 1.0 / 16.0 * s5)
    perpendicular = 1.0 - (9.0 / 8.0 * s - 1.0 / 2.0 * s3 + 1.0 / 8.0 * s5)
    return parallel, perpendicular


@njit(cache=True)
def rpb_kernel(x, a, out):
    """Fill out (3n, 3n) with the Rotne-Prager-Blake mobility of positions x (n, 3), every z > 0."""
    n = x.shape[0]
    z = np.empty(n)
    b = np.empty(n)
    for i in range(n):
        z[i] = max(x[i, 2], a)
        b[i] = min(x[i, 2] / a, 1.0)
    block = np.empty((3, 3))
    for i in range(n):
        parallel, perpendicular = self_mobility(a, z[i])
        bb = b[i] * b[i]
        for p in range(3):
            for q in range(3):
                out[3 * i + p, 3 * i + q] = 0.0
        out[3 * i, 3 * i] = bb * parallel
        out[3 * i + 1, 3 * i + 1] = bb * parallel
        out[3 * i + 2, 3 * i + 2] = bb * perpendicular
        for j in range(i + 1, n):
            dx = x[i, 0] - x[j, 0]
            dy = x[i, 1] - x[j, 1]
            dz = z[i] - z[j]
            rpy_pair(dx, dy, dz, a, block)
            wall_pair_into(x[i, 0], x[i, 1], z[i], x[j, 0], x[j, 1], z[j], a, block)
            bb = b[i] * b[j]
            for p in range(3):
                for q in range(3):
                    out[3 * i + p, 3 * j + q] = bb * block[p, q]
                    out[3 * j + q, 3 * i + p] = bb * block[p, q]


@njit(cache=True)
def rpb_cross_kernel(x, y, a, out):
    """Fill out (3n, 3m) with the blocks M_ij between beads x (n, 3) and other beads y (m, 3), every z > 0:
    rpb_kernel's off-diagonal blocks for the beads x then y, for kernels that build the mobility in pieces."""
    block = np.empty((3, 3))
    for i in range(x.shape[0]):
        zi = max(x[i, 2], a)
        bi = min(x[i, 2] / a, 1.0)
        for j in range(y.shape[0]):
            zj = max(y[j, 2], a)
            dx = x[i, 0] - y[j, 0]
            dy = x[i, 1] - y[j, 1]
            dz = zi - zj
            rpy_pair(dx, dy, dz, a, block)
            wall_pair_into(x[i, 0], x[i, 1], zi, y[j, 0], y[j, 1], zj, a, block)
            bb = bi * min(y[j, 2] / a, 1.0)
            for p in range(3):
                for q in range(3):
                    out[3 * i + p, 3 * j + q] = bb * block[p, q]


def rpb_into(positions, radius, out: np.ndarray) -> np.ndarray:
    """Write the Rotne-Prager-Blake mobility of `positions` (n, 3), z > 0, into `out` (3n, 3n, float64,
    C-contiguous); returns out. The compiled twin of `rpb`, for calls at every right-hand-side evaluation."""
    x = check_positions(positions)
    a = check_radius(radius)
    check_above_wall(x)
    check_out(out, len(x))
    rpb_kernel(x, a, out)
    return out

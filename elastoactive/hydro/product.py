"""The mobility's product with forces without forming the matrix: velocities = M(positions) forces in O(n) memory.

For sizes where the dense (3n, 3n) matrix is too large to build at every step (an iterative solver needs only this
product). The same blocks as elastoactive.hydro.rpy and elastoactive.hydro.blake, summed on the fly.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..core.errors import ParameterError
from .blake import check_above_wall, self_mobility, wall_pair_into
from .rpy import check_positions, check_radius, rpy_pair


@njit(cache=True)
def product_kernel(x, a, f, wall, u):
    """u = M f for positions x (n, 3), forces f (n, 3), into u (n, 3); the wall's mobility if `wall`."""
    n = x.shape[0]
    z = np.empty(n)
    b = np.ones(n)
    for i in range(n):
        z[i] = x[i, 2]
        if wall:
            z[i] = max(x[i, 2], a)
            b[i] = min(x[i, 2] / a, 1.0)
    fb = np.empty((n, 3))
    for i in range(n):
        for p in range(3):
            fb[i, p] = b[i] * f[i, p]
            u[i, p] = 0.0
    block = np.empty((3, 3))
    for i in range(n):
        parallel = 1.0
        perpendicular = 1.0
        if wall:
            parallel, perpendicular = self_mobility(a, z[i])
        u[i, 0] += parallel * fb[i, 0]
        u[i, 1] += parallel * fb[i, 1]
        u[i, 2] += perpendicular * fb[i, 2]
        for j in range(i + 1, n):
            dx = x[i, 0] - x[j, 0]
            dy = x[i, 1] - x[j, 1]
            dz = z[i] - z[j]
            rpy_pair(dx, dy, dz, a, block)
            if wall:
                wall_pair_into(x[i, 0], x[i, 1], z[i], x[j, 0], x[j, 1], z[j], a, block)
            for p in range(3):
                for q in range(3):
                    u[i, p] += block[p, q] * fb[j, q]
                    u[j, q] += block[p, q] * fb[i, p]
    for i in range(n):
        for p in range(3):
            u[i, p] *= b[i]


def apply(positions, radius, forces, wall: bool) -> np.ndarray:
    """Velocities (n, 3) of beads at `positions` (n, 3) under `forces` (n, 3): the free-space RPY mobility's product
    (wall=False) or the Rotne-Prager-Blake mobility's above the wall z = 0 (wall=True), never forming the matrix."""
    x = check_positions(positions)
    a = check_radius(radius)
    f = np.ascontiguousarray(forces, dtype=float)
    if f.shape != x.shape:
        raise ParameterError(f"forces must have the shape of positions {x.shape}, got {f.shape}")
    if wall:
        check_above_wall(x)
    u = np.empty_like(x)
    product_kernel(x, a, f, bool(wall), u)
    return u

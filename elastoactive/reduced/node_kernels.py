"""The reduced model's right-hand side with periodic point forces, compiled (numba).

A PeriodicForce (elastoactive.terms.base) puts vector sin(omega t + phase) on one particle whatever the positions
are, so its generalised force needs no positions: Q_j = sin(omega t + phase) (-F_x sin theta_j + F_y cos theta_j)
for the joints j of its chain up to its particle (engines.node_forces). `periodic_rhs` evaluates the chain's own
right-hand side (kernels.eval_rhs) and adds D^-1 Q (the chain's drag block by Cholesky) in one compiled call: about
1 us at N = 7 where the Python right-hand side of engines.node_forces, with the positions and numpy's solve, took
~80-160 us; scipy's DOP853 around it then costs a few us per evaluation more. The same arithmetic as the Python
path up to round-off (within the solver's tolerance of its results).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernels import chol_solve, cholesky, drag_block, eval_rhs, workspace

__all__ = ["force_table", "periodic_rhs", "workspace"]


def force_table(laws) -> np.ndarray:
    """The PeriodicForces as rows (particle, F_x, F_y, omega, phase) for periodic_rhs."""
    return np.array(
        [[law.particle, law.vector[0], law.vector[1], law.omega, law.phase] for law in laws], dtype=float
    ).reshape(len(laws), 5)


@njit(cache=True)
def periodic_rhs(t, th, fac, system, beta, out, L, D, X, lam, table, Lc, Dc, q):
    """out = th' at time t: the model's own right-hand side (eval_rhs with its workspace L, D, X, lam) plus D^-1 Q of
    the periodic point forces in `table` (force_table's rows); Lc, Dc (n, n) and q (n_angles) are scratch."""
    eval_rhs(th, fac, system, beta, out, L, D, X, lam)
    n = system.n
    for k in range(q.size):
        q[k] = 0.0
    for p in range(table.shape[0]):
        particle = int(table[p, 0])
        s = math.sin(table[p, 3] * t + table[p, 4])
        fx = table[p, 1] * s
        fy = table[p, 2] * s
        for j in range((particle // n) * n, particle + 1):
            q[j] += -fx * math.sin(th[j]) + fy * math.cos(th[j])
    for ch in range(system.n_chains):
        off = ch * n
        loaded = False
        for j in range(off, off + n):
            if q[j] != 0.0:
                loaded = True
        if not loaded:
            continue
        drag_block(th, off, n, system.gamma_l, system.gamma_t, Dc)
        cholesky(Dc, Lc)
        chol_solve(Lc, q, off)
        for j in range(off, off + n):
            out[j] += q[j]

"""The reduced model's right-hand side with periodic point forces, compiled (numba).

A PeriodicForce (elastoactive.terms.base) puts vector sin(omega t + phase) on one particle whatever the positions
are, so its generalised force needs no positions: Q_j = sin(omega t + phase) (-F_x sin theta_j + F_y cos theta_j)
for the joints j of its chain up to its particle (engines.node_forces). `periodic_rhs` evaluates the chain's own
right-hand side (kernels.eval_rhs) and adds D^-1 Q (the chain's drag block by Cholesky) in one compiled call: about
1 us at N = 7 where the Python right-hand side of engines.node_forces, with the positions and numpy's solve, took
~80-160 us. The same arithmetic as the Python path up to round-off (within the solver's tolerance of its results).

`dop853` is reduced.dop853_loop's driver around periodic_rhs, each stage at its own time: the whole run compiled, no
Python per step (scipy's DOP853 around the compiled right-hand side spent ~45 us per evaluation in its own Python).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .dop853_loop import dop853_sums, sum_columns
from .kernels import chol_solve, cholesky, drag_block, eval_rhs, state_arrays, workspace

__all__ = ["dop853", "force_table", "periodic_rhs", "workspace"]


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


@njit(cache=True, inline="always")
def _rate(t, y, out, args):
    """periodic_rhs in dop853_loop's form: args = (fac, system, beta, L, D, X, lam, table, Lc, Dc, q)."""
    fac, system, beta, L, D, X, lam, table, Lc, Dc, q = args
    periodic_rhs(t, y, fac, system, beta, out, L, D, X, lam, table, Lc, Dc, q)


@njit(cache=True)
def dop853(y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps, args):
    """dop853_loop's driver around periodic_rhs, its sums by sum_columns as the chain's own (reduced.dop853): args =
    (system, beta, fac, table), fac the per-particle force factors, table force_table's rows. The workspace is
    allocated at each call (its contents are not carried from one evaluation to the next)."""
    system, beta, fac, table = args
    L, D, X, lam = state_arrays(system, y.size)
    n = system.n
    scratch = (np.zeros((n, n)), np.zeros((n, n)), np.zeros(system.n_chains * n))  # Lc, Dc, q
    rate_args = (fac, system, beta, L, D, X, lam, table) + scratch
    sums = sum_columns  # stages and dense output alike
    return dop853_sums(
        _rate, rate_args, sums, sums, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps
    )

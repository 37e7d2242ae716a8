"""The links' tensions of chains coupled through the fluid: the B x B system D lambda = z (symmetric positive definite,
D = Q^T N Q, elastoactive.reduced.fluid), its blocks those of the chains' pairs that the kernel builds.

Up to DIRECT_UP_TO links a Cholesky factorisation of the whole matrix; beyond, conjugate gradients preconditioned by
each chain's own block (block Jacobi), no O(B^3) part left. Compiled (numba); arrays in, arrays out.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["CG_TOLERANCE", "DIRECT_UP_TO", "own_tensions", "tensions"]


@njit(cache=True)
def _cholesky_solve(dm, z, lo, hi):
    """z[lo:hi] <- D^-1 z[lo:hi] of the block D = dm[lo:hi, lo:hi] (lower triangle read), factorised in place."""
    _cholesky_factor(dm, lo, hi)
    _factor_solve(dm, z, lo, hi)


@njit(cache=True)
def _cholesky_factor(dm, lo, hi):
    """D = L L^T of the block dm[lo:hi, lo:hi] in place (lower triangle read and written)."""
    for j in range(lo, hi):
        s = dm[j, j]
        for p in range(lo, j):
            s -= dm[j, p] * dm[j, p]
        dj = math.sqrt(s)
        dm[j, j] = dj
        for i in range(j + 1, hi):
            s = dm[i, j]
            for p in range(lo, j):
                s -= dm[i, p] * dm[j, p]
            dm[i, j] = s / dj


@njit(cache=True)
def _factor_solve(L, z, lo, hi):
    """z[lo:hi] <- (L L^T)^-1 z[lo:hi], L = L[lo:hi, lo:hi] lower triangular."""
    for i in range(lo, hi):
        s = z[i]
        for p in range(lo, i):
            s -= L[i, p] * z[p]
        z[i] = s / L[i, i]
    for i in range(hi - 1, lo - 1, -1):
        s = z[i]
        for p in range(i + 1, hi):
            s -= L[p, i] * z[p]
        z[i] = s / L[i, i]


DIRECT_UP_TO = 100
"""Links up to which the tensions are solved by Cholesky (B^3 / 3); beyond, by conjugate gradients (`_tensions`)."""
CG_TOLERANCE = 1e-13
"""The conjugate gradients' stop: |D lambda - z| <= CG_TOLERANCE |z| (2-norms)."""


@njit(cache=True)
def _block_product(db, p, n, nbr, count, out):
    """out = D p, D by its blocks db[c, s]."""
    out[:] = 0.0
    for c in range(nbr.shape[0]):
        for s in range(count[c]):
            o2 = nbr[c, s] * n
            dd = db[c, s]
            for i in range(n):
                acc = 0.0
                for j in range(n):
                    acc += dd[i, j] * p[o2 + j]
                out[c * n + i] += acc


@njit(cache=True)
def _block_jacobi(factors, r, n, out):
    """out = blockdiag(D_cc)^-1 r, the chains' own blocks' Cholesky factors `factors` (C, n, n)."""
    for i in range(r.size):
        out[i] = r[i]
    for c in range(factors.shape[0]):
        _factor_solve(factors[c], out[c * n : c * n + n], 0, n)


@njit(cache=True)
def tensions(db, z, n, nbr, count, self_slot):
    """z <- D^-1 z, D symmetric positive definite by its blocks db[c, s] (n, n) between chains c and nbr[c, s]: by
    Cholesky of the whole matrix up to DIRECT_UP_TO links; beyond, by conjugate gradients preconditioned by each
    chain's own block D_cc (Cholesky), from the block solution, until |D lambda - z| <= CG_TOLERANCE |z| (2-norms).
    Returns the iterations (0: Cholesky), or -1 with z NaN where D proves not positive definite or the iterations
    do not converge within as many as unknowns (the solver then rejects the step)."""
    chains = nbr.shape[0]
    b = z.size
    if b <= DIRECT_UP_TO:
        dm = np.zeros((b, b))
        for c in range(chains):
            for s in range(count[c]):
                o2 = nbr[c, s] * n
                for i in range(n):
                    for j in range(n):
                        dm[c * n + i, o2 + j] = db[c, s, i, j]
        _cholesky_solve(dm, z, 0, b)
        return 0
    factors = np.empty((chains, n, n))
    for c in range(chains):
        dd = db[c, self_slot[c]]
        for i in range(n):
            for j in range(i + 1):
                factors[c, i, j] = dd[i, j]
        _cholesky_factor(factors[c], 0, n)
    rhs_ = z.copy()
    target = CG_TOLERANCE * CG_TOLERANCE * (rhs_ @ rhs_)
    _block_jacobi(factors, rhs_, n, z)
    r = np.empty(b)
    dp = np.empty(b)
    _block_product(db, z, n, nbr, count, dp)
    for i in range(b):
        r[i] = rhs_[i] - dp[i]
    s_ = np.empty(b)
    _block_jacobi(factors, r, n, s_)
    p = s_.copy()
    rs = r @ s_
    for it in range(1, b + 1):
        if r @ r <= target:
            return it
        _block_product(db, p, n, nbr, count, dp)
        curvature = p @ dp
        if not curvature > 0.0:  # D not positive definite (a cutoff's truncated mobility can lose it): no tensions
            z[:] = np.nan
            return -1
        alpha = rs / curvature
        for i in range(b):
            z[i] += alpha * p[i]
            r[i] -= alpha * dp[i]
        _block_jacobi(factors, r, n, s_)
        rs_new = r @ s_
        beta = rs_new / rs
        rs = rs_new
        for i in range(b):
            p[i] = s_[i] + beta * p[i]
    z[:] = np.nan  # not converged in as many iterations as unknowns
    return -1


@njit(cache=True)
def own_tensions(db, z, n):
    """z <- D^-1 z for a D without blocks between chains (db (C, 1, n, n): each chain's own block, symmetric positive
    definite): Cholesky chain by chain, the arithmetic of `tensions`' Cholesky on the whole block-diagonal matrix."""
    factor = np.empty((n, n))
    for c in range(db.shape[0]):
        dd = db[c, 0]
        for i in range(n):
            for j in range(i + 1):
                factor[i, j] = dd[i, j]
        _cholesky_factor(factor, 0, n)
        _factor_solve(factor, z[c * n : c * n + n], 0, n)

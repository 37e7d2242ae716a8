"""The compiled right-hand side of chains coupled through the fluid (reduced.fluid: the equations, the scale, the
mobilities), and DOP853 compiled around it.

`eval_rhs_fluid(y, *arguments, out)` is t' of the chains at their chain-frame tangents y; `motion` is the same with the
links also moved by a given background flow (the extrapolated interaction's evaluations, reduced.fluid_extrapolated).
N is built chain pair by chain pair into the workspace `Work` between the chains `Near` lists; the tensions are solved
by Cholesky up to tensions.DIRECT_UP_TO links, by conjugate gradients beyond. `dop853` is reduced.dop853_loop's driver
around eval_rhs_fluid.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..hydro.blake import rpb_cross_kernel, rpb_kernel
from ..hydro.rpy import rpy_cross_kernel, rpy_kernel
from .chain3d import _basis_into, _bend_into
from .dop853_loop import dop853_steps
from .tensions import own_tensions, tensions

__all__ = ["MOBILITIES", "Near", "Work", "dop853", "eval_rhs_fluid", "motion"]

MOBILITIES = ("local", "identity", "rpy", "rpb")
"""The kernel's mobilities, by their code (the index): reduced.fluid's docstring."""
LOCAL, IDENTITY, RPY, RPB = range(4)


@njit(cache=True)
def eval_rhs_fluid(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work, out):
    """t' of the chains into out (3 C n), at the chain-frame tangents y (3 C n, chain by chain, link by link): the
    module docstring's q' = (A - B D^-1 B^T) r with N built block by block between the chains `near` lists
    (`Near`: every chain, or those within the cutoff), into the workspace `work` (`Work`); the tensions D^-1 B^T r by
    Cholesky up to DIRECT_UP_TO links, by conjugate gradients beyond (`tensions`)."""
    x = np.zeros(3 * chains * n)
    motion(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work, x, out)
    return out


@njit(cache=True)
def motion(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work, x, out):
    """eval_rhs_fluid's t' into out, the links also moved by the background velocities x (3B: the links' end-to-end
    velocities a flow from outside the chains `near` pairs would give them; zeros: none). On return x holds the links'
    end-to-end velocities; returns (w, lambda): P r per link (b, 3) and the tensions (b), or (w, None) with out NaN
    where a bead is through the wall."""
    u, norm2, E, P, Q, pos, w = _links(y, n, chains, sigma, clamped, coupling, bases, rot)
    b = chains * n
    z = np.empty(b)
    if code == RPB:
        for k in range(pos.shape[0]):
            if not pos[k, 2] > 0.0:  # a bead through the wall: no mobility; the solver stops on the NaN
                out[:] = np.nan
                z[:] = np.nan
                return w, z
    nbr, count, rev, self_slot = near
    nb, nqb, db = work
    _link_mobility(code, pos, Q, radius, gamma_l, n, nbr, count, rev, nb)
    _tension_system(nb, w, Q, n, nbr, count, x, nqb, db, z)
    if nbr.shape[1] == 1:  # each chain alone (its own block only): the tensions chain by chain
        own_tensions(db, z, n)
    else:
        tensions(db, z, n, nbr, count, self_slot)
    _velocities(x, nqb, z, P, E, u, norm2, n, nbr, count, out)
    return w, z


@njit(cache=True)
def _links(y, n, chains, sigma, clamped, coupling, bases, rot):
    """(u, norm2, E, P, Q, pos, w) at the chain-frame tangents y: unit tangents u and their squared lengths, the
    chain-frame bases E (b, 2, 3), the lab frames P (b, 2, 3) and tangents Q (b, 3), the beads' lab positions, and
    w = P r (lab, one vector per link), r = J^T F - dU/dq."""
    b = chains * n
    u = np.empty((b, 3))
    norm2 = np.empty(b)
    for k in range(b):
        x0, x1, x2 = y[3 * k], y[3 * k + 1], y[3 * k + 2]
        norm2[k] = x0 * x0 + x1 * x1 + x2 * x2
        r = 1.0 / math.sqrt(norm2[k])
        u[k, 0], u[k, 1], u[k, 2] = x0 * r, x1 * r, x2 * r
    E = np.empty((b, 2, 3))  # chain frame: E[k, 0] = a_k, E[k, 1] = b_k (chain3d.basis_of)
    _basis_into(u, E)
    grad = np.zeros((b, 3))
    for c in range(chains):
        o = c * n
        if clamped:
            _bend_into(1.0, 0.0, 0.0, u[o, 0], u[o, 1], u[o, 2], grad, o, 1.0)
        for k in range(o + 1, o + n):
            _bend_into(u[k - 1, 0], u[k - 1, 1], u[k - 1, 2], u[k, 0], u[k, 1], u[k, 2], grad, k, 1.0)
            _bend_into(u[k, 0], u[k, 1], u[k, 2], u[k - 1, 0], u[k - 1, 1], u[k - 1, 2], grad, k - 1, 1.0)
    P = np.empty((b, 2, 3))
    Q = np.empty((b, 3))
    pos = np.empty((b, 3))
    force = np.empty((b, 3))
    for k in range(b):
        for a in range(3):
            Q[k, a] = rot[a, 0] * u[k, 0] + rot[a, 1] * u[k, 1] + rot[a, 2] * u[k, 2]
            for al in range(2):
                P[k, al, a] = rot[a, 0] * E[k, al, 0] + rot[a, 1] * E[k, al, 1] + rot[a, 2] * E[k, al, 2]
            force[k, a] = -sigma * Q[k, a]
    for c in range(chains):
        for a in range(3):
            acc = bases[c, a]
            for k in range(c * n, c * n + n):
                acc += Q[k, a]
                pos[k, a] = acc
    if coupling != 0.0:
        for c in range(chains - 1):
            i, j = c * n + n - 1, c * n + 2 * n - 1
            for a in range(3):
                f = coupling * (pos[i, a] - pos[j, a] - bases[c, a] + bases[c + 1, a])
                force[i, a] -= f
                force[j, a] += f
    w = np.zeros((b, 3))
    for c in range(chains):
        s0 = s1 = s2 = 0.0
        for k in range(c * n + n - 1, c * n - 1, -1):
            s0 += force[k, 0]
            s1 += force[k, 1]
            s2 += force[k, 2]
            for al in range(2):
                rk = P[k, al, 0] * s0 + P[k, al, 1] * s1 + P[k, al, 2] * s2
                rk -= E[k, al, 0] * grad[k, 0] + E[k, al, 1] * grad[k, 1] + E[k, al, 2] * grad[k, 2]
                for a in range(3):
                    w[k, a] += P[k, al, a] * rk
    return u, norm2, E, P, Q, pos, w


@njit(cache=True)
def _link_mobility(code, pos, Q, radius, gamma_l, n, nbr, count, rev, nb):
    """nb[c, s] <- N_{c c'} (3n, 3n), c' = nbr[c, s]: the beads' mobility M between chains c and c', then its
    differences of consecutive beads' rows and columns within each chain (N = S^-1 M S^-T, blockwise). Each pair of
    chains is built once (c <= c'), its transpose copied."""
    size = 3 * n
    d = 1.0 / gamma_l - 1.0 if code == LOCAL else 0.0
    for c in range(nbr.shape[0]):
        for s in range(count[c]):
            c2 = nbr[c, s]
            if c2 < c:
                continue
            blk = nb[c, s]
            mine, theirs = pos[c * n : c * n + n], pos[c2 * n : c2 * n + n]
            if code == RPB:
                if c2 == c:
                    rpb_kernel(mine, radius, blk)
                else:
                    rpb_cross_kernel(mine, theirs, radius, blk)
            elif code == RPY:
                if c2 == c:
                    rpy_kernel(mine, radius, blk)
                else:
                    rpy_cross_kernel(mine, theirs, radius, blk)
            else:
                blk[:, :] = 0.0
                if c2 == c:
                    for i in range(n):
                        k = c * n + i
                        for p in range(3):
                            for q in range(3):
                                blk[3 * i + p, 3 * i + q] = (1.0 if p == q else 0.0) + d * Q[k, p] * Q[k, q]
            for i in range(n - 1, 0, -1):
                for p in range(3):
                    for col in range(size):
                        blk[3 * i + p, col] -= blk[3 * i - 3 + p, col]
            for row in range(size):
                for j in range(n - 1, 0, -1):
                    for q in range(3):
                        blk[row, 3 * j + q] -= blk[row, 3 * j - 3 + q]
            if c2 != c:
                other = nb[c2, rev[c, s]]
                for row in range(size):
                    for col in range(size):
                        other[col, row] = blk[row, col]


@njit(cache=True)
def _tension_system(nb, w, Q, n, nbr, count, x, nqb, db, z):
    """x += N w, nqb[c, s] = N_{c c'} Q_c', the tensions' matrix D = Q^T N Q by blocks db[c, s] (n, n) and its
    right-hand side z = Q^T x."""
    for c in range(nbr.shape[0]):
        for s in range(count[c]):
            o2 = nbr[c, s] * n
            blk = nb[c, s]
            nq = nqb[c, s]
            for row in range(3 * n):
                sx = 0.0
                for j in range(n):
                    k = o2 + j
                    m0, m1, m2 = blk[row, 3 * j], blk[row, 3 * j + 1], blk[row, 3 * j + 2]
                    sx += m0 * w[k, 0] + m1 * w[k, 1] + m2 * w[k, 2]
                    nq[row, j] = m0 * Q[k, 0] + m1 * Q[k, 1] + m2 * Q[k, 2]
                x[3 * c * n + row] += sx
            dd = db[c, s]
            for i in range(n):
                k = c * n + i
                for j in range(n):
                    dd[i, j] = Q[k, 0] * nq[3 * i, j] + Q[k, 1] * nq[3 * i + 1, j] + Q[k, 2] * nq[3 * i + 2, j]
    for k in range(z.size):
        z[k] = Q[k, 0] * x[3 * k] + Q[k, 1] * x[3 * k + 1] + Q[k, 2] * x[3 * k + 2]


@njit(cache=True)
def _velocities(x, nqb, lam, P, E, u, norm2, n, nbr, count, out):
    """q'_k = P_k^T (x - N Q lambda)_k at the tensions lam; t'_k = E_k q'_k, less the drift off unit length."""
    for c in range(nbr.shape[0]):
        for s in range(count[c]):
            o2 = nbr[c, s] * n
            nq = nqb[c, s]
            for row in range(3 * n):
                acc = 0.0
                for j in range(n):
                    acc += nq[row, j] * lam[o2 + j]
                x[3 * c * n + row] -= acc
    for k in range(lam.size):
        v0, v1, v2 = x[3 * k], x[3 * k + 1], x[3 * k + 2]
        q0 = P[k, 0, 0] * v0 + P[k, 0, 1] * v1 + P[k, 0, 2] * v2
        q1 = P[k, 1, 0] * v0 + P[k, 1, 1] * v1 + P[k, 1, 2] * v2
        h = 0.5 * (norm2[k] - 1.0)
        for a in range(3):
            out[3 * k + a] = E[k, 0, a] * q0 + E[k, 1, a] * q1 - h * u[k, a]


class Near(NamedTuple):
    """Which chains' mobility blocks the kernel builds: chain c's with chains nbr[c, :count[c]] (itself included, at
    slot self_slot[c]); c is at slot rev[c, s] of chain nbr[c, s]'s list."""

    nbr: np.ndarray
    count: np.ndarray
    rev: np.ndarray
    self_slot: np.ndarray


class Work(NamedTuple):
    """The kernel's workspace: N's blocks nb (C, S, 3n, 3n), N Q's nqb (C, S, 3n, n), D's db (C, S, n, n), S the
    longest Near list."""

    nb: np.ndarray
    nqb: np.ndarray
    db: np.ndarray


@njit(cache=True, inline="always")
def _rate(t, y, out, args):
    """eval_rhs_fluid in dop853_loop's form: args = reduced.fluid's arguments of the beds."""
    eval_rhs_fluid(y, *args, out)


@njit(cache=True)
def dop853(y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps, args):
    """dop853_loop.dop853_steps around eval_rhs_fluid (that module's driver; args: reduced.fluid._arguments(beds))."""
    return dop853_steps(_rate, args, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps)

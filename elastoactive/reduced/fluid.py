r"""Chains in three dimensions coupled through the fluid: the reduced overdamped model with a mobility among all beads.

The chains are elastoactive.reduced.chain3d's (unit tangents t_k of each chain in its own frame, the clamp along e_x,
bending U = C/2 sum phi_k^2, follower forces F_i = -sigma t_i), placed in the lab: chain c's anchor at the point
b_c and its frame turned by the rotation R (lab = b_c + R chain), so particle i of chain c sits at
r_ci = b_c + R sum_{k<=i} t_ck. Units l = C1 = gamma = 1 (gamma = 6 pi mu a, one bead's drag).

The equations (docs/hydrodynamics.md, "The reduced equations"): with M (3B x 3B) the mobility among all B moving
beads of the scene (velocity of bead i = sum_j M_ij F_j), the beads' velocities v = J q' (J lower block-triangular
within each chain, J_{ci, ck} = R E_ck for i >= k) and the overdamped balance of virtual work

    J^T M^-1 J q' = J^T F - dU/dq,

F the lab forces on the beads (follower, the tips' spring), dU/dq the bending. J = S P, with S the block cumulative
sum along each chain and P = blockdiag(R E_k) (orthonormal columns); Q = blockdiag(R t_k) completes P to an
orthogonal matrix. With N = S^-1 M S^-T (the mobility of the links' end-to-end velocities: differences of M's rows
and columns), J^T M^-1 J = P^T N^-1 P and, by the block inverse of U^T N U (U = [P Q]),

    q' = (A - B D^-1 B^T) r,   A = P^T N P,  B = P^T N Q,  D = Q^T N Q,  r = J^T F - dU/dq:

one solve with the B x B matrix D (the links' tensions are D^-1 B^T r), no factorisation of M and no resistance
matrix formed.

Scale. N is built chain pair by chain pair: the block of M between chains c and c' (elastoactive.hydro's block
functions), then its differences within each chain, N Q and D by the same blocks, into a workspace allocated once
per run. D is solved by Cholesky up to DIRECT_UP_TO links (B^3 / 3), beyond by conjugate gradients preconditioned by
each chain's own block D_cc (O(B^2) per iteration; ~10 iterations to CG_TOLERANCE for rows of cilia on the wall,
whose coupling is weak next to each chain's own tensions). Per evaluation the O(B^2) Blake pair formulas then
dominate (about 10 us at B = 14, a pair of N = 7; tens of ms at B = 640). Beds.cutoff leaves out M's blocks between
chains whose anchors lie farther apart (the reference zeroes the same blocks): O(B x neighbours) per evaluation, an
approximation whose error on a row's period and phase lags is measured (docs), not bounded; the truncated M need
not stay positive definite, and where D proves not to be the kernel's rate is NaN and the solver stops.

The extrapolated interaction (Beds.interaction; by default beyond EXACT_UP_TO links, so a pair or a small row is
exact). The velocities that the other chains' forces on the fluid give chain c's links, u_c = sum_{c' != c}
N_cc' (w_c' - Q_c' lambda_c'), are all that chain c takes from the others: given u_c, chain c alone obeys the same
equations with x_c = N_cc w_c + u_c (D_cc lambda_c = Q_c^T x_c, velocities P_c^T (x_c - N_cc Q_c lambda_c)). So
solve_fluid's compiled DOP853 solves the whole system once per step, at the step's start (the loop's accepted
state), and within the step each chain alone with its own block exact at every evaluation and u taken from a
quadratic in time through the whole solves' u at the last three starts; the quadratic starts where the last step's
ended (continuous in time, so the loop's error estimate sees no jump at the starts) and the gap to the whole solve
decays over the step. The time of an evaluation's state from the step's start comes from the rates at the starts
(`_elapsed`). The error is of third order in the step and is not in the loop's error estimate: it is measured
(docs/hydrodynamics.md, "The cost against the number of cilia": period and phase lags of rows of 8 to 24 cilia).
Per step: one whole solve, O(B^2), and about 12 evaluations chain by chain, O(C n^3). The right-hand side `rhs`,
scipy's method and the budget's Jacobian stay exact.

Mobilities (`MOBILITIES`): "local", the lab-frame drag of each particle (M_ii = W_i^-1, W_i = 1 + (gamma_l - 1)
t_i t_i^T, no coupling: the chain3d model exactly, to round-off); "identity" (M = 1: the local drag at gamma_l = 1,
through the same code as the fluid's, for the tests); "rpy", the Rotne-Prager-Yamakawa mobility in free space;
"rpb", the Rotne-Prager-Blake mobility above a no-slip wall at z = 0 (fluid at z > 0), both of bead radius a / l =
radius (elastoactive.hydro).

Two chains' tips may be joined by a linear spring of stiffness K (tip_coupling): energy K/2 |r_tip,c - r_tip,c+1 -
(b_c - b_c+1)|^2 for each neighbouring pair c, c + 1, relaxed when the chains stand straight and parallel.

`rhs_reference` writes the equations as above in plain numpy (J and M formed, J^T M^-1 J solved), `eval_rhs_fluid`
is the compiled kernel; the tests hold them equal, and the kernel at "identity" and "local" equal to chain3d's.
`solve_fluid` integrates by DOP853 compiled around the kernel (reduced.dop853_loop), or by scipy's on it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import ParameterError
from ..hydro.blake import rpb_cross_kernel, rpb_into, rpb_kernel
from ..hydro.rpy import rpy_cross_kernel, rpy_into, rpy_kernel
from .chain3d import _bend, _bend_into, basis_of
from .dop853_loop import dop853_steps, integrate
from .network import run_loop
from .tensions import CG_TOLERANCE, DIRECT_UP_TO, own_tensions, tensions

__all__ = [
    "CG_TOLERANCE",
    "DIRECT_UP_TO",
    "EXACT_UP_TO",
    "INTERACTIONS",
    "METHODS",
    "MOBILITIES",
    "Beds",
    "Memory",
    "Near",
    "Work",
    "eval_rhs_fluid",
    "fluid_forces",
    "lab_positions",
    "mobility_matrix",
    "near_chains",
    "rhs",
    "rhs_reference",
    "solve_fluid",
]

MOBILITIES = ("local", "identity", "rpy", "rpb")
"""The kernel's mobilities, by their code (the index): module docstring."""
LOCAL, IDENTITY, RPY, RPB = range(4)
INTERACTIONS = ("auto", "exact", "extrapolated")
"""Beds.interaction's values: how the compiled loop takes the flow each chain feels from the others."""
EXACT_UP_TO = 100
"""Links up to which interaction "auto" takes the chains' interaction exactly at every evaluation; beyond, it is
extrapolated over each step (module docstring, "Scale": its measured error)."""


class Beds(NamedTuple):
    """Chains of n links each, anchored at `bases` and turned by `rotation`, in a fluid (units l = C1 = gamma = 1).

    n             particles (links) per chain, >= 1
    sigma         follower force F_a l / C1 on every particle, along its link toward the anchor
    bases         anchor points b_c (C, 3) in the lab, l
    rotation      R (3, 3): lab = b_c + R chain (every chain's clamp axis e_x becomes R e_x)
    mobility      one of MOBILITIES
    radius        bead radius a / l (rpy, rpb; 0 for local, identity)
    gamma_l       drag along each link (local only; the beads of a fluid are spheres)
    tip_coupling  stiffness K l^2 / C1 of the springs between neighbouring chains' tips (0: none)
    clamped       a bending spring holds each chain's first link along its clamp axis (False: a free ball pivot)
    cutoff        chains whose anchors are farther apart than cutoff (l) do not interact: their mobility blocks are
                  left out (inf: none left out, the exact mobility; module docstring, "Scale")
    interaction   how solve_fluid's compiled loop takes the flow each chain feels from the others (INTERACTIONS):
                  "exact" at every evaluation, "extrapolated" exact at each step's start and extrapolated over the
                  step, "auto" exact up to EXACT_UP_TO links and extrapolated beyond (module docstring, "Scale")
    """

    n: int
    sigma: float
    bases: np.ndarray
    rotation: np.ndarray
    mobility: str = "local"
    radius: float = 0.0
    gamma_l: float = 1.0
    tip_coupling: float = 0.0
    clamped: bool = True
    cutoff: float = math.inf
    interaction: str = "auto"

    @property
    def chains(self) -> int:
        return int(np.shape(self.bases)[0])

    @property
    def code(self) -> int:
        return MOBILITIES.index(self.mobility)

    @property
    def extrapolated(self) -> bool:
        """Whether solve_fluid's compiled loop extrapolates the chains' interaction over each step (`interaction`):
        only chains coupled through a fluid have one."""
        coupled = self.mobility in ("rpy", "rpb") and self.chains > 1
        if self.interaction == "auto":
            return coupled and self.chains * int(self.n) > EXACT_UP_TO
        return coupled and self.interaction == "extrapolated"

    def checked(self) -> Beds:
        """The record, or ParameterError naming the first parameter out of range."""
        if int(self.n) < 1:
            raise ParameterError(f"n (number of particles N) must be >= 1, got {self.n}")
        if not (np.isfinite(self.sigma) and self.sigma >= 0):
            raise ParameterError(f"sigma must be finite and >= 0, got {self.sigma}")
        bases = np.asarray(self.bases, dtype=float)
        if bases.ndim != 2 or bases.shape[1] != 3 or bases.shape[0] < 1 or not np.all(np.isfinite(bases)):
            raise ParameterError(f"bases must be finite anchor points of shape (C, 3), got shape {bases.shape}")
        rotation = np.asarray(self.rotation, dtype=float)
        if rotation.shape != (3, 3) or not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-12):
            raise ParameterError("rotation must be a 3 x 3 orthogonal matrix")
        if self.mobility not in MOBILITIES:
            raise ParameterError(f"mobility must be one of {', '.join(MOBILITIES)}, got {self.mobility!r}")
        fluid = self.mobility in ("rpy", "rpb")
        if fluid and not (np.isfinite(self.radius) and self.radius > 0):
            raise ParameterError(f"radius (bead radius a / l) must be > 0 with mobility {self.mobility}")
        if not fluid and self.radius != 0:
            raise ParameterError(f"radius: mobility {self.mobility} has no beads (radius 0), got {self.radius}")
        if not (np.isfinite(self.gamma_l) and self.gamma_l > 0):
            raise ParameterError(f"gamma_l (drag ratio) must be finite and > 0, got {self.gamma_l}")
        if self.mobility != "local" and self.gamma_l != 1.0:
            raise ParameterError(f"gamma_l: mobility {self.mobility} moves spheres (gamma_l 1), got {self.gamma_l}")
        if not (np.isfinite(self.tip_coupling) and self.tip_coupling >= 0):
            raise ParameterError(f"tip_coupling must be finite and >= 0, got {self.tip_coupling}")
        if not (self.cutoff > 0):
            raise ParameterError(f"cutoff (l) must be > 0 (inf: every chain interacts), got {self.cutoff}")
        if self.interaction not in INTERACTIONS:
            raise ParameterError(f"interaction must be one of {', '.join(INTERACTIONS)}, got {self.interaction!r}")
        return self


def lab_positions(tangents: np.ndarray, beds: Beds) -> np.ndarray:
    """Particle positions (..., C, N, 3) in the lab of chain-frame tangents (..., C, N, 3)."""
    t = np.asarray(tangents, dtype=float)
    return np.asarray(beds.bases, dtype=float)[:, None, :] + np.cumsum(t, axis=-2) @ np.asarray(beds.rotation).T


def mobility_matrix(positions: np.ndarray, tangents: np.ndarray, beds: Beds) -> np.ndarray:
    """M (3B, 3B) of the beads at lab positions (B, 3) whose links have lab tangents (B, 3) (the local drag's
    direction): elastoactive.hydro's compiled mobilities (their tests hold them to the references), less the blocks
    between chains beyond beds.cutoff."""
    x = np.ascontiguousarray(positions, dtype=float).reshape(-1, 3)
    b = len(x)
    if beds.mobility in ("rpy", "rpb"):
        m = (rpy_into if beds.mobility == "rpy" else rpb_into)(x, beds.radius, np.empty((3 * b, 3 * b)))
        bases = np.asarray(beds.bases, dtype=float)
        far = np.linalg.norm(bases[:, None, :] - bases[None, :, :], axis=-1) > beds.cutoff
        beads = np.repeat(far, 3 * beds.n, axis=0).repeat(3 * beds.n, axis=1)
        m[beads] = 0.0
        return m
    if beds.mobility == "identity":
        return np.eye(3 * b)
    u = np.asarray(tangents, dtype=float).reshape(-1, 3)
    u = u / np.linalg.norm(u, axis=1)[:, None]
    blocks = np.eye(3)[None] + (1.0 / beds.gamma_l - 1.0) * np.einsum("ia,ib->iab", u, u)
    m = np.zeros((3 * b, 3 * b))
    for i in range(b):
        m[3 * i : 3 * i + 3, 3 * i : 3 * i + 3] = blocks[i]
    return m


def _tip_forces(positions: np.ndarray, beds: Beds) -> np.ndarray:
    """The tips' springs' lab forces (C, N, 3) at lab positions (C, N, 3)."""
    force = np.zeros_like(positions)
    bases = np.asarray(beds.bases, dtype=float)
    for c in range(beds.chains - 1):
        stretch = positions[c, -1] - positions[c + 1, -1] - (bases[c] - bases[c + 1])
        force[c, -1] -= beds.tip_coupling * stretch
        force[c + 1, -1] += beds.tip_coupling * stretch
    return force


def rhs_reference(tangents: np.ndarray, beds: Beds) -> np.ndarray:
    """t' (C, N, 3) of the chains at chain-frame tangents (C, N, 3): J^T M^-1 J q' = J^T F - dU/dq solved as
    written (plain numpy)."""
    n, chains = beds.n, beds.chains
    rot = np.asarray(beds.rotation, dtype=float)
    t = np.asarray(tangents, dtype=float).reshape(chains, n, 3)
    norm2 = np.einsum("cia,cia->ci", t, t)
    u = t / np.sqrt(norm2)[..., None]
    E = np.zeros((chains, n, 3, 2))
    grad = np.zeros((chains, n, 3))
    for c in range(chains):
        for k in range(n):
            E[c, k, :, 0], E[c, k, :, 1] = basis_of(u[c, k])
        if beds.clamped:
            grad[c, 0] += _bend(np.array([1.0, 0.0, 0.0]), u[c, 0])
        for k in range(1, n):
            grad[c, k] += _bend(u[c, k - 1], u[c, k])
            grad[c, k - 1] += _bend(u[c, k], u[c, k - 1])
    positions = lab_positions(u, beds)
    force = -beds.sigma * u @ rot.T + _tip_forces(positions, beds)
    b = chains * n
    J = np.zeros((3 * b, 2 * b))
    for c in range(chains):
        for k in range(n):
            for i in range(k, n):
                row, col = 3 * (c * n + i), 2 * (c * n + k)
                J[row : row + 3, col : col + 2] = rot @ E[c, k]
    g = np.einsum("ckab,cka->ckb", E, grad).ravel()
    M = mobility_matrix(positions.reshape(b, 3), u.reshape(b, 3) @ rot.T, beds)
    D = J.T @ np.linalg.solve(M, J)
    qdot = np.linalg.solve(D, J.T @ force.ravel() - g)
    tdot = np.einsum("ckab,ckb->cka", E, qdot.reshape(chains, n, 2))
    return tdot - 0.5 * (norm2 - 1.0)[..., None] * u


@njit(cache=True)
def eval_rhs_fluid(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work, out):
    """t' of the chains into out (3 C n), at the chain-frame tangents y (3 C n, chain by chain, link by link): the
    module docstring's q' = (A - B D^-1 B^T) r with N built block by block between the chains `near` lists
    (`Near`: every chain, or those within the cutoff), into the workspace `work` (`Work`); the tensions D^-1 B^T r by
    Cholesky up to DIRECT_UP_TO links, by conjugate gradients beyond (`_tensions`)."""
    x = np.zeros(3 * chains * n)
    _motion(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work, x, out)
    return out


@njit(cache=True)
def _motion(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work, x, out):
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
    for k in range(b):
        u0, u1, u2 = u[k, 0], u[k, 1], u[k, 2]
        if u0 * u0 + u1 * u1 > 0.25:
            a0, a1, a2 = -u1, u0, 0.0
        else:
            a0, a1, a2 = 0.0, -u2, u1
        r = 1.0 / math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        a0, a1, a2 = a0 * r, a1 * r, a2 * r
        E[k, 0, 0], E[k, 0, 1], E[k, 0, 2] = a0, a1, a2
        E[k, 1, 0], E[k, 1, 1], E[k, 1, 2] = u1 * a2 - u2 * a1, u2 * a0 - u0 * a2, u0 * a1 - u1 * a0
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


def near_chains(beds: Beds) -> Near:
    """The chains each chain's beads interact with: every chain within beds.cutoff (anchor to anchor), itself
    included; only itself for the local drag's mobilities (no coupling)."""
    bases = np.asarray(beds.bases, dtype=float)
    chains = len(bases)
    if beds.mobility in ("rpy", "rpb"):
        apart = np.linalg.norm(bases[:, None, :] - bases[None, :, :], axis=-1)
        close = apart <= beds.cutoff
        np.fill_diagonal(close, True)
    else:
        close = np.eye(chains, dtype=bool)
    lists = [np.flatnonzero(row) for row in close]
    width = max(len(x) for x in lists)
    nbr = np.zeros((chains, width), dtype=np.int64)
    count = np.array([len(x) for x in lists], dtype=np.int64)
    for c, x in enumerate(lists):
        nbr[c, : len(x)] = x
    slot = {(c, int(c2)): s for c, x in enumerate(lists) for s, c2 in enumerate(x)}
    rev = np.zeros_like(nbr)
    for c, x in enumerate(lists):
        for s, c2 in enumerate(x):
            rev[c, s] = slot[(int(c2), c)]
    self_slot = np.array([slot[(c, c)] for c in range(chains)], dtype=np.int64)
    return Near(nbr, count, rev, self_slot)


def _arguments(beds: Beds) -> tuple:
    """The kernel's arguments after (y, ...) and before out (the workspace allocated here: one per run)."""
    near = near_chains(beds)
    n, chains, width = int(beds.n), beds.chains, near.nbr.shape[1]
    work = Work(
        np.empty((chains, width, 3 * n, 3 * n)), np.empty((chains, width, 3 * n, n)), np.empty((chains, width, n, n))
    )
    return (
        n,
        chains,
        float(beds.sigma),
        float(beds.gamma_l),
        bool(beds.clamped),
        beds.code,
        float(beds.radius),
        float(beds.tip_coupling),
        np.ascontiguousarray(beds.bases, dtype=float),
        np.ascontiguousarray(beds.rotation, dtype=float),
        near,
        work,
    )


def rhs(tangents: np.ndarray, beds: Beds) -> np.ndarray:
    """t' (C, N, 3) by the compiled kernel."""
    y = np.ascontiguousarray(tangents, dtype=float).ravel()
    out = np.empty(y.size)
    eval_rhs_fluid(y, *_arguments(beds), out)
    return out.reshape(beds.chains, beds.n, 3)


def fluid_forces(tangents: np.ndarray, beds: Beds) -> np.ndarray:
    """The forces (C, N, 3) the beads exert on the fluid at chain-frame tangents (C, N, 3): M^-1 v, v the beads' lab
    velocities of the motion the equations give there (zero for the local drag's mobilities, which have no fluid)."""
    if beds.mobility not in ("rpy", "rpb"):
        return np.zeros((beds.chains, beds.n, 3))
    rot = np.asarray(beds.rotation, dtype=float)
    velocity = np.cumsum(rhs(tangents, beds), axis=-2) @ rot.T
    positions = lab_positions(tangents, beds)
    b = beds.chains * beds.n
    m = mobility_matrix(positions.reshape(b, 3), positions.reshape(b, 3), beds)
    return np.linalg.solve(m, velocity.ravel()).reshape(beds.chains, beds.n, 3)


METHODS = ("numba-DOP853", "DOP853")
"""solve_fluid's methods: scipy's DOP853 compiled around eval_rhs_fluid (reduced.dop853_loop: no Python per step),
and scipy's solve_ivp(DOP853) on it (one Python call per evaluation: the reference the compiled loop agrees with to
round-off)."""


@njit(cache=True, inline="always")
def _rate(t, y, out, args):
    """eval_rhs_fluid in dop853_loop's form: args = _arguments(beds)."""
    eval_rhs_fluid(y, *args, out)


@njit(cache=True)
def _dop853_fluid(y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps, args):
    """dop853_loop.dop853_steps around eval_rhs_fluid (that module's driver)."""
    return dop853_steps(_rate, args, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps)


class Memory(NamedTuple):
    """The extrapolated interaction's record, carried from one evaluation to the next within a run, at the current
    step's start (`_new_step`; (3B,) arrays but spans and steps)."""

    start: np.ndarray
    """The loop's state (NaN before the first step)."""
    rate: np.ndarray
    """The loop's rate (from the second start on)."""
    change: np.ndarray
    """The rate's change per unit time since the start before (from the third start on; zeros before)."""
    flow: np.ndarray
    """(3, 3B): the other chains' flow the step's evaluations take is flow[0] + s flow[1] + s^2 flow[2] at the time s
    since the start (`_elapsed`)."""
    known: np.ndarray
    """(2, 3B): the whole solve's other chains' flow at this start and the one before."""
    spans: np.ndarray
    """(1,): the time between the start before and this one."""
    steps: np.ndarray
    """int64 (1,): the starts recorded."""


def _alone(beds: Beds) -> tuple:
    """(Near, Work) of each chain with itself only: the extrapolated interaction's evaluations within a step."""
    chains, n = beds.chains, int(beds.n)
    zero = np.zeros((chains, 1), dtype=np.int64)
    near = Near(np.arange(chains, dtype=np.int64)[:, None], np.ones(chains, dtype=np.int64), zero, zero[:, 0].copy())
    return near, Work(np.empty((chains, 1, 3 * n, 3 * n)), np.empty((chains, 1, 3 * n, n)), np.empty((chains, 1, n, n)))


def _memory(size: int) -> Memory:
    empty = np.full(size, np.nan)
    return Memory(
        empty, empty.copy(), np.zeros(size), np.zeros((3, size)), np.zeros((2, size)), np.zeros(1),
        np.zeros(1, dtype=np.int64),
    )  # fmt: skip


@njit(cache=True)
def _other_flow(nb, nqb, w, lam, x, n, self_slot, flow):
    """flow <- x less each chain's own part N_cc (w_c - Q_c lambda_c): the links' end-to-end velocities that the other
    chains' forces on the fluid give chain c (x the links' velocities of the whole solve, w and lambda its P r and
    tensions, nb and nqb its blocks)."""
    for c in range(self_slot.size):
        blk = nb[c, self_slot[c]]
        nq = nqb[c, self_slot[c]]
        o = c * n
        for row in range(3 * n):
            acc = x[3 * o + row]
            for j in range(n):
                k = o + j
                acc -= blk[row, 3 * j] * w[k, 0] + blk[row, 3 * j + 1] * w[k, 1] + blk[row, 3 * j + 2] * w[k, 2]
                acc += nq[row, j] * lam[k]
            flow[3 * o + row] = acc


@njit(cache=True)
def _elapsed(y, start, rate, change):
    """The time s from the step's start to the state y along the path y(s) = start + s rate + s^2 / 2 change:
    s0 = <d, rate> / <rate, rate>, d = y - start, then s = <d, g> / <g, g> with g = rate + s0 / 2 change (an error
    of third order in s on the path)."""
    travel = 0.0
    speed = 0.0
    for i in range(y.size):
        travel += (y[i] - start[i]) * rate[i]
        speed += rate[i] * rate[i]
    if not speed > 0.0:
        return 0.0
    s0 = travel / speed
    travel = 0.0
    speed = 0.0
    for i in range(y.size):
        g = rate[i] + 0.5 * s0 * change[i]
        travel += (y[i] - start[i]) * g
        speed += g * g
    return travel / speed if speed > 0.0 else s0


@njit(cache=True)
def _new_step(exact, memory, y, f):
    """Record a step's start y (the loop's state; f its rate there, unless no step was taken yet). The whole solve
    there gives the other chains' flow on each chain's links; the flow the step's evaluations take goes on from where
    the last step's ended (continuous in time: the loop's error estimate sees no jump) as the quadratic through the
    whole solve's flows at the last three starts, less that gap decaying linearly over the last step's time."""
    n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work = exact
    start, rate, change, flow, known, spans, steps = memory
    size = y.size
    x = np.zeros(size)
    scratch = np.empty(size)
    w, lam = _motion(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work, x, scratch)
    fresh = np.empty(size)
    _other_flow(work[0], work[1], w, lam, x, n, near[3], fresh)
    if steps[0] == 0:  # the run's start: the whole solve's flow, held over the first step
        for i in range(size):
            flow[0, i] = fresh[i]
            flow[1, i] = 0.0
            flow[2, i] = 0.0
    else:
        if steps[0] == 1:  # no rate known at the first start: the step's time from the rate at its end
            dt = _elapsed(y, start, f, change)
        else:
            dt = _elapsed(y, start, rate, change)
        if not dt > 0.0:
            dt = math.inf  # (a step that went nowhere: the flow held)
        before = spans[0]
        for i in range(size):
            end = flow[0, i] + dt * (flow[1, i] + dt * flow[2, i]) if math.isfinite(dt) else flow[0, i]
            d1 = (fresh[i] - known[0, i]) / dt
            d2 = 0.0
            if steps[0] >= 2 and before > 0.0:
                d2 = (d1 - (known[0, i] - known[1, i]) / before) / (dt + before)
            flow[0, i] = end
            flow[1, i] = d1 + d2 * dt + (fresh[i] - end) / dt
            flow[2, i] = d2
            change[i] = (f[i] - rate[i]) / dt if steps[0] >= 2 else 0.0
        spans[0] = dt if math.isfinite(dt) else 0.0
    for i in range(size):
        start[i] = y[i]
        rate[i] = f[i]
        known[1, i] = known[0, i]
        known[0, i] = fresh[i]
    steps[0] += 1


@njit(cache=True, inline="always")
def _rate_extrapolated(t, y, out, args):
    """t' at y with the other chains' flow extrapolated over the current step (args: the whole solve's arguments,
    each chain alone's (Near, Work), the Memory, the loop's state and rate, which hold the current step's start):
    each chain's own block exact, the others' flow the Memory's quadratic at the time since the start (`_new_step`)."""
    exact, alone, memory, y_step, f_step = args
    fresh = False
    for i in range(y_step.size):
        if y_step[i] != memory.start[i]:  # (NaN before the first step too)
            fresh = True
            break
    if fresh:
        _new_step(exact, memory, y_step, f_step)
    flow = memory.flow
    x = flow[0].copy()
    if memory.steps[0] >= 2:
        s = _elapsed(y, memory.start, memory.rate, memory.change)
        for i in range(y.size):
            x[i] += s * (flow[1, i] + s * flow[2, i])
    n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work = exact
    _motion(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, alone[0], alone[1], x, out)


@njit(cache=True)
def _dop853_extrapolated(y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps, args):
    """dop853_loop.dop853_steps around _rate_extrapolated (args: the whole solve's arguments, each chain alone's
    (Near, Work), the Memory), which sees the loop's state and rate: a run's start clears the Memory."""
    exact, alone, memory = args
    if counts[0] == 0:
        memory.start[:] = np.nan
        memory.steps[0] = 0
    seen = (exact, alone, memory, y, f)
    return dop853_steps(_rate_extrapolated, seen, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps)


def solve_fluid(
    beds: Beds,
    ts: np.ndarray,
    tangents0: np.ndarray,
    *,
    rtol: float = 1e-9,
    atol: float = 1e-9,
    method: str = "numba-DOP853",
    on_time=None,
    budget=None,
    loop=run_loop,
):
    """Tangents (len(ts), C, N, 3) of the chains from tangents0 (C, N, 3) at t = ts[0], sampled at ts, by `method`
    (METHODS). Raises RuntimeError naming the solver's failure.

    budget(method, eig), told the method and the eigenvalues of the right-hand side's Jacobian at the start (central
    differences: 2 x 3CN evaluations) before the first step, may refuse the run (engines.runner.solver_budget).
    Progress: the compiled loop runs through `loop` (reduced.network.run_loop's contract; engines.runner.resume with
    a meter); scipy's tells on_time(t) at every evaluation."""
    beds.checked()
    if method not in METHODS:
        raise ParameterError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    ts = np.asarray(ts, dtype=float)
    args = _arguments(beds)
    size = 3 * beds.chains * beds.n
    out = np.empty(size)

    def rate(_t, y):
        return eval_rhs_fluid(y, *args, out).copy()

    y0 = np.ascontiguousarray(tangents0, dtype=float).ravel()
    if y0.size != size:
        raise ParameterError(
            f"tangents0 must hold {beds.chains} x {beds.n} tangents (shape ({beds.chains}, {beds.n}, 3)), "
            f"got {np.shape(tangents0)}"
        )
    if budget is not None:
        budget(method, np.linalg.eigvals(_jacobian(rate, y0)))
    if method == "numba-DOP853":
        if beds.extrapolated:
            run = integrate(_dop853_extrapolated, (args, _alone(beds), _memory(size)), ts, y0, rtol, atol, loop)
        else:
            run = integrate(_dop853_fluid, args, ts, y0, rtol, atol, loop)
        if run.status != 0:
            raise RuntimeError(
                f"chains in a fluid: the DOP853 step size fell below round-off at t = {run.t:g} (a bead through the "
                "wall, or a state the mobility does not hold)"
            )
        return run.y.reshape(ts.size, beds.chains, beds.n, 3)
    from scipy.integrate import solve_ivp  # start-up time: scipy.integrate costs ~0.4 s to import

    fun = rate
    if on_time is not None:

        def fun(t, y):
            on_time(t)
            return rate(t, y)

    sol = solve_ivp(fun, (ts[0], ts[-1]), y0, method="DOP853", t_eval=ts, rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"chains in a fluid: the DOP853 solver failed ({sol.message})")
    return sol.y.T.reshape(ts.size, beds.chains, beds.n, 3)


def _jacobian(f, y: np.ndarray) -> np.ndarray:
    """d f(0, y) / dy by central differences (relative step 1e-7): what bounds an explicit solver's steps."""
    J = np.empty((y.size, y.size))
    for k in range(y.size):
        h = 1e-7 * max(1.0, abs(y[k]))
        up, down = y.copy(), y.copy()
        up[k] += h
        down[k] -= h
        J[:, k] = (f(0.0, up) - f(0.0, down)) / (2.0 * h)
    return J

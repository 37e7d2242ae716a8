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
exact): each chain takes the others' flow on its links from the whole solve at each DOP853 step's start, extrapolated
over the step (reduced.fluid_extrapolated, with its error). The right-hand side `rhs`, scipy's method and the budget's
Jacobian stay exact.

Mobilities (`MOBILITIES`): "local", the lab-frame drag of each particle (M_ii = W_i^-1, W_i = 1 + (gamma_l - 1)
t_i t_i^T, no coupling: the chain3d model exactly, to round-off); "identity" (M = 1: the local drag at gamma_l = 1,
through the same code as the fluid's, for the tests); "rpy", the Rotne-Prager-Yamakawa mobility in free space;
"rpb", the Rotne-Prager-Blake mobility above a no-slip wall at z = 0 (fluid at z > 0), both of bead radius a / l =
radius (elastoactive.hydro).

Two chains' tips may be joined by a linear spring of stiffness K (tip_coupling): energy K/2 |r_tip,c - r_tip,c+1 -
(b_c - b_c+1)|^2 for each neighbouring pair c, c + 1, relaxed when the chains stand straight and parallel.

`rhs_reference` writes the equations as above in plain numpy (J and M formed, J^T M^-1 J solved), `eval_rhs_fluid`
(reduced.fluid_kernels) is the compiled kernel; the tests hold them equal, and the kernel at "identity" and "local"
equal to chain3d's. `solve_fluid` integrates by DOP853 compiled around the kernel (reduced.dop853_loop), or by scipy's
on it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..core.errors import ParameterError
from ..hydro.blake import rpb_into
from ..hydro.rpy import rpy_into
from . import fluid_extrapolated, fluid_kernels
from .chain3d import _bend, basis_of
from .dop853_loop import Integrated, integrate, run_loop
from .fluid_kernels import MOBILITIES, Near, Work, eval_rhs_fluid
from .tensions import CG_TOLERANCE, DIRECT_UP_TO

__all__ = [
    "CG_TOLERANCE",
    "DIRECT_UP_TO",
    "EXACT_UP_TO",
    "INTERACTIONS",
    "METHODS",
    "MOBILITIES",
    "Beds",
    "Near",
    "Work",
    "eval_rhs_fluid",
    "fluid_forces",
    "integrate_compiled",
    "lab_positions",
    "mobility_matrix",
    "near_chains",
    "rhs",
    "rhs_reference",
    "solve_fluid",
]

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
    Progress: the compiled loop runs through `loop` (reduced.dop853_loop.run_loop's contract; engines.runner.resume with
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
        run = integrate_compiled(beds, ts, y0, rtol, atol, loop, args)
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


def integrate_compiled(beds: Beds, ts, y0, rtol: float, atol: float, loop=run_loop, args=None) -> Integrated:
    """The compiled DOP853 run of the beds from the flat tangents y0 (3 C N) at ts[0], sampled at ts, by the route
    Beds.interaction takes (reduced.fluid_kernels.dop853, exact; reduced.fluid_extrapolated.dop853 beyond it): the
    loop's Integrated, its status unread. args: _arguments(beds), when the caller has them."""
    args = _arguments(beds) if args is None else args
    y0 = np.ascontiguousarray(y0, dtype=float)
    if beds.extrapolated:
        route = (args, fluid_extrapolated.alone(beds.chains, int(beds.n)), fluid_extrapolated.memory(y0.size))
        return integrate(fluid_extrapolated.dop853, route, ts, y0, rtol, atol, loop)
    return integrate(fluid_kernels.dop853, args, ts, y0, rtol, atol, loop)


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

"""The compiled (numba) kernels of the reduced model, in three modules: kernels_chain (drag, forces, pins, the dense
and recursive right-hand sides and their Jacobian), kernels_extended (a free head, a trap, self-contact) and this
one (which path runs, the SDE steppers, the inertial model), which re-exports them all: drag matrix, forces,
right-hand side, Jacobian, Euler-Maruyama steps and the projection onto the pins; the inertial model's right-hand
side, Jacobian and RK4 steps.

Every kernel that needs the model's parameters takes the `ChainSystem` record itself (numba compiles a
NamedTuple as a typed record; fields are read by name) and the Baumgarte rate `beta` as a float
argument. The record must come through `ChainSystem.typed()` (the functions of solve.py do that), so
that the field types are always (int64, int64, bool, bool, float64 x 8, bool, float64 x 3, bool, bool, bool,
float64 x 2) and each kernel is compiled, and cached on disk, once. The formulas are those of equations.py;
rhs_reference there is the plain-numpy twin that tests hold these kernels to.

Two solvers of D(th) th' = f(th)
--------------------------------
* dense (eval_rhs_dense): builds each chain's drag block D in O(N^2) (drag_block), factors it by
  Cholesky in O(N^3) and solves. Its factors are what the analytic Jacobian (eval_jacobian) reuses:
  the Jacobian, used only by the implicit methods on stiff cases, stays O(N^3) (it is a dense N x N
  matrix D^-1 R anyway).
* recursive (eval_rhs_recursive, articulated_solve): the O(N) "articulated drag" recursion derived in
  equations.py (a backward pass carrying one scalar, the longitudinal drag alpha of the subchain
  beyond each joint, and one bias vector per right-hand side; a forward pass for the rates); the
  pinned chain's D^-1 G^T rides along as two more right-hand sides, then the same 2 x 2 Schur
  complement as the dense path; the pair is solved chain by chain (its coupling is in f only).

The inertial model (system.mass_ratio > 0, equations.py): eval_rhs_inertial on the state (th, om) builds
each chain's mass block in O(N^2), its drag and centripetal terms in O(N), and solves by dense Cholesky,
O(N^3); eval_state picks it or eval_rhs by the record's mass_ratio (mass_ratio = 0 runs eval_rhs exactly as
before the inertial model existed); eval_jacobian_inertial differentiates it by central differences;
rk4_piecewise integrates it under step-wise constant noise forces.

The extended terms (a free head, a harmonic trap, self-contact; ChainSystem.head_free, trap, contact_radius):
whenever any is on, eval_rhs takes eval_rhs_general instead: it assembles D over all coordinates (the angles,
then the head) in O(N^2) (_general_drag), the generalised forces with the trap and the contact penalty (O(N^2)
pair loop with a bounding-circle skip, each core end against the other core; general_forces, contact.py), and
solves by dense Cholesky (the pinned chain: the same Schur-complement Baumgarte correction). Measured (numba, one core,
us per evaluation in a compiled loop, a clamped chain at sigma = 0.8, contact R = 0.1 on): N = 7: 0.67 out of contact,
0.84 folded into contact, against 0.59 for the dense path without the new terms; N = 17: 1.6 / 1.7 against 0.6 for the
recursion. 600 tau of N = 17 at sigma = 0.8 with contact (rtol 1e-8) take 2.5 s at K = 1e3 and 15 s at K = 1e4 (the
explicit default is then held to steps ~ 1 / K by the contact's stiffness; without contact 0.1 s). Its workspace is
make_general_workspace's (state_workspace / workspace pick it). The inertial model with an extended term is
eval_rhs_inertial_general (state (q, q'); M by general_mass, with the free head's bead; the particles' drag and
centripetal forces as node forces), taken by eval_state and rk4_piecewise. With every extended term off, the paths below
run exactly as before, bit for bit.

eval_rhs takes the path its workspace was sized for (`workspace`, `make_workspace`): dense below
RECURSIVE_MIN_N particles per chain, recursive from there on (every chain of two particles or more). The two
agree to the dense solver's round-off: the dense solve loses ~cond(D) ~ N^2 times the unit round-off, the
recursion does not (at N = 400, 3e-13 - 8e-13 relative against 5e-15 - 1.5e-14, both measured against an
extended-precision refinement).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernels_chain import (  # noqa: F401  (re-exported: the package imports every kernel from here)
    RECURSIVE_MIN_N,
    _chain_forces,
    articulated_solve,
    chol_solve,
    chol_solve_cols,
    cholesky,
    drag_block,
    eval_jacobian,
    eval_jacobian_recursive,
    eval_rhs_dense,
    eval_rhs_recursive,
    forces,
    make_workspace,
    uses_recursive,
)
from .kernels_extended import (  # noqa: F401  (re-exported, _general_geometry for solve.py)
    CONTACT_LENGTH,
    CROSSING_DISTANCE,
    _general_geometry,
    _particle_forces,
    _pin_acceleration,
    eval_rhs_general,
    eval_rhs_inertial_general,
    general_drag,
    general_forces,
    general_mass,
    is_extended,
    make_general_workspace,
)
from .system import ChainSystem

__all__ = [
    "RECURSIVE_MIN_N",
    "articulated_solve",
    "chol_solve",
    "chol_solve_cols",
    "cholesky",
    "drag_block",
    "eval_jacobian",
    "eval_jacobian_inertial",
    "eval_rhs",
    "eval_rhs_dense",
    "eval_rhs_general",
    "eval_rhs_inertial",
    "eval_rhs_inertial_general",
    "eval_rhs_recursive",
    "eval_state",
    "euler_maruyama",
    "heun",
    "forces",
    "general_drag",
    "general_forces",
    "general_mass",
    "is_extended",
    "make_general_workspace",
    "make_inertial_workspace",
    "make_workspace",
    "mass_block",
    "restore_pins",
    "rk4_piecewise",
    "state_arrays",
    "state_workspace",
    "uses_recursive",
    "workspace",
]


def workspace(system: ChainSystem, dense: bool | None = None):
    """Scratch arrays (L, D, X, lam) of eval_rhs / eval_jacobian (see make_workspace). dense: None picks
    by N (the dense path below RECURSIVE_MIN_N); eval_jacobian needs dense=True. A system with an extended term
    (system.extended) gets make_general_workspace's arrays (eval_rhs_general), whatever dense says."""
    if system.extended:
        return make_general_workspace(system.n_chains, system.n, system.n_angles + system.n_head)
    if dense is None:
        dense = not uses_recursive(system.n)
    return make_workspace(system.n_chains, system.n, bool(dense))


@njit(cache=True)
def eval_rhs(th, fac, system, beta, out, L, D, X, lam):
    """out = th' at th (force factors fac, Baumgarte rate beta), by the path the workspace (L, D, X, lam,
    from `workspace` / `make_workspace`) was sized for: dense Cholesky when L holds n x n factors
    (eval_rhs_dense), else the O(N) recursion (eval_rhs_recursive). X, lam: as in eval_rhs_dense.
    With an extended term on (is_extended), eval_rhs_general on the state th (angles, then the free head) and
    make_general_workspace's arrays."""
    if is_extended(system):
        eval_rhs_general(th, fac, system, beta, out, L, D, X, lam)
    elif L.shape[1] >= system.n:
        eval_rhs_dense(th, fac, system, beta, out, L, D, X, lam)
    else:
        eval_rhs_recursive(th, fac, system, beta, out, D, X, lam)


@njit(cache=True)
def restore_pins(th, delta):
    """Minimum-norm Gauss-Newton steps th -= G^T (G G^T)^-1 g back onto g = 0 (two-pinned SDE steps)."""
    n = th.size
    for _ in range(5):
        g0 = -n * (1.0 - delta)
        g1 = 0.0
        a = 0.0
        b = 0.0
        d = 0.0
        for i in range(n):
            ci = math.cos(th[i])
            si = math.sin(th[i])
            g0 += ci
            g1 += si
            a += si * si
            b -= si * ci
            d += ci * ci
        if max(abs(g0), abs(g1)) < 1e-14 * n:
            return
        det = a * d - b * b
        m0 = (d * g0 - b * g1) / det
        m1 = (a * g1 - b * g0) / det
        for i in range(n):
            th[i] -= -math.sin(th[i]) * m0 + math.cos(th[i]) * m1


@njit(cache=True)
def state_arrays(system, na):
    """The workspace (L, D, X, lam) of eval_state for a state of na numbers, allocated inside a compiled loop (as
    state_workspace's): the overdamped model's make_workspace (dense below RECURSIVE_MIN_N particles, the O(N)
    recursion's from there on), the inertial model's (mass_ratio > 0: its mass matrix solved densely), or, with an
    extended term (a free head, a trap, self-contact), make_general_workspace's, dense over all position coordinates.
    The DOP853 driver (reduced.dop853) and the noisy runs' loops (euler_maruyama, heun: overdamped) allocate by it."""
    nch = system.n_chains
    n = system.n
    inertial = system.mass_ratio > 0
    if is_extended(system):
        nq = na // 2 if inertial else na  # position coordinates (the inertial state: positions, then rates)
        L = np.zeros((2, nq, nq))
        D = np.zeros((nch * n, 8))
        X = np.zeros((nq, 2))
    else:
        m = n if inertial or not uses_recursive(n) else 0
        L = np.zeros((nch, m, m))
        if inertial:
            D = np.zeros((n, n + 2))
        elif m == n:
            D = np.zeros((n, n))
        else:
            D = np.zeros((nch * n, 4))
        X = np.zeros((n, 2))
    return L, D, X, np.zeros(2)


@njit(cache=True)
def euler_maruyama(y, k0, facs, dt, system, beta, sidx, out, jptr):
    """Advance y (in place) through steps k0 .. k0 + len(facs) - 1, recording out[j] = state after sidx[j] steps."""
    na = y.size
    L, D, X, lam = state_arrays(system, na)
    f = np.empty(na)
    for r in range(facs.shape[0]):
        k = k0 + r
        while jptr < sidx.size and sidx[jptr] == k:
            out[jptr, :] = y
            jptr += 1
        eval_rhs(y, facs[r], system, beta, f, L, D, X, lam)
        for i in range(na):
            y[i] += dt * f[i]
        if system.pinned:
            restore_pins(y, system.delta)
    return jptr


@njit(cache=True)
def heun(y, k0, facs, dt, system, beta, sidx, out, jptr):
    """euler_maruyama's loop with the stochastic Heun (predictor-corrector) step, which converges to the
    Stratonovich reading of the multiplicative white noise: with f(y, fac) the right-hand side under step k's
    force factors (its noise increment fixed over the step), y* = y + dt f(y, fac_k),
    y_{k+1} = y + dt (f(y, fac_k) + f(y*, fac_k)) / 2; pinned systems are projected after each step."""
    na = y.size
    L, D, X, lam = state_arrays(system, na)
    f = np.empty(na)
    g = np.empty(na)
    yp = np.empty(na)
    for r in range(facs.shape[0]):
        k = k0 + r
        while jptr < sidx.size and sidx[jptr] == k:
            out[jptr, :] = y
            jptr += 1
        eval_rhs(y, facs[r], system, beta, f, L, D, X, lam)
        for i in range(na):
            yp[i] = y[i] + dt * f[i]
        eval_rhs(yp, facs[r], system, beta, g, L, D, X, lam)
        for i in range(na):
            y[i] += 0.5 * dt * (f[i] + g[i])
        if system.pinned:
            restore_pins(y, system.delta)
    return jptr


# ----------------------------------------------------------------------------------------------
# the inertial model (system.mass_ratio > 0): M(th) th'' + c(th, th') + D(th) th' = f(th), state (th, om)
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def make_inertial_workspace(nch, n):
    """Scratch arrays (L, D, X, lam) of eval_rhs_inertial: L (nch, n, n) Cholesky factors of the mass blocks,
    D (n, n + 2) one mass block and, in its last two columns, the cosines and sines of that chain's angles,
    X (n, 2) particle forces, then M^-1 G^T (pinned), lam (2) the multipliers (pinned)."""
    return np.zeros((nch, n, n)), np.zeros((n, n + 2)), np.zeros((n, 2)), np.zeros(2)


@njit(cache=True)
def mass_block(th, off, n, m, ifac, M):
    """M of the chain th[off:off+n] into M[:n, :n]: M_jk = m (n - max(j, k)) cos(th_j - th_k) + m ifac delta_jk
    (0-based j, k: the particles i >= max(j, k) all move with both angles), the kinetic energy T = th'^T M th' / 2."""
    for j in range(n):
        cj = math.cos(th[off + j])
        sj = math.sin(th[off + j])
        for k in range(j, n):
            v = m * (n - k) * (cj * math.cos(th[off + k]) + sj * math.sin(th[off + k]))
            M[j, k] = v
            M[k, j] = v
        M[j, j] += m * ifac


@njit(cache=True)
def eval_rhs_inertial(y, fac, system, beta, out, L, D, X, lam):
    """out = (th', om') at y = (th, om) of the inertial model (equations.py): om' = M^-1 (f - D om - c), by
    dense Cholesky of each chain's mass block, O(N^3) (the O(N) articulated-body algorithm would do; N is
    small where inertia is run). Pinned: the Baumgarte-stabilised acceleration constraint
    G om' = -G' om - 2 beta G om - beta^2 g through the 2 x 2 Schur complement, as in the overdamped model.
    fac: force factors (1 + eta), first n_angles entries read. L, D, X, lam: make_inertial_workspace."""
    n = system.n
    nch = system.n_chains
    na = n * nch
    m = system.mass_ratio
    ifac = system.inertia_factor
    gl = system.gamma_l
    gt = system.gamma_t
    if L.shape[0] < nch or L.shape[1] < n or D.shape[0] < n or D.shape[1] < n + 2 or X.shape[0] < n:
        raise ValueError("eval_rhs_inertial needs an inertial workspace (L (n_chains, n, n), D (n, n + 2), X (n, 2))")
    if y.size < 2 * na or out.size < 2 * na:
        raise ValueError("eval_rhs_inertial: the state holds 2 n_angles numbers (angles, then rates)")
    th = y[:na]
    acc = out[na:]
    for i in range(na):
        out[i] = y[na + i]
    _chain_forces(th, fac, system, acc)  # springs, follower forces, coupling
    cc = n
    sc = n + 1
    for ch in range(nch):
        off = ch * n
        for j in range(n):
            D[j, cc] = math.cos(th[off + j])
            D[j, sc] = math.sin(th[off + j])
        # particle forces P_i = -W_i v_i - m a_i (a_i: centripetal acceleration), v_i, a_i as prefix sums
        _particle_forces(D, 0, cc, sc, y, na + off, n, 0.0, 0.0, gl, gt, m, X, 0, False)
        # their generalised forces: n_k . sum_{i >= k} P_i
        px = 0.0
        py = 0.0
        for k in range(n - 1, -1, -1):
            px += X[k, 0]
            py += X[k, 1]
            acc[off + k] += -D[k, sc] * px + D[k, cc] * py
        # mass block (columns 0 .. n-1 of D), factor, solve
        for j in range(n):
            cj = D[j, cc]
            sj = D[j, sc]
            for k in range(j, n):
                v = m * (n - k) * (cj * D[k, cc] + sj * D[k, sc])
                D[j, k] = v
                D[k, j] = v
            D[j, j] += m * ifac
        cholesky(D, L[ch])
        chol_solve(L[ch], out, na + off)
    if system.pinned:
        _pin_acceleration(D, cc, sc, y, na, n, beta, system.delta, L[0], X, acc, lam)


@njit(cache=True)
def eval_state(y, fac, system, beta, out, L, D, X, lam):
    """The right-hand side of the integrated state: eval_rhs (overdamped, state th) when system.mass_ratio == 0,
    exactly as before the inertial model existed; eval_rhs_inertial (state (th, om)) when it is > 0, or
    eval_rhs_inertial_general with an extended term (state (q, q'), q = angles then the free head). The workspace
    must match (state_workspace)."""
    if system.mass_ratio > 0:
        if is_extended(system):
            eval_rhs_inertial_general(y, fac, system, beta, out, L, D, X, lam)
        else:
            eval_rhs_inertial(y, fac, system, beta, out, L, D, X, lam)
    else:
        eval_rhs(y, fac, system, beta, out, L, D, X, lam)


def state_workspace(system: ChainSystem):
    """The workspace of eval_state for this system: `workspace` (overdamped; make_general_workspace's with an
    extended term) or make_inertial_workspace."""
    if system.mass_ratio > 0:
        if system.extended:
            return make_general_workspace(system.n_chains, system.n, system.n_angles + system.n_head)
        return make_inertial_workspace(system.n_chains, system.n)
    return workspace(system)


FD_STEP = 6.0554544523933395e-06
"""Relative step of the central differences of eval_jacobian_inertial: the cube root of the unit round-off."""


@njit(cache=True)
def eval_jacobian_inertial(y, system, beta, J, L, D, X, lam):
    """Jacobian d(y')/dy of the deterministic inertial model (fac = 1), written into J (2 n_angles square):
    the exact blocks d th'/d th = 0, d th'/d om = 1, and the accelerations' by central differences
    (2 n_angles evaluations; relative error ~ 1e-10). For the implicit methods and the stiffness check."""
    ns = y.size
    na = ns // 2
    fac = np.ones(ns)
    yp = y.copy()
    fp = np.empty(ns)
    fm = np.empty(ns)
    J[:, :] = 0.0
    for i in range(na):
        J[i, na + i] = 1.0
    for j in range(ns):
        h = FD_STEP * max(1.0, abs(y[j]))
        yp[j] = y[j] + h
        hp = yp[j] - y[j]
        eval_rhs_inertial(yp, fac, system, beta, fp, L, D, X, lam)
        yp[j] = y[j] - h
        hm = y[j] - yp[j]
        eval_rhs_inertial(yp, fac, system, beta, fm, L, D, X, lam)
        yp[j] = y[j]
        for i in range(na, ns):
            J[i, j] = (fp[i] - fm[i]) / (hp + hm)


@njit(cache=True)
def rk4_piecewise(y, k0, facs, dt, nsub, system, beta, sidx, out, jptr):
    """The inertial model with force factors constant over each step of length dt (the noise of MuJoCo's
    steps, elastoactive.controllers.noise): steps k0 .. k0 + len(facs) - 1 of dt, each by nsub classical RK4 substeps
    with facs[r]; records out[j] = the angles after sidx[j] steps. Returns the next jptr."""
    ns = y.size
    na = ns // 2
    if is_extended(system):  # the state (q, q'), q = angles then the free head: make_general_workspace
        L = np.zeros((2, na, na))
        D = np.zeros((system.n_chains * system.n, 8))
        X = np.zeros((na, 2))
        lam = np.zeros(2)
    else:
        L, D, X, lam = make_inertial_workspace(system.n_chains, system.n)
    k1 = np.empty(ns)
    k2 = np.empty(ns)
    k3 = np.empty(ns)
    k4 = np.empty(ns)
    yt = np.empty(ns)
    fac = np.ones(ns)
    h = dt / nsub
    for r in range(facs.shape[0]):
        k = k0 + r
        while jptr < sidx.size and sidx[jptr] == k:
            out[jptr, :] = y[:na]
            jptr += 1
        for i in range(facs.shape[1]):
            fac[i] = facs[r, i]
        for _ in range(nsub):
            eval_state(y, fac, system, beta, k1, L, D, X, lam)
            for i in range(ns):
                yt[i] = y[i] + 0.5 * h * k1[i]
            eval_state(yt, fac, system, beta, k2, L, D, X, lam)
            for i in range(ns):
                yt[i] = y[i] + 0.5 * h * k2[i]
            eval_state(yt, fac, system, beta, k3, L, D, X, lam)
            for i in range(ns):
                yt[i] = y[i] + h * k3[i]
            eval_state(yt, fac, system, beta, k4, L, D, X, lam)
            for i in range(ns):
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    return jptr

"""The compiled (numba) kernels of the reduced model: drag matrix, forces, right-hand side, Jacobian,
Euler-Maruyama steps and the projection onto the pins; the inertial model's right-hand side, Jacobian and
RK4 steps.

Every kernel that needs the model's parameters takes the `ChainSystem` record itself (numba compiles a
NamedTuple as a typed record; fields are read by name) and the Baumgarte rate `beta` as a float
argument. The record must come through `ChainSystem.typed()` (the functions of solve.py do that), so
that the field types are always (int64, int64, bool, bool, float64 x 8, bool, float64 x 3, bool) and each kernel is compiled,
and cached on disk, once. The formulas are those of equations.py; rhs_reference there is the
plain-numpy twin that tests hold these kernels to.

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
pair loop with a bounding-circle skip, each core end against the other core; general_forces, contact.py), and solves by dense Cholesky (the pinned
chain: the same Schur-complement Baumgarte correction). Measured (numba, one core, us per evaluation in a compiled
loop, a clamped chain at sigma = 0.8, contact R = 0.1 on): N = 7: 0.67 out of contact, 0.84 folded into contact,
against 0.59 for the dense path without the new terms; N = 17: 1.6 / 1.7 against 0.6 for the recursion. 600 tau of
N = 17 at sigma = 0.8 with contact (rtol 1e-8) take 2.5 s at K = 1e3 and 15 s at K = 1e4 (the explicit default is
then held to steps ~ 1 / K by the contact's stiffness; without contact 0.1 s). Its workspace is make_general_workspace's
(state_workspace / workspace pick it). The inertial model with an extended term is eval_rhs_inertial_general
(state (q, q'); M by general_mass, with the free head's bead; the particles' drag and centripetal forces as node
forces), taken by eval_state and rk4_piecewise. With every extended term off, the paths below run exactly as
before, bit for bit.

eval_rhs takes the path its workspace was sized for (`workspace`, `make_workspace`): dense below
RECURSIVE_MIN_N particles per chain, recursive from there on. Below it the results are bit for bit
those of the dense solver (as before the recursion existed); above it they agree with it to its
round-off: the dense solve loses ~cond(D) ~ N^2 times the unit round-off, the recursion does not
(at N = 400, 3e-13 - 8e-13 relative against 5e-15 - 1.5e-14, both measured against an extended-
precision refinement).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .contact import CROSSING_DISTANCE as _CROSSING_DISTANCE
from .system import CONTACT_LENGTH as _CONTACT_LENGTH
from .system import ChainSystem

_TWO_PI = 2.0 * math.pi

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
    "state_workspace",
    "uses_recursive",
    "workspace",
]

RECURSIVE_MIN_N = 10
"""Particles per chain from which eval_rhs solves by the O(N) recursion instead of dense Cholesky.

Not a speed crossover: measured (numba, one core of the development machine; us per evaluation, one
chain / two-pinned), the recursion is faster at every N >= 2: N = 2: 0.19 / 0.23 against 0.27 / 0.41 dense;
N = 7: 0.32 / 0.37 against 0.54 / 0.91; N = 9: 0.38 / 0.43 against 0.68 / 1.25; N = 100: 2.7 / 3.0 against
95 / 107. Below 10 the dense path costs at most ~1 us more per evaluation, and keeping it there keeps
every run of the paper's chains (N = 2, 7, 9) bit for bit what it was before the recursion existed.
Lower it to 2 to take the recursion everywhere (results then change at round-off only)."""


@njit(cache=True)
def uses_recursive(n):
    """Whether a chain of n particles is solved by the O(N) recursion (n >= RECURSIVE_MIN_N)."""
    return n >= RECURSIVE_MIN_N


@njit(cache=True)
def make_workspace(nch, n, dense):
    """Scratch arrays (L, D, X, lam) of eval_rhs for nch chains of n particles. dense: L (nch, n, n)
    Cholesky factors, D (n, n) one drag block; recursive: L (nch, 0, 0) (its mark: eval_rhs takes
    the dense path iff L holds n x n factors), D (nch * n, 4) the per-joint records of articulated_solve.
    Both: X (n, 2) D^-1 G^T, lam (2) multipliers of a pinned chain."""
    if dense:
        return np.zeros((nch, n, n)), np.zeros((n, n)), np.zeros((n, 2)), np.zeros(2)
    return np.zeros((nch, 0, 0)), np.zeros((nch * n, 4)), np.zeros((n, 2)), np.zeros(2)


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
def drag_block(th, off, n, gl, gt, D):
    """D of the chain th[off:off+n] via suffix sums S_m = sum_{i>=m} W_i, D_jk = n_j^T S_max(j,k) n_k."""
    sxx = 0.0
    sxy = 0.0
    syy = 0.0
    for m in range(n - 1, -1, -1):
        cm = math.cos(th[off + m])
        sm = math.sin(th[off + m])
        sxx += gl * cm * cm + gt * sm * sm
        sxy += (gl - gt) * cm * sm
        syy += gl * sm * sm + gt * cm * cm
        for j in range(m + 1):
            cj = math.cos(th[off + j])
            sj = math.sin(th[off + j])
            v = sj * sm * sxx - (sj * cm + cj * sm) * sxy + cj * cm * syy
            D[j, m] = v
            D[m, j] = v


@njit(cache=True)
def _drag_block_cached(th, off, n, gl, gt, D, CS):
    """drag_block with the n cosines and sines computed once (into CS[:n, 0:2]) instead of O(N^2) times:
    the same arithmetic in the same order, so bit for bit the same D."""
    for j in range(n):
        CS[j, 0] = math.cos(th[off + j])
        CS[j, 1] = math.sin(th[off + j])
    sxx = 0.0
    sxy = 0.0
    syy = 0.0
    for m in range(n - 1, -1, -1):
        cm = CS[m, 0]
        sm = CS[m, 1]
        sxx += gl * cm * cm + gt * sm * sm
        sxy += (gl - gt) * cm * sm
        syy += gl * sm * sm + gt * cm * cm
        for j in range(m + 1):
            cj = CS[j, 0]
            sj = CS[j, 1]
            v = sj * sm * sxx - (sj * cm + cj * sm) * sxy + cj * cm * syy
            D[j, m] = v
            D[m, j] = v


@njit(cache=True)
def cholesky(A, L):
    n = A.shape[0]
    for j in range(n):
        s = A[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        d = math.sqrt(s)
        L[j, j] = d
        for i in range(j + 1, n):
            s = A[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s / d
        for i in range(j):
            L[i, j] = 0.0


@njit(cache=True)
def chol_solve(L, b, off):
    """Solve (L L^T) x = b[off:off+n] in place."""
    n = L.shape[0]
    for i in range(n):
        s = b[off + i]
        for k in range(i):
            s -= L[i, k] * b[off + k]
        b[off + i] = s / L[i, i]
    for i in range(n - 1, -1, -1):
        s = b[off + i]
        for k in range(i + 1, n):
            s -= L[k, i] * b[off + k]
        b[off + i] = s / L[i, i]


@njit(cache=True)
def chol_solve_cols(L, B, off):
    """Solve (L L^T) X = B[off:off+n, :] in place, column by column."""
    n = L.shape[0]
    for c in range(B.shape[1]):
        for i in range(n):
            s = B[off + i, c]
            for k in range(i):
                s -= L[i, k] * B[off + k, c]
            B[off + i, c] = s / L[i, i]
        for i in range(n - 1, -1, -1):
            s = B[off + i, c]
            for k in range(i + 1, n):
                s -= L[k, i] * B[off + k, c]
            B[off + i, c] = s / L[i, i]


@njit(cache=True)
def forces(th, fac, off, n, sigma, c, clamped, out):
    """out[off:off+n] = -dU/dth + Q for one chain (spring constant c)."""
    for i in range(n):
        f = 0.0
        if i == 0:
            if clamped:
                f -= c * th[off]
        else:
            f += c * (th[off + i - 1] - th[off + i])
        if i < n - 1:
            f += c * (th[off + i + 1] - th[off + i])
        out[off + i] = f
    px = 0.0
    py = 0.0
    for k in range(n - 1, -1, -1):
        ck = math.cos(th[off + k])
        sk = math.sin(th[off + k])
        px -= sigma * fac[off + k] * ck
        py -= sigma * fac[off + k] * sk
        out[off + k] += -sk * px + ck * py


@njit(cache=True)
def _chain_forces(th, fac, system, out):
    """out = f(th) = -dU/dth + Q (springs, follower forces, the pair's coupling) of every chain."""
    n = system.n
    for ch in range(system.n_chains):
        c = 1.0 if ch == 0 else system.rho
        forces(th, fac, ch * n, n, system.sigma, c, system.clamped, out)
    if system.n_chains == 2:
        d = system.kappa * (th[0] - th[n])
        out[0] -= d
        out[n] += d
    if system.closed:
        _closure(th, n, out)


@njit(cache=True, inline="always")
def _closure(th, n, out):
    """A closed chain's last joint: the spring (stiffness 1) between the last link and the first, bent by
    th_0 + 2 pi - th_{n-1} (zero for the straight continuation once round the ring)."""
    d = th[0] + _TWO_PI - th[n - 1]
    out[0] -= d
    out[n - 1] += d


@njit(cache=True)
def _pin_correction(th, n, beta, delta, out, X, lam, CS, cached):
    """Given out = D^-1 f and X = D^-1 G^T (chain 1), solve the Schur complement (G X) lam = G out + beta g
    and set out -= X lam: the rates of the Baumgarte-stabilised saddle point. cached: cos th_i, sin th_i
    are in CS[i, 2], CS[i, 3] (else computed; the same numbers either way)."""
    g0 = -n * (1.0 - delta)
    g1 = 0.0
    for i in range(n):
        if cached:
            g0 += CS[i, 2]
            g1 += CS[i, 3]
        else:
            g0 += math.cos(th[i])
            g1 += math.sin(th[i])
    # Schur complement S = G X, right side G y + beta g
    s00 = 0.0
    s01 = 0.0
    s10 = 0.0
    s11 = 0.0
    r0 = beta * g0
    r1 = beta * g1
    for i in range(n):
        if cached:
            ci = CS[i, 2]
            si = CS[i, 3]
        else:
            ci = math.cos(th[i])
            si = math.sin(th[i])
        s00 -= si * X[i, 0]
        s01 -= si * X[i, 1]
        s10 += ci * X[i, 0]
        s11 += ci * X[i, 1]
        r0 -= si * out[i]
        r1 += ci * out[i]
    det = s00 * s11 - s01 * s10
    l0 = (s11 * r0 - s01 * r1) / det
    l1 = (s00 * r1 - s10 * r0) / det
    lam[0] = l0
    lam[1] = l1
    for i in range(n):
        out[i] -= X[i, 0] * l0 + X[i, 1] * l1


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
def eval_rhs_dense(th, fac, system, beta, out, L, D, X, lam):
    """out = th' at th (force factors fac, Baumgarte rate beta) by dense Cholesky, O(N^3); leaves Cholesky
    factors in L, D^-1 G^T in X, multipliers in lam (L, D, X, lam: a dense workspace, L (nch, n, n),
    D (n, n), X (n, 2), lam (2))."""
    n = system.n
    nch = system.n_chains
    if L.shape[0] < nch or L.shape[1] < n or D.shape[0] < n or D.shape[1] < n or X.shape[0] < n:
        raise ValueError("eval_rhs_dense needs a dense workspace (L of shape (n_chains, n, n), D (n, n))")
    _chain_forces(th, fac, system, out)
    for ch in range(nch):
        _drag_block_cached(th, ch * n, n, system.gamma_l, system.gamma_t, D, X)  # X: scratch until the pins
        cholesky(D, L[ch])
        chol_solve(L[ch], out, ch * n)
    if system.pinned:
        for i in range(n):
            X[i, 0] = -math.sin(th[i])
            X[i, 1] = math.cos(th[i])
        chol_solve_cols(L[0], X, 0)
        _pin_correction(th, n, beta, system.delta, out, X, lam, X, False)


@njit(cache=True, error_model="numpy")  # no zero-division checks: d_k >= gamma_T > 0
def articulated_solve(off, n, gl, gt, b, U, X, ncols):
    """Solve D w = b[off:off+n] in place for the chain of angles th[off:off+n] in O(N) by the articulated-drag
    recursion (equations.py), and with ncols = 2 also D Y = G^T (G^T = (-sin th_i, cos th_i) as columns,
    the pinned chain's constraint directions), written into X[:n, :2]. U: rows off .. off+n-1 hold
    (., ., cos th_k, sin th_k) on entry; columns 0-1 (A_k n_k / d_k) are scratch."""
    # backward pass: alpha = longitudinal articulated drag of the subchain beyond joint k, along
    # e_{k+1}; (bx, by), (px, py), (qx, qy) = its bias force B, one per right-hand side
    alpha = 0.0
    c1 = 1.0
    s1 = 0.0
    bx = 0.0
    by = 0.0
    px = 0.0
    py = 0.0
    qx = 0.0
    qy = 0.0
    for k in range(n - 1, -1, -1):
        c = U[off + k, 2]
        s = U[off + k, 3]
        sd = s1 * c - c1 * s  # e_{k+1} . n_k = sin(th_{k+1} - th_k)
        cd = c1 * c + s1 * s  # e_{k+1} . e_k = cos(th_{k+1} - th_k)
        # A_k = gl e_k e_k^T + gt n_k n_k^T + alpha e_{k+1} e_{k+1}^T;  a = A_k n_k, d = n_k^T A_k n_k
        t = alpha * sd
        ax = -gt * s + t * c1
        ay = gt * c + t * s1
        d = gt + t * sd
        r = 1.0 / d
        # q_k = (b_k - n_k . B) / d, stored in place of b_k; then B += a q_k
        qk = (b[off + k] + s * bx - c * by) * r
        b[off + k] = qk
        bx += ax * qk
        by += ay * qk
        if ncols == 2:
            x0 = (-s + s * px - c * py) * r
            x1 = (c + s * qx - c * qy) * r
            X[k, 0] = x0
            X[k, 1] = x1
            px += ax * x0
            py += ay * x0
            qx += ax * x1
            qy += ay * x1
        U[off + k, 0] = ax * r
        U[off + k, 1] = ay * r
        # alpha_k = det(A_k) / (n_k^T A_k n_k)
        alpha = (gl * gt + alpha * (gl * sd * sd + gt * cd * cd)) * r
        c1 = c
        s1 = s
    # forward pass: w_k = q_k - (A_k n_k / d_k) . v_{k-1},  v_k = v_{k-1} + n_k w_k
    vx = 0.0
    vy = 0.0
    ux0 = 0.0
    uy0 = 0.0
    ux1 = 0.0
    uy1 = 0.0
    for k in range(n):
        gx = U[off + k, 0]
        gy = U[off + k, 1]
        c = U[off + k, 2]
        s = U[off + k, 3]
        w = b[off + k] - (gx * vx + gy * vy)
        b[off + k] = w
        vx -= s * w
        vy += c * w
        if ncols == 2:
            w0 = X[k, 0] - (gx * ux0 + gy * uy0)
            w1 = X[k, 1] - (gx * ux1 + gy * uy1)
            X[k, 0] = w0
            X[k, 1] = w1
            ux0 -= s * w0
            uy0 += c * w0
            ux1 -= s * w1
            uy1 += c * w1


@njit(cache=True)
def _forces_cached(th, fac, off, n, sigma, c, clamped, CS, out):
    """forces() with cos th_k, sin th_k read from CS[k, 2], CS[k, 3] (the same numbers, the same arithmetic)."""
    for i in range(n):
        f = 0.0
        if i == 0:
            if clamped:
                f -= c * th[off]
        else:
            f += c * (th[off + i - 1] - th[off + i])
        if i < n - 1:
            f += c * (th[off + i + 1] - th[off + i])
        out[off + i] = f
    px = 0.0
    py = 0.0
    for k in range(n - 1, -1, -1):
        ck = CS[off + k, 2]
        sk = CS[off + k, 3]
        px -= sigma * fac[off + k] * ck
        py -= sigma * fac[off + k] * sk
        out[off + k] += -sk * px + ck * py


@njit(cache=True)
def eval_rhs_recursive(th, fac, system, beta, out, U, X, lam):
    """out = th' at th (force factors fac, Baumgarte rate beta) by the O(N) articulated-drag recursion;
    leaves D^-1 G^T in X and the multipliers in lam (pinned). U (n_angles, 4), X (n, 2), lam (2): scratch
    (a recursive workspace's D, X, lam); one cosine and sine per angle, kept in U."""
    n = system.n
    nch = system.n_chains
    if U.shape[0] < n * nch or U.shape[1] < 4 or X.shape[0] < n:
        raise ValueError("eval_rhs_recursive needs scratch U of shape (n_angles, 4) and X (n, 2)")
    for i in range(n * nch):
        U[i, 2] = math.cos(th[i])
        U[i, 3] = math.sin(th[i])
    for ch in range(nch):
        c = 1.0 if ch == 0 else system.rho
        _forces_cached(th, fac, ch * n, n, system.sigma, c, system.clamped, U, out)
    if nch == 2:
        d = system.kappa * (th[0] - th[n])
        out[0] -= d
        out[n] += d
    if system.closed:
        _closure(th, n, out)
    for ch in range(nch):
        ncols = 2 if (system.pinned and ch == 0) else 0
        articulated_solve(ch * n, n, system.gamma_l, system.gamma_t, out, U, X, ncols)
    if system.pinned:
        _pin_correction(th, n, beta, system.delta, out, X, lam, U, True)


@njit(cache=True)
def eval_jacobian(th, system, beta, J, L, D, X, lam):
    """Analytic Jacobian d(th')/d(th) of the deterministic ODE (fac = 1), written into J. O(N^3): it
    reuses the dense path's Cholesky factors, so L, D, X, lam must be a dense workspace."""
    n = system.n
    nch = system.n_chains
    fac = np.ones(n * nch)
    w = np.empty(n * nch)
    eval_rhs_dense(th, fac, system, beta, w, L, D, X, lam)
    _jacobian_forces(th, w, system, J, lam)
    for ch in range(nch):
        chol_solve_cols(L[ch], J, ch * n)
    _jacobian_pins(th, w, system, beta, J, X)


@njit(cache=True)
def eval_jacobian_recursive(th, system, beta, J, U, X, lam):
    """The same Jacobian as eval_jacobian with D^-1 applied column by column by the O(N) articulated-drag
    recursion (articulated_solve): O(N^2) instead of O(N^3), equal to round-off. U, X, lam: a recursive
    workspace's D, X, lam. What makes an implicit method affordable on long chains (solve.jacobian)."""
    n = system.n
    nch = system.n_chains
    fac = np.ones(n * nch)
    w = np.empty(n * nch)
    eval_rhs_recursive(th, fac, system, beta, w, U, X, lam)
    _jacobian_forces(th, w, system, J, lam)
    col = np.empty(n)
    for ch in range(nch):
        off = ch * n
        for m in range(n * nch):
            for i in range(n):
                col[i] = J[off + i, m]
            articulated_solve(0, n, system.gamma_l, system.gamma_t, col, U[off:off + n], X, 0)  # X untouched
            for i in range(n):
                J[off + i, m] = col[i]
    _jacobian_pins(th, w, system, beta, J, X)


@njit(cache=True)
def _jacobian_forces(th, w, system, J, lam):
    """J = d(f - D(th) w)/d(th) at fixed w = th' (springs, follower forces, the drag's own derivative, the
    pair's coupling, the pins' multipliers lam): the Jacobian before D^-1 is applied."""
    n = system.n
    nch = system.n_chains
    clamped = system.clamped
    pinned = system.pinned
    sigma = system.sigma
    gl = system.gamma_l
    gt = system.gamma_t
    kappa = system.kappa
    rho = system.rho
    R = J
    R[:, :] = 0.0
    cs = np.cos(th)
    sn = np.sin(th)
    sxx = np.empty(n)
    sxy = np.empty(n)
    syy = np.empty(n)
    hx = np.empty(n)
    hy = np.empty(n)
    vx = np.empty(n)
    vy = np.empty(n)
    for ch in range(nch):
        off = ch * n
        c = 1.0 if ch == 0 else rho
        # springs: -Hessian of U
        for i in range(n):
            diag = 0.0
            if i == 0:
                if clamped:
                    diag += c
            else:
                diag += c
                R[off + i, off + i - 1] += c
            if i < n - 1:
                diag += c
                R[off + i, off + i + 1] += c
            R[off + i, off + i] -= diag
        # follower forces
        px = 0.0
        py = 0.0
        for k in range(n - 1, -1, -1):
            ck = cs[off + k]
            sk = sn[off + k]
            R[off + k, off + k] -= ck * px + sk * py
            for m in range(k + 1, n):
                R[off + k, off + m] -= sigma * (ck * cs[off + m] + sk * sn[off + m])
            px -= sigma * ck
            py -= sigma * sk
        # drag: P[k, m] = d(D w)_k / d th_m at fixed w
        ax = 0.0
        ay = 0.0
        for i in range(n):
            ax -= sn[off + i] * w[off + i]
            ay += cs[off + i] * w[off + i]
            vx[i] = ax
            vy[i] = ay
        a = 0.0
        b = 0.0
        d = 0.0
        qx = 0.0
        qy = 0.0
        for m in range(n - 1, -1, -1):
            cm = cs[off + m]
            sm = sn[off + m]
            wxx = gl * cm * cm + gt * sm * sm
            wxy = (gl - gt) * cm * sm
            wyy = gl * sm * sm + gt * cm * cm
            a += wxx
            b += wxy
            d += wyy
            sxx[m] = a
            sxy[m] = b
            syy[m] = d
            qx += wxx * vx[m] + wxy * vy[m]
            qy += wxy * vx[m] + wyy * vy[m]
            hx[m] = qx
            hy[m] = qy
        for k in range(n):
            ck = cs[off + k]
            sk = sn[off + k]
            # -delta_km e_k . H_k
            R[off + k, off + k] += ck * hx[k] + sk * hy[k]
            for m in range(n):
                cm = cs[off + m]
                sm = sn[off + m]
                p = 0.0
                if m >= k:
                    # n_k . W'_m v_m, W'_m = (gl - gt)(n e^T + e n^T)
                    el = cm * vx[m] + sm * vy[m]
                    et = -sm * vx[m] + cm * vy[m]
                    ux = (gl - gt) * (-sm * el + cm * et)
                    uy = (gl - gt) * (cm * el + sm * et)
                    p += -sk * ux + ck * uy
                    q = m
                else:
                    q = k
                # - w_m n_k^T S_q e_m
                tx = sxx[q] * cm + sxy[q] * sm
                ty = sxy[q] * cm + syy[q] * sm
                p -= w[off + m] * (-sk * tx + ck * ty)
                R[off + k, off + m] -= p
    if nch == 2:
        R[0, 0] -= kappa
        R[0, n] += kappa
        R[n, n] -= kappa
        R[n, 0] += kappa
    if system.closed:
        R[0, 0] -= 1.0
        R[0, n - 1] += 1.0
        R[n - 1, n - 1] -= 1.0
        R[n - 1, 0] += 1.0
    if pinned:
        for m in range(n):
            R[m, m] += cs[m] * lam[0] + sn[m] * lam[1]


@njit(cache=True)
def _jacobian_pins(th, w, system, beta, J, X):
    """The pinned chain's part of the Jacobian (nothing without pins): J, already D^-1 times the forces' part,
    minus D^-1 G^T (X) times the derivative of the multipliers (the saddle point's Schur complement)."""
    n = system.n
    pinned = system.pinned
    R = J
    cs = np.cos(th)
    sn = np.sin(th)
    if pinned:
        # Schur complement of the derivative of the saddle-point system
        s00 = 0.0
        s01 = 0.0
        s10 = 0.0
        s11 = 0.0
        for i in range(n):
            s00 -= sn[i] * X[i, 0]
            s01 -= sn[i] * X[i, 1]
            s10 += cs[i] * X[i, 0]
            s11 += cs[i] * X[i, 1]
        det = s00 * s11 - s01 * s10
        for m in range(n):
            gy0 = 0.0
            gy1 = 0.0
            for i in range(n):
                gy0 -= sn[i] * R[i, m]
                gy1 += cs[i] * R[i, m]
            # minus the second block row: -(-beta G[:, m] + w_m (cos, sin))
            r0 = gy0 - (beta * sn[m] + w[m] * cs[m])
            r1 = gy1 - (-beta * cs[m] + w[m] * sn[m])
            b0 = (s11 * r0 - s01 * r1) / det
            b1 = (s00 * r1 - s10 * r0) / det
            for i in range(n):
                R[i, m] -= X[i, 0] * b0 + X[i, 1] * b1


# ----------------------------------------------------------------------------------------------
# the extended terms: a free head, a harmonic trap, self-contact (equations.py, contact.py)
# ----------------------------------------------------------------------------------------------
CONTACT_LENGTH = _CONTACT_LENGTH
CROSSING_DISTANCE = _CROSSING_DISTANCE


@njit(cache=True)
def is_extended(system):
    """Whether any extended term is on (ChainSystem.extended): head_free, trap > 0 or contact_radius > 0."""
    return system.head_free or system.trap > 0.0 or system.contact_radius > 0.0


@njit(cache=True)
def make_general_workspace(nch, n, nq):
    """Scratch arrays (L, D, X, lam) of eval_rhs_general for nch chains of n particles and nq coordinates (n nch,
    plus 2 with a free head): L (2, nq, nq) (L[0] the Cholesky factor, L[1] the drag matrix D), D (nch n, 8)
    per-link records (cos, sin, pivot x, y, node force x, y, scratch), X (nq, 2) D^-1 G^T (pinned), lam (2)."""
    return np.zeros((2, nq, nq)), np.zeros((nch * n, 8)), np.zeros((nq, 2)), np.zeros(2)


@njit(cache=True)
def _general_geometry(y, system, C):
    """C[i, 0:4] = (cos th_i, sin th_i, pivot P_{i-1} x, y) of every link (the pivot of link 0: the head when
    head_free, else the origin); C[i, 4:6] = the trap's force -trap P_i on particle i."""
    n = system.n
    na = n * system.n_chains
    k = system.trap
    for ch in range(system.n_chains):
        off = ch * n
        px = 0.0
        py = 0.0
        if system.head_free and ch == 0:
            px = y[na]
            py = y[na + 1]
        for i in range(n):
            c = math.cos(y[off + i])
            s = math.sin(y[off + i])
            C[off + i, 0] = c
            C[off + i, 1] = s
            C[off + i, 2] = px
            C[off + i, 3] = py
            px += c
            py += s
            C[off + i, 4] = -k * px
            C[off + i, 5] = -k * py


@njit(cache=True)
def _end_contact(C, off, own, other, s_end, s_a, s_b, radius, stiffness):
    """The penalty of the core end at fraction s_end of link `own` against the core of link `other` (contact.py):
    adds the force on the end and the opposite on its closest point to the node forces C[., 4:6] (a force F at
    fraction s of link i: (1 - s) F to its pivot P_{i-1}, s F to particle i). Returns (force on the chain's pivot
    x, y, energy)."""
    span = s_b - s_a
    co = C[off + own, 0]
    so = C[off + own, 1]
    px = C[off + own, 2] + s_end * co
    py = C[off + own, 3] + s_end * so
    ct = C[off + other, 0]
    st = C[off + other, 1]
    ax = C[off + other, 2] + s_a * ct
    ay = C[off + other, 3] + s_a * st
    dx = span * ct
    dy = span * st
    t = min(max(((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
    cx = ax + t * dx
    cy = ay + t * dy
    sx = px - cx
    sy = py - cy
    dist = math.hypot(sx, sy)
    two_r = 2.0 * radius
    if dist >= two_r:
        return 0.0, 0.0, 0.0
    if dist > CROSSING_DISTANCE:
        ux = sx / dist
        uy = sy / dist
    else:  # the end on the other core: along its normal, away on the side of the end's own core midpoint
        mx = C[off + own, 2] + 0.5 * (s_a + s_b) * co
        my = C[off + own, 3] + 0.5 * (s_a + s_b) * so
        if (mx - cx) * (-st) + (my - cy) * ct >= 0.0:
            ux = -st
            uy = ct
        else:
            ux = st
            uy = -ct
        dist = 0.0
    overlap = two_r - dist
    fx = stiffness * overlap * ux
    fy = stiffness * overlap * uy
    hx = 0.0
    hy = 0.0
    # +F on link own at s_end, -F on link other at s_a + t span
    C[off + own, 4] += s_end * fx
    C[off + own, 5] += s_end * fy
    if own == 0:
        hx += (1.0 - s_end) * fx
        hy += (1.0 - s_end) * fy
    else:
        C[off + own - 1, 4] += (1.0 - s_end) * fx
        C[off + own - 1, 5] += (1.0 - s_end) * fy
    s_o = s_a + t * span
    C[off + other, 4] -= s_o * fx
    C[off + other, 5] -= s_o * fy
    if other == 0:
        hx -= (1.0 - s_o) * fx
        hy -= (1.0 - s_o) * fy
    else:
        C[off + other - 1, 4] -= (1.0 - s_o) * fx
        C[off + other - 1, 5] -= (1.0 - s_o) * fy
    return hx, hy, 0.5 * stiffness * overlap * overlap


@njit(cache=True)
def _chain_contact(C, off, n, radius, stiffness):
    """Add the contact penalty's forces of one chain (links off .. off + n - 1 of C, _general_geometry) to the node
    forces C[., 4:6]: for every pair of non-adjacent links, each of the four core ends against the other core
    (_end_contact, contact.py). Returns (force on the chain's pivot x, y, U_contact). Pairs whose cores' midpoints
    are farther apart than the core length plus 2R cannot touch and are skipped."""
    s_a = (1.0 - CONTACT_LENGTH) / 2.0 + radius
    s_b = (1.0 + CONTACT_LENGTH) / 2.0 - radius
    reach = (s_b - s_a) + 2.0 * radius
    reach2 = reach * reach
    hx = 0.0
    hy = 0.0
    energy = 0.0
    for i in range(n):
        mix = C[off + i, 2] + 0.5 * C[off + i, 0]
        miy = C[off + i, 3] + 0.5 * C[off + i, 1]
        for j in range(i + 2, n):
            dx = mix - (C[off + j, 2] + 0.5 * C[off + j, 0])
            dy = miy - (C[off + j, 3] + 0.5 * C[off + j, 1])
            if dx * dx + dy * dy > reach2:
                continue
            for own, other in ((i, j), (j, i)):
                for s_end in (s_a, s_b):
                    fx, fy, u = _end_contact(C, off, own, other, s_end, s_a, s_b, radius, stiffness)
                    hx += fx
                    hy += fy
                    energy += u
    return hx, hy, energy


@njit(cache=True)
def _node_forces(y, system, C):
    """The geometry (_general_geometry) and the node forces of the trap and the contact penalty: C[i, 4:6] on
    particle i, C[off, 6:8] on the pivot of the chain starting at row off. Returns U_contact."""
    n = system.n
    _general_geometry(y, system, C)
    energy = 0.0
    for ch in range(system.n_chains):
        off = ch * n
        # the trap's force on the pivot (zero for a pivot fixed at the origin)
        C[off, 6] = -system.trap * C[off, 2]
        C[off, 7] = -system.trap * C[off, 3]
        if system.contact_radius > 0.0:
            cx, cy, u = _chain_contact(C, off, n, system.contact_radius, system.contact_stiffness)
            C[off, 6] += cx
            C[off, 7] += cy
            energy += u
    return energy


@njit(cache=True)
def _project_node_forces(fac, system, C, out):
    """Add the generalised forces of the node forces C[:, 4:6] (particles) to the angles' entries of out,
    n_k . sum_{i >= k} F_i, and set the head's: all node forces, the pivot's C[0, 6:8] and the follower forces."""
    n = system.n
    na = n * system.n_chains
    for ch in range(system.n_chains):
        off = ch * n
        fx = 0.0
        fy = 0.0
        ax = 0.0
        ay = 0.0
        for k in range(n - 1, -1, -1):
            c = C[off + k, 0]
            s = C[off + k, 1]
            fx += C[off + k, 4]
            fy += C[off + k, 5]
            out[off + k] += -s * fx + c * fy
            ax -= system.sigma * fac[off + k] * c
            ay -= system.sigma * fac[off + k] * s
        if system.head_free and ch == 0:
            out[na] = fx + C[off, 6] + ax
            out[na + 1] = fy + C[off, 7] + ay


@njit(cache=True)
def general_forces(y, fac, system, C, out):
    """out[:nq] = f(q): the generalised forces of the state y (angles, then the free head) with every term:
    springs, follower forces, the pair's coupling, the trap on the particles and the head, the contact penalty
    (the pinned chain's constraint forces are not in it). C: the (n_angles, 8) records of make_general_workspace;
    on return C[:, 0:4] hold the geometry (_general_geometry). Returns U_contact."""
    _chain_forces(y, fac, system, out)  # springs, follower forces, coupling (angles only)
    energy = _node_forces(y, system, C)
    _project_node_forces(fac, system, C, out)
    return energy


@njit(cache=True)
def general_mass(system, C, A):
    """A[:nq, :nq] = M(q) of the inertial model over the angles and the free head, from the geometry C: the angle
    blocks as mass_block, M_{k,h} = m (N - k) n_k (0-based k: the particles k .. N-1 move with both), and the head's
    bead (one particle's mass m at the pivot, turning with the first pendulum, as MuJoCo's paraboloid scene
    builds it): M_hh = m (N + 1) 1, and m inertia_factor more on th_0."""
    n = system.n
    na = n * system.n_chains
    m = system.mass_ratio
    ifac = system.inertia_factor
    A[:, :] = 0.0
    for ch in range(system.n_chains):
        off = ch * n
        for j in range(n):
            cj = C[off + j, 0]
            sj = C[off + j, 1]
            for k in range(j, n):
                v = m * (n - k) * (cj * C[off + k, 0] + sj * C[off + k, 1])
                A[off + j, off + k] = v
                A[off + k, off + j] = v
            A[off + j, off + j] += m * ifac
        if system.head_free and ch == 0:
            for k in range(n):
                vx = -m * (n - k) * C[off + k, 1]
                vy = m * (n - k) * C[off + k, 0]
                A[off + k, na] = vx
                A[na, off + k] = vx
                A[off + k, na + 1] = vy
                A[na + 1, off + k] = vy
            A[na, na] = m * (n + 1)
            A[na + 1, na + 1] = m * (n + 1)
            A[off, off] += m * ifac


@njit(cache=True, inline="always")
def _particle_forces(CS, off, cc, sc, y, woff, n, vx, vy, gl, gt, m, P, pc, add):
    """The particles' drag and centripetal forces P_i = -W_i v_i - m a_i of the inertial model along one chain
    (eval_rhs_inertial, eval_rhs_inertial_general), v_i and a_i (centripetal) as prefix sums from the pivot's
    velocity (vx, vy): cos th_i, sin th_i read from CS[off + i, cc], CS[off + i, sc], the rates om_i = y[woff + i];
    P_i written into P[off + i, pc], P[off + i, pc + 1] (add: added to what is there). Inlined into its callers
    (inline="always", as _pin_acceleration): the same arithmetic in the same order as the loops it replaced."""
    ax = 0.0
    ay = 0.0
    for i in range(n):
        c = CS[off + i, cc]
        s = CS[off + i, sc]
        w = y[woff + i]
        vx -= s * w
        vy += c * w
        ax -= c * w * w
        ay -= s * w * w
        el = c * vx + s * vy
        et = -s * vx + c * vy
        fx = -(gl * el * c - gt * et * s) - m * ax
        fy = -(gl * el * s + gt * et * c) - m * ay
        if add:
            P[off + i, pc] += fx
            P[off + i, pc + 1] += fy
        else:
            P[off + i, pc] = fx
            P[off + i, pc + 1] = fy


@njit(cache=True, inline="always")
def _pin_acceleration(CS, cc, sc, y, woff, n, beta, delta, L0, X, acc, lam):
    """The pinned chain's Baumgarte-stabilised acceleration constraint G om' = -G' om - 2 beta G om - beta^2 g of
    the inertial model (eval_rhs_inertial, eval_rhs_inertial_general), through the 2 x 2 Schur complement: given
    the unconstrained accelerations a0 = M^-1 (f - D om - c) in acc[:n] and the Cholesky factor L0 of M, sets
    acc[:n] = a0 - X lam with X = M^-1 G^T (left in X) and the multipliers lam. cos th_i, sin th_i are read from
    CS[i, cc], CS[i, sc]; the rates om_0 .. om_{n-1} of chain 1 from y[woff:]. Inlined into its callers
    (inline="always"): a plain call measured ~15 % slower per pinned inertial evaluation (N = 7)."""
    # g, G om and G' om (G' om = -(sum cos th_i om_i^2, sum sin th_i om_i^2)); X = M^-1 G^T
    g0 = -n * (1.0 - delta)
    g1 = 0.0
    v0 = 0.0
    v1 = 0.0
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        c = CS[i, cc]
        s = CS[i, sc]
        w = y[woff + i]
        g0 += c
        g1 += s
        v0 -= s * w
        v1 += c * w
        d0 -= c * w * w
        d1 -= s * w * w
        X[i, 0] = -s
        X[i, 1] = c
    chol_solve_cols(L0, X, 0)
    # (G X) lam = G a0 + G' om + 2 beta G om + beta^2 g;  om' = a0 - X lam
    s00 = 0.0
    s01 = 0.0
    s10 = 0.0
    s11 = 0.0
    r0 = d0 + 2.0 * beta * v0 + beta * beta * g0
    r1 = d1 + 2.0 * beta * v1 + beta * beta * g1
    for i in range(n):
        c = CS[i, cc]
        s = CS[i, sc]
        s00 -= s * X[i, 0]
        s01 -= s * X[i, 1]
        s10 += c * X[i, 0]
        s11 += c * X[i, 1]
        r0 -= s * acc[i]
        r1 += c * acc[i]
    det = s00 * s11 - s01 * s10
    l0 = (s11 * r0 - s01 * r1) / det
    l1 = (s00 * r1 - s10 * r0) / det
    lam[0] = l0
    lam[1] = l1
    for i in range(n):
        acc[i] -= X[i, 0] * l0 + X[i, 1] * l1


@njit(cache=True)
def eval_rhs_inertial_general(y, fac, system, beta, out, L, C, X, lam):
    """out = (q', q'') at y = (q, q') of the inertial model with the extended terms (a free head, the trap,
    self-contact): M q'' = f(q) - D q' - c(q, q') with every force taken as node forces (the particles' drag and
    centripetal terms as in eval_rhs_inertial; the head's bead: one particle's mass and drag), M by general_mass,
    dense Cholesky; the pinned chain's acceleration constraint as in eval_rhs_inertial. L, C, X, lam:
    make_general_workspace with nq position coordinates."""
    n = system.n
    nch = system.n_chains
    na = n * nch
    nq = na + (2 if system.head_free else 0)
    m = system.mass_ratio
    gl = system.gamma_l
    gt = system.gamma_t
    if (L.shape[0] < 2 or L.shape[1] != nq or L.shape[2] != nq or C.shape[0] < na or C.shape[1] < 8
            or X.shape[0] < nq):
        raise ValueError("eval_rhs_inertial_general needs make_general_workspace's arrays: L (2, nq, nq), C (n_angles, 8), X (nq, 2)")
    if y.size < 2 * nq or out.size < 2 * nq:
        raise ValueError("eval_rhs_inertial_general: the state holds 2 nq numbers (positions, then rates)")
    for i in range(nq):
        out[i] = y[nq + i]
    acc = out[nq:]
    _chain_forces(y, fac, system, acc)  # springs, follower forces, coupling (angles)
    _node_forces(y, system, C)  # geometry, trap, contact
    for ch in range(nch):
        off = ch * n
        vx = 0.0
        vy = 0.0
        if system.head_free and ch == 0:  # the head's drag on its velocity
            vx = y[nq + na]
            vy = y[nq + na + 1]
            c = C[off, 0]
            s = C[off, 1]
            el = c * vx + s * vy
            et = -s * vx + c * vy
            C[off, 6] -= gl * el * c - gt * et * s
            C[off, 7] -= gl * el * s + gt * et * c
        _particle_forces(C, off, 0, 1, y, nq + off, n, vx, vy, gl, gt, m, C, 4, True)
    _project_node_forces(fac, system, C, acc)
    general_mass(system, C, L[1])
    cholesky(L[1], L[0])
    chol_solve(L[0], out, nq)
    if system.pinned:  # as eval_rhs_inertial (no head: nq = n)
        _pin_acceleration(C, 0, 1, y, nq, n, beta, system.delta, L[0], X, acc, lam)


@njit(cache=True)
def general_drag(system, C, A):
    """A[:nq, :nq] = D(q) over the angles and the free head, from the geometry C (_general_geometry): the angle
    blocks as drag_block (suffix sums S_m of W_i), D_{k,h} = S_k n_k, D_hh = S_0 + W(th_0) (the head's drag);
    zero between the chains of a pair."""
    n = system.n
    na = n * system.n_chains
    gl = system.gamma_l
    gt = system.gamma_t
    A[:, :] = 0.0
    for ch in range(system.n_chains):
        off = ch * n
        head = system.head_free and ch == 0
        sxx = 0.0
        sxy = 0.0
        syy = 0.0
        for m in range(n - 1, -1, -1):
            cm = C[off + m, 0]
            sm = C[off + m, 1]
            sxx += gl * cm * cm + gt * sm * sm
            sxy += (gl - gt) * cm * sm
            syy += gl * sm * sm + gt * cm * cm
            for j in range(m + 1):
                cj = C[off + j, 0]
                sj = C[off + j, 1]
                v = sj * sm * sxx - (sj * cm + cj * sm) * sxy + cj * cm * syy
                A[off + j, off + m] = v
                A[off + m, off + j] = v
            if head:
                vx = -sm * sxx + cm * sxy
                vy = -sm * sxy + cm * syy
                A[off + m, na] = vx
                A[na, off + m] = vx
                A[off + m, na + 1] = vy
                A[na + 1, off + m] = vy
        if head:
            c0 = C[off, 0]
            s0 = C[off, 1]
            A[na, na] = sxx + gl * c0 * c0 + gt * s0 * s0
            v = sxy + (gl - gt) * c0 * s0
            A[na, na + 1] = v
            A[na + 1, na] = v
            A[na + 1, na + 1] = syy + gl * s0 * s0 + gt * c0 * c0


@njit(cache=True)
def eval_rhs_general(y, fac, system, beta, out, L, C, X, lam):
    """out = q' at the state q = y (the angles, then the free head) with every term on (equations.py: a free
    head, a harmonic trap and self-contact): f by general_forces, D by general_drag (O(N^2) each), dense
    Cholesky (L[0]; L[1] holds D); the pinned chain's Baumgarte saddle point as in eval_rhs_dense (X = D^-1 G^T,
    multipliers in lam). L, C, X, lam: make_general_workspace."""
    n = system.n
    na = n * system.n_chains
    nq = na + (2 if system.head_free else 0)
    if (L.shape[0] < 2 or L.shape[1] != nq or L.shape[2] != nq or C.shape[0] < na or C.shape[1] < 8
            or X.shape[0] < nq):
        raise ValueError("eval_rhs_general needs make_general_workspace's arrays: L (2, nq, nq), C (n_angles, 8), X (nq, 2)")
    if y.size < nq or out.size < nq:
        raise ValueError("eval_rhs_general: the state holds n_angles numbers, plus 2 with a free head")
    general_forces(y, fac, system, C, out)
    general_drag(system, C, L[1])
    cholesky(L[1], L[0])
    chol_solve(L[0], out, 0)
    if system.pinned:
        for i in range(n):
            X[i, 0] = -C[i, 1]
            X[i, 1] = C[i, 0]
        chol_solve_cols(L[0], X, 0)
        _pin_correction(y, n, beta, system.delta, out, X, lam, C, False)


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
def _sde_workspace(system, na):
    """The workspace (L, D, X, lam) of eval_rhs in euler_maruyama and heun for a state of na numbers:
    make_general_workspace's arrays with an extended term (the state: angles, then the free head), else
    make_workspace's (dense below RECURSIVE_MIN_N), allocated as dop853._dop853 allocates them."""
    n = system.n
    nch = system.n_chains
    if is_extended(system):  # make_general_workspace
        L = np.zeros((2, na, na))
        D = np.zeros((nch * n, 8))
        X = np.zeros((na, 2))
    else:
        m = 0 if uses_recursive(n) else n  # make_workspace
        L = np.zeros((nch, m, m))
        D = np.zeros((n, n)) if m == n else np.zeros((nch * n, 4))
        X = np.zeros((n, 2))
    return L, D, X, np.zeros(2)


@njit(cache=True)
def euler_maruyama(y, k0, facs, dt, system, beta, sidx, out, jptr):
    """Advance y (in place) through steps k0 .. k0 + len(facs) - 1, recording out[j] = state after sidx[j] steps."""
    na = y.size
    L, D, X, lam = _sde_workspace(system, na)
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
    L, D, X, lam = _sde_workspace(system, na)
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
    steps, elastoactive.noise): steps k0 .. k0 + len(facs) - 1 of dt, each by nsub classical RK4 substeps
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

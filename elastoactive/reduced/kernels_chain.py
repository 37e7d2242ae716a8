"""The reduced model's compiled kernels for chains of angles: the drag matrix (dense, and the O(N) articulated-drag
recursion), the springs and follower forces (ChainSystem.closed: the ring's closing spring), the pins' Baumgarte
correction, the dense and recursive right-hand sides and their analytic Jacobian.

Part of elastoactive.reduced.kernels, which documents the whole (the two solvers, the workspaces, which
path runs when) and is where the rest of the package imports these from.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_TWO_PI = 2.0 * math.pi

RECURSIVE_MIN_N = 2
"""Particles per chain from which eval_rhs solves by the O(N) recursion instead of dense Cholesky: every chain.

The recursion is faster at every N >= 2 (numba, one core; us per evaluation, one chain / two-pinned): N = 2: 0.19 /
0.23 against 0.27 / 0.41 dense; N = 7: 0.32 / 0.37 against 0.54 / 0.91; N = 9: 0.38 / 0.43 against 0.68 / 1.25;
N = 100: 2.7 / 3.0 against 95 / 107. Inside the compiled DOP853 the paper's N = 7 pair runs 1000 tau in 0.15 s
against 0.40 s dense, in the same steps (the two agree to round-off). The dense path stays for the Jacobian's
factors (workspace(dense=True)) and a lone particle."""


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
    if system.star:
        _star_clamps(th, system, out)


@njit(cache=True)
def _star_clamps(th, system, out):
    """A star's arms (ChainSystem.star): chain ch's clamp spring refers to alpha_ch + phi (alpha_ch = 2 pi ch /
    n_chains, phi = th[n_angles] the hub's angle when hub_free, else 0) instead of 0: add c (alpha_ch + phi) to the
    clamp force -c th_{ch,0} that forces() wrote (adds exactly 0 for arm 0 on a clamped hub). hub_free: set
    out[n_angles] = -hub_stiffness phi + sum_ch c (th_{ch,0} - alpha_ch - phi), the torque on the hub."""
    n = system.n
    nch = system.n_chains
    na = n * nch
    phi = th[na] if system.hub_free else 0.0
    torque = -system.hub_stiffness * phi
    for ch in range(nch):
        c = 1.0 if ch == 0 else system.rho
        ref = _TWO_PI * ch / nch + phi
        out[ch * n] += c * ref
        torque += c * (th[ch * n] - ref)
    if system.hub_free:
        out[na] = torque


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
    if system.star:
        _star_clamps(th, system, out)
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
            articulated_solve(0, n, system.gamma_l, system.gamma_t, col, U[off : off + n], X, 0)  # X untouched
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

"""The compiled (numba) kernels of the reduced model: drag matrix, forces, right-hand side, Jacobian,
Euler-Maruyama steps and the projection onto the pins.

Every kernel that needs the model's parameters takes the `ChainSystem` record itself (numba compiles a
NamedTuple as a typed record; fields are read by name) and the Baumgarte rate `beta` as a float
argument. The record must come through `ChainSystem.typed()` (the functions of solve.py do that), so
that the field types are always (int64, int64, bool, bool, float64 x 6) and each kernel is compiled,
and cached on disk, once. The formulas are those of equations.py; rhs_reference there is the
plain-numpy twin that tests hold these kernels to.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .system import ChainSystem

__all__ = [
    "chol_solve",
    "chol_solve_cols",
    "cholesky",
    "drag_block",
    "eval_jacobian",
    "eval_rhs",
    "euler_maruyama",
    "forces",
    "restore_pins",
    "workspace",
]


def workspace(system: ChainSystem):
    """Scratch arrays of eval_rhs / eval_jacobian: L (Cholesky factors per chain), D (one drag block),
    X (D^-1 G^T), lam (multipliers)."""
    n, nch = system.n, system.n_chains
    return np.zeros((nch, n, n)), np.zeros((n, n)), np.zeros((n, 2)), np.zeros(2)


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
def eval_rhs(th, fac, system, beta, out, L, D, X, lam):
    """out = th' at th (force factors fac, Baumgarte rate beta); leaves Cholesky factors in L, D^-1 G^T in X,
    multipliers in lam (L, D, X, lam: the arrays of `workspace`)."""
    n = system.n
    nch = system.n_chains
    clamped = system.clamped
    pinned = system.pinned
    sigma = system.sigma
    gl = system.gamma_l
    gt = system.gamma_t
    kappa = system.kappa
    rho = system.rho
    for ch in range(nch):
        c = 1.0 if ch == 0 else rho
        forces(th, fac, ch * n, n, sigma, c, clamped, out)
    if nch == 2:
        d = kappa * (th[0] - th[n])
        out[0] -= d
        out[n] += d
    for ch in range(nch):
        drag_block(th, ch * n, n, gl, gt, D)
        cholesky(D, L[ch])
        chol_solve(L[ch], out, ch * n)
    if pinned:
        delta = system.delta
        g0 = -n * (1.0 - delta)
        g1 = 0.0
        for i in range(n):
            ci = math.cos(th[i])
            si = math.sin(th[i])
            g0 += ci
            g1 += si
            X[i, 0] = -si
            X[i, 1] = ci
        chol_solve_cols(L[0], X, 0)
        # Schur complement S = G X, right side G y + beta g
        s00 = 0.0
        s01 = 0.0
        s10 = 0.0
        s11 = 0.0
        r0 = beta * g0
        r1 = beta * g1
        for i in range(n):
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
def eval_jacobian(th, system, beta, J, L, D, X, lam):
    """Analytic Jacobian d(th')/d(th) of the deterministic ODE (fac = 1), written into J."""
    n = system.n
    nch = system.n_chains
    clamped = system.clamped
    pinned = system.pinned
    sigma = system.sigma
    gl = system.gamma_l
    gt = system.gamma_t
    kappa = system.kappa
    rho = system.rho
    na = n * nch
    fac = np.ones(na)
    w = np.empty(na)
    eval_rhs(th, fac, system, beta, w, L, D, X, lam)
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
    if pinned:
        for m in range(n):
            R[m, m] += cs[m] * lam[0] + sn[m] * lam[1]
    for ch in range(nch):
        chol_solve_cols(L[ch], R, ch * n)
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
def euler_maruyama(y, k0, facs, dt, system, beta, sidx, out, jptr):
    """Advance y (in place) through steps k0 .. k0 + len(facs) - 1, recording out[j] = state after sidx[j] steps."""
    n = system.n
    nch = system.n_chains
    na = y.size
    L = np.zeros((nch, n, n))
    D = np.zeros((n, n))
    X = np.zeros((n, 2))
    lam = np.zeros(2)
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

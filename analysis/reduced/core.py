r"""The reduced (overdamped) model of the elasto-active chains, integrated without MuJoCo.

Derivation (virtual work, units l = C1 = gamma_T = 1)
-----------------------------------------------------
Particle i sits at r_i = sum_{j<=i} e_j with e_j = (cos th_j, sin th_j); put n_j = (-sin th_j, cos th_j).
Then dr_i/dth_k = n_k [k <= i] and v_i = dr_i/dt = sum_{j<=i} n_j th'_j.

* Drag on particle i (longitudinal gamma_L along e_i, transverse gamma_T along n_i):
  F^d_i = -(gamma_L e_i e_i^T + gamma_T n_i n_i^T) v_i.  Its generalised force is
  Q^d_k = sum_{i>=k} n_k . F^d_i = -sum_j D_kj th'_j with, using e_i.n_j = sin(th_i - th_j) and
  n_i.n_j = cos(th_i - th_j),

      D_jk = sum_{i >= max(j,k)} [gamma_L sin(th_i - th_j) sin(th_i - th_k) + gamma_T cos(th_i - th_j) cos(th_i - th_k)],

  symmetric positive definite; isotropic drag gives D_jk = gamma (N - max(j,k) + 1) cos(th_j - th_k).
* Follower force F^a_i = -sigma (1 + eta_i) e_i:  Q_k = sum_{i>=k} n_k . F^a_i = sigma sum_{i>=k} (1 + eta_i) sin(th_k - th_i).
* Springs: U = c/2 th_1^2 (absent on the rotating pin) + c/2 sum_i (th_{i+1} - th_i)^2 with c = 1 for chain 1
  (theta) and c = rho for chain 2 (phi) of the coupled pair, plus U_c = kappa/2 (th_1 - phi_1)^2.
* Without inertia the virtual work of all forces vanishes for every dth, so

      D(th) th' = f(th) := -dU/dth + Q(th)          [+ G^T mu for the two-pinned chain].

  The pair's D is block diagonal (one block per chain, same sigma and drag); its state is [theta, phi].
* Two-pinned chain: g(th) = (sum cos th_i - N (1 - delta), sum sin th_i) = 0, G = dg/dth (2 x N). The
  index-2 DAE is replaced by its Baumgarte-stabilised index-1 form G th' = -beta g, i.e. each RHS
  evaluation solves the saddle-point system  [[D, G^T], [G, 0]] [th'; lam] = [f; -beta g]  (Schur
  complement on the Cholesky factor of D). Drift off g = 0 decays at rate beta (default 10); the largest
  |g| over the samples is reported in Trajectory.info["constraint_violation"].

N = 2 (isotropic, one pinned end) gives exactly the paper's main-text Eqs. (1)-(2):
  2 th1' + cos(th1 - th2) th2' = th2 - 2 th1 + sigma sin(th1 - th2);  cos(th1 - th2) th1' + th2' = th1 - th2.

Where the paper's printed equations are wrong (first principles win; checked in tests/test_reduced.py)
------------------------------------------------------------------------------------------------------
* Appendix C, single chain, equation "i = 1": the drag term reads tau (N th1' + sum_{j>=2} th_j' cos(th1 - th_j));
  the coefficient of th_j' must be (N - j + 1) (= D_1j). The printed form is right only for N = 2 (for
  N >= 3 it misses e.g. the factor 2 = N - j + 1 on th_2' at N = 3; the pair's "i = 1" equations and the
  linear-limit matrix A_ij print the factor correctly, the linear "i = 1" equation again omits it).
* Equation "i = N": the drag sum runs from j = i (= N), i.e. only tau th_N'; it must be sum_{j=1}^{N}
  th_j' cos(th_N - th_j) (row N of D). Same misprint in the pair's and the two-pinned "i = N" equations
  and in the linear limit.
* Supplement, anisotropic drag, N = 2: the printed coefficients (e.g. tau_T/4 (cos 4th1 + 2 cos 2th1 cos 2th2 + 5))
  depend on the absolute angles, so they break the rotation invariance that any drag law defined in the
  pendulum frame has (and that the isotropic limit tau_L = tau_T has). They coincide with the correct
  D = [[tau_T (1 + cos^2 d) + tau_L sin^2 d, tau_T cos d], [tau_T cos d, tau_T]] (d = th1 - th2) at
  th1 = th2 = 0, hence in the linear limit (so the "onset unchanged" claim stands), but not elsewhere:
  at th1 = th2 = pi/4 the printed matrix is half the correct [[2, 1], [1, 1]] tau_T for any tau_L; it is
  not symmetric (at (th1, th2) = (0.3, -0.2): printed D_12 = 0.804, D_21 = 0.990, correct 0.878); and with
  tau_L = tau_T it does not reduce to the isotropic matrix (test_paper_anisotropic_n2_is_wrong).
  Here D_jk above is used for every N.
* The linear-limit matrix A_ij writes the elastic part as tridiag(-1, 2, -1) in every row; the free end
  has K_NN = 1. (With K_NN = 2, sigma_c(7) would be 0.187 instead of 0.157, and N = 2 would lose
  stability through a real eigenvalue at sigma = 3 rather than through a Hopf pair. With the misprinted
  drag rows above, sigma_c(7) would be 0.137.) The paper's sigma_c(7) = 0.15 matches the correct
  equations (0.1575, see analysis.stability), so these are misprints, not errors in its computations.
* N = 2 Landau-Stuart form, z = th1 + i sqrt((1 + mu)/(1 - mu)) th2, mu = sigma - 3: the linear part
  (i + mu) z is right (eigenvalues mu +- i sqrt(1 - mu^2)). The cubic coefficients differ between the
  main text, -(sigma - 5/2) + i (17/4 - sigma) = -1/2 + 5i/4 at sigma = 3, and the supplement,
  -1 - i/8 at mu = 0. Simulating this model near onset (mu = 0.0025 ... 0.01, rtol 1e-11) gives
  mu / <|z|^2> = 0.996, 0.993, 0.985 and (omega - 1) / <|z|^2> = -0.124, -0.122, -0.119, i.e. c -> -1 - i/8:
  the supplement is right, the main text's coefficient is wrong (it would make the limit-cycle radius
  sqrt(2 mu) instead of sqrt(mu) and the frequency rise instead of fall with amplitude).

Integration and the choice of method
------------------------------------
The right-hand side and its analytic Jacobian are compiled with numba. The spectral radius of the
linearised operator D^{-1} K is bounded independently of N (D0^{-1} = B^{-1} B^{-T} with B the lower
triangular matrix of ones, so |lambda| <~ 16 for unit springs and drag): long chains are not stiff,
only slow (their slowest rate falls like N^-4). The default (method=None) is therefore "numba-DOP853",
scipy's DOP853 algorithm (same tableau, error estimator, step control, dense output) compiled together
with the RHS, which avoids the per-step Python overhead of scipy.integrate.solve_ivp: for N = 7,
sigma = 0.8, duration 400, rtol 1e-9 it takes 0.042 s against 2.1 s for solve_ivp(DOP853) on
rhs_reference (0.37 s for solve_ivp on the compiled RHS), with the same steps (results agree to 1e-11);
35-53x over the four scenes. When the
linearisation at theta0 is stiff (fastest decay rate max(-Re lambda) above STIFF_RADIUS, e.g. a pair with kappa >~ 1e3, or
near-singular anisotropic drag), the default switches to scipy's implicit "Radau" with the compiled
analytic Jacobian. Any scipy.integrate.solve_ivp method name can be given explicitly ("DOP853",
"RK45", "Radau", "BDF", "LSODA", ...); implicit ones get the analytic Jacobian.

With noise > 0 the follower forces carry multiplicative white noise and the ODE becomes an Ito SDE,
integrated by fixed-step Euler-Maruyama (step numerics.dt, drift at the step start) with the counter-
based force factors of elastoactive.noise shared with the MuJoCo engine (particles numbered chain 1
then chain 2). For the two-pinned chain each Euler-Maruyama step is followed by a minimum-norm projection
back onto g = 0 (the noise increments, ~ a sqrt(dt), would otherwise leave an O(a^2 dt) drift that the
Baumgarte term only partly removes).
"""

from __future__ import annotations

import math
import time

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp
from scipy.integrate._ivp import dop853_coefficients as _dop

from ..initial import initial_angles, pin_jacobian, pin_residual
from ..noise import force_factor
from ..params import Numerics, ParameterError, Physics
from ..trajectory import Trajectory

__all__ = [
    "DEFAULT_BETA",
    "STIFF_RADIUS",
    "drag_matrix",
    "jacobian",
    "rhs",
    "rhs_reference",
    "simulate_reduced",
    "simulate_reference",
    "spectral_radius",
    "stiffness",
]

DEFAULT_BETA = 10.0
"""Baumgarte rate of the two-pinned constraint drift (per tau)."""

STIFF_RADIUS = 2.0e3
"""Spectral radius of the Jacobian at theta0 above which method=None picks implicit Radau."""

SCIPY_METHODS = ("RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA")
IMPLICIT_METHODS = ("Radau", "BDF", "LSODA")
COMPILED_METHODS = ("numba-DOP853",)


# ----------------------------------------------------------------------------------------------
# packing of the parameters for the compiled kernels
# ----------------------------------------------------------------------------------------------
def _pack(physics: Physics, beta: float):
    ip = np.array(
        [physics.n, physics.n_chains, int(physics.clamped), int(physics.scene == "two-pinned")], dtype=np.int64
    )
    fp = np.array(
        [physics.sigma, physics.drag_ratio, 1.0, physics.kappa, physics.rho, physics.delta, float(beta)],
        dtype=np.float64,
    )
    return ip, fp


def _workspace(n: int, nch: int):
    """L (Cholesky factors per chain), D (one block), X (D^-1 G^T), lam (multipliers)."""
    return np.zeros((nch, n, n)), np.zeros((n, n)), np.zeros((n, 2)), np.zeros(2)


# ----------------------------------------------------------------------------------------------
# compiled kernels
# ----------------------------------------------------------------------------------------------
@njit(cache=True)
def _drag_block(th, off, n, gl, gt, D):
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
def _cholesky(A, L):
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
def _chol_solve(L, b, off):
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
def _chol_solve_cols(L, B, off):
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
def _forces(th, fac, off, n, sigma, c, clamped, out):
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
def _eval(th, fac, ip, fp, out, L, D, X, lam):
    """out = th' at th (force factors fac); leaves Cholesky factors in L, D^-1 G^T in X, multipliers in lam."""
    n = ip[0]
    nch = ip[1]
    clamped = ip[2]
    pinned = ip[3]
    sigma = fp[0]
    gl = fp[1]
    gt = fp[2]
    kappa = fp[3]
    rho = fp[4]
    for ch in range(nch):
        c = 1.0 if ch == 0 else rho
        _forces(th, fac, ch * n, n, sigma, c, clamped, out)
    if nch == 2:
        d = kappa * (th[0] - th[n])
        out[0] -= d
        out[n] += d
    for ch in range(nch):
        _drag_block(th, ch * n, n, gl, gt, D)
        _cholesky(D, L[ch])
        _chol_solve(L[ch], out, ch * n)
    if pinned:
        delta = fp[5]
        beta = fp[6]
        g0 = -n * (1.0 - delta)
        g1 = 0.0
        for i in range(n):
            ci = math.cos(th[i])
            si = math.sin(th[i])
            g0 += ci
            g1 += si
            X[i, 0] = -si
            X[i, 1] = ci
        _chol_solve_cols(L[0], X, 0)
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
def _jac(th, ip, fp, J, L, D, X, lam):
    """Analytic Jacobian d(th')/d(th) of the deterministic ODE (fac = 1), written into J."""
    n = ip[0]
    nch = ip[1]
    clamped = ip[2]
    pinned = ip[3]
    sigma = fp[0]
    gl = fp[1]
    gt = fp[2]
    kappa = fp[3]
    rho = fp[4]
    beta = fp[6]
    na = n * nch
    fac = np.ones(na)
    w = np.empty(na)
    _eval(th, fac, ip, fp, w, L, D, X, lam)
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
        _chol_solve_cols(L[ch], R, ch * n)
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
def _rms(x):
    s = 0.0
    for v in x:
        s += v * v
    return math.sqrt(s / x.size)


@njit(cache=True)
def _dop853(y0, ts, ip, fp, rtol, atol, A, B, C, E3, E5, DD, out):
    """scipy's DOP853 (same tableau, error norm, step control and 7th-order dense output), compiled.

    Writes the solution at the sample times ts (ts[0] = 0 is y0) into out; returns (status, nfev, naccept, nreject).
    """
    ns = 12
    nse = 16
    na = y0.size
    nch = ip[1]
    n = ip[0]
    L = np.zeros((nch, n, n))
    D = np.zeros((n, n))
    X = np.zeros((n, 2))
    lam = np.zeros(2)
    fac = np.ones(na)
    K = np.zeros((nse, na))
    F = np.zeros((7, na))
    y = y0.copy()
    ytmp = np.empty(na)
    y_new = np.empty(na)
    f = np.empty(na)
    f_new = np.empty(na)
    scale = np.empty(na)
    e3 = np.empty(na)
    e5 = np.empty(na)
    T = ts[-1]
    t = 0.0
    _eval(y, fac, ip, fp, f, L, D, X, lam)
    nfev = 1
    # initial step (scipy.integrate._ivp.common.select_initial_step, order 7)
    for i in range(na):
        scale[i] = atol + abs(y[i]) * rtol
        e3[i] = y[i] / scale[i]
        e5[i] = f[i] / scale[i]
    d0 = _rms(e3)
    d1 = _rms(e5)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, T)
    for i in range(na):
        ytmp[i] = y[i] + h0 * f[i]
    _eval(ytmp, fac, ip, fp, f_new, L, D, X, lam)
    nfev += 1
    for i in range(na):
        e3[i] = (f_new[i] - f[i]) / scale[i]
    d2 = _rms(e3) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    h_abs = min(100 * h0, h1, T)

    out[0, :] = y
    isamp = 1
    nsamp = ts.size
    naccept = 0
    nreject = 0
    status = 0
    while t < T:
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs < min_step:
            h_abs = min_step
        accepted = False
        rejected = False
        h = 0.0
        t_new = t
        while not accepted:
            if h_abs < min_step:
                status = -1
                break
            h = h_abs
            t_new = t + h
            if t_new > T:
                t_new = T
            h = t_new - t
            h_abs = abs(h)
            K[0, :] = f
            for s in range(1, ns):
                for i in range(na):
                    acc = 0.0
                    for j in range(s):
                        acc += A[s, j] * K[j, i]
                    ytmp[i] = y[i] + h * acc
                _eval(ytmp, fac, ip, fp, K[s], L, D, X, lam)
            for i in range(na):
                acc = 0.0
                for j in range(ns):
                    acc += B[j] * K[j, i]
                y_new[i] = y[i] + h * acc
            _eval(y_new, fac, ip, fp, f_new, L, D, X, lam)
            K[ns, :] = f_new
            nfev += ns
            n5 = 0.0
            n3 = 0.0
            for i in range(na):
                sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
                a5 = 0.0
                a3 = 0.0
                for j in range(ns + 1):
                    a5 += K[j, i] * E5[j]
                    a3 += K[j, i] * E3[j]
                a5 /= sc
                a3 /= sc
                n5 += a5 * a5
                n3 += a3 * a3
            if n5 == 0.0 and n3 == 0.0:
                err = 0.0
            else:
                err = h_abs * n5 / math.sqrt((n5 + 0.01 * n3) * na)
            if err < 1.0:
                if err == 0.0:
                    factor = 10.0
                else:
                    factor = min(10.0, 0.9 * err ** (-1.0 / 8.0))
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                accepted = True
            else:
                h_abs *= max(0.2, 0.9 * err ** (-1.0 / 8.0))
                rejected = True
                nreject += 1
        if status != 0:
            break
        naccept += 1
        # samples in (t, t_new]
        if isamp < nsamp and ts[isamp] < t_new:
            for s in range(ns + 1, nse):
                for i in range(na):
                    acc = 0.0
                    for j in range(s):
                        acc += A[s, j] * K[j, i]
                    ytmp[i] = y[i] + h * acc
                _eval(ytmp, fac, ip, fp, K[s], L, D, X, lam)
            nfev += nse - ns - 1
            for i in range(na):
                dy = y_new[i] - y[i]
                F[0, i] = dy
                F[1, i] = h * K[0, i] - dy
                F[2, i] = 2.0 * dy - h * (f_new[i] + K[0, i])
                for r in range(4):
                    acc = 0.0
                    for j in range(nse):
                        acc += DD[r, j] * K[j, i]
                    F[3 + r, i] = h * acc
        while isamp < nsamp and ts[isamp] <= t_new:
            if ts[isamp] == t_new:
                out[isamp, :] = y_new
            else:
                x = (ts[isamp] - t) / h
                for i in range(na):
                    acc = 0.0
                    for r in range(6, -1, -1):
                        acc += F[r, i]
                        if (6 - r) % 2 == 0:
                            acc *= x
                        else:
                            acc *= 1.0 - x
                    out[isamp, i] = acc + y[i]
            isamp += 1
        t = t_new
        y[:] = y_new
        f[:] = f_new
    return status, nfev, naccept, nreject


@njit(cache=True)
def _euler_maruyama(y, k0, facs, dt, ip, fp, sidx, out, jptr):
    """Advance y (in place) through steps k0 .. k0 + len(facs) - 1, recording out[j] = state after sidx[j] steps."""
    n = ip[0]
    nch = ip[1]
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
        _eval(y, facs[r], ip, fp, f, L, D, X, lam)
        for i in range(na):
            y[i] += dt * f[i]
        if ip[3]:
            _project_on_pins(y, fp[5])
    return jptr


@njit(cache=True)
def _project_on_pins(th, delta):
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


# ----------------------------------------------------------------------------------------------
# Python-facing functions
# ----------------------------------------------------------------------------------------------
def _factor_array(physics: Physics, factor):
    if factor is None:
        return np.ones(physics.n_angles)
    fac = np.ascontiguousarray(factor, dtype=float).reshape(-1)
    if fac.size != physics.n_angles:
        raise ParameterError(f"factor must have {physics.n_angles} entries (one per particle), got {fac.size}")
    return fac


def rhs(physics: Physics, *, beta: float = DEFAULT_BETA, factor=None):
    """Compiled right-hand side f(t, theta) -> dtheta/dt of the deterministic model.

    factor: optional per-particle force factor (1 + eta_i), default ones. beta: Baumgarte rate (two-pinned).
    """
    ip, fp = _pack(physics, beta)
    fac = _factor_array(physics, factor)
    L, D, X, lam = _workspace(physics.n, physics.n_chains)

    def f(t, theta):
        th = np.ascontiguousarray(theta, dtype=float)
        out = np.empty(th.size)
        _eval(th, fac, ip, fp, out, L, D, X, lam)
        return out

    return f


def jacobian(physics: Physics, *, beta: float = DEFAULT_BETA):
    """Compiled analytic Jacobian J(t, theta) = d(dtheta/dt)/d(theta) of the deterministic model."""
    ip, fp = _pack(physics, beta)
    L, D, X, lam = _workspace(physics.n, physics.n_chains)

    def jac(t, theta):
        th = np.ascontiguousarray(theta, dtype=float)
        J = np.empty((th.size, th.size))
        _jac(th, ip, fp, J, L, D, X, lam)
        return J

    return jac


def drag_matrix(physics: Physics, theta) -> np.ndarray:
    """D(theta) of the whole system (block diagonal for the pair), from the compiled kernel."""
    theta = np.ascontiguousarray(theta, dtype=float)
    n = physics.n
    out = np.zeros((physics.n_angles, physics.n_angles))
    D = np.zeros((n, n))
    for ch in range(physics.n_chains):
        _drag_block(theta, ch * n, n, physics.drag_ratio, 1.0, D)
        out[ch * n : (ch + 1) * n, ch * n : (ch + 1) * n] = D
    return out


def rhs_reference(physics: Physics, *, beta: float = DEFAULT_BETA, factor=None):
    """Plain-numpy f(t, theta), written straight from the formulas (for tests and benchmarks)."""
    n = physics.n
    nch = physics.n_chains
    gl, gt = physics.drag_ratio, 1.0
    fac = _factor_array(physics, factor)
    i_idx = np.arange(n)
    # mask[i, j, k] = i >= max(j, k)
    mask = (i_idx[:, None, None] >= i_idx[None, :, None]) & (i_idx[:, None, None] >= i_idx[None, None, :])
    upper = i_idx[None, :] >= i_idx[:, None]  # upper[k, i] = i >= k

    def chain_terms(th, c, a):
        diff = th[:, None] - th[None, :]  # diff[i, j] = th_i - th_j
        s, co = np.sin(diff), np.cos(diff)
        D = np.einsum("ijk,ij,ik->jk", mask, gl * s, s) + np.einsum("ijk,ij,ik->jk", mask, gt * co, co)
        Q = physics.sigma * np.sum(upper * a[None, :] * np.sin(th[:, None] - th[None, :]), axis=1)
        grad = np.zeros(n)
        if physics.clamped:
            grad[0] += c * th[0]
        bend = np.diff(th)
        grad[:-1] -= c * bend
        grad[1:] += c * bend
        return D, Q - grad

    def f(t, theta):
        theta = np.asarray(theta, dtype=float)
        Dfull = np.zeros((n * nch, n * nch))
        force = np.zeros(n * nch)
        for ch, c in enumerate(physics.stiffness):
            sl = slice(ch * n, (ch + 1) * n)
            Dfull[sl, sl], force[sl] = chain_terms(theta[sl], c, fac[sl])
        if nch == 2:
            force[0] -= physics.kappa * (theta[0] - theta[n])
            force[n] += physics.kappa * (theta[0] - theta[n])
        if physics.scene != "two-pinned":
            return np.linalg.solve(Dfull, force)
        G = pin_jacobian(theta)
        M = np.block([[Dfull, G.T], [G, np.zeros((2, 2))]])
        sol = np.linalg.solve(M, np.concatenate([force, -beta * pin_residual(theta, physics.delta)]))
        return sol[:n]

    return f


def spectral_radius(physics: Physics, theta, *, beta: float = DEFAULT_BETA) -> float:
    """Largest |eigenvalue| of the Jacobian at theta."""
    return float(np.max(np.abs(np.linalg.eigvals(jacobian(physics, beta=beta)(0.0, theta)))))


def stiffness(physics: Physics, theta, *, beta: float = DEFAULT_BETA) -> float:
    """Fastest decay rate max(-Re lambda) of the Jacobian at theta: the stiffness indicator used by
    method=None. Fast *growing* modes (high sigma or N) are not stiffness: an implicit method does
    not help with them, and Radau was 9-25x slower than the explicit default there."""
    eig = np.linalg.eigvals(jacobian(physics, beta=beta)(0.0, theta))
    return float(max(0.0, np.max(-eig.real)))


def _constraint_info(physics: Physics, theta: np.ndarray, info: dict) -> None:
    if physics.scene == "two-pinned":
        c = np.cos(theta).sum(axis=1) - physics.n * (1.0 - physics.delta)
        s = np.sin(theta).sum(axis=1)
        info["constraint_violation"] = float(np.max(np.maximum(np.abs(c), np.abs(s))))


def _initial(physics: Physics, numerics: Numerics, theta0) -> np.ndarray:
    if theta0 is None:
        return initial_angles(physics, numerics)
    theta0 = np.array(theta0, dtype=float).reshape(-1)
    if theta0.size != physics.n_angles:
        raise ParameterError(f"theta0 must have {physics.n_angles} angles, got {theta0.size}")
    return theta0


def _solve_ode(physics, t, theta0, rtol, atol, method, beta):
    ip, fp = _pack(physics, beta)
    info = {"rtol": rtol, "atol": atol}
    if method is None:
        info["spectral_radius"] = spectral_radius(physics, theta0, beta=beta)
        info["stiffness"] = stiffness(physics, theta0, beta=beta)
        method = "Radau" if info["stiffness"] > STIFF_RADIUS else "numba-DOP853"
    info["method"] = method
    if t[-1] == 0.0:
        info.update(nfev=0, njev=0, nsteps=0, status=0)
        return theta0[None, :].copy(), info
    if method == "numba-DOP853":
        out = np.empty((t.size, theta0.size))
        A = np.ascontiguousarray(_dop.A)
        status, nfev, nacc, nrej = _dop853(
            theta0.copy(), t, ip, fp, float(rtol), float(atol), A, _dop.B, _dop.C, _dop.E3, _dop.E5, _dop.D, out
        )
        if status != 0:
            raise RuntimeError(f"numba-DOP853 failed: step size became too small (physics {physics.relevant()})")
        info.update(nfev=int(nfev), njev=0, nsteps=int(nacc), nreject=int(nrej), status=0)
        return out, info
    if method not in SCIPY_METHODS:
        raise ParameterError(f"method must be None, one of {COMPILED_METHODS + SCIPY_METHODS}, got {method!r}")
    kw = {"jac": jacobian(physics, beta=beta)} if method in IMPLICIT_METHODS else {}
    sol = solve_ivp(
        rhs(physics, beta=beta), (0.0, float(t[-1])), theta0, method=method, t_eval=t, rtol=rtol, atol=atol, **kw
    )
    if not sol.success:
        raise RuntimeError(f"solve_ivp ({method}) failed: {sol.message}")
    info.update(nfev=int(sol.nfev), njev=int(sol.njev), nlu=int(sol.nlu), status=int(sol.status))
    return sol.y.T.copy(), info


def _solve_sde(physics, numerics, t, theta0, beta, chunk=20000):
    ip, fp = _pack(physics, beta)
    dt = numerics.dt
    sidx = np.rint(t / dt).astype(np.int64)
    total = int(sidx[-1])
    out = np.empty((t.size, theta0.size))
    y = theta0.copy()
    jptr = 0
    for k0 in range(0, total, chunk):
        steps = np.arange(k0, min(total, k0 + chunk))
        facs = force_factor(numerics.seed, steps, physics.n_angles, physics.noise, dt)
        jptr = _euler_maruyama(y, k0, np.ascontiguousarray(facs), dt, ip, fp, sidx, out, jptr)
    while jptr < t.size:  # samples at the final step
        out[jptr] = y
        jptr += 1
    info = {"method": "Euler-Maruyama", "dt": dt, "nsteps": total, "nfev": total, "seed": numerics.seed}
    return out, info


def simulate_reduced(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    *,
    theta0=None,
    rtol: float = 1e-9,
    atol: float = 1e-11,
    method: str | None = None,
    beta: float = DEFAULT_BETA,
) -> Trajectory:
    """Integrate the reduced model from theta0 (default: initial_angles) and sample every numerics.sample_dt.

    Deterministic (noise = 0): adaptive ODE solver, see the module docstring for `method`.
    noise > 0: Euler-Maruyama with step numerics.dt and the shared counter-based noise (seed numerics.seed);
    rtol, atol and method are then unused.
    """
    t = numerics.sample_times(duration)
    theta0 = _initial(physics, numerics, theta0)
    start = time.perf_counter()
    if physics.noise > 0:
        theta, info = _solve_sde(physics, numerics, t, theta0, beta)
    else:
        theta, info = _solve_ode(physics, t, theta0, rtol, atol, method, beta)
    wall = time.perf_counter() - start
    if physics.scene == "two-pinned":
        info["beta"] = beta
    _constraint_info(physics, theta, info)
    return Trajectory(t=t, theta=theta, physics=physics, engine="reduced", wall_time_s=wall, info=info)


def simulate_reference(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    *,
    theta0=None,
    rtol: float = 1e-9,
    atol: float = 1e-11,
    method: str = "DOP853",
    beta: float = DEFAULT_BETA,
) -> Trajectory:
    """The plain numpy/scipy baseline: solve_ivp on rhs_reference (deterministic only), for benchmarks."""
    if physics.noise > 0:
        raise ParameterError("simulate_reference integrates the deterministic model only (noise must be 0)")
    t = numerics.sample_times(duration)
    theta0 = _initial(physics, numerics, theta0)
    start = time.perf_counter()
    sol = solve_ivp(
        rhs_reference(physics, beta=beta), (0.0, float(t[-1])), theta0, method=method, t_eval=t, rtol=rtol, atol=atol
    )
    wall = time.perf_counter() - start
    if not sol.success:
        raise RuntimeError(f"solve_ivp ({method}) failed: {sol.message}")
    info = {"method": method, "rtol": rtol, "atol": atol, "nfev": int(sol.nfev), "rhs": "numpy reference"}
    theta = sol.y.T.copy()
    _constraint_info(physics, theta, info)
    return Trajectory(t=t, theta=theta, physics=physics, engine="reduced-reference", wall_time_s=wall, info=info)

"""Linear stability of the straight chain with inertia: a quadratic eigenvalue problem (l = C = gamma_T = 1).

The MuJoCo chain carries a mass m_i on particle i (a sphere of radius BEAD_RADIUS centred on the particle,
rigidly attached to pendulum i, so it also has a rotational inertia I_i = (2/5) m_i BEAD_RADIUS^2 about
the vertical axis) and massless links. With absolute angles theta_i, particle i sits at
r_i = sum_{j<=i} e_j, e_j = (cos theta_j, sin theta_j), and moves with v_i = sum_{j<=i} n_j theta_j'
(n_j = (-sin theta_j, cos theta_j)). Its kinetic energy T = sum_i (1/2 m_i |v_i|^2 + 1/2 I_i theta_i'^2)
gives the mass matrix

    M_jk(theta) = cos(theta_j - theta_k) sum_{i >= max(j, k)} m_i + I_j delta_jk,

and the equations of motion are M(theta) theta'' + (velocity^2 terms) + D(theta) theta' = -K theta + Q(theta),
with Q_k = sigma sum_{i >= k, i active} sin(theta_k - theta_i) the generalised follower force (a force
-sigma e_i on each active particle). Linearised about the straight chain theta = 0:

    M0 x'' + C0 x' + (K - sigma S) x = 0,
    M0_jk = sum_{i >= max(j, k)} m_i + I_j delta_jk      (= m D0 + I Id for equal masses)
    C0    = sum_{i >= max(j, k)} gamma_i + c K           (lab-frame drag: only gamma_T survives at linear
                                                           order; plus joint damping proportional to K)
    K     = tridiag(-1, 2, -1), K_NN = 1 (K_11 = 1 on a free pin)
    S_kk  = #{i > k active},  S_ki = -1 for i > k active   (all active: S_kk = N - k, S_km = -1, m > k)

(1-based). The force on the particle at the pin (i = 1) passes through the pin and exerts no torque, so
for N = 2 "every particle loaded" and "tip only" give the same S.

The quadratic problem is solved as the generalised eigenproblem of its companion form
[[0, I], [-(K - sigma S), -C0]] z = lambda [[I, 0], [0, M0]] z, which never inverts M0: at M0 = 0 the N
infinite eigenvalues are dropped and the overdamped problem (K - sigma S + lambda C0) x = 0 of
`elastoactive.analysis.stability` is recovered exactly; for small masses the N extra eigenvalues are fast
inertial relaxations, lambda ~ -gamma / m.

Without any damping (C0 = 0) the eigenvalues are lambda = +- sqrt(-mu), mu the eigenvalues of
M0^{-1} (K - sigma S): stable (purely imaginary lambda) while all mu are real and positive; flutter when
two mu merge and leave the real axis. Ziegler's double pendulum (two bars, masses 2m and m, springs C at
both joints, a follower load P on the tip) is the N = 2 chain with masses (2m, m), a tip-only load,
no lab-frame drag and no rotational inertia. Routh-Hurwitz on its quartic characteristic polynomial
(see `ziegler_damped_load`, `ziegler_drag_load`) gives, exactly,

    undamped:                 P_c = 7/2 - sqrt 2 = 2.0858 C/l,  omega_c = 2^(-1/4) sqrt(C / m l^2)
    joint damping c K:        P_c = 41/28 + c^2 / (2m)  ->  41/28 = 1.4643 C/l as c -> 0, omega_c^2 -> 2/7
    lab-frame drag gamma D0:  4P^2 - (30 + 6 gamma^2/m) P + 45 + 18 gamma^2/m = 0
                               ->  P_c = (15 - 3 sqrt 5)/4 = 2.0729 C/l as gamma -> 0, omega_c^2 -> (sqrt5 - 1)/2

Both vanishing dampings give a destabilisation paradox (a limit below the undamped 2.0858): a large one
(-30 %) for joint damping, a small one (-0.6 %) for the lab-frame drag of this model.

With the rotational inertia proportional to the mass (the default), sigma_c depends on the mass ratio and
the drag only through gamma / sqrt(m): the drag-free limit at fixed mass is the m -> infinity end of the
sigma_c(mass_ratio) curve at gamma = 1. For the paper's chain (equal point masses) the drag gamma D0 is
proportional to M0 = m D0, so vanishing drag tends to the undamped flutter load (no paradox; sigma_c = 2 for
N = 2); the bead's rotational inertia breaks the proportionality and leaves a tiny paradox
(N = 2: 1.992198 against 1.992228 undamped; N = 7: 0.08726877 against 0.08726882).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
from scipy.optimize import brentq

from elastoactive.core.constants import BEAD_INERTIA_FACTOR, BEAD_RADIUS
from elastoactive.core.errors import ParameterError

__all__ = [
    "BEAD_RADIUS",
    "BEAD_INERTIA_FACTOR",
    "ZIEGLER_UNDAMPED",
    "ZIEGLER_DAMPED_LIMIT",
    "ZIEGLER_DRAG_LIMIT",
    "mass_matrix",
    "drag_matrix",
    "stiffness_matrix",
    "follower_matrix",
    "linear_operators",
    "eigenvalues",
    "growth_rate",
    "critical_sigma",
    "critical_sigma_curve",
    "onset_shift_mass_ratio",
    "mass_matrix_at",
    "drag_matrix_at",
    "follower_forces",
    "ziegler_operators",
    "ziegler_critical_load",
    "ziegler_damped_load",
    "ziegler_drag_load",
]


ZIEGLER_UNDAMPED = 3.5 - math.sqrt(2.0)
"""Ziegler's flutter load of the undamped double pendulum, in C / l: 7/2 - sqrt 2 = 2.0857864."""

ZIEGLER_DAMPED_LIMIT = 41.0 / 28.0
"""Limit of Ziegler's flutter load as joint damping proportional to the stiffness vanishes: 41/28 = 1.4642857."""

ZIEGLER_DRAG_LIMIT = (15.0 - 3.0 * math.sqrt(5.0)) / 4.0
"""Limit of the flutter load of Ziegler's pendulum as this model's lab-frame drag vanishes: 2.0729490."""

_INFINITE = 1e13  # generalised eigenvalues with |lambda| above this are the infinite ones of a singular M0


# ----------------------------------------------------------------------------------------------- operators


def _per_particle(value, n: int, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise ParameterError(f"{name} must be a scalar or have length n = {n}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise ParameterError(f"{name} must be finite and >= 0, got {value!r}")
    return arr


def _check_n(n) -> int:
    if int(n) != n or int(n) < 1:
        raise ParameterError(f"n must be an integer >= 1, got {n!r}")
    return int(n)


def _tail_sums(w: np.ndarray) -> np.ndarray:
    """W_jk = sum_{i >= max(j, k)} w_i."""
    tail = np.cumsum(w[::-1])[::-1]
    idx = np.arange(len(w))
    return tail[np.maximum(idx[:, None], idx[None, :])]


def _active_mask(active, n: int) -> np.ndarray:
    if active is None:
        return np.ones(n, dtype=bool)
    arr = np.asarray(active)
    if arr.dtype == bool:
        if arr.shape != (n,):
            raise ParameterError(f"active mask must have length n = {n}, got shape {arr.shape}")
        return arr.copy()
    idx = arr.astype(int).ravel()  # indices (0-based) of the loaded particles
    if np.any(idx < 0) or np.any(idx >= n):
        raise ParameterError(f"active indices must lie in 0..{n - 1}, got {active!r}")
    mask = np.zeros(n, dtype=bool)
    mask[idx] = True
    return mask


def mass_matrix(n: int, mass_ratio=1.0, inertia=None) -> np.ndarray:
    """Inertia matrix M0 of the chain at theta = 0.

    Parameters
    ----------
    n : int
        Number of pendula.
    mass_ratio : float or array_like of shape (n,)
        Particle masses in units of gamma_T tau (the same for all particles, or one per particle).
    inertia : float, array_like of shape (n,) or None
        Rotational inertia of each particle's body about the vertical axis. None: MuJoCo's bead,
        BEAD_INERTIA_FACTOR * m_i.

    Returns
    -------
    ndarray, shape (n, n)
        M0_jk = sum_{i >= max(j, k)} m_i + I_j delta_jk.
    """
    n = _check_n(n)
    m = _per_particle(mass_ratio, n, "mass_ratio")
    inert = BEAD_INERTIA_FACTOR * m if inertia is None else _per_particle(inertia, n, "inertia")
    return _tail_sums(m) + np.diag(inert)


def drag_matrix(n: int, drag=1.0) -> np.ndarray:
    """Lab-frame drag matrix at theta = 0: C_jk = sum_{i >= max(j, k)} gamma_i (only gamma_T enters).

    Parameters
    ----------
    n : int
        Number of pendula.
    drag : float or array_like of shape (n,)
        Transverse drag coefficient of each particle in units of gamma_T (1: the paper's model; 0: none).
    """
    n = _check_n(n)
    return _tail_sums(_per_particle(drag, n, "drag"))


def stiffness_matrix(n: int, clamped: bool = True) -> np.ndarray:
    """K = tridiag(-1, 2, -1) with K_NN = 1 (free end); K_11 = 1 instead of 2 on a freely rotating pin."""
    n = _check_n(n)
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    if not clamped:
        K[0, 0] -= 1.0
    return K


def follower_matrix(n: int, active=None) -> np.ndarray:
    """Linearised follower forces, Q ~ sigma S theta, for a load on a subset of particles.

    From Q_k = sigma sum_{i >= k, i active} sin(theta_k - theta_i) ~ sigma sum_{i > k, i active}
    (theta_k - theta_i): S_kk = #{i > k active}, S_ki = -1 for i > k active, 0 otherwise. Every row
    sums to zero (a rigid rotation is force-free).

    Parameters
    ----------
    n : int
        Number of pendula.
    active : None, bool array of shape (n,) or sequence of 0-based indices
        The particles carrying a follower force (None: all).
    """
    n = _check_n(n)
    a = _active_mask(active, n).astype(float)
    upper = np.triu(np.ones((n, n)), k=1) * a[None, :]
    return np.diag(upper.sum(axis=1)) - upper


def linear_operators(
    n: int,
    mass_ratio=1.0,
    *,
    inertia=None,
    drag=1.0,
    joint_damping: float = 0.0,
    clamped: bool = True,
    active=None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(M0, C0, K, S) of M0 x'' + C0 x' + (K - sigma S) x = 0 about the straight chain.

    Parameters
    ----------
    n : int
        Number of pendula.
    mass_ratio : float or array_like of shape (n,)
        Particle mass(es), in units of gamma_T tau (0: the overdamped chain).
    inertia : float, array_like or None
        Rotational inertia per particle (None: MuJoCo's bead sphere, BEAD_INERTIA_FACTOR * m_i).
    drag : float or array_like of shape (n,)
        Lab-frame transverse drag per particle, in units of gamma_T (0 allowed).
    joint_damping : float
        c >= 0 of the joint (Rayleigh) damping c K, proportional to the stiffness.
    clamped : bool
        Clamp spring on pendulum 1 (True) or a freely rotating pin (False).
    active : None, bool mask or indices
        Particles carrying the follower force (None: all).
    """
    n = _check_n(n)
    c = float(joint_damping)
    if not math.isfinite(c) or c < 0:
        raise ParameterError(f"joint_damping must be finite and >= 0, got {joint_damping!r}")
    K = stiffness_matrix(n, clamped)
    M = mass_matrix(n, mass_ratio, inertia)
    C = drag_matrix(n, drag) + c * K
    return M, C, K, follower_matrix(n, active)


# ----------------------------------------------------------------------------------------------- spectrum


def _companion_eigenvalues(M, C, A, clamped: bool) -> np.ndarray:
    n = M.shape[0]
    if clamped:
        Z, Id = np.zeros((n, n)), np.eye(n)
        big_a = np.block([[Z, Id], [-A, -C]])
        big_b = np.block([[Id, Z], [Z, M]])
    else:
        # Free pin: A 1 = 0, so theta_1 never enters except through its derivatives. In y = (theta_1, psi),
        # psi_i = theta_{i+1} - theta_i, theta = L y; the state (psi, v = theta') closes on itself:
        # psi' = R v, M v' = -C v - A L[:, 1:] psi. This drops exactly the structural zero eigenvalue.
        R = np.diff(np.eye(n), axis=0)  # (n-1) x n
        L1 = np.tril(np.ones((n, n)))[:, 1:]  # n x (n-1)
        big_a = np.block([[np.zeros((n - 1, n - 1)), R], [-A @ L1, -C]])
        big_b = np.block([[np.eye(n - 1), np.zeros((n - 1, n))], [np.zeros((n, n - 1)), M]])
    ab = scipy.linalg.eig(big_a, big_b, right=False, homogeneous_eigvals=True)
    alpha, beta = ab[0], ab[1]
    finite = np.abs(beta) * _INFINITE > np.abs(alpha)
    return alpha[finite] / beta[finite]


def _undamped_eigenvalues(M, A) -> np.ndarray:
    """lambda = +- sqrt(-mu), mu = eig(M^-1 A): real positive mu give exactly imaginary lambda."""
    if np.linalg.cond(M) > 1e12:
        raise ParameterError("without damping the mass matrix must be nonsingular (give the particles mass)")
    mu = np.linalg.eigvals(np.linalg.solve(M, A)).astype(complex)
    lam = np.sqrt(-mu)
    return np.concatenate([lam, -lam])


def _spectrum(n, sigma, mass_ratio, inertia, drag, joint_damping, clamped, active) -> tuple[np.ndarray, bool]:
    M, C, K, S = linear_operators(
        n, mass_ratio, inertia=inertia, drag=drag, joint_damping=joint_damping, clamped=clamped, active=active
    )
    A = K - float(sigma) * S
    if not np.any(C):
        if not clamped:
            raise ParameterError("a free pin without lab-frame drag or damping has an undamped rigid rotation")
        return _undamped_eigenvalues(M, A), True
    if not clamped and not np.any(drag_matrix(n, drag)):
        raise ParameterError("a free pin needs lab-frame drag (joint damping leaves the rigid rotation undamped)")
    return _companion_eigenvalues(M, C, A, clamped), False


def eigenvalues(
    n: int,
    sigma: float,
    mass_ratio=1.0,
    *,
    inertia=None,
    drag=1.0,
    joint_damping: float = 0.0,
    clamped: bool = True,
    active=None,
) -> np.ndarray:
    """Finite eigenvalues lambda of det(lambda^2 M0 + lambda C0 + K - sigma S) = 0, in units of 1/tau.

    Sorted by decreasing real part, then decreasing imaginary part. 2N of them for nonsingular M0 (2N - 1
    on a free pin, whose structural zero eigenvalue, the rigid rotation, is factored out); N at M0 = 0,
    the overdamped spectrum. Parameters as in `linear_operators`.
    """
    lam, _ = _spectrum(n, sigma, mass_ratio, inertia, drag, joint_damping, clamped, active)
    scale = max(1.0, float(np.max(np.abs(lam)))) if lam.size else 1.0
    key = np.round(lam.real / scale, 12)  # conjugate pairs share a key despite rounding
    return lam[np.lexsort((-lam.imag, -key))]


def growth_rate(
    n: int,
    sigma: float,
    mass_ratio=1.0,
    *,
    inertia=None,
    drag=1.0,
    joint_damping: float = 0.0,
    clamped: bool = True,
    active=None,
) -> float:
    """Largest real part of `eigenvalues` (exactly 0 for a stable undamped chain)."""
    lam, _ = _spectrum(n, sigma, mass_ratio, inertia, drag, joint_damping, clamped, active)
    return float(np.max(lam.real))


def critical_sigma(
    n: int,
    mass_ratio=1.0,
    *,
    inertia=None,
    drag=1.0,
    joint_damping: float = 0.0,
    clamped: bool = True,
    active=None,
    tol: float = 1e-12,
    sigma_max: float = 1e4,
) -> tuple[float, float]:
    """(sigma_c, omega_c): the first load at which the straight chain loses stability, and |Im lambda| there.

    A geometric scan (factor 1.2) upward from 1e-3 * 76 / N^3 brackets the first sign change of the
    largest real part, then brentq refines it (a stability window narrower than the scan step could be
    missed). Without damping (no drag, no joint damping) the largest real part is exactly zero on the
    stable side, so the threshold (merging of two real mu = -lambda^2) is bisected instead.

    Parameters
    ----------
    n, mass_ratio, inertia, drag, joint_damping, clamped, active
        As in `linear_operators`.
    tol : float
        Absolute tolerance on sigma_c.
    sigma_max : float
        Give up above this load.

    Returns
    -------
    sigma_c : float
        inf when no instability is found up to sigma_max (e.g. N = 1, or a load on the first particle only).
    omega_c : float
        Angular frequency (1/tau) of the critical mode: 0 for a divergence (real eigenvalue), nan if none.
    """
    n = _check_n(n)
    kw = dict(inertia=inertia, drag=drag, joint_damping=joint_damping, clamped=clamped, active=active)
    S = follower_matrix(n, active)
    if not np.any(S):
        return float("inf"), float("nan")

    undamped = _spectrum(n, 0.0, mass_ratio, **kw)[1]

    def g(s: float) -> float:
        return growth_rate(n, s, mass_ratio, **kw)

    lo, hi = 0.0, 1e-3 * 76.0 / n**3
    if g(lo) > 0:
        return 0.0, _onset_frequency(n, 0.0, mass_ratio, kw)
    while g(hi) <= 0:
        lo = hi
        hi *= 1.2
        if hi > sigma_max:
            return float("inf"), float("nan")
    if undamped:
        while hi - lo > tol:
            mid = 0.5 * (lo + hi)
            if g(mid) > 0:
                hi = mid
            else:
                lo = mid
        sigma_c = 0.5 * (lo + hi)
        return float(sigma_c), _onset_frequency(n, hi, mass_ratio, kw)
    sigma_c = brentq(g, lo, hi, xtol=tol, rtol=4 * np.finfo(float).eps, maxiter=300)
    return float(sigma_c), _onset_frequency(n, sigma_c, mass_ratio, kw)


def _onset_frequency(n, sigma, mass_ratio, kw) -> float:
    lam = eigenvalues(n, sigma, mass_ratio, **kw)
    return float(abs(lam[0].imag))


def critical_sigma_curve(n: int, mass_ratios, **kwargs) -> tuple[np.ndarray, np.ndarray]:
    """sigma_c(mass_ratio) and omega_c(mass_ratio) for an array of mass ratios (keywords of `critical_sigma`)."""
    res = [critical_sigma(n, float(m), **kwargs) for m in np.atleast_1d(mass_ratios)]
    return np.array([r[0] for r in res]), np.array([r[1] for r in res])


def onset_shift_mass_ratio(n: int, fraction: float = 0.01, m_min: float = 1e-8, m_max: float = 1e4, **kwargs):
    """Smallest mass ratio at which sigma_c moves by `fraction` (relative) from its overdamped value.

    Scans the mass ratio geometrically (factor 1.5) upward from m_min, then brentq on
    |sigma_c(m) / sigma_c(0) - 1| - fraction. Returns (mass_ratio, sigma_c there, sigma_c(0));
    mass_ratio is inf when the shift stays below `fraction` up to m_max.
    """
    s0, _ = critical_sigma(n, 0.0, **kwargs)

    def shift(m: float) -> float:
        return abs(critical_sigma(n, m, **kwargs)[0] / s0 - 1.0) - fraction

    lo = hi = float(m_min)
    while shift(hi) < 0:
        lo = hi
        hi *= 1.5
        if hi > m_max:
            return float("inf"), float("nan"), s0
    if lo == hi:
        lo = 0.0
    m = brentq(shift, lo, hi, xtol=1e-12, rtol=1e-10)
    return float(m), critical_sigma(n, m, **kwargs)[0], s0


# ------------------------------------------------------------------------------------- nonlinear pieces


def mass_matrix_at(theta, mass_ratio=1.0, inertia=None) -> np.ndarray:
    """M(theta)_jk = cos(theta_j - theta_k) sum_{i >= max(j, k)} m_i + I_j delta_jk (kinetic energy 1/2 th' M th')."""
    th = np.asarray(theta, dtype=float)
    n = th.size
    m = _per_particle(mass_ratio, n, "mass_ratio")
    inert = BEAD_INERTIA_FACTOR * m if inertia is None else _per_particle(inertia, n, "inertia")
    return np.cos(th[:, None] - th[None, :]) * _tail_sums(m) + np.diag(inert)


def drag_matrix_at(theta, drag=1.0, drag_ratio: float = 1.0) -> np.ndarray:
    """D(theta): generalised drag, Q = -D theta', for particle forces -(gamma_L e e^T + gamma_T n n^T) v_i.

    e, n are the unit vectors of pendulum i; gamma_T = drag (scalar or per particle) and
    gamma_L = drag_ratio * gamma_T (drag_ratio = gamma_L / gamma_T, as in `Physics`). At theta = 0 this is
    `drag_matrix`: gamma_L drops out at linear order.
    D_jk = sum_{i >= max(j, k)} [gamma_T,i cos(th_j - th_i) cos(th_k - th_i)
                                 + gamma_L,i sin(th_j - th_i) sin(th_k - th_i)].
    """
    th = np.asarray(theta, dtype=float)
    n = th.size
    gt = _per_particle(drag, n, "drag")
    gl = gt * float(drag_ratio)
    D = np.zeros((n, n))
    for i in range(n):
        c = np.cos(th[: i + 1] - th[i])
        s = np.sin(th[: i + 1] - th[i])
        D[: i + 1, : i + 1] += gt[i] * np.outer(c, c) + gl[i] * np.outer(s, s)
    return D


def follower_forces(theta, sigma: float, active=None) -> np.ndarray:
    """Generalised follower forces Q_k = sigma sum_{i >= k, i active} sin(theta_k - theta_i)."""
    th = np.asarray(theta, dtype=float)
    n = th.size
    a = _active_mask(active, n)
    diff = np.sin(th[:, None] - th[None, :]) * np.triu(np.ones((n, n))) * a[None, :]
    return float(sigma) * diff.sum(axis=1)


# ------------------------------------------------------------------------------------------------ Ziegler


def ziegler_operators(mass: float = 1.0, damping: float = 0.0, drag: float = 0.0, inertia=0.0):
    """(M0, C0, K, S) of Ziegler's double pendulum: the N = 2 chain with masses (2m, m), load on the tip.

    Parameters
    ----------
    mass : float
        m (the tip mass; the middle joint carries 2m).
    damping : float
        c of the joint damping c K (equal dampers at both joints).
    drag : float
        Lab-frame drag per particle (0: Ziegler's column).
    inertia : float, array_like or None
        Rotational inertia of the masses (0: point masses, Ziegler's column; None: MuJoCo's bead).
    """
    return linear_operators(
        2, [2.0 * mass, mass], inertia=inertia, drag=drag, joint_damping=damping, active=[False, True]
    )


def ziegler_critical_load(mass: float = 1.0, damping: float = 0.0, drag: float = 0.0, inertia=0.0, tol=1e-12):
    """(P_c, omega_c) of Ziegler's double pendulum (units C/l and sqrt(C / m l^2) at mass = 1), computed."""
    return critical_sigma(
        2, [2.0 * mass, mass], inertia=inertia, drag=drag, joint_damping=damping, active=[False, True], tol=tol
    )


def ziegler_damped_load(damping: float, mass: float = 1.0) -> float:
    """Closed form for joint damping c K, point masses, no drag: P_c = 41/28 + c^2 / (2m).

    Characteristic polynomial (m = 1): 2 l^4 + 7c l^3 + (7 - 2P + c^2) l^2 + 2c l + 1; Routh-Hurwitz
    a1 a2 a3 > a0 a3^2 + a1^2 a4 gives 14 (7 - 2P + c^2) > 57, i.e. P < 41/28 + c^2/2 (for any c > 0;
    at c = 0 exactly the threshold is ZIEGLER_UNDAMPED instead). Crossing frequency omega^2 = a3/a1 = 2/7.
    """
    return ZIEGLER_DAMPED_LIMIT + damping**2 / (2.0 * mass)


def ziegler_drag_load(drag: float, mass: float = 1.0) -> float:
    """Closed form for this model's lab-frame drag gamma D0 on Ziegler's pendulum (point masses, no joint damping).

    Characteristic polynomial (m = 1): 2 l^4 + 3g l^3 + (7 - 2P + g^2) l^2 + g (6 - 2P) l + 1;
    Routh-Hurwitz gives 4P^2 - (30 + 6 g^2) P + 45 + 18 g^2 > 0 (g^2 -> gamma^2 / m): P_c is its smaller
    root, tending to (15 - 3 sqrt 5)/4 as gamma -> 0.
    """
    g2 = drag**2 / mass
    b = 30.0 + 6.0 * g2
    c = 45.0 + 18.0 * g2
    return (b - math.sqrt(b * b - 16.0 * c)) / 8.0

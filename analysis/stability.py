"""Linear stability of the straight chain (one pinned end, isotropic drag; l = C = gamma = 1).

About theta = 0 the reduced model D(theta) theta' = -K theta + Q(theta) becomes theta' = A theta with

    A(sigma, N) = -D0^{-1} (K - sigma S),
    D0_jk = N - max(j, k) + 1          (drag matrix at theta = 0; anisotropic drag does not enter:
                                         only gamma_T survives at linear order)
    K     = tridiag(-1, 2, -1) with K_NN = 1  (clamp spring on pendulum 1, free end)
    S_kk  = N - k,  S_km = -1 for m > k  (linearised follower forces, Q ~ sigma S theta)

(1-based indices). N = 2 gives trace A = 2 (sigma - 3), det A = 1: eigenvalues
(sigma - 3) +- i sqrt(1 - (sigma - 3)^2), a Hopf bifurcation at sigma_c = 3 with angular frequency 1/tau.
The straight chain loses stability through a complex pair (flutter), never through a real eigenvalue;
sigma_c falls like N^-3 and N^3 sigma_c tends to the continuum value (~ 76) of a clamped filament with a
distributed follower force.

On a freely rotating pin (no clamp spring: K_11 = 1) the straight chain instead loses stability through
a real eigenvalue, a steady rotation (rotating_operator, rotation_threshold).

Long chains (onset, slow_eigenvalues): the onset's eigenvalues are the slowest of A, |lambda| ~ 200 / N^4 against
|A| ~ 16, so a dense eigensolver gets them to ~1e-16 x 16 N^4 / 200 (1e-4 relative at N = 100) at O(N^3) per
sigma. Instead, D0 = B^T B with B the lower triangular matrix of ones, and B^-T (K - sigma S) is banded (five
diagonals; B^-T S = B^-T diag(N - k) - the superdiagonal of ones), so A^-1 = -(K - sigma S)^-1 D0 is applied in
O(N): D0 x by two cumulative sums, then a banded LU solve. The slowest eigenvalues of A are the largest of A^-1
(Arnoldi, scipy.sparse.linalg.eigs), to ~1e-10 relative at N = 1000, and the onset at N = 1000 takes ~0.3 s
(banded_operator, slow_eigenvalues, onset).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq
from scipy.sparse.linalg import LinearOperator, eigs, splu

from elastoactive.core.errors import ParameterError

from .flutter import follower_matrix

__all__ = [
    "linear_operator",
    "eigenvalues",
    "growth_rate",
    "critical_sigma",
    "critical_sigmas",
    "pair_linear_operator",
    "pair_eigenvalues",
    "subdominant_rate",
    "rotating_operator",
    "rotation_threshold",
    "banded_operator",
    "slow_eigenvalues",
    "onset",
]


def _matrices(n: int, loaded=None):
    """(D0, K, S) of the module's docstring; S with the follower force on the particles `loaded` only (a bool mask or
    0-based indices, analysis.flutter.follower_matrix; None: every particle)."""
    idx = np.arange(1, n + 1)
    D0 = (n - np.maximum(idx[:, None], idx[None, :]) + 1).astype(float)
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    return D0, K, follower_matrix(n, loaded)


def linear_operator(n: int, sigma: float, loaded=None) -> np.ndarray:
    """A(sigma, N) with theta' = A theta about the straight one-pinned chain (the follower force on the particles
    `loaded`: a bool mask or 0-based indices; None: every particle)."""
    n = int(n)
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    D0, K, S = _matrices(n, loaded)
    return -np.linalg.solve(D0, K - sigma * S)


def eigenvalues(n: int, sigma: float, loaded=None) -> np.ndarray:
    """Eigenvalues of A(sigma, N), sorted by decreasing real part (then decreasing imaginary part)."""
    lam = np.linalg.eigvals(linear_operator(n, sigma, loaded))
    return lam[np.lexsort((-lam.imag, -lam.real))]


def growth_rate(n: int, sigma: float, loaded=None) -> float:
    """Largest real part of the eigenvalues."""
    return float(np.max(np.linalg.eigvals(linear_operator(n, sigma, loaded)).real))


def _first_crossing(growth, n: int, tol: float) -> float:
    """The first sigma where growth(sigma) crosses zero: a geometric scan upward from a sigma well below the N^-3
    estimate (10 / N^3: below 76 / N^3, and below sigma_c = 3 at N = 2), then brentq."""
    lo = 10.0 / n**3
    if growth(lo) >= 0:
        lo = 0.0
    hi = lo
    while True:
        hi = 1.25 * hi if hi > 0 else 1e-3
        if growth(hi) > 0:
            break
        lo = hi
        if hi > 1e6:
            raise RuntimeError(f"no instability found for N = {n} up to sigma = {hi}")
    return float(brentq(growth, lo, hi, xtol=tol, rtol=4 * np.finfo(float).eps, maxiter=200))


def critical_sigma(n: int, tol: float = 1e-10, loaded=None) -> tuple[float, float]:
    """(sigma_c, omega_c): first sigma where the largest real part crosses zero, and |Im lambda| there.

    Bracketed by a geometric scan upward from a sigma well below the N^-3 estimate, then brentq. N = 1, or a load
    whose forces exert no torque (on the first particle only), is stable for every sigma: returns (inf, nan).
    """
    n = int(n)
    if n < 2 or not np.any(follower_matrix(n, loaded)):
        return float("inf"), float("nan")
    sigma_c = _first_crossing(lambda s: growth_rate(n, s, loaded), n, tol)
    lam = eigenvalues(n, sigma_c, loaded)
    return float(sigma_c), float(abs(lam[0].imag))


def critical_sigmas(ns, tol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
    """critical_sigma for each N in ns: arrays (sigma_c, omega_c)."""
    res = [critical_sigma(int(n), tol) for n in np.atleast_1d(ns)]
    return np.array([r[0] for r in res]), np.array([r[1] for r in res])


def pair_linear_operator(n: int, sigma: float, kappa: float, rho: float) -> np.ndarray:
    """Linearisation of the coupled pair about theta = phi = 0 (state [theta, phi])."""
    D0, K, S = _matrices(int(n))
    z = np.zeros_like(D0)
    Dp = np.block([[D0, z], [z, D0]])
    Kp = np.block([[K, z], [z, rho * K]])
    Kp[0, 0] += kappa
    Kp[n, n] += kappa
    Kp[0, n] -= kappa
    Kp[n, 0] -= kappa
    Sp = np.block([[S, z], [z, S]])
    return -np.linalg.solve(Dp, Kp - sigma * Sp)


def pair_eigenvalues(n: int, sigma: float, kappa: float, rho: float) -> np.ndarray:
    """Eigenvalues of the pair's linearisation, sorted by decreasing real part."""
    lam = np.linalg.eigvals(pair_linear_operator(n, sigma, kappa, rho))
    return lam[np.lexsort((-lam.imag, -lam.real))]


def subdominant_rate(n: int, sigma: float) -> float:
    """Real part of the first eigenvalue below the dominant (conjugate) pair of A(sigma, N): how fast
    everything but the dominant mode dies out (-inf when nothing else is left)."""
    lam = eigenvalues(n, sigma)
    top = lam[0]
    rest = [l for l in lam[1:] if abs(l - np.conj(top)) > 1e-9 * max(1.0, abs(top))]  # noqa: E741
    return float(rest[0].real) if rest else -np.inf


def rotating_operator(n: int, sigma: float) -> np.ndarray:
    """Linearisation of the rotating-pin chain (no clamp spring) about the straight state, on the
    rotation-invariant bend angles psi_i = theta_{i+1} - theta_i (the rigid rotation, eigenvalue 0,
    factored out): an (n-1) x (n-1) matrix."""
    idx = np.arange(1, n + 1)
    D0 = (n - np.maximum(idx[:, None], idx[None, :]) + 1).astype(float)  # drag at rest
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[0, 0] = K[-1, -1] = 1.0  # no clamp spring; free end
    S = np.diag((n - idx).astype(float)) - np.triu(np.ones((n, n)), k=1)  # linearised follower forces
    A = -np.linalg.solve(D0, K - sigma * S)
    R = np.diff(np.eye(n), axis=0)  # (n-1) x n
    return R @ A @ np.linalg.pinv(R)


def rotation_threshold(n: int = 7) -> float:
    """sigma above which the straight chain on a free pin is unstable (a real eigenvalue of
    rotating_operator crosses zero: steady rotation). N^3 sigma_r rises from 20 (N = 2) towards ~30.5 (N = 200)."""

    def g(s: float) -> float:
        return float(np.max(np.linalg.eigvals(rotating_operator(n, s)).real))

    hi = ROTATION_SCAN_START / n**3
    while g(hi) >= 0:  # the scan must start below the threshold, whatever N
        hi /= 4.0
    lo = hi
    while g(hi) < 0:
        lo, hi = hi, 1.25 * hi
    return float(brentq(g, lo, hi, xtol=1e-15, rtol=1e-12))


ROTATION_SCAN_START = 16.0
"""rotation_threshold scans upward from ROTATION_SCAN_START / N^3: below N^3 sigma_r for every N (20 at N = 2,
rising to ~30.5 at N = 200), so the scan brackets the first crossing from below in a few steps."""


SLOW_MODES = 4
"""Eigenvalues slow_eigenvalues computes by default: the flutter pair and the next two."""
ONSET_BRACKET = (20.0, 80.0)
"""N^3 sigma_c lies in this range for every N >= 2 (24 at N = 2, rising to the continuum's 76.10): onset's bracket."""


def banded_operator(n: int, sigma: float):
    """B^-T (K - sigma S) as a sparse (CSC) matrix of five diagonals (B: the lower triangular matrix of ones, so
    that D0 = B^T B and A = -B^-1 B^-T (K - sigma S))."""
    n = int(n)
    upper = sp.identity(n, format="csr") - sp.eye(n, k=1, format="csr")  # B^-T
    k = sp.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="lil")
    k[n - 1, n - 1] = 1.0
    follower = upper @ sp.diags((n - np.arange(1, n + 1)).astype(float)) - sp.eye(n, k=1)  # B^-T S
    return (upper @ k.tocsr() - sigma * follower).tocsc()


def slow_eigenvalues(n: int, sigma: float, count: int = SLOW_MODES) -> np.ndarray:
    """The `count` eigenvalues of A(sigma, N) smallest in magnitude (the slowest modes, among them the flutter pair
    near the onset), sorted by decreasing real part; O(N) per Arnoldi step (see the module docstring). N must
    exceed count + 1."""
    n = int(n)
    if n <= count + 1:
        raise ValueError(f"slow_eigenvalues needs N > count + 1 = {count + 1}, got N = {n}")
    lu = splu(banded_operator(n, sigma))

    def inverse(x: np.ndarray) -> np.ndarray:  # A^-1 x = -(K - sigma S)^-1 B^T (B^T B x) ... via B^-T
        y = np.cumsum(np.cumsum(x)[::-1])[::-1]  # D0 x = B^T (B x)
        y[:-1] -= y[1:].copy()  # B^-T y
        return -lu.solve(y)

    nu = eigs(
        LinearOperator((n, n), matvec=inverse, dtype=float), k=count, which="LM", return_eigenvectors=False, tol=1e-14
    )
    lam = 1.0 / nu
    return lam[np.lexsort((-lam.imag, -lam.real))]


def onset(n: int, loaded=None) -> tuple[float, float]:
    """(sigma_c, omega_c) of the straight one-pinned chain as critical_sigma gives them, for any N: below
    SLOW_MODES + 2 particles by critical_sigma, from there on by brentq on the leading slow eigenvalue in
    ONSET_BRACKET / N^3 (~0.05 s at N = 200, ~0.3 s at N = 1000; more accurate than the dense eigensolver for
    N >~ 50, see the module docstring). With the follower force on some particles only (`loaded`: a bool mask or
    0-based indices; None or every particle: the paper's chain) by critical_sigma, dense at every N: such a chain's
    onset lies outside that bracket (N = 7 tip loaded: 0.5603), and its unstable mode need not be among the slowest
    (N = 30 loaded on particles 3 and 6: the fourth and fifth slowest)."""
    n = int(n)
    if loaded is not None and np.array_equal(follower_matrix(n, loaded), follower_matrix(n)):
        loaded = None  # every particle (the first's force never exerts a torque): the paper's chain
    if n <= SLOW_MODES + 1 or loaded is not None:
        return critical_sigma(n, loaded=loaded)

    def growth(s: float) -> float:
        return float(slow_eigenvalues(n, s)[0].real)

    lo, hi = (v / n**3 for v in ONSET_BRACKET)
    sigma_c = brentq(growth, lo, hi, xtol=1e-300, rtol=1e-13, maxiter=200)
    return float(sigma_c), float(abs(slow_eigenvalues(n, sigma_c)[0].imag))


def pair_onset(n: int, kappa: float, rho: float) -> tuple[float, float]:
    """(sigma_c, omega_c) of the coupled pair: the first sigma where the pair's least stable eigenvalue crosses 0,
    bracketed from below by a geometric scan from a quarter of the softer chain's onset."""

    def growth(s: float) -> float:
        return float(np.max(np.linalg.eigvals(pair_linear_operator(n, s, kappa, rho)).real))

    lo = 0.25 * min(1.0, rho) * onset(n)[0]
    while growth(lo) >= 0:
        lo /= 4.0
    hi = lo
    while growth(hi) < 0:
        lo, hi = hi, 1.25 * hi
        if hi > 1e6:
            raise ParameterError(f"the pair (kappa = {kappa:g}, rho = {rho:g}) is stable up to sigma = 1e6")
    sigma_c = brentq(growth, lo, hi, xtol=1e-300, rtol=1e-12)
    lam = pair_eigenvalues(n, sigma_c, kappa, rho)
    return float(sigma_c), float(abs(lam[0].imag))

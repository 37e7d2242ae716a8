"""The continuum limit of the one-pinned chain, solved independently of the discrete model.

With B = C l, L = N l, drag per length zeta = gamma / l and follower force per length f = F_a / l,
the small deflection y(s, t) of a filament clamped at s = 0, free at s = L, obeys

    zeta dy/dt = -B y'''' - f (L - s) y''

(the follower forces compress the filament with tension T(s) = -f (L - s); the tension gradient
term T' y' = f y' cancels the transverse component -f y' of the follower force), with
y(0) = y'(0) = 0 and y''(L) = y'''(L) = 0. In units of L and of the time zeta L^4 / B = N^4 tau
the only parameter is S = f L^3 / B = N^3 sigma. (The supplement's continuum equation prints
+sigma (l - s) v'', a tension, which never destabilises a clamped rod: a sign slip.)

The eigenproblem  lambda y = -y'''' - S (1 - s) y''  is discretised by Chebyshev collocation
(boundary rows replace the two collocation rows at each end) and the onset S_c is where the
largest real part crosses zero; N^3 sigma_c(N) of the discrete chain tends to S_c and N^4 omega_c(N)
to its onset angular frequency.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import eig
from scipy.optimize import brentq

__all__ = ["chebyshev", "continuum_operator", "continuum_eigenvalues", "continuum_critical"]


def chebyshev(m: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev points x_j = cos(pi j / m), j = 0..m, and the differentiation matrix (Trefethen)."""
    if m < 2:
        raise ValueError("m must be >= 2")
    j = np.arange(m + 1)
    x = np.cos(np.pi * j / m)
    c = np.where((j == 0) | (j == m), 2.0, 1.0) * (-1.0) ** j
    X = x[:, None] - x[None, :]
    D = np.outer(c, 1.0 / c) / (X + np.eye(m + 1))
    D -= np.diag(D.sum(axis=1))
    return x, D


def continuum_operator(S: float, m: int = 32) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A, B, s): the pencil A y = lambda B y on the collocation points s in [0, 1]."""
    x, Dx = chebyshev(m)
    s = (1.0 - x) / 2.0  # s = 0 at x = 1 (j = 0), s = 1 at x = -1 (j = m)
    D1 = -2.0 * Dx
    D2 = D1 @ D1
    D3 = D2 @ D1
    D4 = D2 @ D2
    A = -D4 - np.diag(S * (1.0 - s)) @ D2
    B = np.eye(m + 1)
    # boundary conditions: y(0) = y'(0) = 0 (rows 0, 1), y''(1) = y'''(1) = 0 (rows m, m-1)
    rows = {0: np.eye(m + 1)[0], 1: D1[0], m: D2[m], m - 1: D3[m]}
    for r, bc in rows.items():
        A[r] = bc
        B[r] = 0.0
    return A, B, s


def continuum_eigenvalues(S: float, m: int = 32) -> np.ndarray:
    """Finite eigenvalues (units 1 / (N^4 tau)), sorted by decreasing real part."""
    A, B, _ = continuum_operator(S, m)
    lam = eig(A, B, right=False)
    lam = lam[np.isfinite(lam) & (np.abs(lam) < 1e8)]
    return lam[np.lexsort((-lam.imag, -lam.real))]


def _growth(S: float, m: int) -> float:
    return float(continuum_eigenvalues(S, m)[0].real)


def continuum_critical(
    m: int = 32, bracket: tuple[float, float] = (40.0, 120.0), tol: float = 1e-10
) -> tuple[float, float]:
    """(S_c, omega_c): the continuum onset f L^3 / B and |Im lambda| there (units 1 / (zeta L^4 / B))."""
    S = brentq(lambda v: _growth(v, m), *bracket, xtol=tol)
    return float(S), float(abs(continuum_eigenvalues(S, m)[0].imag))

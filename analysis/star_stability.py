"""Linear stability of the star (the star scene): k one-pinned arms clamped to one hub, about the straight base state.

The base state, each arm straight along its clamp direction (theta_{j,i} = alpha_j) with the hub at phi = 0, is a
fixed point for every sigma: the follower forces point along the straight arms and exert no torque. With u_{j,i} =
theta_{j,i} - alpha_j, the overdamped linearisation is each arm's one-pinned operator (analysis.stability: D0 u_j' =
-(K - sigma S) u_j) whose clamp spring refers to the hub's angle, -(u_{j,0} - phi) instead of -u_{j,0}, and for a
turning hub

    hub_drag phi' = -hub_stiffness phi + sum_j (u_{j,0} - phi).

The arms couple through phi alone and only by their first angles' sum, so the operator splits exactly: the k - 1
modes whose first angles sum to zero (antiphase for k = 2; for k >= 3 the splay states and every other pattern with
no net torque on the hub, degenerate at linear order) never move the hub and are each the one-pinned chain's operator;
the in-phase mode (every arm alike) is the one-pinned operator bordered by the hub's coordinate, with the k arms'
torque k u_0 on it. A clamped hub (phi = 0) leaves k uncoupled one-pinned chains. Arrays in, numbers out.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from .stability import _matrices, linear_operator
from .stability import onset as one_pinned_onset

__all__ = ["star_operator", "in_phase_operator", "star_eigenvalues", "mode_onsets", "star_onset"]

IN_PHASE = "in-phase"
MODES = (IN_PHASE, "antiphase", "splay")
"""The star's linear modes: in phase (the hub turns), and the k - 1 that leave it still (antiphase for k = 2, splay
and the other zero-sum patterns for k >= 3)."""


def star_operator(n: int, k: int, sigma: float, hub_stiffness: float, hub_drag: float) -> np.ndarray:
    """A with (u, phi)' = A (u, phi) about the straight star (u: the arms' angles less alpha_j, arm by arm; phi: the
    turning hub's angle, last): k one-pinned blocks coupled through the hub (module docstring)."""
    D0, K, S = _matrices(int(n))
    size = n * k + 1
    D = np.zeros((size, size))
    F = np.zeros((size, size))
    for j in range(k):
        sl = slice(j * n, (j + 1) * n)
        D[sl, sl] = D0
        F[sl, sl] = -(K - sigma * S)
        F[j * n, -1] = 1.0  # the clamp spring refers to the hub's angle
        F[-1, j * n] = 1.0  # the arm's clamp torque on the hub
    D[-1, -1] = hub_drag
    F[-1, -1] = -(hub_stiffness + k)
    return np.linalg.solve(D, F)


def in_phase_operator(n: int, k: int, sigma: float, hub_stiffness: float, hub_drag: float) -> np.ndarray:
    """The in-phase block (every arm u, the hub phi): the one-pinned operator bordered by the hub, (N + 1) square."""
    D0, K, S = _matrices(int(n))
    D = np.zeros((n + 1, n + 1))
    F = np.zeros((n + 1, n + 1))
    D[:n, :n] = D0
    F[:n, :n] = -(K - sigma * S)
    F[0, n] = 1.0
    F[n, 0] = float(k)
    D[n, n] = hub_drag
    F[n, n] = -(hub_stiffness + k)
    return np.linalg.solve(D, F)


def _leading(A: np.ndarray, neutral: bool = False) -> complex:
    """The eigenvalue of largest real part; neutral: less the one nearest 0 (a hub without a spring: turning the whole
    straight star is neutral at every sigma, its eigenvalue 0, not an instability)."""
    lam = np.linalg.eigvals(A)
    if neutral:
        lam = np.delete(lam, np.argmin(np.abs(lam)))
    return complex(lam[np.argmax(lam.real)])


def star_eigenvalues(n: int, k: int, sigma: float, hub_stiffness: float, hub_drag: float) -> np.ndarray:
    """Eigenvalues of the turning star's operator, by decreasing real part."""
    lam = np.linalg.eigvals(star_operator(n, k, sigma, hub_stiffness, hub_drag))
    return lam[np.lexsort((-lam.imag, -lam.real))]


def _in_phase_onset(n: int, k: int, hub_stiffness: float, hub_drag: float) -> tuple[float, float]:
    """(sigma_c, omega_c) of the in-phase block: a geometric scan from a quarter of the one-pinned onset, then
    brentq."""

    neutral = hub_stiffness == 0

    def growth(s: float) -> float:
        return _leading(in_phase_operator(n, k, s, hub_stiffness, hub_drag), neutral).real

    lo = 0.25 * one_pinned_onset(n)[0]
    while growth(lo) >= 0:
        lo /= 4.0
        if lo < 1e-12:
            return 0.0, abs(_leading(in_phase_operator(n, k, 0.0, hub_stiffness, hub_drag), neutral).imag)
    hi = lo
    while growth(hi) < 0:
        lo, hi = hi, 1.25 * hi
        if hi > 1e6:
            return float("inf"), float("nan")
    sigma_c = brentq(growth, lo, hi, xtol=1e-300, rtol=1e-12)
    return float(sigma_c), abs(_leading(in_phase_operator(n, k, sigma_c, hub_stiffness, hub_drag), neutral).imag)


def mode_onsets(n: int, k: int, hub_stiffness: float | None, hub_drag: float | None) -> dict[str, tuple[float, float]]:
    """{mode: (sigma_c, omega_c)} of the in-phase mode and of the hub-free modes ("antiphase" for k = 2, "splay" for
    k >= 3: the one-pinned onset); a clamped hub (hub_stiffness None) has every mode at the one-pinned onset."""
    free = one_pinned_onset(n)
    other = MODES[1] if k == 2 else MODES[2]
    if hub_stiffness is None:
        return {IN_PHASE: free, other: free}
    return {IN_PHASE: _in_phase_onset(n, k, hub_stiffness, hub_drag), other: free}


def star_onset(n: int, k: int, hub_stiffness: float | None, hub_drag: float | None) -> tuple[float, float, str]:
    """(sigma_c, omega_c, mode) of the first mode to go unstable (ties: the hub-free one, which a clamped hub gives)."""
    if hub_stiffness is None:  # k uncoupled one-pinned chains: every pattern at once
        return (*one_pinned_onset(n), "every (independent arms)")
    onsets = mode_onsets(n, k, hub_stiffness, hub_drag)
    mode = min(reversed(list(onsets)), key=lambda m: onsets[m][0])
    return (*onsets[mode], mode)


def leading_eigenvalue(n: int, k: int, sigma: float, hub_stiffness: float | None, hub_drag: float | None) -> complex:
    """The least stable eigenvalue of the star at sigma (a clamped hub: the one-pinned chain's)."""
    if hub_stiffness is None:
        return _leading(linear_operator(n, sigma))
    return _leading(star_operator(n, k, sigma, hub_stiffness, hub_drag), hub_stiffness == 0)

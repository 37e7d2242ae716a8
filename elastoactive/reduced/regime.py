"""The overdamped limit: when a particle mass needs the inertial model (plain numpy, no compiled kernels).

A chain of particles of mass m (units gamma_T tau) relaxes onto the overdamped dynamics D th' = f within
the inertial time m / gamma. The overdamped model describes it while that time is short against the
fastest overdamped time 1 / rate, rate = max |lambda| of the overdamped linearisation D^-1 df/dth:

    inside the overdamped limit:   m x rate <= INERTIA_RESOLUTION     (the paper's model; MuJoCo approximates
                                                                      it, amplitude and frequency within
                                                                      ~0.2 m x rate, angles ~5 m x rate)
    outside:                       m x rate >  INERTIA_RESOLUTION     (only the inertial model with that m)

With a free head, a trap or self-contact (ChainSystem.extended) the linearisation is taken over the whole state
(the angles, then the head) with df/dq by central differences of equations.drag_and_forces_reference.

This module is the one place of that criterion. elastoactive.engines.reduced.regime applies it at a scene's
base state (for simulate_reduced and elastoactive.engines.timestep alike).
"""

from __future__ import annotations

import numpy as np

from .blas import one_blas_thread
from .equations import drag_and_forces_reference
from .system import ChainSystem

__all__ = [
    "INERTIA_RESOLUTION",
    "force_jacobian",
    "inertia_number",
    "needs_inertia",
    "outside_overdamped_limit",
    "overdamped_rate",
    "rate_bound",
]

INERTIA_RESOLUTION = 0.1
"""The overdamped limit: a mass ratio m is inside it when m x overdamped_rate <= INERTIA_RESOLUTION."""


def _drag(system: ChainSystem, theta: np.ndarray) -> np.ndarray:
    """D(theta) (block diagonal for a pair): D_jk = n_j^T (sum_{i >= max(j,k)} W_i) n_k (equations.py)."""
    n = system.n
    D = np.zeros((system.n_angles, system.n_angles))
    for ch in range(system.n_chains):
        th = theta[ch * n : (ch + 1) * n]
        c, s = np.cos(th), np.sin(th)
        e = np.stack([c, s], axis=1)
        nn = np.stack([-s, c], axis=1)
        W = system.gamma_l * e[:, :, None] * e[:, None, :] + system.gamma_t * nn[:, :, None] * nn[:, None, :]
        S = np.cumsum(W[::-1], axis=0)[::-1]  # S_m = sum_{i >= m} W_i
        idx = np.arange(n)
        Smax = S[np.maximum(idx[:, None], idx[None, :])]  # (n, n, 2, 2)
        D[ch * n : (ch + 1) * n, ch * n : (ch + 1) * n] = np.einsum("ja,jkab,kb->jk", nn, Smax, nn)
    return D


def force_jacobian(system: ChainSystem, theta) -> np.ndarray:
    """df/dtheta of the generalised forces f = -dU/dtheta + Q (springs, coupling, follower forces; fac = 1); the
    extended terms (a free head, the trap, contact) are not in it (see _extended_operators)."""
    system = system.typed()
    theta = np.asarray(theta, dtype=float).reshape(-1)[: system.n_angles]
    n = system.n
    F = np.zeros((system.n_angles, system.n_angles))
    upper = np.triu(np.ones((n, n)), k=1)  # [k, i]: i > k
    for ch in range(system.n_chains):
        sl = slice(ch * n, (ch + 1) * n)
        K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
        K[-1, -1] -= 1.0
        if not system.clamped:
            K[0, 0] -= 1.0
        th = theta[sl]
        cosd = np.cos(th[:, None] - th[None, :])  # cos(th_k - th_i)
        Q = -system.sigma * upper * cosd  # dQ_k/dth_i for i > k (Q_k = sigma sum_{i >= k} sin(th_k - th_i))
        Q[np.diag_indices(n)] = system.sigma * np.sum(upper * cosd, axis=1)
        F[sl, sl] = -system.stiffness(ch) * K + Q
    if system.n_chains == 2:
        F[0, 0] -= system.kappa
        F[n, n] -= system.kappa
        F[0, n] += system.kappa
        F[n, 0] += system.kappa
    return F


FD_STEP = 1e-6
"""Step of the central differences of df/dq for a system with a free head, a trap or self-contact."""


def _extended_operators(system: ChainSystem, theta) -> tuple[np.ndarray, np.ndarray]:
    """(D, df/dq) over the whole state of a system with an extended term (equations.drag_and_forces_reference;
    df/dq by central differences): theta is the state (the angles, then the head) or the angles alone (the head
    at the origin)."""
    y = np.asarray(theta, dtype=float).reshape(-1)
    if system.n_head and y.size == system.n_angles:  # the head at the origin, a star's hub at phi = 0
        y = np.concatenate([y, np.zeros(system.n_head)])
    y = y[: system.state_size]
    D, _ = drag_and_forces_reference(system, y)
    F = np.empty((y.size, y.size))
    for k in range(y.size):
        step = np.zeros(y.size)
        step[k] = FD_STEP
        F[:, k] = (drag_and_forces_reference(system, y + step)[1] - drag_and_forces_reference(system, y - step)[1]) / (
            2.0 * FD_STEP
        )
    return D, F


def _operators(system: ChainSystem, theta) -> tuple[np.ndarray, np.ndarray] | None:
    """(D, df/dth) at theta, on the pins' tangent space for a pinned chain; None when nothing can move. With a
    free head, a trap or self-contact (system.extended): over the whole state, df/dq by central differences."""
    system = system.typed()
    if system.extended:
        D, F = _extended_operators(system, theta)
        theta = np.asarray(theta, dtype=float).reshape(-1)[: system.n_angles]
    else:
        theta = np.asarray(theta, dtype=float).reshape(-1)[: system.n_angles]
        D, F = _drag(system, theta), force_jacobian(system, theta)
    if system.pinned:
        G = np.vstack([-np.sin(theta), np.cos(theta)])
        if D.shape[0] > G.shape[1]:  # the free ring: its head's columns of G are zero
            G = np.hstack([G, np.zeros((2, D.shape[0] - G.shape[1]))])
        _, sv, vt = np.linalg.svd(G)
        basis = vt[np.sum(sv > 1e-9) :].T
        if basis.shape[1] == 0:  # N = 2 on two pins: no free motion
            return None
        D, F = basis.T @ D @ basis, basis.T @ F @ basis
    return D, F


def rate_bound(system: ChainSystem, theta) -> float:
    """An upper bound of overdamped_rate without the eigenvalues: the smaller of the 1- and infinity-norms of
    D^-1 df/dth (any induced norm bounds the spectral radius; measured within 5-25% of it on straight chains
    from N = 7 to 400). O(N^3 / 3) instead of the eigenvalue problem's ~10 N^3."""
    ops = _operators(system, theta)
    if ops is None:
        return 0.0
    with one_blas_thread():
        A = np.linalg.solve(*ops)
    return float(min(np.abs(A).sum(axis=0).max(), np.abs(A).sum(axis=1).max()))


def overdamped_rate(system: ChainSystem, theta) -> float:
    """Fastest rate max |lambda| (1/tau) of the overdamped linearisation D(theta)^-1 df/dtheta at theta (the drag's
    own derivative, which vanishes at rest, left out), on the pins' tangent space for a pinned chain (without
    the Baumgarte modes). elastoactive.engines.timestep's fastest overdamped rate from MuJoCo's operators is the same
    number (to its finite differences, ~1e-9)."""
    ops = _operators(system, theta)
    if ops is None:
        return 0.0
    with one_blas_thread():  # N = 1000: 0.75 s on one thread, 3-9 s threaded on a busy machine (blas.py)
        return float(np.max(np.abs(np.linalg.eigvals(np.linalg.solve(*ops)))))


def inertia_number(system: ChainSystem, theta, mass_ratio: float) -> float:
    """mass_ratio x overdamped_rate(system, theta): the inertial time over the fastest overdamped time."""
    return float(mass_ratio) * overdamped_rate(system, theta)


def outside_overdamped_limit(mass_ratio: float, rate: float) -> bool:
    """The criterion itself: a mass ratio is outside the overdamped limit of a system whose fastest overdamped
    rate is `rate` when mass_ratio x rate > INERTIA_RESOLUTION."""
    return float(mass_ratio) * float(rate) > INERTIA_RESOLUTION


def needs_inertia(system: ChainSystem, theta, mass_ratio: float) -> bool:
    """Whether a particle mass mass_ratio is outside the overdamped limit of the system at theta."""
    return outside_overdamped_limit(mass_ratio, overdamped_rate(system, theta))

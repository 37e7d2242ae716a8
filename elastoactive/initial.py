"""Initial states shared by both engines: the base state plus a small seeded perturbation."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from .params import Numerics, ParameterError, Physics


def pin_residual(theta: np.ndarray, delta: float) -> np.ndarray:
    """Two-pinned constraints g(theta) = (sum cos - N (1 - delta), sum sin); zero when satisfied."""
    n = theta.size
    return np.array([np.cos(theta).sum() - n * (1.0 - delta), np.sin(theta).sum()])


def pin_jacobian(theta: np.ndarray) -> np.ndarray:
    """dg/dtheta, shape (2, N)."""
    return np.vstack([-np.sin(theta), np.cos(theta)])


def project_on_pins(theta: np.ndarray, delta: float, tol: float = 1e-13, max_iter: int = 50) -> np.ndarray:
    """Closest admissible angles (minimum-norm Gauss-Newton steps onto g = 0)."""
    theta = np.array(theta, dtype=float)
    for _ in range(max_iter):
        g = pin_residual(theta, delta)
        if np.max(np.abs(g)) < tol:
            return theta
        G = pin_jacobian(theta)
        theta -= G.T @ np.linalg.lstsq(G @ G.T, g, rcond=None)[0]
    raise ParameterError(f"delta = {delta}: could not place the chain on the pins (constraint residual {g})")


def buckled_arch(n: int, delta: float) -> np.ndarray:
    """Angles of a single arch, theta_i = A cos(pi (i - 1/2) / N), with end-to-end length N (1 - delta).

    The profile is odd about the middle, so sum sin theta = 0 exactly; A solves sum cos = N (1 - delta).
    """
    if delta == 0:
        return np.zeros(n)
    x = np.cos(np.pi * (np.arange(1, n + 1) - 0.5) / n)

    def shortfall(a: float) -> float:
        return np.cos(a * x).sum() - n * (1.0 - delta)

    if shortfall(np.pi) > 0:
        raise ParameterError(f"delta = {delta} is too large a compression for N = {n} (no single-arch shape)")
    return brentq(shortfall, 0.0, np.pi, xtol=1e-15) * x


def pushed_shape(n: int, pushes: np.ndarray) -> np.ndarray:
    """Static shape of a clamped chain under small lateral pushes F_i on its particles.

    Solves K theta = Q with Q_k = sum_{i>=k} F_i (the pushes' torques on theta_k) and K the
    clamped chain's stiffness (2 on the diagonal, 1 at the free end, -1 beside it). The shape
    is smooth, like a chain "slightly pushed off from the equilibrium" in the experiment.
    """
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    return np.linalg.solve(K, np.cumsum(pushes[::-1])[::-1])


def initial_angles(physics: Physics, numerics: Numerics) -> np.ndarray:
    """Absolute angles theta_i at t = 0 (chain 1 then chain 2 for the pair).

    Each chain starts from the static shape under seeded random lateral pushes (pushed_shape),
    scaled so that its largest angle is `numerics.perturbation`. A smooth start excites no
    fast, tip-localised modes; a random angle per particle would, and those are exactly what a
    first-order integrator gets wrong (they decay, but the instability amplifies the error).
    The two-pinned chain starts from a single arch at its compression, pushed the same way and
    projected back onto the pins.
    """
    rng = np.random.default_rng(numerics.seed)
    shapes = []
    for _ in range(physics.n_chains):
        shape = pushed_shape(physics.n, rng.standard_normal(physics.n))
        shapes.append(numerics.perturbation * shape / np.abs(shape).max())
    kick = np.concatenate(shapes)
    if physics.scene == "two-pinned":
        return project_on_pins(buckled_arch(physics.n, physics.delta) + kick, physics.delta)
    return kick

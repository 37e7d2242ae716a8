"""The two-pinned chain's constraints: its last particle held at (N (1 - delta), 0).

    g(theta) = (sum_i cos theta_i - N (1 - delta), sum_i sin theta_i) = 0,    G = dg/dtheta (2 x N).

Plain numpy, used by the reference right-hand side (equations.py), by the reported constraint
violation (solve.py) and by the initial state of the two-pinned scene (elastoactive.reduced.initial). The
compiled kernels (kernels.py) inline the same formulas.
"""

from __future__ import annotations

import numpy as np

from ..core.errors import ParameterError

__all__ = ["pin_jacobian", "pin_residual", "project_on_pins"]


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

"""Initial states shared by both engines: the base state plus a small seeded perturbation.

Each scene chooses its initial state (Scene.initial_angles) from the pieces here. scipy.optimize is imported
inside buckled_arch, the one start that needs a root finder: it costs ~0.3 s, which `import elastoactive` does not pay.
"""

from __future__ import annotations

import numpy as np

from ..core.errors import ParameterError
from .constraints import pin_jacobian, pin_residual, project_on_pins  # noqa: F401 (re-exported)


def buckled_arch(n: int, delta: float) -> np.ndarray:
    """Angles of a single arch, theta_i = A cos(pi (i - 1/2) / N), with end-to-end length N (1 - delta).

    The profile is odd about the middle, so sum sin theta = 0 exactly; A solves sum cos = N (1 - delta).
    """
    from scipy.optimize import brentq  # start-up time: scipy.optimize costs ~0.3 s to import

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


def pushed_chains(n: int, n_chains: int, perturbation: float, seed: int) -> np.ndarray:
    """Absolute angles of `n_chains` chains (chain 1 first), each the static shape under seeded
    random lateral pushes (pushed_shape), scaled so that its largest angle is `perturbation`.

    A smooth start excites no fast, tip-localised modes; a random angle per particle would, and
    those are exactly what a first-order integrator gets wrong (they decay, but the instability
    amplifies the error).
    """
    rng = np.random.default_rng(seed)
    shapes = []
    for _ in range(n_chains):
        shape = pushed_shape(n, rng.standard_normal(n))
        shapes.append(perturbation * shape / np.abs(shape).max())
    return np.concatenate(shapes)

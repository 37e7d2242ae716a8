"""A simulated trajectory: sample times and absolute angles, the same for both engines."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .params import Physics


@dataclass
class Trajectory:
    """t: (T,) times in tau; theta: (T, n_angles) absolute angles (chain 1 then chain 2); head: (T, 2) position
    of the first pendulum's pivot for scenes whose pivot moves (Scene.head_coordinates: the paraboloid), else
    None (the pivot sits at the origin); polarity: (T, units) absolute angles psi of the self-aligning active units
    (elastoactive.terms.self_aligning: one per loaded particle, chain 1 then chain 2; a network scene's: one per
    active unit, in node order), else None; nodes: (T, P, 2) lab positions of every node of a network scene
    (Scene.network; its theta has shape (T, 0)), else None."""

    t: np.ndarray
    theta: np.ndarray
    physics: Physics
    engine: str
    wall_time_s: float = 0.0
    info: dict = field(default_factory=dict)
    head: np.ndarray | None = None
    polarity: np.ndarray | None = None
    nodes: np.ndarray | None = None

    def chain(self, k: int) -> np.ndarray:
        """Angles of chain k (0 or 1), shape (T, N)."""
        n = self.physics.n
        return self.theta[:, k * n : (k + 1) * n]

"""A simulated trajectory: sample times and absolute angles, the same for both engines."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import ParameterError
from .params import Physics


def _array(name: str, values, ndim: int, samples: int | None = None) -> np.ndarray:
    """values as a float array of `ndim` dimensions (and `samples` rows); a ParameterError naming the field else."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"Trajectory.{name} must be an array of numbers, got {type(values).__name__}") from None
    if array.ndim != ndim or (samples is not None and array.shape[0] != samples):
        rows = "" if samples is None else f", one row per time of t ({samples})"
        raise ParameterError(f"Trajectory.{name} must have {ndim} dimension(s){rows}; got shape {array.shape}")
    return array


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

    def __post_init__(self) -> None:
        """The records as float arrays (a Trajectory built from lists measures as one from an engine does), their
        shapes checked: t (T,), theta (T, n_angles), head (T, 2), polarity (T, units), nodes (T, P, 2)."""
        self.t = _array("t", self.t, 1)
        self.theta = _array("theta", self.theta, 2, len(self.t))
        for name, ndim in (("head", 2), ("polarity", 2), ("nodes", 3)):
            if getattr(self, name) is not None:
                setattr(self, name, _array(name, getattr(self, name), ndim, len(self.t)))

    def chain(self, k: int) -> np.ndarray:
        """Angles of chain k (0 or 1), shape (T, N)."""
        n = self.physics.n
        return self.theta[:, k * n : (k + 1) * n]

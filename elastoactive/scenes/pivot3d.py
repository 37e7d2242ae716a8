"""The chain on a free ball pivot in three dimensions: the rotating pin (scenes.rotating_pin) off the table. No spring
holds the first link; above the planar rotating pin's threshold the bent chain turns rigidly about a fixed axis through
the pivot, in a plane that its start sets (docs/model3d.md, section 7).

The clamped 3D chain's kind (scenes.clamped3d: its state, engines, automatic numerics, drawing) with clamped = False.
Its observables are the rigid turn's: rotation_rate, |omega| of the best rigid rotation of the tangents (the sense is a
direction in 3D, not a sign), and turn_tilt, the angle between the turn's axis and e_z (0: a turn in the table's
plane). Its beat signal is the bend between the first and the last link, constant in a rigid turn (no beat).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..analysis import observables as obs
from ..core.observables import Observable
from ..core.trajectory import Trajectory
from ..core.units import Signal
from .base import Onset, PathView, ValidationCase
from .clamped3d import Clamped3D

if TYPE_CHECKING:  # typing only: params imports the registry that holds scenes
    from ..core.params import Physics

BEND = Signal("bend", "bend, the angle between the first and the last link", "rad")


def turn_vectors(t: np.ndarray, tangents: np.ndarray) -> np.ndarray:
    """The angular velocity omega (T, 3) of the best rigid rotation t_k' = omega x t_k of unit tangents (T, N, 3) at
    each sample (central differences in time): the least-squares solution of sum_k (1 - t_k t_k^T) omega =
    sum_k t_k x t_k', exact for a rigid turn."""
    rates = np.gradient(tangents, t, axis=0)
    eye = np.eye(3)
    a = np.einsum("tn,ij->tij", np.ones(tangents.shape[:2]), eye) - np.einsum("tni,tnj->tij", tangents, tangents)
    b = np.cross(tangents, rates).sum(axis=1)
    return np.linalg.solve(a, b[..., None])[..., 0]


class Pivot3D(Clamped3D):
    name = "rotating-pin-3d"
    summary = (
        "chain on a free ball pivot, in three dimensions: turns rigidly about a fixed axis above the pin's threshold"
    )
    clamped = False
    planar_scene = "rotating-pin"
    term_parameters = ("n", "sigma", "drag_ratio")
    """Every particle loaded: the planar rotating pin's threshold (analysis.stability.rotation_threshold) is the fully
    loaded chain's, so a partial load has no onset to hold the 3D turn to."""
    paced_by_beat = False
    compared = ("rotation_rate",)
    observables = (
        "rotation_rate",  # the rotating pin's (scenes.rotating_pin): here |omega| of the rigid turn, rad/tau
        Observable("turn_tilt", "rad", "angle between the turn's axis and e_z (0: a turn in the xy plane)",
                   error="absolute", floor=0.0),
    )  # fmt: skip

    def beat_signal(self, physics: Physics) -> Signal:
        return BEND

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        t = self.tangents(traj)
        return [np.arccos(np.clip(np.einsum("ta,ta->t", t[:, 0], t[:, -1]), -1.0, 1.0))]

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float | str]:
        ts, tangents = obs.steady_part(traj.t, self.tangents(traj), transient=transient)
        omega = turn_vectors(ts, tangents).mean(axis=0)
        rate = float(np.linalg.norm(omega))
        tilt = float(np.arccos(min(1.0, abs(omega[2]) / rate))) if rate > 0 else float("nan")
        return {"rotation_rate": rate, "turn_tilt": tilt}

    def onset(self, physics: Physics) -> Onset:
        from ..analysis import stability  # start-up time: scipy

        return Onset(stability.rotation_threshold(physics.n), 0.0, "steady rotation (a real eigenvalue crosses 0)")

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        """N = 7 at sigma = 0.8, the planar rotating pin's case, from the seeded non-planar start."""
        return (ValidationCase(self.physics(n=7, sigma=0.8), 300.0),)

    def tip_views(self, traj: Trajectory, keep: np.ndarray) -> tuple[PathView, ...]:
        """The tip's path in the plane of the turn (where a rigid turn is a circle about the pivot), then in three
        dimensions. The plane is the path's best fit (its normal the path's direction of least spread), its axes u
        along e_x's projection on it (e_y's where e_x is its normal) and v = normal x u: a turn in the xy plane is
        drawn on x and y."""
        tips = self.tip(traj)[keep]
        path = tips.reshape(-1, 3)
        normal = np.linalg.svd(path - path.mean(axis=0), full_matrices=False)[2][-1]
        u = next(u for e in np.eye(3)[:2] if np.linalg.norm(u := e - (e @ normal) * normal) > 1e-6)
        u /= np.linalg.norm(u)
        v = np.cross(normal if normal[2] >= 0 else -normal, u)
        plane = np.stack([tips @ u, tips @ v], axis=-1)
        return PathView(plane, ("u", "v"), "in the plane of the turn"), PathView(tips, ("x", "y", "z"), "3D")

    def video_period(self, traj: Trajectory) -> float | None:
        """One turn per second of video."""
        omega = self.measure_extra(traj, 0.5 * float(traj.t[-1]))["rotation_rate"]
        return 2.0 * math.pi / omega if omega > 1e-3 else None


SCENE = Pivot3D()

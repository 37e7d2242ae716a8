"""Frames of a chain in three dimensions (the clamped-3d scene): the recorded link directions, interpolated to a
frame's time, are written into a separate MjData of the 3D chain's model (elastoactive.mjcf.chain3d: ball joints at
zero twist) and passed through mj_kinematics; only then is the frame drawn, by a free camera looking obliquely down
the clamp axis (azimuth CAMERA_AZIMUTH, elevation CAMERA_ELEVATION) at the middle of every position the chain takes
over the frames, far enough to hold them all. A caption gives the scene, N, sigma and the time. Rendering never touches
the physics.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ..core.trajectory import Trajectory
from ..mjcf.chain3d import Chain3DModel, build_spec3d, qpos_of_tangents
from .gl import _Caption, _interpolate, _renderer, prepare_visual

CAMERA_AZIMUTH = 210.0
"""Degrees about the vertical: looking from beyond the tip's side, a little aside, back at the clamp."""
CAMERA_ELEVATION = -25.0
"""Degrees: looking down a little on the clamp axis."""
FRAMING = 1.6
"""Camera distance over the largest extent of the chain's positions over the frames."""


class Chain3DPainter:
    """Builds the render model and draws frames (one per time) of one 3D chain's trajectory."""

    def __init__(self, traj: Trajectory, *, width: int, height: int, bounds_times: np.ndarray, **options):
        physics = traj.physics
        self.traj, self.n = traj, physics.n
        self.chain = Chain3DModel(physics.n, physics.sigma, physics.drag_ratio)
        self.model = build_spec3d(self.chain).compile()
        prepare_visual(self.model, width, height)
        self.data = mujoco.MjData(self.model)  # the render's own state: never the simulating one
        self.positions = traj.positions()[:, 0]  # (T, N, 3)
        shown = _interpolate(traj.t, self.positions, np.asarray(bounds_times, dtype=float)).reshape(-1, 3)
        points = np.vstack([shown, np.zeros((1, 3))])
        lo, hi = points.min(axis=0), points.max(axis=0)
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.camera.lookat[:] = 0.5 * (lo + hi)
        self.camera.distance = FRAMING * max(2.0, float(np.max(hi - lo)))
        self.camera.azimuth, self.camera.elevation = CAMERA_AZIMUTH, CAMERA_ELEVATION
        self.caption = _Caption(width, height, physics.scene_def.caption_line(physics))
        self.renderer = _renderer(self.model, height, width, self.model.ngeom + 100)

    def close(self) -> None:
        self.renderer.close()

    def frame(self, t: float) -> np.ndarray:
        r = _interpolate(self.traj.t, self.positions, np.array([t]))[0]
        tangents = np.diff(r, axis=0, prepend=np.zeros((1, 3)))
        self.data.qpos[:] = qpos_of_tangents(self.chain, tangents)
        self.data.time = t
        mujoco.mj_kinematics(self.model, self.data)
        self.renderer.update_scene(self.data, self.camera)
        return self.caption.draw(self.renderer.render(), f"t = {t:.1f} τ")

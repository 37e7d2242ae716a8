"""Frames of a chain in three dimensions (the clamped-3d scene): two orthographic views side by side, each labelled,
with the tip's trace, so that a frame tells a planar beat from a whirl.

  left panel    the side view: looking across the clamp axis along the minor axis of the tip's path across that axis
                (over the frames shown, trails included), so a beat is seen face on; the clamp axis x runs to the
                right, the path's major axis up. A chain that moves in the xy plane is seen from above, as the planar
                scenes are.
  right panel   the end-on view: looking back down the clamp axis from beyond the tip (world y to the right, z up,
                the axis at the centre): a whirl's tip traces a circle here, a planar beat's a line.

Each panel frames what it shows over every frame (and its trail) once, so the cameras hold still through a video. The
tip's trace is its path over the last `trail` seconds of video (by default one beat or turn), fading, drawn in both
views; the clamp axis is a faint line; the planar scenes' table (the floor) is not drawn. A caption gives the scene, N,
sigma and the time; a band at the bottom names each view.

The recorded link directions, interpolated to a frame's time, are written into a separate MjData of the 3D chain's
model (elastoactive.mjcf.chain3d: ball joints at zero twist) and passed through mj_kinematics; only then is the frame
drawn. Rendering never touches the physics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from ..core.trajectory import Trajectory
from ..mjcf.chain3d import Chain3DModel, build_spec3d, qpos_of_tangents
from .gl import _add_geom, _Caption, _interpolate, _renderer, prepare_visual

TRACE_POINTS = 60
"""Segments of the tip's trace in a frame."""
TRACE_RGBA = (0.98, 0.85, 0.25, 0.95)
"""The tip's trace (fading to transparent at its old end)."""
AXIS_RGBA = (0.6, 0.65, 0.75, 0.35)
"""The clamp axis, a faint line."""
DIVIDER_RGB = (90, 90, 100)
"""The line between the panels."""
MARGIN = 0.35
"""Room (units of l) around everything a panel shows: a bead's radius and some air."""
SMALLEST_VIEW = 1.0
"""Least extent (units of l) a panel shows across the clamp axis, so a straight chain is not blown up to fill it."""

SIDE_LABEL = "side, face on to the tip's path: x →"
END_LABEL = "down the clamp axis: y →, z ↑"


@dataclass(frozen=True)
class View:
    """One panel's orthographic camera: it looks along `forward` (unit vector, world frame) at `lookat`, the image's
    axes are `right` (= forward x up) and `up`, and it shows `extent` l from the panel's bottom to its top."""

    label: str
    forward: np.ndarray
    up: np.ndarray
    lookat: np.ndarray
    extent: float
    distance: float

    @property
    def right(self) -> np.ndarray:
        return np.cross(self.forward, self.up)

    def camera(self) -> mujoco.MjvCamera:
        """MuJoCo's free camera along `forward` (azimuth and elevation of that direction; MuJoCo's up is then `up`)."""
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.orthographic = 1  # the model's fovy is then the height shown, in l
        cam.lookat[:] = self.lookat
        cam.distance = self.distance
        f = self.forward
        cam.azimuth = math.degrees(math.atan2(f[1], f[0])) if abs(f[2]) < 1.0 - 1e-12 else 90.0
        cam.elevation = math.degrees(math.asin(float(np.clip(f[2], -1.0, 1.0))))
        return cam


def side_direction(tip_path: np.ndarray) -> np.ndarray:
    """The side view's direction of sight: the minor axis (0, c, s) of the tip's path (..., 3) across the clamp axis,
    with c > 0 (or s < 0: looking down), so that the view is face on to a beat. A path in the xy plane gives -z
    (seen from above, as the planar scenes)."""
    lateral = tip_path.reshape(-1, 3)[:, 1:]
    lateral = lateral - lateral.mean(axis=0)
    _, axes = np.linalg.eigh(lateral.T @ lateral)
    c, s = axes[:, 0]
    if c < 0 or (c == 0 and s > 0):
        c, s = -c, -s
    return np.array([0.0, c, s])


def _framed(label, forward, up, points, width, height, top_px, bottom_px, centre_v=None) -> View:
    """The View along forward with `up` that holds every point (k, 3) inside the panel below its top band (top_px)
    and above its bottom band (bottom_px); centre_v: the up coordinate to keep at the middle (the clamp axis)."""
    right = np.cross(forward, up)
    u, v, w = points @ right, points @ up, points @ forward
    lo_u, hi_u = u.min() - MARGIN, u.max() + MARGIN
    if centre_v is None:
        lo_v, hi_v = v.min() - MARGIN, v.max() + MARGIN
    else:
        half = max(np.abs(v - centre_v).max() + MARGIN, SMALLEST_VIEW / 2)
        lo_v, hi_v = centre_v - half, centre_v + half
    free = 1.0 - (top_px + bottom_px) / height
    extent = max((hi_v - lo_v) / free, (hi_u - lo_u) / (width / height))
    mid_v = 0.5 * (lo_v + hi_v) + 0.5 * (top_px - bottom_px) / height * extent
    depth = 0.5 * (w.min() + w.max())
    lookat = 0.5 * (lo_u + hi_u) * right + mid_v * up + depth * forward
    return View(label, forward, up, lookat, float(extent), float(w.max() - w.min() + 4.0 * MARGIN + 1.0))


def views(positions: np.ndarray, width: int, height: int, top_px: int, bottom_px: int) -> tuple[View, View]:
    """The side view and the end-on view of panels width x height that frame the chain's positions (S, N, 3) (its
    tip's path sets the side view's direction), the clamp and the axis between."""
    clamp = np.array([[x, y, z] for x in (-0.3, 0.0) for y in (-0.3, 0.3) for z in (-0.15, 0.15)])
    points = np.vstack([positions.reshape(-1, 3), clamp])
    forward = side_direction(positions[:, -1])
    up = np.array([0.0, -forward[2], forward[1]])  # across the axis and the sight: the path's major axis
    side = _framed(SIDE_LABEL, forward, up, points, width, height, top_px, bottom_px, centre_v=0.0)
    across = np.vstack([positions.reshape(-1, 3), np.zeros((1, 3))])  # the clamp stays behind the axis
    half = max(np.abs(across[:, 1:]).max(), SMALLEST_VIEW / 2)
    box = np.array([[0.0, y, z] for y in (-half, half) for z in (-half, half)])
    end = _framed(
        END_LABEL,
        np.array([-1.0, 0.0, 0.0]),
        np.array([0.0, 0.0, 1.0]),
        np.vstack([points, box]),
        width,
        height,
        top_px,
        bottom_px,
        centre_v=0.0,
    )
    return side, end


class _Labels:
    """Each panel's name burnt into the bottom band of a frame (matplotlib's Agg renderer), the band dimmed."""

    def __init__(self, width: int, height: int, names: tuple[str, ...]):
        # start-up time: matplotlib (~0.3 s) loads only when a frame is drawn
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.h = max(14, int(round(0.07 * height)))
        dpi = 100
        fig = Figure(figsize=(width / dpi, self.h / dpi), dpi=dpi)
        fig.patch.set_alpha(0.0)
        canvas = FigureCanvasAgg(fig)
        for k, name in enumerate(names):
            fig.text((k + 0.5) / len(names), 0.5, name, ha="center", va="center", color="white",
                     fontsize=0.45 * self.h * 72 / dpi)  # fmt: skip
        canvas.draw()
        self.rgba = np.asarray(canvas.buffer_rgba()).astype(np.float32)

    def draw(self, frame: np.ndarray) -> np.ndarray:
        a = self.rgba[..., 3:4] / 255.0
        band = frame[-self.h :].astype(np.float32) * 0.35
        frame[-self.h :] = (band * (1.0 - a) + self.rgba[..., :3] * a).astype(np.uint8)
        return frame


def _at(t: np.ndarray, values: np.ndarray, times: np.ndarray) -> np.ndarray:
    """values (T, ...) interpolated linearly to `times` (clipped to the record): shape times.shape + (...)."""
    flat = _interpolate(t, values.reshape(len(t), -1), times)
    return flat.reshape(np.shape(times) + values.shape[1:])


class Chain3DPainter:
    """Builds the render model and draws frames (one per time) of one 3D chain's trajectory: two panels side by side
    (the module docstring)."""

    def __init__(
        self, traj: Trajectory, *, width: int, height: int, rate: float, trail: float, bounds_times, **options
    ):
        physics = traj.physics
        self.traj, self.n = traj, physics.n
        self.chain = Chain3DModel(physics.n, physics.sigma, physics.drag_ratio)
        self.model = build_spec3d(self.chain).compile()
        self.panel = width // 2
        prepare_visual(self.model, self.panel, height)
        floor = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_GEOM, "floor")
        if floor >= 0:  # the planar scenes' table would cut through a side view
            self.model.geom_rgba[floor, 3] = 0.0
        self.data = mujoco.MjData(self.model)  # the render's own state: never the simulating one
        self.positions = traj.positions()[:, 0]  # (T, N, 3)
        self.trail_tau = trail * rate
        bounds = np.sort(np.asarray(bounds_times, dtype=float))
        t0 = bounds[0] - self.trail_tau
        span = np.concatenate([bounds, traj.t[(traj.t >= t0) & (traj.t <= bounds[-1])]])
        self.caption = _Caption(width, height, physics.scene_def.caption_line(physics))
        self.labels = _Labels(width, height, (SIDE_LABEL, END_LABEL))
        shown = _at(traj.t, self.positions, span)
        self.views = views(shown, self.panel, height, self.caption.h, self.labels.h)
        self.cameras = [view.camera() for view in self.views]
        self.axis = (np.array([-0.3, 0.0, 0.0]), np.array([physics.n + 0.5, 0.0, 0.0]))
        self.line_px = max(1.5, height / 160)
        self.renderer = _renderer(self.model, height, self.panel, self.model.ngeom + TRACE_POINTS + 50)

    def close(self) -> None:
        self.renderer.close()

    def frame(self, t: float) -> np.ndarray:
        r = _at(self.traj.t, self.positions, np.array([t]))[0]
        tangents = np.diff(r, axis=0, prepend=np.zeros((1, 3)))
        self.data.qpos[:] = qpos_of_tangents(self.chain, tangents)
        self.data.time = t
        mujoco.mj_kinematics(self.model, self.data)
        trace = None
        t0 = max(self.traj.t[0], t - self.trail_tau)
        if t - t0 > 0:
            trace = _at(self.traj.t, self.positions[:, -1], np.linspace(t0, t, TRACE_POINTS + 1))
        panels = []
        for view, camera in zip(self.views, self.cameras):
            self.model.vis.global_.fovy = view.extent
            self.renderer.update_scene(self.data, camera)
            scene = self.renderer.scene
            _add_geom(scene, mujoco.mjtGeom.mjGEOM_LINE, AXIS_RGBA, *self.axis, self.line_px)
            if trace is not None:
                for j in range(TRACE_POINTS):
                    rgba = (*TRACE_RGBA[:3], TRACE_RGBA[3] * (0.4 + 0.6 * (j + 1) / TRACE_POINTS))
                    _add_geom(scene, mujoco.mjtGeom.mjGEOM_LINE, rgba, trace[j], trace[j + 1], self.line_px)
            panels.append(self.renderer.render())
        frame = np.concatenate(panels, axis=1)
        frame[:, self.panel - 1 : self.panel + 1] = DIVIDER_RGB
        self.labels.draw(frame)
        return self.caption.draw(frame, f"t = {t:.1f} τ")

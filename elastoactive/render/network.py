"""Frames of a network scene's trajectory (Trajectory.nodes): the nodes, the springs, an arrow per active unit.

As for chains (elastoactive.render), rendering never touches the physics: the recorded node positions, interpolated
to a frame's time, are written into a separate MjData of the network's model (elastoactive.mjcf.network) and passed
through mj_forward; only then is the frame drawn. What a frame shows (top-down camera framing every node at every
time shown):
  - free nodes as the model's beads (active ones orange, passive ones grey), pinned nodes as dark discs
  - every spring as a bar coloured by its strain (blue compressed, grey at rest, yellow stretched, saturating at
    STRAIN_SCALE), pinned-to-pinned ones included
  - an arrow on every active unit along its polarity (cos psi, sin psi), length ARROW_PER_SIGMA * sigma (within
    ARROW_MIN and ARROW_MAX)
  - the trap's anchor of every free node as a faint ring, when the network has a trap
  - a caption: scene, nodes, sigma, l_a (and the scene's own parameters) and the time
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from ..core.errors import ParameterError
from ..core.params import Numerics
from ..core.trajectory import Trajectory
from ..mjcf.network import build_network_model, qpos_of_positions
from .gl import (
    ARROW_MAX,
    ARROW_PER_SIGMA,
    ARROW_RGBA,
    _add_geom,
    _Caption,
    _interpolate,
    _renderer,
    prepare_visual,
    top_camera,
)

ARROW_MIN = 0.35
"""Shortest arrow (units a): a unit's polarity stays visible beside its bead at small sigma."""
STRAIN_SCALE = 0.1
"""Strain (|r| / a - 1) at which a spring's colour saturates."""
SPRING_WIDTH = 0.05
PINNED_RGBA = (0.2, 0.25, 0.3, 1.0)
PASSIVE_RGBA = (0.6, 0.62, 0.65, 1.0)
ANCHOR_RGBA = (0.5, 0.8, 0.6, 0.5)
REST_RGB = np.array([0.55, 0.6, 0.65])
STRETCHED_RGB = np.array([0.95, 0.8, 0.25])
COMPRESSED_RGB = np.array([0.25, 0.5, 0.95])
Z_SPRING, Z_ARROW = -0.05, 0.2


def strain_colour(strain: float) -> tuple[float, float, float, float]:
    """A spring's colour: grey at rest, towards yellow stretched and blue compressed, saturating at STRAIN_SCALE."""
    w = min(abs(strain) / STRAIN_SCALE, 1.0)
    end = STRETCHED_RGB if strain > 0 else COMPRESSED_RGB
    return (*((1.0 - w) * REST_RGB + w * end), 1.0)


def _unwrapped_polarity(traj: Trajectory) -> np.ndarray | None:
    """The polarity angles, unwrapped in time, so that interpolating between samples never takes the long way."""
    return None if traj.polarity is None else np.unwrap(np.asarray(traj.polarity, dtype=float), axis=0)


def _camera(xy: np.ndarray, width: int, height: int, caption_px: int, fovy_deg: float, pad: float):
    """Top-down free camera (x to the right, y up) whose view holds every point of xy (..., 2) with `pad` around."""
    pts = xy.reshape(-1, 2)
    return top_camera(pts.min(axis=0) - pad, pts.max(axis=0) + pad, width, height, caption_px, fovy_deg)


class NetworkPainter:
    """Builds the network's render model and draws frames (one per time) of one trajectory; the interface of
    elastoactive.render's chain painter (frame(t), close())."""

    def __init__(
        self,
        traj: Trajectory,
        *,
        width: int,
        height: int,
        rate: float,
        trail: float,
        numerics: Numerics | None,
        bounds_times: np.ndarray,
    ):
        """As the chain painter's; `rate` and `trail` are not used (a network's nodes leave no trails)."""
        physics = traj.physics
        if traj.nodes is None:
            raise ParameterError(f"render: {physics.scene} has no network to draw (a chain: elastoactive.render)")
        network = physics.scene_def.network(physics)
        if traj.nodes.shape[1:] != (len(network.positions), 2):
            raise ParameterError(
                f"render: the trajectory's nodes {traj.nodes.shape[1:]} do not match the "
                f"{physics.scene} network's {len(network.positions)} nodes"
            )
        self.traj, self.network = traj, network
        self.nodes = np.asarray(traj.nodes, dtype=float).reshape(traj.t.size, -1)
        self.polarity = _unwrapped_polarity(traj)
        self.model = build_network_model(network, physics, numerics or Numerics())
        prepare_visual(self.model, width, height)
        for i in np.flatnonzero(~network.active & ~network.pinned):  # passive free nodes: grey beads
            self.model.geom(f"bead_{i}").rgba[:] = PASSIVE_RGBA
        self.data = mujoco.MjData(self.model)  # the render's own state: never the simulating one
        self.active = np.flatnonzero(network.active)
        self.arrow = max(ARROW_MIN, min(ARROW_MAX, ARROW_PER_SIGMA * physics.sigma)) if physics.sigma > 0 else 0.0
        self.caption = _Caption(width, height, traj.physics.scene_def.caption_line(traj.physics))
        span = np.concatenate([bounds_times, traj.t[(traj.t >= bounds_times[0]) & (traj.t <= bounds_times[-1])]])
        xy = _interpolate(traj.t, self.nodes, span).reshape(span.size, -1, 2)
        self.camera = _camera(
            xy, width, height, self.caption.h, float(self.model.vis.global_.fovy), pad=0.4 + self.arrow
        )
        extra = len(network.bonds) + 2 * len(network.positions) + 16
        self.renderer = _renderer(self.model, height, width, self.model.ngeom + extra + 100)
        self.options = mujoco.MjvOption()
        self.options.flags[mujoco.mjtVisFlag.mjVIS_TENDON] = False  # the springs are drawn below, strain-coloured

    def close(self) -> None:
        self.renderer.close()

    def positions(self, t: float) -> np.ndarray:
        """Node positions (P, 2) at time t (linear interpolation between samples)."""
        return _interpolate(self.traj.t, self.nodes, np.array([t]))[0].reshape(-1, 2)

    def frame(self, t: float) -> np.ndarray:
        network, data = self.network, self.data
        xy = self.positions(t)
        xy[network.pinned] = network.positions[network.pinned]  # exact: interpolation rounds
        data.qpos[:] = qpos_of_positions(network, xy)
        data.time = t
        mujoco.mj_forward(self.model, data)
        self.renderer.update_scene(data, self.camera, self.options)
        scene = self.renderer.scene
        z = np.zeros((len(xy), 1))
        pts = np.concatenate([xy, z], axis=1)
        for (i, j), a in zip(network.bonds, network.rest_lengths):
            p, q = pts[i].copy(), pts[j].copy()
            p[2] = q[2] = Z_SPRING
            strain = np.linalg.norm(q - p) / a - 1.0 if a > 0 else 0.0
            _add_geom(scene, mujoco.mjtGeom.mjGEOM_CAPSULE, strain_colour(strain), p, q, SPRING_WIDTH)
        for i in np.flatnonzero(network.pinned):
            p = pts[i]
            _add_geom(scene, mujoco.mjtGeom.mjGEOM_CYLINDER, PINNED_RGBA, p + [0, 0, -0.1], p + [0, 0, 0.05], 0.14)
        if network.trap > 0:
            for i in np.flatnonzero(~network.pinned):
                c = np.array([*network.anchors[i], -0.15])
                _add_geom(scene, mujoco.mjtGeom.mjGEOM_CYLINDER, ANCHOR_RGBA, c, c + [0, 0, 0.01], 0.08)
        if self.arrow > 0 and self.polarity is not None:
            psi = _interpolate(self.traj.t, self.polarity, np.array([t]))[0]
            for i, angle in zip(self.active, psi):
                p = pts[i].copy()
                p[2] = Z_ARROW
                tip = p + self.arrow * np.array([math.cos(angle), math.sin(angle), 0.0])
                # MuJoCo 4.0 draws an mjGEOM_ARROW over half the connector's length (elastoactive.render), hence the 2
                _add_geom(scene, mujoco.mjtGeom.mjGEOM_ARROW, ARROW_RGBA, p, p + 2.0 * (tip - p), 0.04)
        pixels = self.renderer.render()
        return self.caption.draw(pixels, f"t = {t:.1f} γ/k")  # a network's time unit (units.NETWORK)


__all__ = ["NetworkPainter", "strain_colour"]

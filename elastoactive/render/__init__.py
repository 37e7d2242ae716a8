"""Off-screen video and stills of a trajectory (MuJoCo's Renderer, mediapy + imageio-ffmpeg).

Rendering never touches the physics: a recorded trajectory (absolute angles theta(t)) is turned
into hinge angles, written into a separate MjData of a separately built model and passed through
mj_forward; only then is the scene drawn. The simulating MjData is never used.

What a frame shows (top-down camera that frames the whole motion):
  - the chain(s): link capsules and particles (beads) of the model, the clamp(s) and the pin
  - an arrow on every particle for its follower force: along -x of the particle site (back
    toward the anchor), length ARROW_PER_SIGMA * sigma (units of l; nominal sigma, without
    noise; capped at ARROW_MAX)
  - fading trails of the particle paths over the last `trail` seconds of video
  - for the coupled pair, the coupling spring as a zigzag between the two first particles
  - with self-contact, the links' capsules and a marker at every contact; for the paraboloid, the dish (rings of
    equal height) and the trap's springs
  - a caption: scene, N, sigma (delta, kappa, rho where they apply) and the time in tau
A scene's kind says which painter draws it (Scene.painter): a network's is elastoactive.render.network's.

Time: frame k shows t = t_start + k * rate / fps, with `rate` in tau per second of video.
The default rate makes one beat of Theta last about a second (rate = 1 / (f tau)); a steadily
rotating chain makes one turn per second; DEFAULT_RATE otherwise.

GL back end: MUJOCO_GL is honoured when set; otherwise egl then osmesa are probed, each in a
subprocess (a failing back end cannot poison this process), and the first that renders is used.
"""

from __future__ import annotations

import errno
import math
import resource
import shutil
import time
from pathlib import Path

import mujoco
import numpy as np

from ..analysis import observables as obs
from ..core.errors import ParameterError
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory, particle_positions
from ..io.outputs import atomic_file
from ..io.progress import progress_bar
from ..mjcf.chain import build_model, qpos_of
from .gl import (  # noqa: F401 (API)
    ARROW_MAX,
    ARROW_PER_SIGMA,
    ARROW_RGBA,
    GL_BACKENDS,
    INSTALL_HINT,
    RenderError,
    _add_geom,
    _Caption,
    _interpolate,
    _renderer,
    gl_backend,
    prepare_visual,
    probe_backend,
    top_camera,
)
from .network import NetworkPainter  # noqa: F401 (API)

DEFAULT_RATE = 10.0  # tau per second of video when there is no oscillation to time it by
TRAIL_POINTS = 40  # samples per trail
MAX_TRAILS = 12  # trails drawn per chain at most (evenly spread, always including the tip)
SPRING_TEETH = 12

SPRING_RGBA = (0.35, 0.85, 0.55, 1.0)


# --------------------------------------------------------------------------- kinematics and timing


def interpolate(traj: Trajectory, times: np.ndarray) -> np.ndarray:
    """Angles at `times` (linear interpolation between samples, clipped to the record)."""
    return _interpolate(traj.t, traj.theta, times)


def interpolate_head(traj: Trajectory, times: np.ndarray) -> np.ndarray | None:
    """The head's position at `times` (as `interpolate`), or None for a scene whose pivot does not move."""
    return None if traj.head is None else _interpolate(traj.t, traj.head, times)


def default_rate(traj: Trajectory) -> float:
    """tau per second of video so that one beat (or one turn) lasts about a second on screen."""
    t = traj.t
    if t.size < 8 or t[-1] - t[0] <= 0:
        return DEFAULT_RATE
    scene = traj.physics.scene_def
    if not scene.paced_by_beat:  # e.g. a network: the scene's period, if it has one
        period = scene.video_period(traj)
        return DEFAULT_RATE if period is None else float(np.clip(period, 0.5, 200.0))
    freqs = []
    try:
        for x in scene.beat_signals(traj):
            if obs.amplitude(t, x) > 1e-3:
                f = obs.frequency(t, x)
                if f > 0:
                    freqs.append(f)
        if freqs:
            return float(np.clip(1.0 / min(freqs), 0.5, 200.0))
        period = traj.physics.scene_def.video_period(traj)
        if period is not None:
            return float(np.clip(period, 0.5, 200.0))
    except ValueError:
        pass
    return DEFAULT_RATE


MAX_FRAMES = 108_000
"""Most frames one video may hold: an hour at 30 fps. More comes from a rate far too small for the record."""


def frame_count(t_start: float, t_end: float, fps: float, rate: float) -> int:
    """Frames of a video of [t_start, t_end] at `fps` frames per second and `rate` tau per second."""
    return int(math.floor((t_end - t_start) / (rate / fps) + 1e-9)) + 1


def check_frames(span: float, fps: float, rate: float) -> None:
    """Refuse, naming --rate, a video of `span` tau with more than MAX_FRAMES frames (before any is made)."""
    count = (span * fps / rate) if span > 0 else 1.0
    if count + 1 > MAX_FRAMES:
        raise ParameterError(
            f"rate = {rate:g} tau per second of video at {fps:g} fps makes {count + 1:.3g} frames of the {span:g} tau "
            f"rendered (limit {MAX_FRAMES}: an hour at 30 fps); raise --rate, or render part of the run with "
            "--start/--end"
        )


def frame_times(t_start: float, t_end: float, fps: float, rate: float) -> np.ndarray:
    """Times (tau) of the frames: t_start + k * rate / fps up to t_end (at most MAX_FRAMES of them)."""
    check_frames(t_end - t_start, fps, rate)
    step = rate / fps
    return t_start + step * np.arange(max(frame_count(t_start, t_end, fps, rate), 1))


# --------------------------------------------------------------------------- the picture


def _camera(physics: Physics, xy: np.ndarray, width: int, height: int, caption_px: int, fovy_deg: float):
    """Top-down free camera (x to the right, y up) whose view holds every point of xy (..., 2)."""
    scene = physics.scene_def
    clamps = np.array([[-0.3, scene.chain_offset(physics, k)] for k in range(physics.n_chains)])
    pts = np.concatenate([xy.reshape(-1, 2), clamps, scene.extent_points(physics)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = max(0.45 + 0.5 * min(ARROW_MAX, ARROW_PER_SIGMA * physics.sigma), 0.04 * (hi - lo).max())
    lo, hi = lo - pad, hi + pad
    size = hi - lo
    floor = max(2.0, 0.25 * size.max())  # a still, straight chain still gets some room around it
    grow = np.maximum(floor - size, 0.0) / 2
    return top_camera(lo - grow, hi + grow, width, height, caption_px, fovy_deg)


def _trail_colours(n: int) -> np.ndarray:
    from matplotlib import colormaps  # start-up time: only when trails are drawn

    return colormaps["plasma"](np.linspace(0.15, 0.85, n))


class ChainPainter:
    """Builds the render model and draws frames (one per time) of one trajectory."""

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
        check_picture(width=width, height=height, trail=trail)
        physics = traj.physics
        self.traj, self.physics = traj, physics
        self.model = build_model(physics, numerics or Numerics())
        prepare_visual(self.model, width, height)
        self.data = mujoco.MjData(self.model)  # the render's own state: never the simulating one
        self._scene = None  # the mjvScene of the frame being made (for spring)
        self.sites = [
            [self.model.site(f"{p}particle_{i}").id for i in range(physics.n)]
            for p in physics.scene_def.chain_prefixes()[: physics.n_chains]
        ]  # the star: k of its arms
        self.trail_tau = trail * rate
        self.line_px = max(1.5, height / 160)  # trails are GL lines (width in pixels): capsules cost 5x more
        stride = max(1, math.ceil(physics.n / MAX_TRAILS))
        self.trailed = sorted({*range(physics.n - 1, -1, -stride)})
        self.colours = _trail_colours(physics.n)
        self.arrow = min(ARROW_MAX, ARROW_PER_SIGMA * physics.sigma)
        n_extra = physics.n_angles * (1 + TRAIL_POINTS) + 2 * SPRING_TEETH + 8
        self.caption = _Caption(width, height, physics.scene_def.caption_line(physics))
        # frame the whole motion: every particle at every time shown, trails included
        t0 = bounds_times[0] - self.trail_tau
        span = np.concatenate([bounds_times, traj.t[(traj.t >= t0) & (traj.t <= bounds_times[-1])]])
        xy = particle_positions(physics, interpolate(traj, span), interpolate_head(traj, span))
        self.camera = _camera(physics, xy, width, height, self.caption.h, float(self.model.vis.global_.fovy))
        self.renderer = _renderer(self.model, height, width, self.model.ngeom + n_extra + 100)
        self.options = mujoco.MjvOption()
        self.clamp = _moving_clamp(self.model, physics)
        if physics.contact:  # self-contacts drawn where the capsules touch (mj_forward of the frame finds them; a
            # force would not be the run's: the render state has no velocities and no follower forces)
            self.options.flags[mujoco.mjtVisFlag.mjVIS_CONTACTPOINT] = True
            self.model.vis.scale.contactwidth = 0.2
            self.model.vis.scale.contactheight = 0.08

    def close(self) -> None:
        self.renderer.close()

    def frame(self, t: float) -> np.ndarray:
        physics, data = self.physics, self.data
        now = np.array([t])
        head = interpolate_head(self.traj, now)
        data.qpos[:] = qpos_of(physics, interpolate(self.traj, now)[0], None if head is None else head[0])
        data.time = t
        if self.clamp is not None:  # a moving clamp: its box where the clamp point is, turned by its angle
            geom, pivot, rest, motion = self.clamp
            shift = pivot + (head[0] if (head is not None and motion.translates) else 0.0)
            angle = float(motion.angle(t))
            c, s = math.cos(angle), math.sin(angle)
            self.model.geom_pos[geom, :2] = (c * rest[0] - s * rest[1] + shift[0], s * rest[0] + c * rest[1] + shift[1])
            self.model.geom_quat[geom] = (math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2))
        mujoco.mj_forward(self.model, data)  # with self-contact, this also finds the contacts drawn
        self.renderer.update_scene(data, self.camera, self.options)
        scene = self.renderer.scene
        if self.trail_tau > 0:
            self._trails(scene, t)
        self._scene = scene
        physics.scene_def.decorate(self)  # scene-specific extras, e.g. the pair's coupling spring
        if self.arrow > 0:
            for sites in self.sites:
                for s in sites:
                    p = data.site_xpos[s].copy()
                    tip = p - self.arrow * data.site_xmat[s].reshape(3, 3)[:, 0]
                    p[2] = tip[2] = 0.2
                    # MuJoCo 4.0's renderer draws an mjGEOM_ARROW over half the connector's
                    # length (measured; tested in tests/render/test_render.py), hence the 2
                    _add_geom(scene, mujoco.mjtGeom.mjGEOM_ARROW, ARROW_RGBA, p, p + 2.0 * (tip - p), 0.04)
        pixels = self.renderer.render()
        return self.caption.draw(pixels, f"t = {t:.1f} τ")

    def _trails(self, scene, t: float) -> None:
        t0 = max(self.traj.t[0], t - self.trail_tau)
        if t - t0 <= 0:
            return
        times = np.linspace(t0, t, TRAIL_POINTS + 1)
        xy = particle_positions(self.physics, interpolate(self.traj, times), interpolate_head(self.traj, times))
        z = np.full(times.shape + (1,), -0.1)
        for c in range(self.physics.n_chains):
            for i in self.trailed:
                pts = np.concatenate([xy[:, c, i], z], axis=1)
                rgb = self.colours[i][:3]
                for j in range(TRAIL_POINTS):
                    w = (j + 1) / TRAIL_POINTS
                    _add_geom(scene, mujoco.mjtGeom.mjGEOM_LINE, (*rgb, 0.9 * w), pts[j], pts[j + 1], self.line_px)

    def spring(self, chain_a: int, particle_a: int, chain_b: int, particle_b: int) -> None:
        """Draw a zigzag spring between two particles into the frame being made (for Scene.decorate)."""
        scene = self._scene
        a = self.data.site_xpos[self.sites[chain_a][particle_a]].copy()
        b = self.data.site_xpos[self.sites[chain_b][particle_b]].copy()
        a[2] = b[2] = -0.05
        axis = b - a
        length = np.linalg.norm(axis)
        if length < 1e-9:
            return
        normal = np.array([-axis[1], axis[0], 0.0]) / length
        s = np.concatenate([[0.0], np.linspace(0.12, 0.88, 2 * SPRING_TEETH + 1), [1.0]])
        offset = np.zeros_like(s)
        offset[2:-2:2] = 0.18
        offset[3:-2:2] = -0.18
        pts = a + s[:, None] * axis + offset[:, None] * normal
        for p, q in zip(pts[:-1], pts[1:]):
            _add_geom(scene, mujoco.mjtGeom.mjGEOM_CAPSULE, SPRING_RGBA, p, q, 0.03)


def _moving_clamp(model, physics: Physics):
    """(geom id, its rest position relative to the clamp point, the ClampMotion) of chain 1's clamp box when a term
    moves the clamp (Term.clamp_motion), else None: the frames draw it where the clamp is (Trajectory.head, the point;
    the motion's angle)."""
    motions = [m for term in physics.active_terms() if (m := term.clamp_motion(physics)) is not None]
    geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "clamp")  # chain 1's clamp in every base file
    if not motions or geom < 0:
        return None
    pivot = model.body_pos[model.body(f"{physics.scene_def.chain_prefixes()[0]}segment_0").id, :2].copy()
    return geom, pivot, model.geom_pos[geom, :2].copy() - pivot, motions[0]


def _painter(traj: Trajectory, **options):
    """The painter of a trajectory: its scene's kind's (Scene.painter: a chain's ChainPainter, a network's
    render.network.NetworkPainter)."""
    return traj.physics.scene_def.painter(traj, **options)


def _window(traj: Trajectory, start: float | None, end: float | None) -> tuple[float, float]:
    t0 = traj.t[0] if start is None else float(start)
    t1 = traj.t[-1] if end is None else float(end)
    if not (math.isfinite(t0) and math.isfinite(t1) and traj.t[0] - 1e-9 <= t0 <= t1 <= traj.t[-1] + 1e-9):
        raise ParameterError(
            f"render window [{t0}, {t1}] must have start <= end and lie inside the record [{traj.t[0]}, {traj.t[-1]}]"
        )
    return t0, t1


MAX_FRAME_BYTES = 2**31
"""Most bytes of frames render_frames returns in one array (a video streams its frames instead)."""
MAX_SIDE = 8192
"""Largest frame width or height in pixels (off-screen GL buffers of this size work everywhere seen)."""
MAX_FPS = 240.0


def check_picture(
    *,
    fps: float = 30.0,
    rate: float | None = None,
    width: int = 640,
    height: int = 480,
    trail: float = 1.0,
    span: float | None = None,
) -> None:
    """Refuse, naming the option, a picture that cannot be made (before any simulation or rendering); `span`: the
    tau a video will show, when known (its number of frames is then checked too)."""
    if not (math.isfinite(fps) and 0 < fps <= MAX_FPS):
        raise ParameterError(f"fps (frames per second) must lie in (0, {MAX_FPS:g}], got {fps}")
    if rate is not None and not (math.isfinite(rate) and rate > 0):
        raise ParameterError(f"rate (tau per second of video) must be > 0, got {rate}")
    for name, side in (("width", width), ("height", height)):
        if not (isinstance(side, (int, np.integer)) and 16 <= side <= MAX_SIDE and side % 2 == 0):
            raise ParameterError(f"{name} must be an even number of pixels in [16, {MAX_SIDE}], got {side}")
    if not (math.isfinite(trail) and trail >= 0):
        raise ParameterError(f"trail (seconds of video) must be >= 0, got {trail}")
    if span is not None and rate is not None:
        check_frames(span, fps, rate)


def _check(fps: float, rate: float) -> None:
    check_picture(fps=fps, rate=rate)


def render_frames(
    traj: Trajectory,
    times: np.ndarray | None = None,
    *,
    fps: float = 30.0,
    rate: float | None = None,
    width: int = 640,
    height: int = 480,
    trail: float = 1.0,
    numerics: Numerics | None = None,
    start: float | None = None,
    end: float | None = None,
) -> np.ndarray:
    """Frames (F, height, width, 3) uint8 at `times` (default: the video's frame times)."""
    rate = default_rate(traj) if rate is None else float(rate)
    _check(fps, rate)
    t0, t1 = _window(traj, start, end)
    if times is None:
        times = frame_times(t0, t1, fps, rate)
    else:  # explicit times (a still): frame what those frames and their trails show
        times = np.atleast_1d(np.asarray(times, float))
        if times.min() < traj.t[0] - 1e-9 or times.max() > traj.t[-1] + 1e-9:
            raise ParameterError(f"times must lie inside the record [{traj.t[0]}, {traj.t[-1]}]")
    if times.size * width * height * 3 > MAX_FRAME_BYTES:
        raise ParameterError(
            f"{times.size} frames of {width}x{height} pixels take {times.size * width * height * 3:.3g} "
            f"bytes (limit {MAX_FRAME_BYTES:.3g}); render fewer times or write a video "
            "(render_trajectory streams its frames)"
        )
    painter = _painter(
        traj, width=width, height=height, rate=rate, trail=trail, numerics=numerics, bounds_times=np.sort(times)
    )
    try:
        return np.stack([painter.frame(float(t)) for t in times])
    finally:
        painter.close()


def render_still(traj: Trajectory, path, *, time: float | None = None, **kwargs) -> dict:
    """One frame (default: the last sample) to an image file (PNG), framed like the video."""
    import mediapy  # start-up time: only when an image is written

    time = traj.t[-1] if time is None else float(time)
    if not (math.isfinite(time) and traj.t[0] - 1e-9 <= time <= traj.t[-1] + 1e-9):
        raise ParameterError(
            f"time of the still must lie inside the record [{traj.t[0]:g}, {traj.t[-1]:g}] tau, got {time}"
        )
    frame = render_frames(traj, np.array([time]), **kwargs)[0]
    path = Path(path)
    with atomic_file(path) as tmp:
        mediapy.write_image(tmp, frame)
    return {"path": str(path), "time": time, "backend": gl_backend()}


def setup_ffmpeg() -> str:
    """Point mediapy at the ffmpeg binary shipped by imageio-ffmpeg (no system ffmpeg needed)."""
    # start-up time: the video writer loads only when a video is written
    import imageio_ffmpeg
    import mediapy

    exe = imageio_ffmpeg.get_ffmpeg_exe()
    mediapy.set_ffmpeg(exe)
    return exe


def _encoder_stopped(tmp: Path, err: BaseException) -> str:
    """Why the video encoder (an ffmpeg process) stopped writing `tmp`: a file-size limit, a full disk, or what it
    said."""
    limit = resource.getrlimit(resource.RLIMIT_FSIZE)[0]
    if limit != resource.RLIM_INFINITY and tmp.exists() and tmp.stat().st_size >= limit - (1 << 16):
        return f"File too large: the video reached the file-size limit (ulimit -f) of {limit} bytes"
    if shutil.disk_usage(tmp.parent).free < (1 << 20):
        return "No space left on device"
    said = [line for line in str(err).splitlines() if line.strip()]
    return f"the video encoder ffmpeg stopped{': ' + said[-1] if said else ''}"


def render_trajectory(
    traj: Trajectory,
    path,
    *,
    fps: float = 30.0,
    rate: float | None = None,
    width: int = 640,
    height: int = 480,
    trail: float = 1.0,
    numerics: Numerics | None = None,
    start: float | None = None,
    end: float | None = None,
    progress: bool = True,
) -> dict:
    """Write an MP4 (H.264) of the trajectory; returns dict(frames, seconds, path, rate, fps, backend, wall_time_s).

    Frame k shows t = start + k * rate / fps (rate in tau per second of video; default: one beat
    per second). A progress bar shows for renders longer than a couple of seconds of video.
    """
    import mediapy  # start-up time: only when a video is written

    rate = default_rate(traj) if rate is None else float(rate)
    _check(fps, rate)
    t0, t1 = _window(traj, start, end)
    times = frame_times(t0, t1, fps, rate)
    setup_ffmpeg()
    path = Path(path)
    begin = time.perf_counter()
    painter = _painter(traj, width=width, height=height, rate=rate, trail=trail, numerics=numerics, bounds_times=times)
    bar = None
    if progress and times.size > 60:
        bar = progress_bar(times.size, f"render {traj.physics.scene}", "frame")
    try:
        with atomic_file(path) as tmp:
            try:
                with mediapy.VideoWriter(tmp, shape=(height, width), fps=fps) as writer:
                    for t in times:
                        writer.add_image(painter.frame(float(t)))
                        if bar is not None:
                            bar.update(1)
            except (RuntimeError, BrokenPipeError) as err:  # the encoder died: atomic_file names the file
                raise OSError(errno.EIO, _encoder_stopped(tmp, err)) from None
    finally:
        painter.close()
        if bar is not None:
            bar.close()
    return {
        "path": str(path),
        "frames": int(times.size),
        "seconds": float(times.size / fps),
        "fps": float(fps),
        "rate": rate,
        "backend": gl_backend(),
        "wall_time_s": time.perf_counter() - begin,
    }


__all__ = [
    "ChainPainter",
    "RenderError",
    "gl_backend",
    "probe_backend",
    "render_frames",
    "render_still",
    "render_trajectory",
    "default_rate",
    "frame_times",
    "particle_positions",
    "interpolate",
    "interpolate_head",
    "setup_ffmpeg",
    "INSTALL_HINT",
]

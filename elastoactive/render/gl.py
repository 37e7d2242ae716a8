"""What every picture of a trajectory needs, chain or network: the off-screen GL back end, the caption band, geoms
added to a frame, samples interpolated to a frame's time (elastoactive.render draws chains, elastoactive.render.network
networks).

GL back end: MUJOCO_GL is honoured when set; otherwise egl then osmesa are probed, each in a
subprocess (a failing back end cannot poison this process), and the first that renders is used.
"""

from __future__ import annotations

import importlib
import math
import os
import subprocess
import sys

import mujoco
import numpy as np

GL_BACKENDS = ("egl", "osmesa")
INSTALL_HINT = (
    "Off-screen rendering needs an OpenGL back end. On Debian/Ubuntu install EGL "
    "(apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 libgl1) or OSMesa "
    "(apt-get install libosmesa6); `bash scripts/setup.sh` installs them when run as root. "
    "Then leave MUJOCO_GL unset (elastoactive tries egl, then osmesa) or set MUJOCO_GL=egl or osmesa."
)

ARROW_PER_SIGMA = 0.6  # follower-force arrow length per unit sigma (units of l)
ARROW_MAX = 0.9  # ... capped so that a strong force does not hide the chain

ARROW_RGBA = (0.95, 0.25, 0.3, 1.0)


class RenderError(RuntimeError):
    """Rendering is impossible here (no working OpenGL back end); the message says what to install."""


_PROBE = """
import mujoco
m = mujoco.MjModel.from_xml_string('<mujoco><worldbody><geom size="1"/></worldbody></mujoco>')
d = mujoco.MjData(m)
mujoco.mj_forward(m, d)
r = mujoco.Renderer(m, 16, 16)
r.update_scene(d)
px = r.render()
r.close()
assert px.shape == (16, 16, 3), px.shape
print("ok")
"""

_backend: str | None = None


def probe_backend(name: str, timeout: float = 60.0) -> str | None:
    """Try back end `name` in a subprocess: None when it renders, else the reason it failed."""
    env = {**os.environ, "MUJOCO_GL": name}
    try:
        out = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return f"timed out after {timeout:g} s"
    if out.returncode == 0 and out.stdout.strip().endswith("ok"):
        return None
    lines = [line for line in (out.stderr or out.stdout).strip().splitlines() if line.strip()]
    return lines[-1] if lines else f"exit status {out.returncode}"


def _activate(name: str) -> None:
    """Make mujoco.Renderer use back end `name` in this process (MUJOCO_GL is read at import)."""
    os.environ["MUJOCO_GL"] = name
    try:  # inside: the GL module must be (re)loaded after MUJOCO_GL is set
        from mujoco.rendering.classic import gl_context
    except ImportError:  # a mujoco without the classic renderer: it reads MUJOCO_GL itself
        return
    if getattr(gl_context, "_MUJOCO_GL", name) != name:
        try:
            importlib.reload(gl_context)
        except Exception as err:  # e.g. PyOpenGL already loaded for another platform
            raise RenderError(f"could not switch MuJoCo to MUJOCO_GL={name}: {err}\n{INSTALL_HINT}") from err
        mujoco.GLContext = getattr(gl_context, "GLContext", None)


def gl_backend() -> str:
    """The GL back end rendering uses (chosen once per process); RenderError when none works.

    A MUJOCO_GL set by the user is used as is (an error shows when the renderer is created);
    otherwise egl then osmesa are probed in a subprocess and the first that works is kept, and
    MUJOCO_GL is set so that child processes use it too.
    """
    global _backend
    if _backend is not None:
        return _backend
    user = os.environ.get("MUJOCO_GL", "").strip().lower()
    if user:
        _activate(user)
        _backend = user
        return user
    failures = []
    for name in GL_BACKENDS:
        reason = probe_backend(name)
        if reason is None:
            _activate(name)
            _backend = name
            return name
        failures.append(f"  MUJOCO_GL={name}: {reason}")
    raise RenderError("no OpenGL back end works on this machine:\n" + "\n".join(failures) + "\n" + INSTALL_HINT)


def _renderer(model, height: int, width: int, max_geom: int):
    backend = gl_backend()
    try:
        return mujoco.Renderer(model, height, width, max_geom=max_geom)
    except Exception as err:
        raise RenderError(f"could not render with MUJOCO_GL={backend}: {err}\n{INSTALL_HINT}") from err


# --------------------------------------------------------------------------- the picture


def prepare_visual(model, width: int, height: int) -> None:
    """Set a model's visual options for off-screen frames of width x height: the offscreen buffer at least that
    large, and the soft headlight every drawing uses."""
    vis = model.vis
    vis.global_.offwidth = max(vis.global_.offwidth, width)
    vis.global_.offheight = max(vis.global_.offheight, height)
    vis.headlight.ambient[:] = 0.35
    vis.headlight.diffuse[:] = 0.45
    vis.headlight.specular[:] = 0.0


def top_camera(lo: np.ndarray, hi: np.ndarray, width: int, height: int, caption_px: int, fovy_deg: float):
    """Top-down free camera (x to the right, y up) that frames the box [lo, hi] (world x, y) in a frame of
    width x height pixels whose top caption_px rows hold the caption band."""
    size = hi - lo
    free = 1.0 - caption_px / height  # fraction of the height below the caption
    half_h = max(size[1] / free, size[0] / (width / height)) / 2  # half the world height seen
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    centre = (lo + hi) / 2
    cam.lookat[:] = [centre[0], centre[1] + half_h * (1.0 - free), 0.0]
    cam.distance = half_h / math.tan(math.radians(fovy_deg) / 2)
    cam.elevation = -90.0
    cam.azimuth = 90.0
    return cam


def _interpolate(t: np.ndarray, values: np.ndarray, times: np.ndarray) -> np.ndarray:
    times = np.clip(np.asarray(times, dtype=float), t[0], t[-1])
    if t.size == 1:
        return np.broadcast_to(values[0], times.shape + values.shape[1:]).copy()
    i = np.clip(np.searchsorted(t, times, side="right") - 1, 0, t.size - 2)
    w = ((times - t[i]) / (t[i + 1] - t[i]))[..., None]
    return (1.0 - w) * values[i] + w * values[i + 1]


class _Caption:
    """Text burnt into the top band of a frame with matplotlib's Agg renderer (no window needed)."""

    def __init__(self, width: int, height: int, left: str):
        # start-up time: matplotlib (~0.3 s) loads only when a frame is drawn
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.h = max(14, int(round(0.07 * height)))
        dpi = 100
        fontsize = 0.5 * self.h * 72 / dpi
        self.fig = Figure(figsize=(width / dpi, self.h / dpi), dpi=dpi)
        self.fig.patch.set_alpha(0.0)
        self.canvas = FigureCanvasAgg(self.fig)
        kw = dict(color="white", va="center", fontsize=fontsize)
        self.fig.text(0.012, 0.5, left, ha="left", **kw)
        self.right = self.fig.text(0.988, 0.5, "", ha="right", **kw)

    def draw(self, frame: np.ndarray, right: str) -> np.ndarray:
        self.right.set_text(right)
        self.canvas.draw()
        rgba = np.asarray(self.canvas.buffer_rgba())
        a = rgba[..., 3:4].astype(np.float32) / 255.0
        band = frame[: self.h].astype(np.float32) * 0.35
        frame[: self.h] = (band * (1.0 - a) + rgba[..., :3].astype(np.float32) * a).astype(np.uint8)
        return frame


def _add_geom(scene, gtype, rgba, a, b, width: float) -> None:
    if scene.ngeom >= scene.maxgeom:
        return
    g = scene.geoms[scene.ngeom]
    mujoco.mjv_initGeom(g, gtype, np.zeros(3), np.zeros(3), np.eye(3).ravel(), np.asarray(rgba, np.float32))
    mujoco.mjv_connector(g, gtype, width, np.asarray(a, float), np.asarray(b, float))
    g.emission, g.specular = 0.3, 0.1
    scene.ngeom += 1

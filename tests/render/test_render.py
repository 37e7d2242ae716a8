"""Off-screen rendering: pixels of short clips, the MP4, the CLI, and the missing-GL error.

Everything that draws is skipped only when no OpenGL back end can be made to work on this
machine (the skip reason says so and what to install); the missing-GL error test always runs.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from elastoactive import render
from elastoactive.cli import main
from elastoactive.core.params import Numerics, Physics
from elastoactive.core.trajectory import Trajectory
from elastoactive.engines.mujoco import simulate_mujoco


@pytest.fixture(scope="module")
def beating():
    """N = 7 at sigma = 0.8: beats with a period of about 40 tau."""
    return simulate_mujoco(Physics(scene="one-pinned", n=7, sigma=0.8), Numerics(), 120.0)


def _colours(frame) -> int:
    return np.unique(frame.reshape(-1, 3) // 8, axis=0).shape[0]


def test_clip_pixels_count_and_motion(backend, beating):
    frames = render.render_frames(beating, fps=5, rate=4, width=160, height=120, start=100, end=120)
    assert frames.shape == (26, 120, 160, 3) and frames.dtype == np.uint8  # t = 100 + 0.8 k, k = 0..25
    for frame in frames[[0, -1]]:
        assert frame.std() > 10 and _colours(frame) > 40, "a blank or uniform frame"
    below_caption = frames[:, 20:].astype(int)
    steps = np.abs(np.diff(below_caption, axis=0)).mean(axis=(1, 2, 3))
    assert np.all(steps > 0.05), "the chain does not move between frames"


def test_frame_times_follow_simulated_time():
    np.testing.assert_allclose(render.frame_times(100.0, 120.0, fps=5, rate=4), 100 + 0.8 * np.arange(26))
    periodic = Trajectory(t=np.arange(0, 200, 0.1), theta=np.zeros((2000, 3)), physics=Physics(n=3), engine="x")
    periodic.theta[:, 2] = 0.3 * np.sin(2 * np.pi * periodic.t / 25.0)  # Theta beats with period 25 tau
    assert render.default_rate(periodic) == pytest.approx(25.0, rel=0.02)  # one beat per second
    periodic.theta[:] = 0.0
    assert render.default_rate(periodic) == render.DEFAULT_RATE


def _red(frame):  # the follower-force arrows (pinkish red once lit)
    r, g, b = np.moveaxis(frame.astype(float) / 255, -1, 0)
    return (r > 0.6) & (r - g > 0.25) & (b > g - 0.1)


def _orange(frame):  # the particles
    r, g, b = np.moveaxis(frame.astype(float) / 255, -1, 0)
    return (r > 0.6) & (g > 0.3) & (r - g > 0.15) & (b < 0.5 * g)


def _green(frame):  # the coupling spring
    r, g, b = np.moveaxis(frame.astype(float) / 255, -1, 0)
    return (g > 0.5) & (g - r > 0.2) & (g - b > 0.1)


@pytest.mark.parametrize("scene", ["one-pinned", "two-pinned", "rotating-pin", "coupled-pair"])
def test_every_scene_shows_chain_forces_and_caption(backend, scene):
    physics = Physics(scene=scene, n=5)  # delta at its default 0.1 on two-pinned
    numerics = Numerics(perturbation=0.3)
    traj = simulate_mujoco(physics, numerics, 4.0)
    frame = render.render_frames(traj, [traj.t[-1]], width=192, height=144, rate=2.0)[0]
    assert _orange(frame).sum() > 30, "no particles"
    assert _red(frame).sum() > 10, "no follower-force arrows"
    caption = render._Caption(192, 144, "")
    assert (frame[: caption.h] > 200).all(axis=-1).sum() > 20, "no caption text"
    if scene == "coupled-pair":
        assert _green(frame).sum() > 20, "no coupling spring"


@pytest.mark.parametrize("sigma", [0.8, 1.2])
def test_arrow_points_to_the_anchor_with_length_proportional_to_sigma(backend, sigma):
    straight = Trajectory(t=np.zeros(1), theta=np.zeros((1, 2)), physics=Physics(n=2, sigma=sigma), engine="x")
    frame = render.render_frames(straight, [0.0], width=320, height=240, trail=0.0)[0]
    rows = slice(100, 140)  # the chain lies along the middle row
    ys, xs = np.nonzero(_orange(frame)[rows])
    left = xs < xs.mean()
    b1, b2 = xs[left].mean(), xs[~left].mean()  # bead centres at x = 1 and x = 2 (units of l)
    _, rx = np.nonzero(_red(frame)[rows])
    second = rx[(rx > b1 + 4) & (rx <= b2 + 2)]  # arrow of particle 2, from x = 2 toward the anchor
    length = (b2 - second.min()) / (b2 - b1)
    assert length == pytest.approx(render.ARROW_PER_SIGMA * sigma, rel=0.15)


def test_video_file_has_the_frames(backend, beating, tmp_path):
    import imageio_ffmpeg

    out = render.render_trajectory(
        beating, tmp_path / "clip.mp4", fps=10, rate=5, width=160, height=120, start=110, end=120, progress=False
    )
    assert out["frames"] == 21 and out["seconds"] == pytest.approx(2.1)
    frames, seconds = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / "clip.mp4"))
    assert frames == 21 and seconds == pytest.approx(2.1, abs=0.15)


def test_trajectory_identical_with_and_without_video(backend, tmp_path, capsys):
    run = ["run", "one-pinned", "--duration", "20", "--quiet", "--sigma", "0.8"]
    assert main(run + ["--out", str(tmp_path / "plain")]) == 0
    video = ["--video", str(tmp_path / "v.mp4"), "--fps", "5", "--width", "96", "--height", "64"]
    assert main(run + ["--out", str(tmp_path / "filmed")] + video) == 0
    assert (tmp_path / "v.mp4").stat().st_size > 0
    with np.load(tmp_path / "plain" / "trajectory.npz") as a, np.load(tmp_path / "filmed" / "trajectory.npz") as b:
        np.testing.assert_array_equal(a["theta"], b["theta"])
        np.testing.assert_array_equal(a["t"], b["t"])
    # and a saved run renders on its own
    args = [
        "render",
        str(tmp_path / "plain"),
        "-o",
        str(tmp_path / "r.mp4"),
        "--still",
        str(tmp_path / "s.png"),
        "--fps",
        "2",
        "--width",
        "96",
        "--height",
        "64",
        "--quiet",
    ]
    assert main(args) == 0
    assert (tmp_path / "r.mp4").stat().st_size > 0 and (tmp_path / "s.png").stat().st_size > 0


def _recorded(folder):
    """A minimal recorded run in `folder`: a 3-sample trajectory of N = 2 and its summary (with its digest)."""
    from elastoactive.records import settings_digest

    np.savez(folder / "trajectory.npz", t=np.arange(3.0), theta=np.zeros((3, 2)))
    summary = {"parameters": {"scene": "one-pinned", "n": 2, "sigma": 0.8}}
    (folder / "summary.json").write_text(json.dumps({**summary, "settings_sha256": settings_digest(summary)}))


def test_missing_gl_gives_install_instructions(tmp_path):
    """PyOpenGL pinned to a platform that does not exist: neither egl nor osmesa can start."""
    _recorded(tmp_path)
    env = {k: v for k, v in os.environ.items() if k != "MUJOCO_GL"}
    env["PYOPENGL_PLATFORM"] = "no-such-platform"
    cmd = [sys.executable, "-m", "elastoactive", "render", str(tmp_path), "-o", str(tmp_path / "x.mp4")]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 4, out.stderr
    for hint in (
        "no OpenGL back end",
        "MUJOCO_GL=egl",
        "MUJOCO_GL=osmesa",
        "libegl1",
        "libosmesa6",
        "scripts/setup.sh",
    ):
        assert hint in out.stderr
    assert not (tmp_path / "x.mp4").exists()


@pytest.mark.parametrize(
    "command",
    [
        ["render", "RUN", "--still", "OUT.png"],
        ["run", "one-pinned", "--n", "2", "--duration", "1", "--video", "OUT.mp4"],
    ],
)
def test_unknown_mujoco_gl_is_one_line_naming_the_variable(tmp_path, command):
    """MuJoCo raises on a MUJOCO_GL it does not know when it is imported: every command refuses it in one line."""
    _recorded(tmp_path)
    argv = [str(tmp_path) if a == "RUN" else str(tmp_path / a) if a.startswith("OUT") else a for a in command]
    env = {**os.environ, "MUJOCO_GL": "bogus"}
    out = subprocess.run(
        [sys.executable, "-m", "elastoactive", *argv], env=env, capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 2 and out.stdout == ""
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("elastoactive: error: environment variable MUJOCO_GL='bogus'")
    assert not list(tmp_path.glob("OUT*"))

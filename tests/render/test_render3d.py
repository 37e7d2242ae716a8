"""Pictures of the chain in three dimensions (elastoactive.render.chain3d): two labelled panels, a whirl against a
planar beat seen edge on, the side view's direction, a short video's frames, and the render command on a saved run.

Everything that draws is skipped only when no OpenGL back end works on this machine (the skip says so)."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive import render
from elastoactive.cli import main
from elastoactive.render.chain3d import side_direction

N, SIGMA = 3, 4.0
"""A whirl that settles in a few tau (onset 1.16 at N = 3): turn period ~3 tau."""
WIDTH, HEIGHT = 240, 120


@pytest.fixture(scope="module")
def whirl():
    """From the scene's seeded non-planar start: whirls (tip aspect ~1)."""
    return ea.simulate(ea.Physics(scene="clamped-3d", n=N, sigma=SIGMA), duration=30.0, engine="reduced")


@pytest.fixture(scope="module")
def beat():
    """From a planar start (elevations 0): beats in the xy plane, the tangents' z exactly 0."""
    theta = 0.1 * np.sin(0.3 * np.arange(1, N + 1))
    traj = ea.simulate(ea.Physics(scene="clamped-3d", n=N, sigma=SIGMA), duration=30.0, engine="reduced",
                       theta0=np.concatenate([theta, np.zeros(N)]))  # fmt: skip
    assert np.all(traj.positions()[..., 2] == 0.0)
    return traj


def _chain(frame):
    """Pixels of the beads (orange), the links (grey) and the tip's trace (yellow): anything lit and not dark."""
    return frame.astype(int).sum(axis=-1) > 180


def _halves(frame, band: int):
    body = frame[band:-band]
    return body[:, : WIDTH // 2 - 2], body[:, WIDTH // 2 + 2 :]


def _spread(mask) -> tuple[int, int]:
    rows, cols = np.nonzero(mask)
    return int(np.ptp(rows)), int(np.ptp(cols))


def _band() -> int:
    return max(14, round(0.07 * HEIGHT))


def test_a_whirl_shows_in_both_panels_and_fills_the_end_on_view(backend, whirl):
    frame = render.render_frames(whirl, [whirl.t[-1]], width=WIDTH, height=HEIGHT)[0]
    assert frame.shape == (HEIGHT, WIDTH, 3)
    side, end = _halves(frame, _band())
    assert _chain(side).sum() > 40 and _chain(end).sum() > 40, "a panel without the chain"
    rows, cols = _spread(_chain(end))
    assert rows > 0.3 * end.shape[0] and cols > 0.3 * end.shape[1], "the whirl's end-on view is not two dimensional"
    assert np.abs(side.astype(int) - end.astype(int)).mean() > 5, "the two panels show the same picture"


def test_a_planar_beat_is_a_line_down_the_clamp_axis(backend, beat):
    frame = render.render_frames(beat, [beat.t[-1]], width=WIDTH, height=HEIGHT)[0]
    side, end = _halves(frame, _band())
    side_rows, _ = _spread(_chain(side))
    end_rows, end_cols = _spread(_chain(end))
    assert end_rows < 0.1 * end.shape[0] and end_cols > 4 * end_rows, "the planar beat seen edge on is not a line"
    assert side_rows > 0.3 * side.shape[0], "the planar beat is not seen face on in the side view"


def test_each_panel_is_labelled_and_the_caption_runs_across(backend, whirl):
    frame = render.render_frames(whirl, [whirl.t[-1]], width=WIDTH, height=HEIGHT, trail=0.0)[0]
    white = (frame > 200).all(axis=-1)
    band = _band()
    for half in (slice(0, WIDTH // 2), slice(WIDTH // 2, WIDTH)):
        assert white[-band:, half].sum() > 10, "a panel without its label"
    assert white[:band].sum() > 20, "no caption"


def test_side_view_looks_along_the_minor_axis_of_the_tip_path():
    s = np.linspace(0.0, 2 * np.pi, 50)
    flat = np.stack([np.full_like(s, 3.0), np.sin(s), 0 * s], axis=-1)
    np.testing.assert_array_equal(side_direction(flat), [0.0, 0.0, -1.0])  # from above, as the planar scenes
    tilted = np.stack([np.full_like(s, 3.0), np.cos(0.4) * np.sin(s), np.sin(0.4) * np.sin(s)], axis=-1)
    np.testing.assert_allclose(side_direction(tilted), [0.0, np.sin(0.4), -np.cos(0.4)], atol=1e-12)
    upright = np.stack([np.full_like(s, 3.0), 0 * s, np.sin(s)], axis=-1)
    np.testing.assert_allclose(side_direction(upright), [0.0, 1.0, 0.0], atol=1e-12)


def test_a_video_shows_one_turn_a_second(whirl):
    """The tip's beat paces a 3D video as Theta's paces a planar one (the trace then covers one turn)."""
    assert render.default_rate(whirl) == pytest.approx(1.0 / ea.measure(whirl).frequency, rel=0.02)


def test_a_short_video_has_its_frames(backend, whirl, tmp_path):
    import imageio_ffmpeg

    out = render.render_trajectory(whirl, tmp_path / "whirl.mp4", fps=10, rate=1.0, width=WIDTH, height=HEIGHT,
                                   start=28.0, end=29.0, progress=False)  # fmt: skip
    assert out["frames"] == 11
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / "whirl.mp4"))
    assert frames == 11
    clip = render.render_frames(whirl, fps=3, rate=1.0, width=WIDTH, height=HEIGHT, start=28.0, end=29.0)
    assert clip.shape == (4, HEIGHT, WIDTH, 3)  # the chain turns between frames
    assert np.abs(np.diff(clip[:, _band() : -_band()].astype(int), axis=0)).mean(axis=(1, 2, 3)).min() > 0.05


def test_render_command_draws_a_saved_3d_run(backend, tmp_path):
    run = tmp_path / "run"
    assert main(["run", "clamped-3d", "--n", "2", "--sigma", "4", "--duration", "10", "--engine", "reduced",
                 "--quiet", "--out", str(run)]) == 0  # fmt: skip
    still = tmp_path / "whirl.png"
    assert main(["render", str(run), "--still", str(still), "--width", "160", "--height", "96"]) == 0
    import mediapy

    image = mediapy.read_image(still)
    assert image.shape[:2] == (96, 160) and image.std() > 10

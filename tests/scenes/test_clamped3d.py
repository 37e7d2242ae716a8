"""The clamped chain in 3D as a scene (elastoactive.scenes.clamped3d): both engines through the front door, its 3D
observables, its recorded angles, a planar start against the planar scene, its stability report."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.scenes.clamped3d import angles_of, tangents_of


@pytest.fixture(scope="module")
def runs():
    """N = 3 at sigma = 2.5 (onset 1.163) from the scene's seeded non-planar start, 60 tau in each engine."""
    physics = ea.Physics(scene="clamped-3d", n=3, sigma=2.5)
    return {engine: ea.simulate(physics, duration=60.0, engine=engine) for engine in ("reduced", "mujoco")}


def test_both_engines_whirl_alike(runs):
    results = {engine: ea.measure(traj) for engine, traj in runs.items()}
    reduced, mujoco = results["reduced"], results["mujoco"]
    assert reduced.extra["motion_state"] == mujoco.extra["motion_state"] == "whirl"
    assert mujoco.frequency == pytest.approx(reduced.frequency, rel=0.01)
    assert mujoco.amplitude == pytest.approx(reduced.amplitude, rel=0.01)
    assert mujoco.extra["whirl_rate"] == pytest.approx(reduced.extra["whirl_rate"], rel=0.01)
    assert abs(reduced.extra["whirl_rate"]) == pytest.approx(reduced.frequency, rel=0.01)


def test_recorded_state_and_positions(runs):
    traj = runs["reduced"]
    assert traj.theta.shape == (traj.t.size, 6)
    tangents = tangents_of(traj.theta, 3)
    np.testing.assert_allclose(np.linalg.norm(tangents, axis=-1), 1.0, atol=1e-12)
    np.testing.assert_allclose(angles_of(tangents), traj.theta, atol=1e-9)
    assert traj.positions().shape == (traj.t.size, 1, 3, 3)
    dataset = traj.to_xarray()
    assert dataset["tangent"].dims == ("time", "particle", "xyz")


def test_planar_start_is_the_planar_scene():
    """Elevations 0 at the start: the chain stays in the plane and its azimuths are the one-pinned scene's angles."""
    theta = 0.01 * np.sin(0.3 * np.arange(1, 6))
    flat = ea.simulate(ea.Physics(scene="clamped-3d", n=5, sigma=0.8), duration=20.0, engine="mujoco",
                       theta0=np.concatenate([theta, np.zeros(5)]))  # fmt: skip
    planar = ea.simulate(ea.Physics(scene="one-pinned", n=5, sigma=0.8), duration=20.0, engine="mujoco", theta0=theta)
    assert np.all(flat.theta[:, 5:] == 0.0)
    assert np.abs(flat.theta[:, :5] - planar.theta).max() < 1e-11


def test_stability_is_the_planar_onset():
    scene = ea.scenes.get("clamped-3d")
    physics = ea.Physics(scene="clamped-3d", n=7, sigma=0.8)
    assert scene.onset(physics).sigma_c == pytest.approx(0.157470, abs=1e-6)
    assert "sigma_c = 0.157469" in "\n".join(scene.stability_report(physics, 0.8))

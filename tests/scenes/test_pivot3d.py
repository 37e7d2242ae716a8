"""The chain on a free ball pivot in 3D (elastoactive.scenes.pivot3d): both engines turn it rigidly at the planar
rotating pin's rate, in a plane its non-planar start tilts; its rate from the best rigid rotation is exact."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.scenes.pivot3d import turn_vectors


@pytest.fixture(scope="module")
def runs():
    """N = 3 at sigma = 1.64 (twice the rotation threshold 0.8195) from the scene's seeded non-planar start."""
    physics = ea.Physics(scene="rotating-pin-3d", n=3, sigma=1.64)
    return {engine: ea.simulate(physics, duration=60.0, engine=engine) for engine in ("reduced", "mujoco")}


def test_both_engines_turn_rigidly_at_the_planar_rate(runs):
    results = {engine: ea.measure(traj) for engine, traj in runs.items()}
    reduced, mujoco = results["reduced"], results["mujoco"]
    planar = ea.measure(ea.simulate(ea.Physics(scene="rotating-pin", n=3, sigma=1.64), duration=60.0, engine="reduced"))
    assert reduced.frequency is None and mujoco.frequency is None  # a rigid turn: no beat
    assert mujoco.rotation_rate == pytest.approx(reduced.rotation_rate, rel=1e-3)
    assert reduced.rotation_rate == pytest.approx(abs(planar.rotation_rate), rel=1e-3)  # 1.4e-4: still settling
    assert reduced.extra["turn_tilt"] > 0.01  # the start's push out of the plane tilts the turn
    assert mujoco.extra["turn_tilt"] == pytest.approx(reduced.extra["turn_tilt"], abs=1e-2)
    assert ea.scenes.get("rotating-pin-3d").onset(runs["reduced"].physics).sigma_c == pytest.approx(0.8195, abs=1e-4)


def test_turn_vector_of_a_rigid_rotation():
    """Tangents turned rigidly about a tilted axis at 0.3 rad per unit time give that angular velocity."""
    axis = np.array([0.2, -0.5, 1.0]) / np.linalg.norm([0.2, -0.5, 1.0])
    t = np.linspace(0.0, 2.0, 401)
    base = np.random.default_rng(1).standard_normal((4, 3))
    base /= np.linalg.norm(base, axis=1)[:, None]
    angle = 0.3 * t[:, None, None]
    along = (base @ axis)[None, :, None] * axis
    turned = along + np.cos(angle) * (base - along) + np.sin(angle) * np.cross(axis, base)[None]
    omega = turn_vectors(t, turned)[5:-5]
    np.testing.assert_allclose(omega, 0.3 * axis[None].repeat(len(omega), 0), atol=1e-5)

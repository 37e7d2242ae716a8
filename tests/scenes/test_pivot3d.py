"""The chain on a free ball pivot in 3D (elastoactive.scenes.pivot3d): both engines turn it rigidly at the planar
rotating pin's rate, in a plane its non-planar start tilts; its rate from the best rigid rotation is exact."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.scenes.pivot3d import rotation_threshold_fluid, turn_quotient, turn_vectors


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


def test_through_the_fluid_the_engines_turn_alike():
    """N = 3 at sigma = 1.64 with the beads coupled by the RPY mobility (bead_radius 0.2): both engines turn it
    rigidly at one rate within 0.1%, another than the lab-frame drag's."""
    physics = ea.Physics(scene="rotating-pin-3d", n=3, sigma=1.64, bead_radius=0.2)
    reduced, mujoco = (ea.measure(ea.simulate(physics, duration=60.0, engine=e)) for e in ("reduced", "mujoco"))
    local = ea.measure(ea.simulate(ea.Physics(scene="rotating-pin-3d", n=3, sigma=1.64), duration=60.0))
    assert mujoco.rotation_rate == pytest.approx(reduced.rotation_rate, rel=1e-3)
    assert abs(reduced.rotation_rate / local.rotation_rate - 1) > 0.05


def test_the_threshold_through_the_fluid():
    """On the quotient by the rigid turns, the lab-frame drag's operator crosses at the planar rotating pin's threshold
    (to 1e-10); the fluid lowers it (N = 7: 0.078751 -> 0.076008 at a / l = 0.1), a real eigenvalue still."""
    from elastoactive.analysis import stability
    from elastoactive.analysis.stability_fluid import linear_operator_fluid
    from elastoactive.reduced.fluid import Beds

    for n in (3, 7):
        local = Beds(n, 0.5, np.zeros((1, 3)), np.eye(3), clamped=False)
        assert rotation_threshold_fluid(local) == (pytest.approx(stability.rotation_threshold(n), rel=1e-10), 0.0)
    scene = ea.scenes.get("rotating-pin-3d")
    physics = ea.Physics(scene="rotating-pin-3d", n=7, bead_radius=0.1)
    onset = scene.onset(physics)
    assert onset.sigma_c == pytest.approx(0.076008, abs=1e-6) and onset.omega_c == pytest.approx(0.0, abs=1e-6)
    operator = linear_operator_fluid(scene.beds(physics), onset.sigma_c)
    full, quotient = np.linalg.eigvals(operator), np.linalg.eigvals(turn_quotient(operator, 7))
    # at the threshold: the two turns' zeros and the crossing pair (both planes) in L, the crossing pair alone on the
    # quotient, whose other eigenvalues are L's
    assert np.sum(np.abs(full) < 1e-7) == 4 and np.sum(np.abs(quotient) < 1e-7) == 2
    np.testing.assert_allclose(np.sort(np.abs(full))[4:], np.sort(np.abs(quotient))[2:], rtol=1e-9)

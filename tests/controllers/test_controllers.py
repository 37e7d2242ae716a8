"""The compiled follower-force callback against its readable Python twin."""

import mujoco
import numpy as np
import pytest

from elastoactive import scenes
from elastoactive.controllers import _follower, compiled_passive, follower_forces, reference_passive
from elastoactive.controllers.noise import standard_normal
from elastoactive.core.params import Numerics, Physics, scene_parameters
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.mjcf.chain import build_model
from elastoactive.scenes import names as scene_names


def passive_forces(model, data, callback):
    with follower_forces(callback):
        mujoco.mj_forward(model, data)
    return data.qfrc_passive.copy()


FOLLOWER_SCENES = [s for s in scene_names() if "noise" in scene_parameters(scenes.get(s))]
"""The scenes whose particles may carry the follower force and its noise, which the Python reference specifies (a
network's units are self-aligning: its MuJoCo model is held to its reduced one in
tests/engines/test_network_mujoco.py)."""


@pytest.mark.parametrize("noise", [0.0, 0.4])
@pytest.mark.parametrize("scene", FOLLOWER_SCENES)
def test_compiled_equals_reference(scene, noise):
    model = build_model(Physics(scene=scene, n=6, sigma=1.3, noise=noise), Numerics(seed=11))
    data = mujoco.MjData(model)
    data.qpos[:] = np.random.default_rng(5).uniform(-1.5, 1.5, model.nq)
    data.time = 0.73
    fast = passive_forces(model, data, compiled_passive)
    slow = passive_forces(model, data, reference_passive)
    bare = passive_forces(model, data, None)
    np.testing.assert_allclose(fast, slow, atol=1e-12)
    assert np.abs(fast - bare).max() > 0.1  # the follower forces are really there


def test_follower_force_is_generalised_force_of_paper():
    """Q_k = sigma sum_{i>=k} sin(theta_k - theta_i) for a clamped chain (docs/model.md, section 3)."""
    physics = Physics(scene="rotating-pin", n=5, sigma=0.9)  # no springs on hinge 0; subtract the rest
    model = build_model(physics)
    data = mujoco.MjData(model)
    theta = np.random.default_rng(2).uniform(-1, 1, 5)
    data.qpos[:] = np.diff(theta, prepend=0.0)
    follower = passive_forces(model, data, reference_passive) - passive_forces(model, data, None)
    Q = np.array([0.9 * np.sum(np.sin(theta[k] - theta[k:])) for k in range(5)])
    # generalised forces on relative angles q are sums over absolute ones: F_q_j = sum_{k>=j} Q_k
    np.testing.assert_allclose(follower, np.cumsum(Q[::-1])[::-1], atol=1e-12)


def test_trajectory_same_with_either_callback():
    physics, numerics = Physics(n=4, sigma=0.8, noise=0.1), Numerics(seed=3)
    fast = simulate_mujoco(physics, numerics, 5.0)
    import elastoactive.engines.mujoco as sim

    original = sim.follower_forces
    sim.follower_forces = lambda: original(reference_passive)
    try:
        slow = simulate_mujoco(physics, numerics, 5.0)
    finally:
        sim.follower_forces = original
    np.testing.assert_allclose(fast.theta, slow.theta, atol=1e-12)


def test_noise_draw_matches_numpy():
    xi = standard_normal(7, np.arange(5), 3)
    for k in range(5):
        for p in range(3):
            assert _follower.standard_normal(7, k, p) == xi[k, p]
    big = standard_normal(1, np.arange(4000), 5).ravel()
    assert abs(big.mean()) < 0.03 and abs(big.std() - 1) < 0.03


def test_other_models_are_left_alone():
    xml = """<mujoco><size nuser_site="1"/><worldbody><body><joint axis="0 0 1"/>
             <geom size=".1" pos="1 0 0"/><site pos="1 0 0" user="5"/></body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qpos[0] = 0.3
    assert np.all(passive_forces(model, data, compiled_passive) == 0)


def test_callback_is_restored():
    before = mujoco.get_mjcb_passive()
    with follower_forces():
        assert mujoco.get_mjcb_passive() is not None
    assert mujoco.get_mjcb_passive() is before

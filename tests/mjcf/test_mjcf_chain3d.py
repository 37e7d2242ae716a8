"""The MuJoCo chain in three dimensions (elastoactive.mjcf.chain3d): its forces are the model's, a planar start is the
planar MuJoCo scene, and a whirl agrees with the reduced 3D model."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import elastoactive as ea
from elastoactive.analysis.motion3d import measure3d
from elastoactive.core.errors import ParameterError
from elastoactive.mjcf.chain3d import (
    TWIST_DAMPING_STEPS,
    TWIST_INERTIA_STEPS,
    Chain3DModel,
    prepare3d,
    qpos_of_tangents,
    simulate3d,
    tangents_of,
    twist_dofs,
)
from elastoactive.reduced.chain3d import Chain3D, planar_angles, solve3d, tangents_of_angles


def _random_tangents(n: int, seed: int = 0, spread: float = 0.6) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.column_stack([np.ones(n), spread * rng.standard_normal((n, 2))])
    return t / np.linalg.norm(t, axis=1)[:, None]


@pytest.mark.parametrize("joints", ["ball", "hinges"])
def test_tangents_round_trip(joints):
    chain = Chain3DModel(n=5, sigma=0.3, joints=joints)
    t = _random_tangents(5)
    _, data = prepare3d(chain, t)
    np.testing.assert_allclose(tangents_of(data, 5), t, atol=1e-12)
    assert qpos_of_tangents(chain, t).size == (20 if joints == "ball" else 10)


@pytest.mark.parametrize("joints", ["ball", "hinges"])
def test_actuators_are_the_follower_force_and_the_lab_frame_drag(joints):
    """At a non-planar state and a random velocity, the actuators' generalised force is sum_k J_k^T (-sigma t_k -
    W_k v_k) (anisotropic drag W_k); the only passive damping is -twist_damping on each ball joint's twist rate."""
    n, sigma, ratio = 4, 0.7, 2.5
    chain = Chain3DModel(n=n, sigma=sigma, drag_ratio=ratio, joints=joints)
    model, data = prepare3d(chain, _random_tangents(n, seed=1))
    data.qvel[:] = np.random.default_rng(2).standard_normal(model.nv)
    mujoco.mj_forward(model, data)
    expected = np.zeros(model.nv)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    t = tangents_of(data, n)
    for k in range(n):
        mujoco.mj_jacSite(model, data, jacp, jacr, model.site(f"particle_{k}").id)
        v, tk = jacp @ data.qvel, t[k]
        drag = -(v + (ratio - 1.0) * (v @ tk) * tk)
        expected += jacp.T @ (-sigma * tk + drag)
    np.testing.assert_allclose(data.qfrc_actuator, expected, atol=1e-10)
    damping = np.zeros(model.nv)
    if joints == "ball":
        damping[0::3] = -chain.damping * data.qvel[0::3]
    np.testing.assert_allclose(data.qfrc_damper, damping, atol=1e-14)


def test_twist_inertia_and_damping_sit_on_the_twist_dofs_only():
    """Each ball joint's first dof turns its link about the link's own axis (the twist): the armature and damping are
    there and nowhere else, at their defaults C dt^2 x TWIST_INERTIA_STEPS and C dt x TWIST_DAMPING_STEPS."""
    chain = Chain3DModel(n=4, sigma=0.5, dt=0.004)
    model, data = prepare3d(chain, _random_tangents(4, seed=5))
    twist = twist_dofs(model)
    np.testing.assert_array_equal(twist, [0, 3, 6, 9])
    assert chain.inertia == pytest.approx(TWIST_INERTIA_STEPS * 0.004**2)
    assert chain.damping == pytest.approx(TWIST_DAMPING_STEPS * 0.004)
    np.testing.assert_array_equal(np.flatnonzero(model.dof_armature), twist)
    np.testing.assert_array_equal(np.flatnonzero(model.dof_damping), twist)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    t = tangents_of(data, 4)
    for k in range(4):  # a twist dof turns its own link about that link's axis and moves no particle
        mujoco.mj_jacSite(model, data, jacp, jacr, model.site(f"particle_{k}").id)
        np.testing.assert_allclose(jacr[:, twist[k]], t[k], atol=1e-12)
        np.testing.assert_allclose(jacp[:, twist[k]], 0.0, atol=1e-12)


@pytest.mark.parametrize("joints", ["ball", "hinges"])
@pytest.mark.parametrize("scene, clamped", [("one-pinned", True), ("rotating-pin", False)])
def test_planar_start_is_the_planar_mujoco_scene(joints, scene, clamped):
    """From the planar scene's own start, the 3D chain (clamped, or on a free ball pivot) stays in the plane exactly
    and follows the planar MuJoCo chain (hinges, compiled follower callback) to round-off, at the same dt and mass."""
    physics = ea.Physics(scene=scene, n=5, sigma=0.8)
    planar = ea.simulate(physics, ea.Numerics(), duration=10.0, engine="mujoco")
    chain = Chain3DModel(n=5, sigma=0.8, joints=joints, clamped=clamped)
    path = simulate3d(chain, planar.t, tangents_of_angles(planar.theta[0]))
    assert np.all(path[..., 2] == 0.0)
    assert np.abs(planar_angles(path) - planar.theta).max() < 1e-11


@pytest.mark.parametrize("drag_ratio", [1.0, 0.5])
def test_whirl_agrees_with_the_reduced_model(drag_ratio):
    """N = 3 at sigma = 2.5 (onset 1.163) from a non-planar start whirls in both engines, with isotropic and
    anisotropic drag; amplitude and frequency agree within 1% (default numerics, ball joints)."""
    n, sigma = 3, 2.5
    ts = np.arange(0.0, 50.0 + 1e-9, 0.01)
    t0 = _random_tangents(n, seed=3, spread=0.3)
    chain = Chain3D(n=n, sigma=sigma, gamma_l=drag_ratio)
    reduced = measure3d(ts, solve3d(chain, ts, t0, rtol=1e-10, atol=1e-10))
    mujoco_ = measure3d(ts, simulate3d(Chain3DModel(n=n, sigma=sigma, drag_ratio=drag_ratio), ts, t0))
    assert reduced.state == mujoco_.state == "whirl"
    assert abs(mujoco_.tip_amplitude / reduced.tip_amplitude - 1.0) < 0.01
    assert abs(mujoco_.frequency / reduced.frequency - 1.0) < 0.01
    assert abs(mujoco_.whirl_rate / reduced.whirl_rate - 1.0) < 0.01


def test_bad_input_names_the_field():
    with pytest.raises(ParameterError, match="joints"):
        Chain3DModel(n=3, sigma=0.5, joints="gimbal").checked()
    with pytest.raises(ParameterError, match="twist_damping"):
        Chain3DModel(n=3, sigma=0.5, twist_damping=0.0).checked()
    with pytest.raises(ParameterError, match="twist_inertia"):
        Chain3DModel(n=3, sigma=0.5, twist_inertia=-1.0).checked()
    with pytest.raises(ParameterError, match="ts must"):
        simulate3d(Chain3DModel(n=3, sigma=0.5), np.array([0.0, 0.0011]), _random_tangents(3))


def _turn_rate(path: np.ndarray, dt: float) -> np.ndarray:
    """|omega| of the best rigid rotation t_k' = omega x t_k at each inner sample (central differences)."""
    rates = []
    for t, v in zip(path[1:-1], (path[2:] - path[:-2]) / (2 * dt)):
        cross = np.concatenate([[[0, tk[2], -tk[1]], [-tk[2], 0, tk[0]], [tk[1], -tk[0], 0]] for tk in t])
        rates.append(np.linalg.norm(np.linalg.lstsq(cross, v.ravel(), rcond=None)[0]))
    return np.array(rates)


def test_free_ball_pivot_turns_rigidly_in_both_engines():
    """On a free ball pivot (N = 3, twice the planar rotation threshold 0.8195) a non-planar start settles into a rigid
    turn about a fixed axis; both engines turn at the same rate within 0.1%."""
    n, sigma, dt = 3, 1.64, 0.01
    ts = np.arange(0.0, 60.0 + 1e-9, dt)
    t0 = _random_tangents(n, seed=3, spread=0.3)
    reduced = _turn_rate(solve3d(Chain3D(n=n, sigma=sigma, clamped=False), ts, t0, rtol=1e-10, atol=1e-10)[-500:], dt)
    mujoco_ = _turn_rate(simulate3d(Chain3DModel(n=n, sigma=sigma, clamped=False), ts, t0)[-500:], dt)
    assert reduced.std() < 1e-6 * reduced.mean() and mujoco_.std() < 1e-6 * mujoco_.mean()  # rigid and steady
    assert mujoco_.mean() == pytest.approx(reduced.mean(), rel=1e-3)


def test_the_load_places_the_follower_force_on_the_loaded_particles_only():
    """With load weights w_k the actuators' generalised force is sum_k J_k^T (-w_k sigma t_k - W_k v_k): the tip alone
    at (0, 0, 0, 1); a load of the wrong length is refused in one line."""
    n, sigma = 4, 0.7
    chain = Chain3DModel(n=n, sigma=sigma, load=(0.0, 0.0, 0.0, 1.0))
    model, data = prepare3d(chain, _random_tangents(n, seed=3))
    mujoco.mj_forward(model, data)  # at rest: the drag is zero, the actuators carry the follower force alone
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jacSite(model, data, jacp, jacr, model.site(f"particle_{n - 1}").id)
    np.testing.assert_allclose(data.qfrc_actuator, jacp.T @ (-sigma * tangents_of(data, n)[-1]), atol=1e-12)
    with pytest.raises(ParameterError, match="load must hold 4 weights"):
        Chain3DModel(n=n, sigma=sigma, load=(1.0, 1.0)).checked()

"""Coloured (Ornstein-Uhlenbeck) active-force noise and the Stratonovich reading of white noise."""

import copy

import mujoco
import numpy as np
import pytest

from elastoactive import scenes
from elastoactive.controllers import compiled_passive, follower_forces, reference_passive
from elastoactive.controllers.noise import ColouredNoise, ou_constants
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import Numerics, Physics, replace, scene_parameters
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.engines.reduced import simulate_reduced
from elastoactive.mjcf.chain import build_model, prepare
from elastoactive.results import measure
from elastoactive.scenes import names as scene_names


# ------------------------------------------------------------------ the process itself
def test_ou_statistics():
    """Stationary variance a^2 / (2 tau_c), correlation time tau_c, and the white limit's intensity:
    the integral of eta over T >> tau_c has variance a^2 (T - tau_c (1 - exp(-T / tau_c)))."""
    a, tau_c, dt = 0.3, 0.5, 0.05
    eta = ColouredNoise(seed=9, n_particles=8, amplitude=a, tau_c=tau_c, dt=dt).eta(np.arange(200_000))
    var = a * a / (2 * tau_c)
    assert abs(eta.var() / var - 1) < 0.03
    assert abs(eta.mean()) < 0.03 * np.sqrt(var)
    lag = int(round(tau_c / dt))  # autocorrelation at lag tau_c: 1/e
    rho = np.mean(eta[lag:] * eta[:-lag]) / eta.var()
    assert abs(rho - np.exp(-1)) < 0.03
    rho1 = np.mean(eta[1:] * eta[:-1]) / eta.var()
    assert abs(-dt / np.log(rho1) / tau_c - 1) < 0.05  # correlation time from the lag-1 decay
    block = 200  # T = 10 = 20 tau_c
    T = block * dt
    integrals = eta[: eta.shape[0] // block * block].reshape(-1, block, 8).sum(axis=1) * dt
    expected = a * a * (T - tau_c * (1 - np.exp(-T / tau_c)))
    assert abs(integrals.var() / expected - 1) < 0.06


def test_ou_is_a_function_of_seed_and_step():
    noise = ColouredNoise(3, 4, 0.1, 0.5, 0.0025)
    whole = noise.eta(np.arange(3000))
    again = ColouredNoise(3, 4, 0.1, 0.5, 0.0025)
    parts = np.vstack([again.eta(np.arange(0, 1000)), again.eta(np.arange(1000, 3000))])
    assert np.array_equal(whole, parts)
    assert np.array_equal(again.eta([5, 7, 2999]), whole[[5, 7, 2999]])  # going back replays from step 0
    std, decay, kick = ou_constants(0.1, 0.5, 0.0025)
    np.testing.assert_allclose(kick**2, std**2 * (1 - decay**2))
    assert not np.array_equal(whole, ColouredNoise(4, 4, 0.1, 0.5, 0.0025).eta(np.arange(3000)))


# ------------------------------------------------------------------ the C callback and its twin
def _forward(model, data, callback):
    with follower_forces(callback):
        mujoco.mj_forward(model, data)
    return data.qfrc_passive.copy(), data.userdata.copy()


NOISY_SCENES = [s for s in scene_names() if "noise" in scene_parameters(scenes.get(s))]  # the noise acts on them


@pytest.mark.parametrize("scene", NOISY_SCENES)
def test_compiled_equals_reference_coloured(scene):
    physics = Physics(scene=scene, n=6, sigma=1.3, noise=0.4, noise_correlation=0.3)
    numerics = Numerics(seed=11)
    model = build_model(physics, numerics)
    assert model.nuserdata == 1 + physics.n_angles
    qpos = np.random.default_rng(5).uniform(-1.5, 1.5, model.nq)
    noise = ColouredNoise(11, physics.n_angles, 0.4, 0.3, numerics.dt)
    runs = {}
    for callback in (compiled_passive, reference_passive):
        data = mujoco.MjData(model)
        data.qpos[:] = qpos
        out = []
        for time in (0.0, 0.0, numerics.dt, 0.73, 0.73, 0.2, 0.2 + 0.5 * numerics.dt):  # on, repeated, back
            data.time = time
            out.append(_forward(model, data, callback))
        runs[callback is compiled_passive] = out
    bare = mujoco.MjData(model)
    bare.qpos[:] = qpos
    no_follower = _forward(model, bare, None)[0]
    for (fast, fast_user), (slow, slow_user), time in zip(runs[True], runs[False], (0, 0, 1, 292, 292, 80, 80)):
        np.testing.assert_allclose(fast, slow, atol=1e-12)
        np.testing.assert_allclose(fast_user, slow_user, atol=1e-12)
        assert fast_user[0] == time + 1  # the step held
        np.testing.assert_allclose(fast_user[1:], noise.eta([time])[0], atol=1e-12)
    assert np.abs(runs[True][3][0] - no_follower).max() > 0.1


@pytest.mark.parametrize("integrator", ["implicitfast", "RK4"])
def test_trajectory_same_with_either_callback_coloured(integrator):
    physics = Physics(n=4, sigma=0.8, noise=0.3, noise_correlation=0.2)
    numerics = Numerics(seed=3, integrator=integrator, mass_ratio=1e-4 if integrator == "implicitfast" else 0.01)
    fast = simulate_mujoco(physics, numerics, 3.0)
    import elastoactive.engines.mujoco as sim

    original = sim.follower_forces
    sim.follower_forces = lambda: original(reference_passive)
    try:
        slow = simulate_mujoco(physics, numerics, 3.0)
    finally:
        sim.follower_forces = original
    np.testing.assert_allclose(fast.theta, slow.theta, atol=1e-12)


@pytest.mark.parametrize("integrator", ["implicitfast", "RK4", "Euler"])
def test_noise_advances_once_per_step(integrator):
    """Whatever the integrator (RK4: four callback calls per step), the held eta after each step is that of
    the step reached, and the realisation is ColouredNoise's."""
    physics = Physics(n=3, sigma=0.8, noise=0.3, noise_correlation=0.2)
    numerics = Numerics(seed=2, integrator=integrator, mass_ratio=1e-4 if integrator == "implicitfast" else 0.01)
    model, data = prepare(physics, numerics)
    noise = ColouredNoise(2, 3, 0.3, 0.2, numerics.dt)
    assert data.userdata[0] == 0  # prepare runs mj_forward without the callback: nothing held yet
    with follower_forces():
        for k in range(1, 60):
            mujoco.mj_step(model, data)
            held = int(data.userdata[0]) - 1
            assert held in (k - 1, k)  # implicit: the last call was at step k - 1; RK4's last stage at t + dt
            np.testing.assert_allclose(data.userdata[1:], noise.eta([held])[0], atol=1e-12)


# ------------------------------------------------------------------ the state lives in mjData
@pytest.mark.parametrize("integrator", ["implicitfast", "RK4"])
def test_state_lives_in_mjdata(integrator):
    physics = Physics(n=5, sigma=0.8, noise=0.3, noise_correlation=0.1)
    numerics = Numerics(seed=7, integrator=integrator, mass_ratio=1e-4 if integrator == "implicitfast" else 0.01)
    model, data = prepare(physics, numerics)
    with follower_forces():
        mujoco.mj_step(model, data, nstep=333)
        copied = copy.copy(data)  # mj_copyData
        state = np.empty(mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_INTEGRATION))
        mujoco.mj_getState(model, data, state, mujoco.mjtState.mjSTATE_INTEGRATION)
        restored = mujoco.MjData(model)
        mujoco.mj_setState(model, restored, state, mujoco.mjtState.mjSTATE_INTEGRATION)
        assert np.array_equal(restored.userdata, data.userdata) and data.userdata[0] > 300
        runs = []
        for d in (data, copied, restored):
            trace = []
            for _ in range(50):
                mujoco.mj_step(model, d, nstep=7)
                trace.append(d.qpos.copy())
            runs.append(np.array(trace))
    assert np.array_equal(runs[0], runs[1]) and np.array_equal(runs[0], runs[2])


def test_white_models_carry_no_noise_state():
    model = build_model(Physics(n=4, noise=0.3), Numerics())
    assert model.nuserdata == 0 and list(model.numeric("elastoactive_follower").data) == [0.3, 0.0, 0.0]


# ------------------------------------------------------------------ both engines, one realisation
def test_engines_agree_on_a_coloured_realisation():
    physics = Physics(n=7, sigma=0.8, noise=0.1, noise_correlation=0.5)
    numerics = Numerics(seed=3)
    reduced = simulate_reduced(physics, numerics, 150.0)
    mujoco_run = simulate_mujoco(physics, numerics, 150.0)
    a, b = measure(reduced), measure(mujoco_run)
    assert abs(a.amplitude / b.amplitude - 1) < 0.02
    assert abs(a.frequency / b.frequency - 1) < 0.02
    assert np.abs(reduced.theta - mujoco_run.theta).max() < 0.05  # the same path, not only the same statistics
    other = simulate_reduced(physics, replace(numerics, seed=4), 150.0)
    assert np.abs(other.theta - mujoco_run.theta).max() > 10 * np.abs(reduced.theta - mujoco_run.theta).max()


def test_summary_reports_noise_parameters_only_with_noise():
    quiet = Physics(n=4).relevant()
    assert "noise_correlation" not in quiet and "noise_calculus" not in quiet
    noisy = Physics(n=4, noise=0.2, noise_correlation=0.5).relevant()
    assert noisy["noise_correlation"] == 0.5 and "noise_calculus" not in noisy  # it reads white noise only
    assert Physics(n=4, noise=0.2).relevant()["noise_calculus"] == "ito"


def test_parameter_checks():
    with pytest.raises(ParameterError):
        Physics(noise_correlation=-1.0)
    with pytest.raises(ParameterError):
        Physics(noise_calculus="klimontovich")
    with pytest.raises(ParameterError, match="Ito"):  # MuJoCo: Stratonovich only as the coloured limit
        build_model(Physics(n=4, noise=0.2, noise_calculus="stratonovich"))


# ------------------------------------------------------------------ the Stratonovich limit
def test_coloured_noise_tends_to_stratonovich():
    """Wong-Zakai, pathwise: the OU noise is built from the white noise's own draws (the integral of eta is
    a W(t) - tau_c (eta(t) - eta(0))), so as tau_c -> 0 (dt << tau_c) the coloured run approaches the
    Stratonovich (Heun) run on the same Brownian path, not the Ito (Euler-Maruyama) one."""
    base = Physics(n=7, sigma=0.8, noise=0.3)
    numerics = Numerics(seed=4, dt=0.0005, sample_dt=0.1)
    end = lambda physics: simulate_reduced(physics, numerics, 10.0).theta[-1]
    ito, strat = end(base), end(replace(base, noise_calculus="stratonovich"))
    gap = np.abs(ito - strat).max()
    assert gap > 0.03  # the two readings differ visibly on this path
    errors = {}
    for tau_c in (0.05, 0.01):
        coloured = end(replace(base, noise_correlation=tau_c))
        errors[tau_c] = np.abs(coloured - strat).max()
        assert errors[tau_c] < np.abs(coloured - ito).max()
    assert errors[0.01] < errors[0.05] and errors[0.01] < 0.3 * gap


def test_mujoco_reaches_stratonovich_through_short_correlation():
    """MuJoCo has no white Stratonovich reading of its own: its coloured noise with a short tau_c (dt << tau_c)
    follows the reduced model's Stratonovich (Heun) path on the same draws, not its Ito path."""
    base = Physics(n=7, sigma=0.8, noise=0.3)
    numerics = Numerics(seed=4, dt=0.0005, sample_dt=0.1)
    ito = simulate_reduced(base, numerics, 10.0).theta[-1]
    strat = simulate_reduced(replace(base, noise_calculus="stratonovich"), numerics, 10.0).theta[-1]
    coloured = simulate_mujoco(replace(base, noise_correlation=0.01), numerics, 10.0).theta[-1]
    assert np.abs(coloured - strat).max() < 0.3 * np.abs(ito - strat).max()
    assert np.abs(coloured - strat).max() < 0.3 * np.abs(coloured - ito).max()

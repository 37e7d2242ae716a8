"""The star scene: k one-pinned arms on one hub (elastoactive/scenes/star.py, docs/star.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.analysis import star as sync
from elastoactive.reduced import ChainSystem, rhs, rhs_reference, solve_ode
from elastoactive.scenes import star


def _numerics(engine: str) -> ea.Numerics:
    """Coarse samples; MuJoCo at dt = 0.005 (the reduced engine takes no dt)."""
    return ea.Numerics(dt=0.005, sample_dt=0.1) if engine == "mujoco" else ea.Numerics(sample_dt=0.1)


def test_registered_with_its_parameters():
    scene = ea.scenes.get("star")
    assert scene.own_parameter_names() == ("arms", "hub", "hub_stiffness", "hub_drag")
    physics = ea.Physics(scene="star", arms=4)
    assert physics.n_chains == 4 and physics.n_angles == 4 * physics.n


@pytest.mark.parametrize(
    "values, name",
    [
        (dict(arms=0), "arms"),
        (dict(arms=1), "arms"),
        (dict(arms=7), "arms"),
        (dict(n=0), "n"),
        (dict(hub_drag=0.0), "hub_drag"),
        (dict(hub_stiffness=-1.0), "hub_stiffness"),
        (dict(hub="clamped", hub_stiffness=2.0), "hub_stiffness"),
        (dict(hub="loose"), "hub"),
        (dict(contact=True), "contact"),
    ],
)
def test_refusals_name_the_parameter(values, name):
    with pytest.raises(ea.ParameterError) as err:
        ea.Physics(scene="star", **values)
    message = str(err.value)
    assert "\n" not in message and name in message


@pytest.mark.parametrize("k, hub", [(2, False), (3, True), (5, True)])
def test_compiled_rhs_equals_the_numpy_reference(k, hub):
    system = ChainSystem(
        n=6, n_chains=k, sigma=0.9, gamma_l=0.7, star=True, hub_free=hub, hub_stiffness=0.4, hub_drag=0.3
    )
    rng = np.random.default_rng(k)
    y = rng.normal(size=system.state_size) + np.r_[np.repeat(star.clamp_angles(k), 6), np.zeros(system.n_head)]
    np.testing.assert_allclose(rhs(system, beta=1.0)(0.0, y), rhs_reference(system, beta=1.0)(0.0, y), atol=1e-12)


def test_hub_torque_is_the_clamp_springs():
    """hub_drag phi' = -K phi + sum_j (theta_{j,1} - alpha_j - phi), whatever the arms' other angles."""
    k, n, K, drag = 3, 4, 0.7, 0.25
    system = ChainSystem(n=n, n_chains=k, sigma=0.8, star=True, hub_free=True, hub_stiffness=K, hub_drag=drag)
    rng = np.random.default_rng(0)
    y = rng.normal(size=system.state_size)
    phi = y[-1]
    first = y[:-1:n]
    expected = (-K * phi + np.sum(first - star.clamp_angles(k) - phi)) / drag
    assert rhs(system, beta=1.0)(0.0, y)[-1] == pytest.approx(expected, rel=1e-12)


def test_clamped_star_is_independent_one_pinned_chains_reduced():
    """The clamped hub: each arm, turned back by alpha_j, follows the one-pinned chain from the same start."""
    k, n = 3, 7
    t = np.arange(0.0, 150.0, 0.5)
    theta0 = 0.05 * np.random.default_rng(2).normal(size=k * n)
    alpha = np.repeat(star.clamp_angles(k), n)
    arms, _ = solve_ode(
        ChainSystem(n=n, n_chains=k, sigma=0.8, star=True), t, theta0 + alpha, rtol=1e-10, atol=1e-12, beta=1.0
    )
    for j in range(k):
        alone, _ = solve_ode(
            ChainSystem(n=n, sigma=0.8), t, theta0[j * n : (j + 1) * n], rtol=1e-10, atol=1e-12, beta=1.0
        )
        np.testing.assert_allclose(arms[:, j * n : (j + 1) * n] - alpha[j * n], alone, atol=1e-6)


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
def test_clamped_star_beats_as_the_one_pinned_chain(engine):
    """Both engines: every arm of a clamped star has the one-pinned chain's amplitude and frequency, the hub stays
    at 0, and the arms point at 2 pi j / k."""
    duration = 200.0
    one = ea.measure(
        ea.simulate(ea.Physics(scene="one-pinned", n=5, sigma=1.0), _numerics(engine), duration=duration, engine=engine)
    )
    traj = ea.simulate(
        ea.Physics(scene="star", n=5, sigma=1.0, arms=2, hub="clamped"),
        _numerics(engine),
        duration=duration,
        engine=engine,
    )
    res = ea.measure(traj)
    assert np.allclose(res.amplitude, one.amplitude, rtol=1e-3)
    assert np.allclose(res.frequency, one.frequency, rtol=1e-3)
    assert traj.head.shape == (traj.t.size, 1) and np.all(traj.head == 0.0)
    assert abs(np.mean(traj.chain(1)[:, 0] - traj.chain(0)[:, 0]) - math.pi) < 0.5


def test_engines_agree_on_a_turning_hub():
    """The validation case's physics (k = 3, K_h = hub_drag = 1) over a shorter run: in phase, within 1%."""
    physics = ea.Physics(scene="star", n=7, sigma=0.8, arms=3, hub_stiffness=1.0, hub_drag=1.0)
    a, b = (ea.measure(ea.simulate(physics, duration=300.0, engine=e)) for e in ("mujoco", "reduced"))
    assert a.extra["sync_state"] == b.extra["sync_state"] == "in-phase"
    for name in ("amplitude", "frequency"):
        assert np.allclose(getattr(a, name), getattr(b, name), rtol=0.01), name
    assert a.extra["hub_amplitude"] == pytest.approx(b.extra["hub_amplitude"], rel=0.01)
    assert a.extra["hub_amplitude"] > 1.0  # the hub swings with the arms


@pytest.mark.slow
def test_validate_holds_both_engines_within_one_percent():
    from elastoactive.checks.validate import compare

    for case in ea.scenes.get("star").validation_cases():
        comparison = compare(case.physics, ea.Numerics(), case.duration)
        assert comparison.worst() < 0.01, (case.physics, comparison.errors)


def _signals(lags, t, f=0.04):
    return np.stack([np.cos(2 * math.pi * f * t - lag) for lag in lags])


@pytest.mark.parametrize(
    "lags, state",
    [
        ((0.0, 0.0, 0.0), "in-phase"),
        ((0.0, math.pi), "antiphase"),
        ((0.0, 2 * math.pi / 3, 4 * math.pi / 3), "splay"),
        ((0.0, math.pi, 0.0, math.pi), "locked"),
        ((0.0, 1.5), "locked"),
    ],
)
def test_sync_state_of_constructed_signals(lags, state):
    t = np.arange(0.0, 500.0, 0.1)
    _, phases = sync.arm_phases(t, _signals(lags, t), 250.0)
    assert sync.sync_state(phases) == state
    assert sync.phase_locking(phases) > 0.999
    np.testing.assert_allclose(np.cos(sync.phase_differences(phases)), np.cos(np.array(lags[1:])), atol=1e-3)
    if state == "splay":
        assert sync.order_parameter(phases, 1) < 1e-3 and sync.order_parameter(phases, 3) > 0.999


def test_drifting_arms_are_unlocked():
    t = np.arange(0.0, 500.0, 0.1)
    signals = np.stack([np.cos(2 * math.pi * 0.04 * t), np.cos(2 * math.pi * 0.055 * t)])
    _, phases = sync.arm_phases(t, signals, 250.0)
    assert sync.sync_state(phases) == "unlocked"


def test_effective_coupling_of_a_fast_hub():
    clamp, pair = star.effective_coupling(10.0, 2)
    assert clamp == pytest.approx(10 / 12) and pair == pytest.approx(1 / 12)


def test_clamped_hub_onset_is_the_one_pinned_chains():
    from elastoactive.analysis import stability

    onset = star.SCENE.onset(ea.Physics(scene="star", n=7, arms=3, hub="clamped"))
    sigma_c, omega_c = stability.onset(7)
    assert onset.sigma_c == pytest.approx(sigma_c, rel=1e-12) and onset.omega_c == pytest.approx(omega_c, rel=1e-9)


@pytest.mark.parametrize("k, hub_stiffness, hub_drag", [(2, 1.0, 1.0), (3, 0.3, 2.0)])
def test_turning_hub_operator_is_the_reduced_models_jacobian(k, hub_stiffness, hub_drag):
    """The linear operator about the straight star against central differences of the compiled right-hand side."""
    from elastoactive.analysis.star_stability import star_operator
    from elastoactive.engines.reduced import system_of

    n, sigma = 5, 0.3
    system = system_of(
        ea.Physics(scene="star", n=n, arms=k, sigma=sigma, hub_stiffness=hub_stiffness, hub_drag=hub_drag)
    ).typed()
    base = np.r_[np.repeat(star.clamp_angles(k), n), 0.0]
    f, eps = rhs(system, beta=1.0), 1e-6
    numeric = np.array([(f(0.0, base + eps * e) - f(0.0, base - eps * e)) / (2 * eps) for e in np.eye(base.size)]).T
    np.testing.assert_allclose(star_operator(n, k, sigma, hub_stiffness, hub_drag), numeric, atol=1e-7)


def test_the_in_phase_mode_goes_first_on_a_turning_hub():
    """N = 7, k = 3: the in-phase mode (the hub turns) loses stability first, between the rotating pin's threshold
    (no hub spring: a divergence, the star starts turning) and the one-pinned onset (a stiff hub); the hub-free
    modes (splay) stay at the one-pinned onset."""
    from elastoactive.analysis import stability, star_stability

    free = stability.onset(7)[0]
    onsets = star_stability.mode_onsets(7, 3, 1.0, 1.0)
    assert onsets["splay"][0] == pytest.approx(free, rel=1e-12)
    assert onsets["in-phase"][0] == pytest.approx(0.1027015, rel=1e-6)
    onset = star.SCENE.onset(ea.Physics(scene="star", n=7, arms=3, hub_stiffness=1.0, hub_drag=1.0))
    assert onset.sigma_c == pytest.approx(onsets["in-phase"][0], rel=1e-10) and "in-phase" in onset.kind
    soft = star_stability.mode_onsets(7, 3, 0.0, 1e-3)["in-phase"]
    assert soft[0] == pytest.approx(stability.rotation_threshold(7), rel=1e-3) and soft[1] < 1e-6  # a real eigenvalue
    assert star_stability.mode_onsets(7, 3, 1e4, 1.0)["in-phase"][0] == pytest.approx(free, rel=1e-3)
    lam = star.SCENE.leading_eigenvalue(ea.Physics(scene="star", n=7, arms=3), 1.1 * onset.sigma_c)
    assert (
        lam.real > 0
        and star.SCENE.leading_eigenvalue(ea.Physics(scene="star", n=7, arms=3), 0.9 * onset.sigma_c).real < 0
    )

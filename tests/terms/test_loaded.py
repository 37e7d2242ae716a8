"""The follower force on chosen particles only (Physics.loaded): the tip-loaded column in both engines."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive import reduced as M
from elastoactive.analysis.flutter import critical_sigma
from elastoactive.cli import build_parser
from elastoactive.cli.run import settings_from
from elastoactive.core import registry
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import Numerics, Physics
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.engines.reduced import load_factors, rhs, simulate_reduced, system_of
from elastoactive.mjcf.chain import build_model
from elastoactive.results import measure


def _site_users(physics: Physics) -> np.ndarray:
    model = build_model(physics)
    return np.array(
        [
            model.site_user[model.site(f"{prefix}particle_{i}").id, 0]
            for prefix in physics.scene_def.chain_prefixes()
            for i in range(physics.n)
        ]
    )


# ---------------------------------------------------------------------------------------------- parameter
@pytest.mark.parametrize(
    "value, mask",
    [
        ("all", [1, 1, 1, 1, 1]),
        ("tip", [0, 0, 0, 0, 1]),
        ("1,3", [1, 0, 1, 0, 0]),
        (" 5, 2 ", [0, 1, 0, 0, 1]),
    ],
)
def test_load_mask(value, mask):
    physics = Physics(n=5, loaded=value)
    np.testing.assert_array_equal(physics.load_mask(), np.array(mask, dtype=bool))


def test_loaded_is_normalised():
    assert Physics(n=5, loaded="3,1").loaded == "1,3"
    assert Physics(n=5, loaded="TIP").loaded == "tip"


@pytest.mark.parametrize(
    "value, message",
    [
        ("0", "1..5"),
        ("6", "1..5"),
        ("1,1", "more than once"),
        ("x", "1-based"),
        ("", "1-based"),
        ("1;2", "1-based"),
        (3, "string"),
    ],
)
def test_loaded_validation(value, message):
    with pytest.raises(ParameterError, match="loaded") as err:
        Physics(n=5, loaded=value)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_summaries_unchanged_for_all():
    for scene in registry.names():
        assert "loaded" not in Physics(scene=scene).relevant()
    assert Physics(n=5, loaded="tip").relevant()["loaded"] == "tip"
    assert list(Physics().relevant()) == ["scene", "n", "sigma", "drag_ratio", "noise"]


def test_cli_option():
    parser = build_parser()
    physics, *_ = settings_from(parser.parse_args(["run", "one-pinned", "--n", "5", "--loaded", "tip"]))
    assert physics.loaded == "tip"
    physics, *_ = settings_from(parser.parse_args(["run", "one-pinned"]))
    assert physics.loaded == "all"


# ---------------------------------------------------------------------------------------------- MuJoCo model
def test_site_user_values_follow_the_mask():
    np.testing.assert_array_equal(_site_users(Physics(n=5, sigma=0.7)), [0.7] * 5)
    np.testing.assert_array_equal(_site_users(Physics(n=5, sigma=0.7, loaded="tip")), [0, 0, 0, 0, 0.7])
    np.testing.assert_array_equal(_site_users(Physics(n=5, sigma=0.7, loaded="2,4")), [0, 0.7, 0, 0.7, 0])


def test_pair_masks_both_chains():
    physics = Physics(scene="coupled-pair", n=4, sigma=0.5, loaded="tip")
    np.testing.assert_array_equal(load_factors(physics), [0, 0, 0, 1, 0, 0, 0, 1])
    users = _site_users(physics)
    assert np.count_nonzero(users) == 2 and users[3] > 0 and users[7] > 0


# ---------------------------------------------------------------------------------------------- reduced model
def test_all_loaded_is_bit_identical():
    physics = Physics(n=7, sigma=0.8)
    nu = Numerics()
    base = simulate_reduced(physics, nu, 20.0)
    system = system_of(physics)
    t, th0 = nu.sample_times(20.0), base.theta[0]
    ones, _ = M.solve_ode(system, t, th0, rtol=1e-9, atol=1e-11, beta=M.DEFAULT_BETA, loads=np.ones(7))
    np.testing.assert_array_equal(base.theta, ones)
    assert load_factors(physics) is None


def test_masked_rhs_drops_the_unloaded_forces():
    th = np.linspace(0.1, 0.5, 5)
    tip, every = rhs(Physics(n=5, sigma=1.0, loaded="tip"), beta=10.0), rhs(Physics(n=5, sigma=1.0), beta=10.0)
    sigma0 = rhs(Physics(n=5, sigma=0.0), beta=10.0)
    assert not np.allclose(tip(0, th), every(0, th)) and not np.allclose(tip(0, th), sigma0(0, th))
    # the first particle's follower force acts along the first pendulum, through the clamp: no torque
    np.testing.assert_allclose(rhs(Physics(n=5, sigma=1.0, loaded="1"), beta=10.0)(0, th), sigma0(0, th), atol=1e-14)


def test_masked_radau_agrees_with_dop853():
    physics = Physics(n=5, sigma=1.2, loaded="2,5")
    system, loads = system_of(physics), load_factors(physics)
    t = 0.5 * np.arange(41)
    th0 = 0.05 * np.ones(5)
    a, _ = M.solve_ode(system, t, th0, rtol=1e-10, atol=1e-12, beta=10.0, loads=loads)
    b, _ = M.solve_ode(system, t, th0, rtol=1e-10, atol=1e-12, beta=10.0, loads=loads, method="Radau")
    np.testing.assert_allclose(a, b, atol=1e-6)


# ---------------------------------------------------------------------------------------------- both engines
TIP_ONSET = {2: 2.99990, 5: 0.95908}
"""flutter.critical_sigma(n, 1e-4, active=[n - 1]): the tip-loaded column's onset (N = 2: the same as all
loaded, since the first particle's force never exerts a torque)."""


@pytest.mark.parametrize("n", [2, 5])
def test_tip_onset_table(n):
    assert critical_sigma(n, 1e-4, active=[n - 1])[0] == pytest.approx(TIP_ONSET[n], rel=1e-4)


@pytest.mark.parametrize("n, sigma, duration", [(2, 3.5, 200.0), (5, 1.2, 400.0)])
def test_engines_agree_tip_loaded(n, sigma, duration):
    assert sigma > TIP_ONSET[n]
    physics, nu = Physics(n=n, sigma=sigma, loaded="tip"), Numerics()
    red = measure(simulate_reduced(physics, nu, duration))
    mj = measure(simulate_mujoco(physics, nu, duration))
    assert red.amplitude > 0.3
    assert mj.amplitude == pytest.approx(red.amplitude, rel=0.01)
    assert mj.frequency == pytest.approx(red.frequency, rel=0.01)


def test_tip_onset_from_simulation():
    """N = 5, tip loaded: a short MuJoCo run decays at 0.8 sigma_c and grows at 1.25 sigma_c (flutter's onset)."""
    for factor, grows in ((0.8, False), (1.25, True)):
        physics = Physics(n=5, sigma=factor * TIP_ONSET[5], loaded="tip")
        a = np.abs(simulate_mujoco(physics, Numerics(dt=0.01, sample_dt=0.1), 150.0).theta)
        k = a.shape[0] // 3
        assert (a[-k:].max() > 2 * a[:k].max()) == grows
    # the all-loaded chain is unstable at 0.8 of the tip-loaded onset: the mask matters
    a = np.abs(simulate_mujoco(Physics(n=5, sigma=0.8 * TIP_ONSET[5]), Numerics(dt=0.01, sample_dt=0.1), 150.0).theta)
    assert a[-a.shape[0] // 3 :].max() > 10 * a[0].max()


def test_noise_goes_to_the_loaded_particles_only():
    physics = Physics(n=5, sigma=1.2, loaded="tip", noise=0.1)
    nu = Numerics(dt=0.01, sample_dt=0.1)
    red, mj = simulate_reduced(physics, nu, 20.0), simulate_mujoco(physics, nu, 20.0)
    assert np.max(np.abs(red.theta - mj.theta)) < 0.05 * np.max(np.abs(red.theta)) + 1e-3

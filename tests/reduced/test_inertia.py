"""The reduced model with the particles' inertia: MuJoCo's chain at a finite mass, equation for equation.

The inertial model (elastoactive/reduced/equations.py) must be MuJoCo's continuous dynamics exactly (mass
matrix, accelerations), its compiled kernels must match the plain-numpy formulas, the one criterion
(engines.reduced.regime) decides which model runs, diagnose classifies instead of refusing the mass,
and MuJoCo agrees with the inertial model at a finite mass (validate.inertial_cases).
"""

from __future__ import annotations

import re

import mujoco
import numpy as np
import pytest

from elastoactive import reduced as M
from elastoactive.analysis.flutter import BEAD_INERTIA_FACTOR, mass_matrix_at
from elastoactive.checks.validate import compare, inertial_cases
from elastoactive.cli import main
from elastoactive.controllers import follower_forces
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import Numerics, Physics
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.engines.reduced import regime, simulate_reduced, system_of
from elastoactive.engines.timestep import check_timestep, stability_limits
from elastoactive.mjcf.chain import build_model
from elastoactive.results import measure

CHAIN = Physics(n=7, sigma=0.8)


def _absolute(physics: Physics) -> np.ndarray:
    """theta = L q: MuJoCo's relative hinge angles to the model's absolute angles, chain by chain."""
    n = physics.n
    return np.kron(np.eye(physics.n_angles // n), np.tril(np.ones((n, n))))


# ------------------------------------------------------------------------------------------------
# the equations are MuJoCo's
# ------------------------------------------------------------------------------------------------
def test_bead_inertia_is_flutter_and_mujoco():
    assert M.BEAD_INERTIA_FACTOR == BEAD_INERTIA_FACTOR
    model = build_model(CHAIN, Numerics(mass_ratio=0.5))
    assert np.allclose(model.body_inertia[1:, 2], 0.5 * BEAD_INERTIA_FACTOR, rtol=1e-12)
    assert system_of(CHAIN).inertia_factor == BEAD_INERTIA_FACTOR


@pytest.mark.parametrize("physics", [Physics(n=5, sigma=0.8), Physics(scene="coupled-pair", n=3, kappa=1.0)])
def test_mass_matrix_is_mujocos(physics):
    model = build_model(physics, Numerics(mass_ratio=0.37))
    data = mujoco.MjData(model)
    data.qpos[:] = np.random.default_rng(1).normal(size=model.nq)
    mujoco.mj_forward(model, data)
    mq = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, mq)
    L = _absolute(physics)
    system = system_of(physics, 0.37)
    theta = L @ data.qpos
    ours = M.mass_matrix(system, theta)
    np.testing.assert_allclose(L.T @ ours @ L, mq, rtol=0, atol=1e-13)
    np.testing.assert_allclose(ours[: physics.n, : physics.n], mass_matrix_at(theta[: physics.n], 0.37), atol=1e-14)


@pytest.mark.parametrize(
    "physics",
    [
        Physics(n=5, sigma=0.8),
        Physics(n=4, sigma=0.8, drag_ratio=2.5),
        Physics(scene="rotating-pin", n=6, sigma=0.5),
        Physics(scene="coupled-pair", n=4, sigma=0.8, kappa=1.7, rho=4 / 3),
    ],
)
def test_accelerations_are_mujocos(physics):
    """At a random state (angles and rates), MuJoCo's qacc (springs, drag actuators, follower callback,
    Coriolis and centripetal terms) is the inertial model's theta'' to round-off."""
    m = 0.37
    model = build_model(physics, Numerics(mass_ratio=m))
    data = mujoco.MjData(model)
    rng = np.random.default_rng(3)
    data.qpos[:] = rng.normal(size=model.nq)
    data.qvel[:] = rng.normal(size=model.nv)
    with follower_forces():
        mujoco.mj_forward(model, data)
    L = _absolute(physics)
    y = np.concatenate([L @ data.qpos, L @ data.qvel])
    out = M.rhs(system_of(physics, m), beta=M.DEFAULT_BETA)(0.0, y)
    acc = L @ data.qacc
    assert np.abs(out[physics.n_angles :] - acc).max() < 1e-12 * np.abs(acc).max()
    np.testing.assert_array_equal(out[: physics.n_angles], y[physics.n_angles :])


@pytest.mark.parametrize(
    "kw",
    [
        dict(n=5, sigma=0.8),
        dict(n=4, sigma=0.8, gamma_l=2.0),
        dict(n=6, pinned=True, sigma=0.8, delta=0.1),
        dict(n=4, n_chains=2, sigma=0.7, kappa=1.3, rho=1.4),
        dict(n=5, clamped=False, sigma=0.3),
        dict(n=12, sigma=0.3),
        dict(n=1, sigma=0.5),
    ],
)
def test_compiled_inertial_rhs_matches_the_formulas(kw):
    rng = np.random.default_rng(0)
    system = M.ChainSystem(mass_ratio=0.37, **kw)
    y = rng.normal(size=2 * system.n_angles)
    fac = 1 + 0.1 * rng.normal(size=system.n_angles)
    ours = M.rhs(system, beta=7.0, factor=fac)(0.0, y)
    ref = M.rhs_inertial_reference(system, beta=7.0, factor=fac)(0.0, y)
    assert np.abs(ours - ref).max() < 1e-13 * np.abs(ref).max()


def test_jacobian_is_the_derivative():
    system = M.ChainSystem(n=5, pinned=True, sigma=0.8, delta=0.2, mass_ratio=0.2)
    y = np.concatenate([M.project_on_pins(0.3 * np.cos(np.arange(5)), 0.2), 0.2 * np.ones(5)])
    J = M.jacobian(system, beta=10.0)(0.0, y)
    f = M.rhs(system, beta=10.0)
    h = 1e-6
    fd = np.column_stack([(f(0, y + h * e) - f(0, y - h * e)) / (2 * h) for e in np.eye(y.size)])
    np.testing.assert_allclose(J, fd, rtol=0, atol=1e-6 * np.abs(fd).max())


def test_mass_zero_is_the_overdamped_model_whatever_the_inertia_factor():
    t = 0.05 * np.arange(201)
    th0 = 0.1 * np.sin(np.arange(7))
    base = M.ChainSystem(n=7, sigma=0.8)
    a, ia = M.solve_ode(base, t, th0, rtol=1e-9, atol=1e-11, beta=10.0)
    b, ib = M.solve_ode(base._replace(inertia_factor=0.3), t, th0, rtol=1e-9, atol=1e-11, beta=10.0)
    np.testing.assert_array_equal(a, b)
    assert "model" not in ia


def test_inertial_model_tends_to_the_overdamped_one():
    """The angles' inertial lag is proportional to the mass (the Radau path at the smallest mass)."""
    t = 0.05 * np.arange(201)
    th0 = 0.1 * np.sin(np.arange(7))
    base = M.ChainSystem(n=7, sigma=0.8)
    over, _ = M.solve_ode(base, t, th0, rtol=1e-10, atol=1e-12, beta=10.0)
    gaps = []
    for m in (1e-2, 1e-3, 1e-4):
        theta, info = M.solve_ode(base._replace(mass_ratio=m), t, th0, rtol=1e-10, atol=1e-12, beta=10.0)
        assert info["model"] == "inertial" and info["method"] == ("Radau" if m == 1e-4 else "numba-DOP853")
        gaps.append(np.abs(theta - over).max())
    assert 7 < gaps[0] / gaps[1] < 13 and 7 < gaps[1] / gaps[2] < 13


def test_inertial_pins_hold():
    system = M.ChainSystem(n=7, pinned=True, sigma=0.8, delta=0.1, mass_ratio=0.5)
    th0 = M.project_on_pins(0.5 * np.cos(np.pi * (np.arange(7) + 0.5) / 7) + 0.01 * np.sin(np.arange(7)), 0.1)
    theta, _ = M.solve_ode(system, 0.05 * np.arange(2001), th0, rtol=1e-10, atol=1e-12, beta=10.0)
    assert M.constraint_violation(system, theta) < 1e-8
    assert np.ptp(theta[1000:, 2]) > 0.5  # it snaps


# ------------------------------------------------------------------------------------------------
# the one criterion, and what diagnose makes of it
# ------------------------------------------------------------------------------------------------
def test_regime_is_the_overdamped_limit():
    pair = Physics(scene="coupled-pair", n=7, sigma=0.8, kappa=2.0, rho=4 / 3)
    assert regime(CHAIN, Numerics()).model == "overdamped"
    assert regime(CHAIN, Numerics(mass_ratio=0.01)).model == "overdamped"  # 0.01 x 7.32 = 0.073
    assert regime(pair, Numerics(mass_ratio=0.01)).model == "inertial"  # 0.01 x 11.5 = 0.115
    r = regime(CHAIN, Numerics(mass_ratio=0.5))
    assert r.inertial and r.inertia_number == pytest.approx(0.5 * 7.3232, rel=1e-4)
    assert r.mass_limit == pytest.approx(M.INERTIA_RESOLUTION / r.rate)
    for physics in (CHAIN, pair, Physics(scene="two-pinned", n=7, sigma=0.8, delta=0.1)):
        assert regime(physics, Numerics()).rate == pytest.approx(
            stability_limits(physics, Numerics()).fastest_rate, rel=1e-6
        )


def test_reduced_engine_records_and_overrides_the_model():
    nu = Numerics(mass_ratio=0.5)
    auto = simulate_reduced(CHAIN, nu, 5.0)
    assert auto.info["model"] == "inertial" and auto.info["mass_ratio"] == 0.5
    assert auto.info["inertia_number"] == pytest.approx(3.66, rel=1e-3)
    over = simulate_reduced(CHAIN, nu, 5.0, inertial=False)
    assert over.info["model"] == "overdamped"
    np.testing.assert_array_equal(over.theta, simulate_reduced(CHAIN, Numerics(), 5.0).theta)
    forced = simulate_reduced(CHAIN, Numerics(mass_ratio=0.01), 5.0, inertial=True)
    assert forced.info["model"] == "inertial"
    assert simulate_reduced(CHAIN, Numerics(mass_ratio=0.01), 5.0).info["model"] == "overdamped"
    np.testing.assert_array_equal(auto.theta[0], over.theta[0])  # same initial angles, at rest
    with pytest.raises(ParameterError, match="inertial"):
        simulate_reduced(CHAIN, nu, 5.0, inertial="yes")


def test_mass_ratio_cap_is_100():
    assert Numerics(mass_ratio=100.0).mass_ratio == 100.0
    with pytest.raises(ParameterError, match="mass_ratio"):
        Numerics(mass_ratio=100.5)


def test_diagnose_classifies_the_mass_instead_of_refusing_it():
    limits = check_timestep(CHAIN, Numerics(mass_ratio=0.5))
    assert limits.inertial and limits.inertia_number == pytest.approx(3.66, rel=1e-3)
    assert not check_timestep(CHAIN, Numerics()).inertial
    for m in (0.01, 10.0):
        for case in inertial_cases(m):
            check_timestep(case.physics, Numerics(mass_ratio=m))  # the default dt resolves every case


def test_unresolved_inertial_oscillation_is_refused_with_a_passing_suggestion():
    """The kappa = 1000 pair at m = 0.1: the coupling oscillates at |lambda| = 140/tau, which dt = 0.0025 does
    not resolve (dt x rate = 0.35 > 0.2); the suggested dt passes."""
    physics = Physics(scene="coupled-pair", n=7, sigma=0.8, kappa=1000.0)
    with pytest.raises(ParameterError, match="does not resolve the inertial chain") as err:
        check_timestep(physics, Numerics(mass_ratio=0.1))
    passing = re.search(r"passes every check: Numerics\(dt=([^,]+), mass_ratio=([^,]+),", str(err.value))
    dt, mass = float(passing[1]), float(passing[2])
    assert mass == 0.1 and dt < 0.0025
    check_timestep(physics, Numerics(dt=dt, mass_ratio=mass, sample_dt=dt * max(1, round(0.05 / dt))))


def test_inertial_step_limit_is_the_measured_one():
    """The linearised implicitfast step predicts where the kappa = 1000 pair at m = 0.1 goes unstable."""
    physics = Physics(scene="coupled-pair", n=7, sigma=0.8, kappa=1000.0)
    predicted = stability_limits(physics, Numerics(mass_ratio=0.1)).limit("implicitfast")
    assert 0.01 < predicted < 0.02

    def blows_up(dt):
        try:
            traj = simulate_mujoco(physics, Numerics(dt=dt, sample_dt=dt * round(0.1 / dt), mass_ratio=0.1), 10.0)
        except Exception:
            return True
        return np.abs(traj.theta).max() > 3.0

    assert not blows_up(0.9 * predicted) and blows_up(1.2 * predicted)


# ------------------------------------------------------------------------------------------------
# MuJoCo against the inertial model at a finite mass
# ------------------------------------------------------------------------------------------------
def test_heavy_chain_numbers():
    """The issue's MuJoCo check (N = 7, sigma = 0.8): amplitude 3.06 and f tau 0.0390 at m = 0.5, 4.22 and 0.0178
    at m = 10."""
    for m, amplitude, frequency in ((0.5, 3.054, 0.03901), (10.0, 4.219, 0.01781)):
        r = measure(simulate_reduced(CHAIN, Numerics(mass_ratio=m), 600.0))
        assert r.amplitude == pytest.approx(amplitude, rel=1e-3) and r.frequency == pytest.approx(frequency, rel=1e-3)


@pytest.mark.parametrize("case", inertial_cases(0.5), ids=lambda c: c.physics.scene_def.label(c.physics))
def test_mujoco_agrees_with_the_inertial_model_at_mass_ratio_half(case):
    result = compare(case.physics, Numerics(mass_ratio=0.5), case.duration, inertial=True)
    compared = [k for k in case.physics.scene_def.compared if k in result.errors]
    assert compared
    for key in compared:
        assert result.errors[key] < 0.01, (key, result.errors)
    assert result.errors["angle"] < 0.01, result.errors
    assert result.reduced is not None


def test_mujoco_agrees_with_the_inertial_model_under_noise():
    physics = Physics(n=7, sigma=0.8, noise=0.1)
    nu = Numerics(mass_ratio=0.5)
    red, mj = simulate_reduced(physics, nu, 20.0), simulate_mujoco(physics, nu, 20.0)
    assert red.info["model"] == "inertial"
    assert np.abs(red.theta - mj.theta).max() < 0.01 * np.abs(red.theta).max()


def test_validate_cli_at_a_finite_mass(capsys):
    assert main(["validate", "one-pinned", "--mass-ratio", "0.5", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "inertial reduced model at mass ratio 0.5" in out and "PASS" in out

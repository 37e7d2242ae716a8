"""Stiff and extreme cells (a small, fast part of scripts/stability_grid.py): every cell either agrees
with the reduced model or stops with a clear, named error; none ends silently wrong or in NaN."""

from __future__ import annotations

import math

import numpy as np
import pytest

from elastoactive.checks import extremes as X
from elastoactive.core.params import Numerics, ParameterError, Physics
from elastoactive.engines.timestep import PROBE_STEPS, _discrete_probe, check_accuracy, stability_limits

CHAIN = Physics(n=7, sigma=0.8)


@pytest.fixture(scope="module")
def chain_ref():
    return X.reference(CHAIN, 100.0, 0.05)


def _cell(physics, ref, integrator, dt, mass, **kw):
    numerics = Numerics(dt=dt, mass_ratio=mass, integrator=integrator, sample_dt=X.sample_dt_for(dt, ref.duration))
    cell = X.run_cell(physics, numerics, ref, **kw)
    assert cell.outcome != "NaN"
    return cell


def test_defaults_agree_on_the_paper_chain(chain_ref):
    cell = _cell(CHAIN, chain_ref, "implicitfast", 0.0025, 1e-4)
    assert cell.outcome == "agrees", cell.message
    assert cell.errors["amplitude"] < 0.01 and cell.errors["angle"] < 0.01


@pytest.mark.parametrize("integrator", X.INTEGRATORS)
@pytest.mark.parametrize("mass", [1e-4, 1e-7])
def test_largest_allowed_dt_is_refused_not_silently_wrong(chain_ref, integrator, mass):
    """dt = 0.1 is stable for implicitfast/implicit/discrete but 13-40% wrong: it must be refused."""
    cell = _cell(CHAIN, chain_ref, integrator, 0.1, mass)
    assert cell.outcome == "refused", (cell.outcome, cell.message, cell.errors)
    if integrator in ("Euler", "RK4"):
        assert "the particle mass" in cell.message
    else:
        assert "does not resolve the fastest overdamped rate" in cell.message


def test_smallest_mass_two_pinned_pin_is_refused_or_held():
    physics = Physics(scene="two-pinned", n=7, sigma=0.8, delta=0.5)
    ref = X.reference(physics, 40.0, 0.05)
    soft = _cell(physics, ref, "implicitfast", 0.0025, 1e-7)  # the pin would drift off by ~1 l
    assert soft.outcome == "refused" and "the pin cannot hold" in soft.message
    held = _cell(physics, ref, "discrete", 0.0025, 1e-7)
    assert held.outcome == "agrees", held.message
    assert held.errors["pin_violation"] < 1e-3


def test_high_sigma_unresolved_dt_is_refused_resolved_dt_agrees():
    physics = Physics(scene="rotating-pin", n=7, sigma=100.0)
    ref = X.reference(physics, 1.0, 0.025)
    coarse = _cell(physics, ref, "implicitfast", 0.0025, 1e-4)  # 32% wrong rotation rate if it ran
    assert coarse.outcome == "refused" and "grow this fast at high sigma" in coarse.message
    fine = _cell(physics, ref, "implicitfast", 1e-4, 1e-6)
    assert fine.outcome == "agrees", fine.message
    assert fine.errors["rotation_rate"] < 0.01


def test_unresolved_high_sigma_run_would_be_wrong():
    """The guard is needed: without it the same cell runs to the end and disagrees."""
    physics = Physics(scene="rotating-pin", n=7, sigma=100.0)
    ref = X.reference(physics, 1.0, 0.025)
    cell = _cell(physics, ref, "implicitfast", 0.0025, 1e-4, preflight=False)
    assert cell.outcome == "WRONG" and "rotation_rate" in cell.failed


def test_stiff_coupling_refused_for_explicit_springs_discrete_agrees():
    physics = Physics(scene="coupled-pair", n=7, sigma=0.8, kappa=1000.0)
    ref = X.reference(physics, 40.0, 0.05)
    refused = _cell(physics, ref, "implicitfast", 0.0025, 1e-4)
    assert refused.outcome == "refused" and "stability limit" in refused.message
    ok = _cell(physics, ref, "discrete", 0.0025, 1e-4)
    assert ok.outcome == "agrees", ok.message


def test_run_beyond_the_stability_limit_stops_with_the_named_cause():
    physics = Physics(scene="coupled-pair", n=7, sigma=0.8, kappa=1000.0)
    ref = X.reference(physics, 10.0, 0.05)
    cell = _cell(physics, ref, "implicitfast", 0.0025, 1e-4, preflight=False)
    assert cell.outcome == "diverged"
    assert "Likely cause: dt too large" in cell.message


def test_predicted_limit_matches_bisection_for_stiff_coupling():
    """In the overdamped limit (m * rate << 1) the overdamped linear estimate is the measured limit; with inertia
    (m * rate = 0.2 at m = 1e-4, outside the overdamped limit) the measured limit is larger, and the estimate from
    the inertial chain's linearised step (diagnose.step_limit) is the measured one again."""
    physics = Physics(scene="coupled-pair", n=7, sigma=0.8, kappa=1000.0)
    predicted = stability_limits(physics, Numerics(mass_ratio=1e-6)).limit("implicitfast")
    stable, unstable = X.largest_stable_dt(physics, "implicitfast", 1e-6, 5.0, predicted)
    assert unstable is not None
    assert 0.85 * predicted < stable <= unstable < 1.2 * predicted
    heavy = stability_limits(physics, Numerics())
    assert heavy.inertial and heavy.limit("implicitfast") > predicted
    stable_heavy, unstable_heavy = X.largest_stable_dt(physics, "implicitfast", 1e-4, 5.0, heavy.limit("implicitfast"))
    assert stable_heavy > predicted
    assert unstable_heavy is not None and 0.85 * heavy.limit(
        "implicitfast"
    ) < stable_heavy <= unstable_heavy < 1.2 * heavy.limit("implicitfast")


def test_discrete_on_a_long_chain_is_refused_by_the_probe():
    """MuJoCo 4.0's effective-metric solve does not converge on long chains (mjWARN_INERTIA)."""
    physics = Physics(n=50, sigma=0.8)
    numerics = Numerics(dt=1e-4, mass_ratio=1e-4, integrator="discrete", sample_dt=1e-4)
    assert _discrete_probe(physics, numerics) > 0
    with pytest.raises(ParameterError, match="effective-metric solve"):
        check_accuracy(physics, numerics)
    assert _discrete_probe(Physics(n=7), Numerics(integrator="discrete")) == 0


def test_reduced_model_answers_at_sigma_100_n_100():
    from elastoactive.engines.reduced import simulate_reduced

    physics = Physics(n=100, sigma=100.0)
    numerics = Numerics(dt=0.001, sample_dt=0.001)
    implicit = simulate_reduced(physics, numerics, 0.004, method="Radau")
    default = simulate_reduced(physics, numerics, 0.004)
    # |lambda| ~ 4e4 here comes from growing modes, not stiffness: the explicit default is kept
    assert default.info["method"] == "numba-DOP853" and default.info["spectral_radius"] > 2e3
    assert np.all(np.isfinite(implicit.theta)) and np.all(np.isfinite(default.theta))
    assert np.abs(implicit.theta - default.theta).max() < 1e-6


def test_reduced_model_goes_implicit_when_stiff():
    """A very stiff coupling gives fast *decaying* modes: then the default switches to Radau."""
    from elastoactive.engines.reduced import simulate_reduced

    traj = simulate_reduced(Physics(scene="coupled-pair", n=7, kappa=3000.0), Numerics(), 1.0)
    assert traj.info["method"] == "Radau" and traj.info["stiffness"] > 2e3
    assert np.all(np.isfinite(traj.theta))


def test_grid_definitions_are_consistent():
    for p in X.physics_grid():
        d = X.cell_duration(p)
        for column in X.NUMERICS:
            n = X.numerics_for(column, "implicitfast", d)
            assert n.sample_dt >= n.dt and math.isfinite(d)
    assert X.NUMERICS["dt=0.1"]["dt"] == 0.1 and X.NUMERICS["m=1e-7"]["mass_ratio"] == 1e-7
    assert PROBE_STEPS >= 1

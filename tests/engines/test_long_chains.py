"""Long chains: the automatic numerics (Numerics.for_physics) and their accuracy; short chains unchanged.

Correctness only: the speed of the automatic choice is measured by scripts/benchmark.py (part D), not here."""

import dataclasses
import json
import pickle
import subprocess
import sys

import numpy as np
import pytest

from elastoactive.checks.validate import validation_cases
from elastoactive.cli import main
from elastoactive.core.params import LONG_CHAIN, Numerics, Physics, long_chain_numerics
from elastoactive.engines import timestep as diagnose
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.engines.mujoco_batch import simulate_mujoco_batch
from elastoactive.engines.reduced import regime, simulate_reduced
from elastoactive.engines.timestep import INERTIA_RESOLUTION

EXPLICIT = Numerics(dt=0.0025, mass_ratio=1e-4, integrator="implicitfast")  # the defaults, given by hand


def test_defaults_are_marked_but_plain_values():
    n = Numerics()
    assert n.automatic and n == EXPLICIT and hash(n) == hash(EXPLICIT) and not EXPLICIT.automatic
    assert json.dumps(dataclasses.asdict(n)) == json.dumps(dataclasses.asdict(EXPLICIT))
    assert repr(n) == repr(EXPLICIT)
    # the mark survives what the package does with numerics: replace, copies, pickling (process pools, Dask)
    for same in (
        dataclasses.replace(n, seed=3),
        pickle.loads(pickle.dumps(n)),
        Numerics(**dataclasses.asdict(n)),
        Numerics.preset("accurate"),
        Numerics(sample_dt=0.1),
    ):
        assert same.automatic
    # any one of dt, mass_ratio, integrator given (even equal to its default) is a choice
    for given in (dict(dt=0.0025), dict(mass_ratio=1e-4), dict(integrator="implicitfast")):
        assert not Numerics(**given).automatic
    assert not Numerics.preset("fast").automatic


def test_short_chains_and_the_papers_cases_keep_their_numerics():
    for case in validation_cases():  # the paper's N = 7 chains, at the defaults and at the 'fast' preset
        for numerics in (Numerics(), Numerics.preset("fast")):
            assert numerics.for_physics(case.physics) is numerics
    for n in (7, 15, LONG_CHAIN - 1):
        assert Numerics().for_physics(Physics(n=n, sigma=0.05)).integrator == "implicitfast"
    physics = Physics(n=7, sigma=0.8)
    auto, given = simulate_mujoco(physics, Numerics(), 5.0), simulate_mujoco(physics, EXPLICIT, 5.0)
    np.testing.assert_array_equal(auto.theta, given.theta)  # bit for bit
    assert "automatic_numerics" not in auto.info and auto.info["integrator"] == "implicitfast"


def test_an_explicit_choice_wins_on_a_long_chain():
    physics = Physics(n=100, sigma=0.05)
    for given in (
        EXPLICIT,
        Numerics(integrator="implicitfast"),
        Numerics(dt=0.001),
        Numerics(mass_ratio=1e-3),
        Numerics.preset("fast"),
    ):
        assert given.for_physics(physics) is given
    assert Numerics().for_physics(physics).integrator == "Euler"


@pytest.mark.parametrize("n", [LONG_CHAIN, 100])
def test_automatic_choice_is_overdamped_and_passes_the_preflight_check(n):
    physics = Physics(n=n, sigma=0.05)
    chosen = Numerics().for_physics(physics)
    assert chosen.integrator == "Euler" and not chosen.automatic
    assert chosen == long_chain_numerics(physics, Numerics())
    assert chosen.steps_per_sample * chosen.dt == pytest.approx(Numerics().sample_dt)  # the same sample grid
    r = regime(physics, chosen)
    assert r.model == "overdamped" and r.inertia_number <= INERTIA_RESOLUTION
    limits = diagnose.check_timestep(physics, Numerics())  # refuses nothing: the check resolves as a run does
    assert chosen.dt < limits.limit("Euler") and chosen.dt <= limits.accuracy_limit("Euler")


def test_stiff_long_chains_keep_the_defaults_when_explicit_drag_would_cost_more():
    # sigma 0.8 at N = 100: the rates are fast, the matched mass (and dt) would be tiny
    physics = Physics(n=100, sigma=0.8)
    assert Numerics().for_physics(physics).integrator == "implicitfast"


def test_n100_agrees_with_the_reduced_model_within_one_percent():
    """The long-chain accuracy target: N = 100, sigma = 0.05, 20 tau: the largest angle difference against the
    reduced (overdamped, the paper's) model, relative to the largest angle, within 1%."""
    physics = Physics(n=100, sigma=0.05)
    mj = simulate_mujoco(physics, Numerics(), 20.0)
    ref = simulate_reduced(physics, Numerics(), 20.0)
    assert mj.info["integrator"] == "Euler" and mj.info["automatic_numerics"]["integrator"] == "Euler"
    assert ref.info.get("model", "overdamped") == "overdamped"
    np.testing.assert_allclose(mj.t, ref.t, rtol=0, atol=1e-9)
    error = np.abs(mj.theta - ref.theta).max() / np.abs(ref.theta).max()
    assert np.abs(ref.theta).max() > 0.3  # the chain has buckled: the comparison is not of the initial kick
    assert error < 0.01, error


def test_batch_runs_the_automatic_numerics_as_simulate_mujoco_does():
    runs = [Physics(n=LONG_CHAIN, sigma=s) for s in (0.05, 0.1)] + [Physics(n=7, sigma=0.8)]
    batch = simulate_mujoco_batch(runs, Numerics(), 3.0, threads=2)
    for physics, traj in zip(runs, batch):
        single = simulate_mujoco(physics, Numerics(), 3.0)
        np.testing.assert_array_equal(traj.theta, single.theta)
        assert traj.info["integrator"] == single.info["integrator"]
        assert traj.info.get("automatic_numerics") == single.info.get("automatic_numerics")
    assert batch[0].info["integrator"] == "Euler" and batch[2].info["integrator"] == "implicitfast"


def test_the_checks_regime_is_the_reduced_engines():
    """One criterion: the pre-flight check classifies a run with the function the reduced engine runs by, from a
    light module (no compiled solver loaded)."""
    assert diagnose.regime is regime
    code = "import sys, elastoactive.engines.timestep; print('numba' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.strip() == "False"


def test_summary_records_the_numerics_that_ran_and_from_repeats_them(tmp_path):
    """A long chain's automatic numerics are what summary.json records, so `run --from` repeats the run exactly."""
    first, again = tmp_path / "a", tmp_path / "b"
    assert (
        main(["run", "one-pinned", "--n", "100", "--sigma", "0.05", "--duration", "2", "--out", str(first), "--quiet"])
        == 0
    )
    numerics = json.loads((first / "summary.json").read_text())["numerics"]
    assert numerics["integrator"] == "Euler" and numerics["mass_ratio"] != 1e-4
    assert main(["run", "--from", str(first), "--out", str(again), "--quiet"]) == 0
    with np.load(first / "trajectory.npz") as a, np.load(again / "trajectory.npz") as b:
        np.testing.assert_array_equal(a["theta"], b["theta"])

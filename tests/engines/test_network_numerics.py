"""A network run's automatic numerics in the reduced engine: its tolerance (a chain's for a small network, looser for a
large one, chosen on the measured error against cost), the errors it reports beside its time means, and the coarser
record of a large network."""

from __future__ import annotations

import json

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.analysis.network import observables as nobs
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import Numerics, Physics
from elastoactive.engines import network_step
from elastoactive.engines.reduced import simulate_reduced
from elastoactive.records import summary
from elastoactive.reduced import network as network_model
from elastoactive.results import measure
from elastoactive.scenes.base import CHAIN_TOLERANCES
from elastoactive.scenes.network_kind import LARGE_TOLERANCES

ERRORS = ("polarization", "polarity_speed", "actuation")


def test_a_network_runs_at_its_kinds_tolerance_and_a_given_one_wins(monkeypatch):
    lattice = Physics(scene="lattice", rings=1, sigma=0.2, alignment_length=0.1)
    small = simulate_reduced(lattice, Numerics(), 5.0)
    assert (small.info["rtol"], small.info["atol"]) == CHAIN_TOLERANCES  # cheap at any tolerance: a chain's
    large = Physics(scene="network", geometry="triangular", size=18, sigma=0.2, alignment_length=0.1)
    assert large.scene_def.reduced_tolerances(large) == LARGE_TOLERANCES  # 1027 nodes: sparse, and looser
    assert LARGE_TOLERANCES[0] > 1e-8  # the point of the choice
    monkeypatch.setattr(network_model, "DENSE_MODES", 1)  # the small lattice treated as large
    loose = simulate_reduced(lattice, Numerics(), 5.0)
    assert (loose.info["rtol"], loose.info["atol"]) == LARGE_TOLERANCES
    given = simulate_reduced(lattice, Numerics(), 5.0, rtol=1e-9, atol=1e-11)
    assert (given.info["rtol"], given.info["atol"]) == (1e-9, 1e-11)
    chain = simulate_reduced(Physics(scene="one-pinned", n=5, sigma=0.5), Numerics(), 2.0)
    assert (chain.info["rtol"], chain.info["atol"]) == CHAIN_TOLERANCES


@pytest.mark.parametrize(
    "sigma",
    [
        0.2,  # Pi = 2: the units turn (collective actuation)
        0.05,  # Pi = 0.5, below the patch's onset: the units stop; the solver's jitter is all there is
    ],
)
def test_the_large_networks_tolerance_changes_the_time_means_well_within_their_reported_errors(sigma, monkeypatch):
    physics = Physics(scene="lattice", rings=3, sigma=sigma, alignment_length=0.1)
    duration = 300.0
    tight = measure(simulate_reduced(physics, Numerics(), duration, rtol=1e-11, atol=1e-13), duration / 2).as_dict()
    monkeypatch.setattr(network_model, "DENSE_MODES", 2)  # the R = 3 patch run (and measured) as a large one
    traj = simulate_reduced(physics, Numerics(), duration)
    assert traj.info["rtol"] == LARGE_TOLERANCES[0]
    run = summary(traj, Numerics(), duration)["results"]
    for name in ERRORS:
        error = run[f"{name}_error"]
        assert np.isfinite(error) and error > 0, name
        assert abs(run[name] - tight[name]) < 0.1 * error, (name, run[name], tight[name], error)
    assert run["network_state"] == tight["network_state"]


def test_block_errors_are_the_blocks_spread_plus_the_solvers_part():
    t = np.linspace(0.0, 80.0, 801)
    still = np.tile(np.linspace(0.0, 3.0, 5), (t.size, 1))  # units at rest: no spread
    assert nobs.block_errors(t, still, scale=2.0) == pytest.approx((0.0, 0.0, 0.0), abs=1e-15)
    solver = nobs.block_errors(t, still, scale=2.0, rtol=1e-5)
    assert solver == pytest.approx((1e-5, nobs.SOLVER_JITTER * 1e-5 * 2.0, 1e-5), rel=1e-9)
    rng = np.random.default_rng(0)
    turning = np.cumsum(rng.normal(0.0, 0.3, (t.size, 5)), axis=0)  # units turning at random: a spread
    errors = nobs.block_errors(t, turning, scale=2.0)
    blocks = np.array_split(np.arange(800), nobs.ERROR_BLOCKS)
    speeds = [nobs.polarity_speed(t[b], turning[b]) for b in blocks]
    assert errors.polarity_speed == pytest.approx(np.std(speeds, ddof=1) / np.sqrt(nobs.ERROR_BLOCKS))
    assert np.isnan(nobs.block_errors(t[:20], turning[:20]).polarization)  # blocks too short to say


def test_unwrapped_is_numpys_unwrap_and_copies_nothing_when_continuous():
    rng = np.random.default_rng(1)
    psi = np.cumsum(rng.normal(0.0, 0.5, (200, 7)), axis=0)
    assert nobs.unwrapped(psi) is psi
    wrapped = np.angle(np.exp(1j * psi))
    np.testing.assert_allclose(nobs.unwrapped(wrapped), np.unwrap(wrapped, axis=0))
    np.testing.assert_allclose(nobs.unwrapped(wrapped), psi - (psi[0] - wrapped[0]), atol=1e-9)


@pytest.mark.parametrize("centre", [None, np.array([0.3, -0.2])])
def test_rotation_angle_is_the_least_squares_rotation(centre):
    rng = np.random.default_rng(2)
    rest = rng.normal(0.0, 1.0, (30, 2))
    angles = np.linspace(0.0, 7.0, 40)  # more than a turn: unwrapped
    origin = rest.mean(axis=0) if centre is None else centre
    c, s = np.cos(angles)[:, None], np.sin(angles)[:, None]
    r = rest - origin
    turned = origin + np.stack([c * r[:, 0] - s * r[:, 1], s * r[:, 0] + c * r[:, 1]], axis=-1)
    if centre is None:
        turned = turned + np.array([1.5, -0.5])  # a free patch may also move: its own centroid is used
    turned = turned + rng.normal(0.0, 1e-3, turned.shape)
    np.testing.assert_allclose(nobs.rotation_angle(turned, rest, centre), angles, atol=1e-3)


def test_a_large_networks_default_record_is_coarsened_to_the_aliasing_limit(monkeypatch):
    physics = Physics(scene="lattice", rings=3, sigma=0.2, alignment_length=0.1)  # 37 nodes, Pi = 2
    scene = physics.scene_def
    assert scene.record_numerics(physics, Numerics(), 1000.0) == Numerics()  # within the budget: as it was
    monkeypatch.setattr(network_step, "RECORD_BUDGET", 10_000)
    coarse = scene.record_numerics(physics, Numerics(), 1000.0)
    assert coarse.sample_dt == pytest.approx(0.5)  # Pi x sample_dt = 1 rad: the finest the budget may not force past
    assert scene.record_numerics(physics, Numerics(sample_dt=0.05), 1000.0).sample_dt == 0.05  # given: kept
    traj = simulate_reduced(physics, coarse.for_duration(40.0), 40.0)
    assert not [note for note in measure(traj, 20.0).notes if "alias" in note]
    monkeypatch.setattr(network_step, "RECORD_BUDGET", 400_000)
    assert scene.record_numerics(physics, Numerics(), 1000.0).sample_dt == pytest.approx(0.25)  # the budget's


def test_run_takes_a_tolerance_and_from_repeats_it(tmp_path):
    from elastoactive.cli import main

    out = tmp_path / "run"
    args = ["run", "lattice", "--rings", "1", "--sigma", "0.2", "--alignment-length", "0.1", "--engine", "reduced"]
    assert main([*args, "--duration", "10", "--rtol", "1e-7", "--out", str(out), "--quiet"]) == 0
    assert json.loads((out / "summary.json").read_text())["solver"]["rtol"] == 1e-7
    again = tmp_path / "again"
    assert main(["run", "--from", str(out), "--out", str(again), "--quiet"]) == 0
    assert json.loads((again / "summary.json").read_text())["solver"]["rtol"] == 1e-7
    with pytest.raises(ParameterError, match="rtol"):
        ea.simulate("lattice", duration=10, engine="mujoco", rtol=1e-6)


def test_a_run_through_the_gate_records_a_large_network_coarser(monkeypatch):
    monkeypatch.setattr(network_step, "RECORD_BUDGET", 2_000)
    physics = Physics(scene="lattice", rings=3, sigma=0.2, alignment_length=0.1)
    for engine in ("reduced", "mujoco"):
        traj = ea.simulate(physics, duration=40, engine=engine)
        assert traj.t[1] - traj.t[0] == pytest.approx(0.5), engine  # 1 rad of the units' turning at Pi = 2


def test_the_size_checked_before_a_run_is_the_networks_record(tmp_path):
    from elastoactive.cli.run import trajectory_bytes
    from elastoactive.records import write_run

    physics = Physics(scene="lattice", rings=3, sigma=0.2, alignment_length=0.1)
    traj = simulate_reduced(physics, Numerics(), 100.0)
    write_run(tmp_path, traj, summary(traj, Numerics(), 100.0))
    estimate = trajectory_bytes(physics, traj.t.size)
    with np.load(tmp_path / "trajectory.npz") as held:
        assert estimate == sum(held[name].nbytes for name in ("t", "theta", "nodes", "polarity"))
    assert (tmp_path / "trajectory.npz").stat().st_size < 1.05 * estimate  # uncompressed above 64 MB: about this
    chain = Physics(scene="one-pinned", n=7)
    assert trajectory_bytes(chain, 100) == 8 * 100 * (1 + 7)  # a chain's: its angles

"""Every entry point passes the one pre-flight gate (gate.preflight) before anything runs.

Each test makes the gate refuse with a mark of its own, then drives one entry point: the entry point must stop with
that refusal (or record it as the run's error) and simulate nothing.
"""

from __future__ import annotations

import json

import pytest

import elastoactive as ea
from elastoactive import gate
from elastoactive.batch import Case, run_case, run_cases
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import Numerics, Physics

MARK = "refused by the gate in a test"


@pytest.fixture
def gate_refuses(monkeypatch):
    """The gate refuses every run (through a check only the gate makes), and any simulation fails the test."""
    seen = []

    def refuse(physics):
        seen.append(physics)
        raise ParameterError(MARK)

    def no_run(*args, **kwargs):
        raise AssertionError("simulated past the gate")

    monkeypatch.setattr(gate, "check_measurable", refuse)
    from elastoactive import api, batch
    from elastoactive.engines import mujoco as mujoco_engine

    monkeypatch.setattr(api, "run_engine", no_run)
    monkeypatch.setattr(batch, "run_engine", no_run)
    monkeypatch.setattr(mujoco_engine, "simulate_mujoco", no_run)
    return seen


@pytest.mark.parametrize("engine", ["mujoco", "reduced"])
def test_simulate(gate_refuses, engine):
    with pytest.raises(ParameterError, match=MARK):
        ea.simulate("one-pinned", duration=5, engine=engine)
    assert gate_refuses


@pytest.mark.parametrize("engine", ["mujoco", "reduced"])
def test_the_batch_every_study_uses(gate_refuses, engine):
    cases = [Case(Physics(n=3, sigma=s), Numerics(), 5, engine) for s in (0.5, 1.0, 1.5)]
    with pytest.raises(ParameterError, match=MARK):
        run_cases(cases, workers=2, progress=False)
    with pytest.raises(ParameterError, match=MARK):
        run_case(cases[0])
    assert len(gate_refuses) == 4


def test_sweep_points_alone_and_in_a_mujoco_batch(gate_refuses):
    from elastoactive.sweep.points import run_point, run_points

    case = Case(Physics(n=3), Numerics(), 5, "reduced")
    assert MARK in run_point(case)["error"]
    records = run_points([Case(Physics(n=3, sigma=s), Numerics(), 5) for s in (0.5, 1.0)], threads=1)
    assert all(MARK in r["error"] for r in records)


def test_validate(gate_refuses):
    from elastoactive.checks.validate import compare

    with pytest.raises(ParameterError, match=MARK):
        compare(Physics(n=3), Numerics(), 5)


def test_run_from_a_recorded_run(gate_refuses, tmp_path, monkeypatch, capsys):
    """`run --from` re-runs through the API, so through the gate."""
    from elastoactive.cli import main

    monkeypatch.undo()  # record a real run first
    out = tmp_path / "first"
    assert (
        main(["run", "one-pinned", "--n", "3", "--duration", "5", "--engine", "reduced", "--out", str(out), "--quiet"])
        == 0
    )
    assert json.loads((out / "summary.json").read_text())["engine"] == "reduced"
    monkeypatch.setattr(gate, "check_measurable", lambda physics: (_ for _ in ()).throw(ParameterError(MARK)))
    capsys.readouterr()
    assert main(["run", "--from", str(out / "summary.json"), "--out", str(tmp_path / "again"), "--quiet"]) == 2
    assert MARK in capsys.readouterr().err


def test_a_study_run_with_a_bad_dt_is_refused_as_run_refuses_it():
    """The batch applies the same timestep check as `run`: a dt that would diverge is refused before any case runs,
    with the message `run` gives."""
    bad = Numerics(integrator="Euler", mass_ratio=1e-2, dt=0.01, sample_dt=0.05)
    physics = Physics(n=3, sigma=100.0)
    with pytest.raises(ParameterError) as direct:
        ea.simulate(physics, bad, duration=10)
    with pytest.raises(ParameterError) as batched:
        run_cases([Case(physics, bad, 10)], workers=1, progress=False)
    assert str(batched.value) == str(direct.value)


def test_a_batch_checks_each_distinct_model_once(monkeypatch):
    from elastoactive.engines import timestep

    calls = []
    original = timestep.check_timestep

    def counted(physics, numerics, *args, **kwargs):
        if kwargs.get("suggest", True):
            calls.append(physics.sigma)
        return original(physics, numerics, *args, **kwargs)

    monkeypatch.setattr(timestep, "check_timestep", counted)
    cases = [Case(Physics(n=3, sigma=s), Numerics.preset("fast"), 2) for s in (0.5, 0.5, 1.0)]
    run_cases(cases, workers=1, progress=False)
    assert sorted(calls) == [0.5, 1.0]

"""Irregular runs come with the errors of their numbers and a verdict on whether their dynamics is sensitive
(elastoactive.sensitivity); regular runs pay nothing for it."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import elastoactive as ea
from elastoactive import records, sensitivity
from elastoactive.core.trajectory import Trajectory


def _beating(irregular: bool) -> Trajectory:
    t = np.arange(0.0, 200.0, 0.05)
    amplitude = 0.5 * (1.0 + (0.2 * np.sin(2 * np.pi * t / 37.0) if irregular else 0.0))
    theta = np.zeros((t.size, 4))
    theta[:, -1] = amplitude * np.sin(2 * np.pi * t / 10.0)
    return Trajectory(t=t, theta=theta, physics=ea.Physics(n=4, sigma=1.2), engine="reduced")


def test_separation_rate_is_the_growth_rate_of_the_pilots_distance():
    t = np.linspace(0.0, 10.0, 201)
    a = np.zeros((t.size, 3))
    parting = a.copy()
    parting[:, 1] = 1e-9 * np.exp(1.5 * t)  # saturates (0.1 rad) at t ~ 12: never here
    assert sensitivity.separation_rate(t, a, parting) == pytest.approx(1.5, rel=0.05)
    steady = a.copy()
    steady[1:, 2] = 3e-9  # the solvers' error, not growing: a limit cycle's pilots stay together
    assert abs(sensitivity.separation_rate(t, a, steady)) < 0.05
    saturated = a.copy()
    saturated[:, 0] = np.minimum(1e-9 * np.exp(4.0 * t), 1.0)
    assert sensitivity.separation_rate(t, a, saturated) == pytest.approx(4.0, rel=0.1)


def test_an_irregular_run_comes_with_the_errors_of_its_numbers():
    s = records.summary(_beating(irregular=True), ea.Numerics(), 200.0)
    assert s["results"]["periodic"] is False
    record = s["results"]["sensitivity"]
    assert record["amplitude_error"] > 0 and record["frequency_error"] >= 0 and math.isfinite(record["lyapunov"])
    assert record["pilot_tau"] == 10.0 and record["sensitive"] == (record["lyapunov"] > sensitivity.SENSITIVE_RATE)
    assert any("+-" in note and "standard errors" in note for note in s["results"]["notes"])


def test_a_regular_run_pays_nothing_for_the_estimate(monkeypatch):
    def boom(*args, **kwargs):
        raise AssertionError("a regular run ran the sensitivity pilots")

    monkeypatch.setattr(records, "estimate_sensitivity", boom)
    s = records.summary(_beating(irregular=False), ea.Numerics(), 200.0)
    assert s["results"]["periodic"] is True and "sensitivity" not in s["results"]


def test_a_sensitive_run_is_named_with_its_horizon(monkeypatch):
    monkeypatch.setattr(sensitivity, "separation_rate", lambda *a: 2.0)  # as the pilots part on chaotic dynamics
    s = records.summary(_beating(irregular=True), ea.Numerics(), 200.0)
    record = s["results"]["sensitivity"]
    assert record["sensitive"] and record["horizon_tau"] == pytest.approx(math.log(1e5) / 2.0)
    assert any(note.startswith("sensitive dynamics") for note in s["results"]["notes"])


def test_a_run_the_reduced_pilots_cannot_take_keeps_its_results(tmp_path, capsys, monkeypatch):
    """An irregular MuJoCo run whose pilots the reduced engine refuses (as it refuses a term it does not cover) is
    written with a note that it has no error estimate; it had been thrown away after the simulation by the refusal."""
    from elastoactive.cli import main

    def refused(*args, **kwargs):
        raise ea.ParameterError("the reduced engine does not cover this run's terms")

    monkeypatch.setattr(records, "estimate_sensitivity", refused)
    monkeypatch.setattr(records, "needs_estimate", lambda *args: True)  # as an irregular run: a short one is not
    out = tmp_path / "ring"
    assert (
        main(["run", "ring", "--sigma", "3", "--engine", "mujoco", "--duration", "5", "--out", str(out), "--quiet"])
        == 0
    )
    summary = json.loads((out / "summary.json").read_text())
    assert any("no error estimate" in note for note in summary["results"]["notes"])


def _no_pilots(monkeypatch):
    from elastoactive.engines import reduced

    def boom(*args, **kwargs):
        raise AssertionError("the pilots ran from a state off the attractor")

    monkeypatch.setattr(reduced, "simulate_reduced", boom)


def test_a_run_still_leaving_its_unstable_start_is_too_short_to_measure(monkeypatch):
    """A 1-tau run of the straight chain above onset grows away from its unstable base state: pilots from there
    would part at its linear growth rate, which is not chaos. No pilots run and no verdict is given."""
    traj = ea.simulate(ea.Physics(sigma=0.8), duration=1.0, engine="reduced")
    _no_pilots(monkeypatch)
    record = sensitivity.estimate(traj, 0.5, ea.Numerics())
    assert record.sensitive is None and record.lyapunov is None and "whole cycles" in record.unsettled
    assert "too short to measure" in record.note(0.1, None)
    s = records.summary(traj, ea.Numerics(), 1.0)
    assert (s["results"].get("sensitivity") or {}).get("sensitive") is None
    assert not any("sensitive dynamics" in note or "chaotic" in note for note in s["results"]["notes"])


def test_a_beat_still_growing_is_not_on_its_attractor(monkeypatch):
    t = np.arange(0.0, 200.0, 0.05)
    theta = np.zeros((t.size, 4))
    theta[:, -1] = 0.01 * np.exp(0.03 * t) * np.sin(2 * np.pi * t / 10.0)  # spiralling out of the unstable state
    traj = Trajectory(t=t, theta=theta, physics=ea.Physics(n=4, sigma=1.2), engine="reduced")
    _no_pilots(monkeypatch)
    s = records.summary(traj, ea.Numerics(), 200.0)
    assert s["results"]["periodic"] is False
    assert s["results"]["sensitivity"]["sensitive"] is None and "growing" in s["results"]["sensitivity"]["unsettled"]
    assert sensitivity.unsettled(_beating(irregular=True), 100.0) is None

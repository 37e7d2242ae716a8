"""The pair through the fluid at the tiny size (N = 5, 3 sigma_c, d = 1.5, short runs): planar beats started near in
phase lock in phase and near anti-phase lock in anti-phase (both locks reached), co-rotating whirls lock in phase from
both starts; the claim rows follow the data; the figure and the saved summary are made."""

from __future__ import annotations

import dataclasses
import importlib
import math

import numpy as np
import pytest

from elastoactive.studies import cilia_runs, load_study


@pytest.fixture(scope="module")
def mod():
    return importlib.import_module("elastoactive.studies.cilia_pair_sync")


@pytest.fixture(scope="module")
def study(mod):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cilia_runs, "CYCLE_SETTLE", 24)
        mp.setattr(mod, "RUN_PERIODS", 20)
        mp.setattr(mod, "MEASURED_PERIODS", 6)
        return mod.cilia_pair_sync_study("tiny", workers=1, progress=False)


def test_locks(mod, study):
    s = study.summary
    states = {(r.cycle, round(r.start_lag, 2)): r for r in s.runs}
    assert states["beat", 0.2].state == "in-phase" and abs(states["beat", 0.2].lag) < 0.05
    assert states["beat", 2.94].state == "anti-phase" and abs(abs(states["beat", 2.94].lag) - math.pi) < 0.05
    assert states["beat", 2.94].closest < 2 * s.radius  # anti-phase at d = 1.5: the chains pass through each other
    assert states["whirl", 0.2].state == states["whirl", 2.94].state == "in-phase"
    assert set(s.periods) == {"beat", "whirl"} and s.scene == []
    assert all(np.isfinite(r.drift) for r in s.runs)
    assert study.data["trace_psi"].shape == (4, mod.TRACE_POINTS)


def test_starts_and_angles(mod):
    assert mod.start_lags("tiny", "beat") == (0.2, math.pi - 0.2)
    assert len(mod.start_lags("quick", "beat")) == 4 and len(mod.start_lags("full", "whirl")) == 8
    t = np.linspace(0.0, 2 * math.pi, 50)
    positions = np.zeros((50, 2, 1, 3))
    positions[:, 0, 0, :2] = np.column_stack([np.cos(t), np.sin(t)])
    positions[:, 1, 0, :2] = np.column_stack([np.cos(t + 1.0), np.sin(t + 1.0)])
    angles = mod.tip_angles(positions)
    assert np.allclose(np.angle(np.exp(1j * (angles[1] - angles[0]))), 1.0)


def _with(study, **changes):
    runs = [dataclasses.replace(r, **changes) for r in study.summary.runs]
    return dataclasses.replace(study, summary=dataclasses.replace(study.summary, runs=runs))


def test_claims_follow_the_data(mod, study, tmp_path):
    rows = mod.cilia_pair_sync_claims(study, {})
    assert rows[-1].agree == "yes"  # the whirls lock in phase
    apart = _with(study, closest=1.0)
    assert mod.cilia_pair_sync_claims(apart, {})[0].agree == "yes"  # in phase and anti-phase, the chains apart
    through = _with(study, closest=0.0)
    assert mod.cilia_pair_sync_claims(through, {})[0].agree == "no"  # runs whose beads overlap do not count
    assert mod.cilia_pair_sync_claims(_with(apart, state="in-phase", lag=0.0), {})[0].agree == "no"
    assert mod.cilia_pair_sync_claims(_with(apart, state="lag", lag=1.9), {})[1].agree == "yes"
    assert mod.cilia_pair_sync_claims(_with(apart, drift=0.5), {})[0].agree == "no"  # a drifting lag is no lock yet
    assert mod.cilia_pair_sync_figures(study, tmp_path)[0].exists()
    study.save(tmp_path)
    assert load_study(tmp_path, "cilia_pair_sync").summary.runs[0].state == study.summary.runs[0].state

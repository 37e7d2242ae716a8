"""The row through the fluid at the tiny size (M = 3 cilia of N = 5, d = 1.5, short runs): both cycles run, the
neighbours' lags and the flux are measured (the flux's mean well below its back-and-forth); the claim rows follow the
data; the figure and the saved summary are made."""

from __future__ import annotations

import dataclasses
import importlib
import math

import numpy as np
import pytest

from elastoactive.studies import cilia_runs, load_study


@pytest.fixture(scope="module")
def mod():
    return importlib.import_module("elastoactive.studies.cilia_row_waves")


@pytest.fixture(scope="module")
def study(mod):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cilia_runs, "CYCLE_SETTLE", 24)
        mp.setattr(mod, "RUN_PERIODS", 16)
        mp.setattr(mod, "MEASURED_PERIODS", 6)
        return mod.cilia_row_waves_study("tiny", workers=1, progress=False)


def test_runs(mod, study):
    s = study.summary
    assert [r.cycle for r in s.runs] == ["beat", "whirl"] and s.cilia == 3
    for r in s.runs:
        assert len(r.lags) == 2 and r.flux_rms > 0 and abs(r.flux_x) < 0.5 * r.flux_rms
        assert r.start_phases == mod.start_phases(3)
    beat = s.runs[0]
    assert beat.flux_y == 0.0  # the planar row stays in its plane: no force across it


def test_start_phases(mod):
    phases = mod.start_phases(5, seed=3)
    assert phases[0] == 0.0 and len(phases) == 5 and all(0 <= p < 2 * math.pi for p in phases)
    assert mod.start_phases(5, seed=3) == phases


def test_claims_follow_the_data(mod, study, tmp_path):
    rows = mod.cilia_row_waves_claims(study, {})
    assert len(rows) == 3
    waves = [dataclasses.replace(r, direction="+x", wave_number=0.1) for r in study.summary.runs]
    changed = dataclasses.replace(study, summary=dataclasses.replace(study.summary, runs=waves))
    assert mod.cilia_row_waves_claims(changed, {})[0].agree == "yes"
    pumping = [dataclasses.replace(r, flux_x=r.flux_rms) for r in study.summary.runs]
    changed = dataclasses.replace(study, summary=dataclasses.replace(study.summary, runs=pumping))
    assert mod.cilia_row_waves_claims(changed, {})[-1].agree == "no"
    assert mod.cilia_row_waves_figures(study, tmp_path)[0].exists()
    study.save(tmp_path)
    assert np.isclose(load_study(tmp_path, "cilia_row_waves").summary.runs[0].flux_rms, study.summary.runs[0].flux_rms)

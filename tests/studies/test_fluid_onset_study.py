"""The onset through the fluid at the tiny size (N = 5, a / l = 0.01 and 0.1): the small radius's onset is the local
drag's within 1%, the interactions lower it, one chain's planes stay degenerate and a pair's split; the claim rows
follow the data; the figure and the saved summary are made."""

from __future__ import annotations

import dataclasses
import importlib

import pytest

from elastoactive.analysis import stability
from elastoactive.studies import load_study


@pytest.fixture(scope="module")
def mod():
    return importlib.import_module("elastoactive.studies.fluid_onset")


@pytest.fixture(scope="module")
def study(mod):
    return mod.fluid_onset_study("tiny", workers=1, progress=False)


def test_onsets(study):
    s = study.summary
    assert s.local_sigma_c == pytest.approx(stability.onset(5)[0], rel=1e-12)
    small = [o for o in s.onsets if o.radius == 0.01]
    assert {o.geometry for o in small} == {"free", "wall"}
    for o in small:
        assert o.sigma_c == pytest.approx(s.local_sigma_c, rel=1e-2)
    for o in s.onsets:
        assert o.sigma_c < s.local_sigma_c and o.splitting < 1e-10 and o.coupling == 0.0
    assert s.pair.splitting > 1e-6 and s.pair.coupling == 0.0
    assert study.data["sigma_c"].shape == (2, 2)


def test_claims_follow_the_data(mod, study, tmp_path):
    rows = mod.fluid_onset_claims(study, {})
    assert [r.agree for r in rows] == ["yes"] * 4
    split = dataclasses.replace(study.summary.onsets[0], splitting=1e-3)
    changed = dataclasses.replace(
        study, summary=dataclasses.replace(study.summary, onsets=[split, *study.summary.onsets[1:]])
    )
    assert mod.fluid_onset_claims(changed, {})[-1].agree == "no"
    assert mod.fluid_onset_figures(study, tmp_path)[0].exists()
    study.save(tmp_path)
    assert load_study(tmp_path, "fluid_onset").summary.pair.splitting == study.summary.pair.splitting

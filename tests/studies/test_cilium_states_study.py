"""The single cilium on the wall at the tiny size (N = 5, 3 sigma_c through the fluid): the planar start beats in
its plane, the tilted start and the helix whirl at one rate, faster than the local drag's whirl; the claim rows
follow the data; the figure and the saved summary are made."""

from __future__ import annotations

import dataclasses
import importlib

import pytest

from elastoactive.studies import load_study


@pytest.fixture(scope="module")
def mod():
    return importlib.import_module("elastoactive.studies.cilium_states")


@pytest.fixture(scope="module")
def study(mod):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(mod, "RUN_PERIODS", 24)
        return mod.cilium_states_study("tiny", workers=1, progress=False)


def test_states_and_numbers(study):
    runs = {r.start: r for r in study.summary.runs}
    assert (runs["planar"].state, runs["planar"].out_of_plane) == ("beat", 0.0)
    assert runs["tilted"].state == runs["helix"].state == runs["local helix"].state == "whirl"
    assert abs(runs["tilted"].whirl_rate) == pytest.approx(abs(runs["helix"].whirl_rate), rel=1e-4)
    assert abs(runs["helix"].whirl_rate) > abs(runs["local helix"].whirl_rate)
    assert abs(runs["helix"].whirl_rate) > runs["planar"].frequency


def test_claims_follow_the_data(mod, study, tmp_path):
    rows = mod.cilium_states_claims(study, {})
    verdicts = {r.claim: r.agree for r in rows}
    assert verdicts["a follower-force cilium on the wall whirls from a non-planar start at every load tested"] == "yes"
    tilted = next(r for r in study.summary.runs if r.start == "tilted")
    runs = [dataclasses.replace(r, state="beat") if r is tilted else r for r in study.summary.runs]
    changed = dataclasses.replace(study, summary=dataclasses.replace(study.summary, runs=runs))
    rows = {r.claim.split(" (")[0]: r.agree for r in mod.cilium_states_claims(changed, {})}
    assert rows["the planar beat is unstable out of its plane and the whirl is the attractor"] == "no"
    assert mod.cilium_states_figures(study, tmp_path)[0].exists()
    study.save(tmp_path)
    assert load_study(tmp_path, "cilium_states").summary.runs[0].state == study.summary.runs[0].state

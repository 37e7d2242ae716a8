"""The 3D state diagram study on one load (N = 7, sigma = 5 sigma_c, drag ratio 1): the planar start beats in its
plane, the helix whirls (Newton's whirl stable, at the measured rate), the beat is unstable out of its plane, the 3D
onset is the planar one; the claim rows' verdicts follow the data; the figure and the saved summary are made."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.studies import load_study, registry, states3d
from elastoactive.studies.states3d import start_tangents, states3d_claims, states3d_figures, states3d_study


@pytest.fixture(scope="module")
def study():
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(states3d, "_grid", lambda size: (7, (1.0,), (5.0,), (5.0,)))
        mp.setattr(states3d, "_engine_loads", lambda size: (5.0,))
        mp.setattr(states3d, "ENGINE_PERIODS", 4)  # 92 tau: the whirl settles within ~40
        return states3d_study("tiny", workers=1, progress=False)


def test_states_and_numbers(study):
    s = study.summary
    planar, helix = s.runs
    assert (planar.start, planar.state, planar.out_of_plane) == ("planar", "beat", 0.0)
    assert helix.state == "whirl" and helix.newton_growth < 0
    assert abs(helix.newton_rate) == pytest.approx(helix.frequency, rel=1e-5)
    assert abs(helix.newton_rate) == pytest.approx(
        0.0562066, rel=1e-4
    )  # sigma = 0.7873 (docs/model3d.md: 0.8 turns at 0.05738)
    (floquet,) = s.floquet
    assert floquet.growth > 0.3 and floquet.neutral < 1e-9
    (onset,) = s.onsets
    assert onset.sigma_c == pytest.approx(onset.planar_sigma_c, rel=1e-9)
    assert study.data["state"].shape == (1, 1, 2)
    (engines,) = s.engines  # the scene from its seeded start in both engines, default numerics
    assert engines.states == ("whirl", "whirl") and engines.dt == 0.0025
    assert abs(engines.difference("frequency")) < 0.01 and abs(engines.difference("amplitude")) < 0.01


def test_claims_follow_the_data(study, tmp_path):
    rows = states3d_claims(study, {})
    assert [r.agree for r in rows] == ["yes"] * 7
    other = dataclasses.replace(study.summary.runs[1], state="other")
    changed = dataclasses.replace(
        study, summary=dataclasses.replace(study.summary, runs=[study.summary.runs[0], other])
    )
    verdicts = {r.claim: r.agree for r in states3d_claims(changed, {})}
    assert verdicts["from a non-planar start the chain whirls at every load tested"] == "no"
    apart = dataclasses.replace(study.summary.engines[0], amplitude=(1.0, 1.02))
    changed = dataclasses.replace(study, summary=dataclasses.replace(study.summary, engines=[apart]))
    verdicts = {r.claim: r.agree for r in states3d_claims(changed, {})}
    assert verdicts["MuJoCo and the reduced 3D engine agree on the whirl at their default numerics"] == "no"
    assert states3d_figures(study, tmp_path)[0].exists()
    study.save(tmp_path)
    assert load_study(tmp_path, "states3d").summary.runs[1].state == "whirl"
    assert load_study(tmp_path, "states3d").summary.engines == study.summary.engines
    assert "states3d" in registry.names()


def test_starts():
    assert np.all(start_tangents(5, "planar")[:, 2] == 0.0)
    assert np.all(start_tangents(5, "non-planar")[:, 2] > 0.0)
    with pytest.raises(ParameterError, match="start"):
        start_tangents(5, "sideways")

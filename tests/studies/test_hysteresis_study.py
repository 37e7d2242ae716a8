"""The hysteresis study at its tiny size: the pinned hexagon (R = 2) is frozen at Pi = 1 both ways and moves at 1.6,
inside its linear bracket; a kagome patch moves at the top; the claims, the figure and the saved summary are made."""

from __future__ import annotations

import numpy as np

from elastoactive.studies import load_study, registry
from elastoactive.studies.hysteresis import hysteresis_claims, hysteresis_figures, hysteresis_study


def test_hysteresis_study_tiny(tmp_path):
    study = hysteresis_study("tiny", workers=1, progress=False)
    triangular, kagome = study.summary.loops
    assert triangular.up_start == [1.6] and triangular.down_stop == [1.6] and triangular.down_freeze == [1.0]
    assert triangular.softest < 1.6 < triangular.linear_threshold + 0.2
    assert triangular.moving_states == ["collective"]  # the small patch turns as one at Pi = 1.6
    assert abs(triangular.edge_rate - triangular.bulk_rate) < 1e-3 * triangular.bulk_rate
    assert kagome.up_start == [1.2] and kagome.softest < 1.2
    assert study.data["loop0_network_state"].shape == (1, 2, 2)
    claims = hysteresis_claims(study, {})
    assert len(claims) == 2 and all("lambda_1" in c.note for c in claims)
    assert [c.judge("tiny").agree for c in claims] == ["not judged at this size"] * 2
    assert hysteresis_figures(study, tmp_path)[0].exists()
    study.save(tmp_path)
    assert np.isclose(load_study(tmp_path, "hysteresis").summary.loops[0].softest, triangular.softest)
    assert "hysteresis" in registry.names()

"""The disorder study at its tiny size: the pinned triangular hexagon (size 2) whole and with 15% of its bonds removed,
Pi ramped 0.5 -> 2 and back: still at 0.5 (below lambda_1), turning at 2 in both; dilution lowers lambda_1 and the
median Pi_c; the claims, the figure and the saved summary are made."""

from __future__ import annotations

import numpy as np

from elastoactive.studies import load_study, registry
from elastoactive.studies.disorder import disorder_claims, disorder_figures, disorder_study


def test_disorder_study_tiny(tmp_path):
    study = disorder_study("tiny", workers=1, progress=False)
    whole, diluted = study.summary.networks
    assert (whole.dilution, diluted.dilution) == (0.0, 0.15) and diluted.bonds < whole.bonds
    assert abs(whole.softest - 1.13584) < 1e-5  # the R = 2 hexagon's lambda_1
    assert diluted.softest < whole.softest and diluted.typical < whole.typical and diluted.floppy == 0
    assert np.isnan(whole.best_found)  # the search runs at the full size only
    for net in (whole, diluted):
        assert net.softest <= net.typical <= net.ceiling
        assert net.up_motion == net.up_start == [2.0] and net.down_stop == [2.0]  # still at 0.5 (< lambda_1)
        assert net.top_states[0] in ("collective", "mixed", "heterogeneous", "irregular")
    speed = study.data["polarity_speed"]  # (network, seed, direction, coupling)
    assert speed.shape == (2, 1, 2, 2) and np.all(speed[:, 0, :, 1] > 100 * speed[:, 0, :, 0])
    claims = disorder_claims(study, {})
    assert len(claims) == 3 and claims[0].agree == "yes"
    assert "2504.08572" in claims[2].paper
    assert all(c.judge("tiny").agree == "not judged at this size" for c in claims)
    assert disorder_figures(study, tmp_path)[0].exists()
    study.save(tmp_path)
    loaded = load_study(tmp_path, "disorder").summary.networks[1]
    assert np.isclose(loaded.softest, diluted.softest) and loaded.top_states == diluted.top_states
    assert "disorder" in registry.names()

"""The noise-threshold study at its tiny size: the pinned hexagon (R = 2) still at Pi = 1 and turning at 1.6, with and
without rotational noise on the polarities (noise alone makes the still state swing, not turn); the claim, the figure
and the saved summary are made."""

from __future__ import annotations

import numpy as np

from elastoactive.studies import load_study, registry
from elastoactive.studies.noise_threshold import noise_threshold_claims, noise_threshold_figures, noise_threshold_study


def test_noise_threshold_study_tiny(tmp_path):
    study = noise_threshold_study("tiny", workers=1, progress=False)
    quiet, noisy = study.summary.levels
    assert quiet.rotational_diffusion == 0 and noisy.rotational_diffusion > 0
    assert quiet.up_start == [1.6] and noisy.up_start == [1.6] and noisy.down_stop == [1.6]
    assert study.summary.softest < 1.6
    speed = study.data["polarity_speed"]  # (level, seed, direction, coupling)
    assert speed.shape == (2, 1, 2, 2) and speed[1, 0, 0, 0] > 100 * speed[0, 0, 0, 0]  # the noise's swinging
    claims = noise_threshold_claims(study, {})
    assert len(claims) == 1 and "lambda_1" in claims[0].note and claims[0].agree == "no"
    assert claims[0].judge("tiny").agree == "not judged at this size"
    assert noise_threshold_figures(study, tmp_path)[0].exists()
    study.save(tmp_path)
    assert np.isclose(load_study(tmp_path, "noise_threshold").summary.softest, study.summary.softest)
    assert "noise_threshold" in registry.names()

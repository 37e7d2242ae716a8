"""The report's claim rows quote what was measured over the whole range they name, and judge only what their size
can judge."""

from __future__ import annotations

import numpy as np

from elastoactive.studies.base import Study
from elastoactive.studies.ring import rate_per_sigma, ring_claims


def _rings(ratios, sigma=(0.2, 3.0, 30.0)):
    """A rings study whose N = 7 ring turns at rate / sigma = `ratios` (both engines), other numbers plausible."""
    from elastoactive.studies.ring import RingSummary

    sigma = np.asarray(sigma)
    rate = np.asarray(ratios) * sigma
    data = {
        "sigma_small": sigma,
        "sigma_large": np.array([0.5]),
        "sigma_free": np.array([0.8]),
        "rate_7_mujoco": rate,
        "rate_7_reduced": rate * (1 + 1e-6),
    }
    summary = RingSummary(
        sigma_small=list(sigma),
        sigma_large=[0.5],
        sigma_free=[0.8],
        rigid_amplitude_mujoco=1e-12,
        rigid_amplitude_reduced=1e-6,
        rate_per_sigma_mujoco=float(ratios[0]),
        rate_per_sigma_reduced=float(ratios[0]),
        rate_difference=1e-6,
        beating_mujoco=[0.5],
        beating_reduced=[0.5],
        free_rate_ratio_mujoco=0.01,
        free_rate_ratio_reduced=0.01,
        free_rate_difference=1e-6,
        free_drift=1e-6,
        free_rigid_amplitude=1e-6,
    )
    return Study("rings", "quick", data, summary, 1.0)


def test_a_rate_per_sigma_that_changes_is_quoted_over_every_sigma():
    """The rigid ring's rate / sigma is not one number (-0.392 at sigma 0.2, -0.650 at 80): the row gives its range
    with the sigma of each end, and one value only where it does not change."""
    row = ring_claims(_rings([-0.3917, -0.4863, -0.6254]), {})[0]
    for cell in (row.mujoco, row.reduced):
        assert "-0.3917 (sigma 0.2) to -0.6254 (sigma 30)" in cell, cell
    steady = _rings([-0.39174, -0.39174, -0.39174])
    assert rate_per_sigma(steady, "mujoco") == "-0.3917"


def test_a_row_is_judged_only_at_a_size_that_can_judge_it(monkeypatch):
    """A row declares the smallest size whose grids can meet its rule (Claim.judged_from): below it the report marks
    it 'not judged at this size', keeping its numbers, instead of a verdict the size cannot support (the tiny size's
    onset fit, N^-3 slope and Landau coefficient had read **no**); from that size on the rule's verdict stands."""
    from elastoactive.report import claims
    from elastoactive.studies import registry
    from elastoactive.studies.claim_rows import NOT_JUDGED, VERDICTS, Claim

    row = Claim("a fitted exponent", "0.5", "0.41", "0.42", "no", "fit over 3 points", judged_from="quick")
    monkeypatch.setattr(registry.get("rings"), "claims_fn", lambda study, read: [row, Claim("x", "", "", "", "yes")])
    study = _rings([-0.39, -0.39, -0.39])
    for size, verdicts in (("tiny", [NOT_JUDGED, "yes"]), ("quick", ["no", "yes"]), ("full", ["no", "yes"])):
        study.size = size
        rows = claims.build_claims({"rings": study})
        assert [r.agree for r in rows] == verdicts and rows[0].mujoco == "0.41"
        assert all(r.agree in VERDICTS for r in rows)
    study.size = "tiny"
    judged = claims.build_claims({"rings": study})[0]
    assert "not judged at the tiny size" in judged.note and "fit over 3 points" in judged.note
    assert f"**{NOT_JUDGED}**" in claims.claims_table([judged])

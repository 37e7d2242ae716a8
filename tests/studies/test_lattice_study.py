"""The active-solid study at its tiny size: the pinned hexagon rests at Pi = 1 and actuates at 1.5 and 2, inside the
linear bracket, in both engines; the trapped unit follows its derivation; the claims and the figure are made."""

from __future__ import annotations

from elastoactive.studies import registry
from elastoactive.studies.lattice import active_solid_claims, active_solid_figures, active_solid_study


def test_active_solid_study_tiny(tmp_path):
    study = active_solid_study("tiny", workers=1, progress=False)
    s = study.summary
    assert s.actuated_fraction == [0.0, 1.0, 1.0] and s.still_below == 1.0 and s.actuated_above == 1.5
    assert s.softest < s.actuated_above < s.linear_threshold + 0.2
    assert s.trap_radius_error < 1e-4 and s.trap_rate_error < 1e-4
    assert s.mujoco_couplings == [1.0, 1.5] and s.mujoco_actuation[0] == 0.0 and s.mujoco_actuation[1] > 0.9
    assert sorted(s.mujoco_modes[1]) == sorted(s.reduced_modes[1]) == [1, 2]  # MuJoCo: the same transition, modes
    claims = active_solid_claims(study, {})
    assert claims[0].mujoco.startswith("seed 0") and claims[1].mujoco != "-"
    assert [c.agree for c in claims] == ["yes", "yes", "yes"]
    assert active_solid_figures(study, tmp_path)[0].exists()
    assert "active_solid" in registry.names()

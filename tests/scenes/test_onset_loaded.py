"""The planar chain's onset takes the follower's `loaded`: the tip-loaded column's flutter, not the paper's chain's,
in onset, leading_eigenvalue and `elastoactive stability`'s report (checked against analysis.flutter's dense
overdamped problem)."""

from __future__ import annotations

import pytest

import elastoactive as ea
from elastoactive.analysis import flutter

SCENE = ea.scenes.get("one-pinned")


@pytest.mark.parametrize("n, loaded, active", [(7, "tip", [6]), (7, "3,6", [2, 5]), (30, "3,6", [2, 5])])
def test_the_onset_is_the_loaded_chains(n, loaded, active):
    onset = SCENE.onset(ea.Physics(n=n, loaded=loaded))
    sigma_c, omega_c = flutter.critical_sigma(n, 0.0, active=active)
    assert onset.sigma_c == pytest.approx(sigma_c, rel=1e-9) and onset.omega_c == pytest.approx(omega_c, rel=1e-6)
    assert loaded in onset.kind


def test_tip_loaded_seven():
    tip, every = ea.Physics(n=7, loaded="tip"), ea.Physics(n=7)
    assert SCENE.onset(tip).sigma_c == pytest.approx(0.56032, abs=1e-5)
    assert SCENE.onset(every).sigma_c == pytest.approx(0.157470, abs=1e-6)  # the paper's chain, as before
    assert SCENE.leading_eigenvalue(tip, 0.3).real < 0 < SCENE.leading_eigenvalue(every, 0.3).real
    assert SCENE.leading_eigenvalue(tip, 0.57).real > 0


def test_the_report_leaves_the_filament_out_of_a_partial_load():
    lines = SCENE.stability_report(ea.Physics(n=7, loaded="tip"), None)
    assert "sigma_c = 0.56031" in lines[1] and not any("filament" in line for line in lines)
    assert any("filament" in line for line in SCENE.stability_report(ea.Physics(n=7), None))

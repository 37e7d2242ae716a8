"""elastoactive.cli.warm: the kernels' warm-up that scripts/setup.sh runs covers every scene and term and runs
through."""

from elastoactive.checks.validate import validation_cases
from elastoactive.cli import warm


def test_warm_up_runs_every_validation_case_and_the_other_paths():
    runs = warm.runs()
    scenes = {physics.scene for physics, _, _ in runs}
    assert {case.physics.scene for case in validation_cases()} <= scenes
    assert any(physics.noise > 0 for physics, _, _ in runs)  # the SDE steppers
    assert any(physics.stochastic and not physics.noise for physics, _, _ in runs)  # a network's noisy polarities
    assert {physics.scene for physics, _, _ in runs if physics.bead_radius > 0} >= {"cilium", "cilia-row"}  # the fluid
    assert any(keywords.get("inertial") for _, _, keywords in runs)  # the inertial model
    assert {"LSODA", "Radau", "BDF"} <= {keywords.get("method") for _, _, keywords in runs}
    count, failed, seconds = warm.warm()
    assert count == len(runs) and failed == 0 and seconds > 0

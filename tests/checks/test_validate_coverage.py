"""validate reports every case: one that cannot run at a setting is a row saying why, and the verdict says so."""

import math

import pytest

from elastoactive.checks.validate import (
    Comparison,
    format_table,
    inertial_gap,
    inertial_plan,
    not_run,
    validation_cases,
    verdict,
)
from elastoactive.cli import main
from elastoactive.core.params import Numerics
from elastoactive.scenes import NetworkScene


def test_inertial_plan_keeps_every_case_with_its_reason():
    cases = validation_cases()
    plan = inertial_plan(1e-3)
    assert [c.physics for c, _ in plan] == [c.physics for c in cases]
    gaps = {c.physics.scene_def.label(c.physics): gap for c, gap in plan}
    assert any(gaps.values()) and not all(gaps.values())
    for case, gap in plan:
        assert gap == inertial_gap(case.physics)
        network = isinstance(case.physics.scene_def, NetworkScene)
        assert not network or gap  # a network's reduced model is overdamped only


def _ran(case, error: float) -> Comparison:
    return Comparison(
        case.physics,
        Numerics(),
        case.duration,
        None,
        None,
        1.0,
        1.0,
        {"amplitude": error, "angle": error, "angle_rad": error, "window": 20.0},
        None,
    )


def test_verdict_names_cases_not_run():
    first, second = validation_cases()[:2]
    rows = [_ran(first, 0.001), not_run(second, Numerics(), "no model")]
    line, passed = verdict(rows, 0.01)
    assert passed and "1 NOT RUN" in line and "1 of 2" in line
    assert "not run: no model" in format_table(rows)
    assert math.isnan(rows[1].worst())
    line, passed = verdict(rows[1:], 0.01)
    assert not passed and "no case ran" in line
    assert verdict(rows[:1], 0.01) == ("largest relative error 0.100% (tolerance 1%): PASS", True)


@pytest.mark.parametrize(
    "argv", [["validate", "lattice", "--inertial"], ["validate", "trapped-unit", "--mass-ratio", "0.01"]]
)
def test_validate_refuses_a_scene_with_no_case_at_the_mass(argv, capsys):
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("elastoactive: error: --") and "overdamped" in err[0]


def test_validate_reports_a_case_it_cannot_run(monkeypatch, capsys):
    import elastoactive.checks.validate as validate

    monkeypatch.setattr(
        validate,
        "compare",
        lambda physics, numerics, duration, inertial=None: _ran(
            next(c for c in validation_cases("ring") if c.physics == physics), 0.001
        ),
    )
    assert main(["validate", "ring", "--mass-ratio", "0.001", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "ring N=7 sigma=0.8 free | not run: " in out and "1 NOT RUN" in out

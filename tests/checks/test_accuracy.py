"""The accuracy study (elastoactive accuracy): its errors are validate.compare's, they fall as the
settings tighten, unstable settings are recorded rather than raised, and the outputs are written."""

from __future__ import annotations

import csv
import math

import pytest

from elastoactive.checks import accuracy as A
from elastoactive.checks.validate import compare
from elastoactive.core.params import Numerics, Physics

CHAIN = Physics(n=7, sigma=0.8)
DURATION = 100.0  # two periods (f ~ 0.042) in the measured second half


@pytest.fixture(scope="module")
def reference():
    return A.reference_solution(CHAIN, DURATION)


def test_errors_are_validate_compare_errors(reference):
    setting = A.Setting("mujoco", "implicitfast", dt=0.01, mass_ratio=1e-3)
    row = A.run_setting(CHAIN, DURATION, setting, reference, repeats=1)
    expected = compare(CHAIN, setting.numerics(), DURATION, reference=reference).errors
    for key in ("amplitude", "frequency", "angle", "angle_rad", "window"):
        assert row[key] == pytest.approx(expected[key], rel=1e-12, abs=1e-15), key
    assert row["worst"] == max(expected[k] for k in ("amplitude", "frequency", "angle"))
    assert row["status"] == "ok" and row["wall_s"] > 0
    assert row["guard"] == "pass"  # the 'fast' preset passes the pre-flight accuracy guard


def test_settings_the_guard_refuses_are_still_measured(reference):
    """dt = 0.04 is stable for implicitfast (limit 0.27) but unresolved: measured, and marked."""
    row = A.run_setting(
        CHAIN, DURATION, A.Setting("mujoco", "implicitfast", dt=0.04, mass_ratio=1e-4), reference, repeats=1
    )
    assert row["status"] == "ok" and row["guard"].startswith("refuse: dt = 0.04 does not resolve")
    assert row["angle"] > 0.03  # and it is indeed several times worse than the 1% target


def test_mujoco_error_falls_with_dt_first_order(reference):
    rows = [
        A.run_setting(
            CHAIN, DURATION, A.Setting("mujoco", "implicitfast", dt=dt, mass_ratio=1e-6), reference, repeats=1
        )
        for dt in (0.02, 0.005)
    ]
    coarse, fine = rows
    # implicitfast is first order: 4x smaller dt, about 4x smaller error (transient angles and amplitude)
    assert 2.5 < coarse["angle"] / fine["angle"] < 6
    assert 2.5 < coarse["amplitude"] / fine["amplitude"] < 6
    assert fine["worst"] < 0.02


def test_mujoco_error_falls_with_mass_ratio_for_rk4(reference):
    """RK4's error at small dt is the inertia's: about proportional to the mass ratio."""
    rows = [
        A.run_setting(CHAIN, DURATION, A.Setting("mujoco", "RK4", dt=0.02, mass_ratio=m), reference, repeats=1)
        for m in (1e-2,)
    ] + [A.run_setting(CHAIN, DURATION, A.Setting("mujoco", "RK4", dt=0.0025, mass_ratio=1e-3), reference, repeats=1)]
    assert all(r["status"] == "ok" for r in rows)
    assert rows[0]["angle"] / rows[1]["angle"] > 5


def test_reduced_error_falls_with_tolerance(reference):
    loose, tight = (
        A.run_setting(CHAIN, DURATION, A.Setting("reduced", "numba-DOP853", rtol=r), reference, repeats=1)
        for r in (1e-4, 1e-8)
    )
    assert tight["worst"] < 1e-3 * loose["worst"]
    assert tight["worst"] < 1e-5


def test_unstable_settings_are_recorded_not_raised(reference, monkeypatch):
    refused = A.run_setting(CHAIN, DURATION, A.Setting("mujoco", "Euler", dt=0.01, mass_ratio=1e-4), reference)
    assert refused["status"] == "refused" and "mass_ratio" in refused["message"]
    assert math.isnan(refused["wall_s"])
    # with the pre-flight check switched off the same setting blows up: recorded as diverged
    monkeypatch.setattr(A, "check_timestep", lambda *a, **k: None)
    diverged = A.run_setting(
        CHAIN, 20.0, A.Setting("mujoco", "Euler", dt=0.01, mass_ratio=1e-4), A.reference_solution(CHAIN, 20.0)
    )
    assert diverged["status"] == "diverged" and "diverged" in diverged["message"]


def test_recommend_picks_the_cheapest_setting_meeting_each_level():
    def s(series, dt, worst, wall):
        return {
            "engine": "mujoco",
            "series": series,
            "dt": dt,
            "mass_ratio": 1e-4,
            "rtol": None,
            "status": "ok",
            "worst": worst,
            "steady": worst,
            "wall_s": wall,
            "wall_per_100tau": wall,
        }

    summary = [
        s("implicitfast", 0.04, 0.05, 1.0),
        s("implicitfast", 0.01, 0.008, 2.0),
        s("implicitfast", 0.0025, 0.002, 8.0),
        s("implicitfast", 0.001, 0.0009, 20.0),
        s("RK4", 0.001, 0.0005, 30.0),
    ]
    summary.append({**s("implicitfast", 0.1, 1e-9, 0.1), "status": "diverged"})  # never recommended
    recs = {(r["level"], r["series"]): r["setting"] for r in A.recommend(summary)}
    assert recs[(1e-2, "implicitfast")]["dt"] == 0.01
    assert recs[(1e-3, "implicitfast")]["dt"] == 0.001
    assert recs[(1e-4, "implicitfast")] is None
    assert recs[(1e-3, "RK4")]["dt"] == 0.001
    text = A.format_recommendations(A.recommend(summary))
    assert "not reached in the grid" in text and "dt=0.01" in text


def test_study_writes_plot_tables_and_csv(tmp_path):
    physics = Physics(n=3, sigma=3.0)
    cases = [(physics, 40.0)]
    mujoco = [
        A.Setting("mujoco", "implicitfast", dt=0.01, mass_ratio=1e-3),
        A.Setting("mujoco", "implicitfast", dt=0.0025, mass_ratio=1e-4),
        A.Setting("mujoco", "Euler", dt=0.01, mass_ratio=1e-4),
    ]  # refused: recorded
    reduced = [
        A.Setting("reduced", "numba-DOP853", rtol=1e-6),
        A.Setting("reduced", "numba-DOP853", rtol=1e-9),
        A.Setting("reduced", "RK45", rtol=1e-6),
    ]
    rows, meta = A.run_study(cases=cases, mujoco=mujoco, reduced=reduced, workers=1, progress=False, repeats=1)
    A.write_outputs(tmp_path, rows, meta)
    with open(tmp_path / "accuracy.csv") as fh:
        table = list(csv.DictReader(fh))
    assert len(table) == 6
    assert [r["status"] for r in table].count("refused") == 1
    md = (tmp_path / "accuracy.md").read_text()
    assert "Cost of the defaults" in md and "MuJoCo default" in md and "reduced default" in md
    assert "| 1% | mujoco | implicitfast |" in md
    for png in ("accuracy.png", "accuracy_steady.png"):
        data = (tmp_path / png).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


def test_grids_hold_the_defaults_and_respect_the_drag_limit():
    for quick in (True, False):
        grid = A.mujoco_grid(quick)
        keys = {(s.series, s.dt, s.mass_ratio) for s in grid}
        assert ("implicitfast", 0.0025, 1e-4) in keys and ("implicitfast", 0.01, 1e-3) in keys
        for s in grid:
            Numerics(dt=s.dt, mass_ratio=s.mass_ratio, sample_dt=A.SAMPLE_DT)  # whole steps per sample
            if s.series == "Euler":
                assert s.dt < 2 * s.mass_ratio
            if s.series == "RK4":
                assert s.dt < 2.78 * s.mass_ratio
        assert A.Setting("reduced", "numba-DOP853", rtol=1e-9) in A.reduced_grid(quick)


def test_every_size_of_the_study_is_within_the_full_one():
    """The quick and tiny sizes' cases and reduced settings are among the full size's, so running the full size's
    (the test below) runs each of theirs."""
    cases, grid = A.paper_cases("full"), A.reduced_grid("full")
    for size in A.SIZES:
        assert all(physics in [p for p, _ in cases] for physics, _ in A.paper_cases(size)), size
        assert all(setting in grid for setting in A.reduced_grid(size)), size


@pytest.mark.parametrize("case", range(len(A.paper_cases("full"))))
def test_every_case_of_the_study_takes_every_setting_of_its_grid(case):
    """The study's cases are the ones its grids were made for: each case's reference and every reduced setting run
    (a short span), and each MuJoCo setting is within its stability limit or recorded as refused, never raised."""
    cases = A.paper_cases("full")
    assert cases and {p.scene for p, _ in cases} <= set(A.study_scenes())
    physics, _ = cases[case]
    reference = A.reference_solution(physics, 2.0)
    for setting in A.reduced_grid("full"):
        row = A.run_setting(physics, 2.0, setting, reference, repeats=1)
        assert row["status"] == "ok", (physics, setting, row["message"])


def test_reference_of_a_network_scene_uses_a_method_its_engine_takes():
    from elastoactive.core.registry import get

    physics = get("lattice").validation_cases()[0].physics
    assert A.reference_method(physics) == "DOP853" and A.reference_method(CHAIN) == A.REFERENCE["method"]
    assert A.reference_solution(physics, 0.8).t[-1] == pytest.approx(0.8)

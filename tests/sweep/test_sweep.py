"""`elastoactive sweep`: grid parsing, agreement with run_case, resume, refusal, Dask, MuJoCo batches (its storage and
one-line refusals: test_sweep_trust.py)."""

import json
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr
from sweep_helpers import FAST, REDUCED, VOLATILE, Stop, load  # shared with test_sweep_trust.py

from elastoactive.batch import Case, run_case
from elastoactive.cli import main
from elastoactive.core.params import Numerics, ParameterError, Physics
from elastoactive.sweep import SweepMismatch, normalize_grid, parse_grid, run_point, run_sweep, run_sweep_outcome


def check_against_run_case(ds, scene, fixed, numerics, duration, engine, timestep=True):
    dims = [d for d in ds["status"].dims]
    for index in np.ndindex(*ds["status"].shape):
        point = {d: ds[d].values[i].item() for d, i in zip(dims, index)}
        assert ds["status"].values[index] == "ok", ds["error"].values[index]
        phys = {k: v for k, v in point.items() if k != "seed"}
        num = numerics if "seed" not in point else Numerics(**{**numerics.__dict__, "seed": point["seed"]})
        case = Case(Physics(scene=scene, **fixed, **phys), num, duration, engine)
        expected = run_case(case, timestep=timestep).results.as_dict()
        for name, value in expected.items():
            if name == "notes":  # text: one string per point
                assert ds["notes"].values[index] == "; ".join(value), point
                continue
            np.testing.assert_array_equal(
                ds[name].values[index], np.asarray(value, dtype=float), err_msg=f"{name} at {point}"
            )


def test_parse_grid():
    grid = parse_grid(["sigma=0.2:1.0:5", "kappa=0.5,1,2", "n=3:7:3", "drag-ratio=2", "seed=0,1"])
    assert list(grid) == ["sigma", "kappa", "n", "drag_ratio", "seed"]
    np.testing.assert_array_equal(grid["sigma"], np.linspace(0.2, 1.0, 5))
    np.testing.assert_array_equal(grid["kappa"], [0.5, 1.0, 2.0])
    assert grid["n"].dtype.kind == "i" and grid["n"].tolist() == [3, 5, 7]
    assert grid["drag_ratio"].tolist() == [2.0] and grid["seed"].dtype.kind == "i"
    assert normalize_grid({"sigma": "0:1:3", "n": [5, 7.0]})["n"].tolist() == [5, 7]
    for bad in (
        ["sigma"],
        ["sigma=1:2"],
        ["sigma=0:1:0"],
        ["sigma=0:1:2.5"],
        ["sigma=a,b"],
        ["sigma=1,,2"],
        ["sigma=1,1"],
        ["n=2.5"],
        ["nan=1"],
        ["scene=1"],
        ["sigma=1", "sigma=2"],
        ["sigma=inf"],
        [],
    ):
        with pytest.raises(ParameterError):
            parse_grid(bad)


def test_reduced_sweep_matches_run_case(tmp_path):
    out = tmp_path / "r.nc"
    ds = run_sweep(
        "one-pinned",
        {"sigma": [0.3, 0.8], "n": [3, 4]},
        numerics=FAST,
        duration=40,
        engine="reduced",
        out=out,
        workers=2,
        progress=False,
    )
    assert dict(ds.sizes) == {"sigma": 2, "n": 2, "harmonic": 5}  # harmonics: one value per harmonic
    check_against_run_case(ds, "one-pinned", {}, FAST, 40, "reduced")
    disk = load(out)
    xr.testing.assert_identical(disk, ds)
    assert disk.attrs["scene"] == "one-pinned" and disk.attrs["engine"] == "reduced" and disk.attrs["duration"] == 40
    assert disk.attrs["complete"] == 1 and disk.attrs["fixed_drag_ratio"] == 1.0 and disk.attrs["numerics_dt"] == 0.01
    assert "package_version" in disk.attrs and not (tmp_path / "r.nc.journal").exists()


@pytest.mark.parametrize(
    "scene, grid, fixed",
    [
        ("coupled-pair", {"kappa": [0.5, 2.0]}, {"n": 3}),
        ("two-pinned", {"n": [3, 4], "seed": [1]}, {"sigma": 2.0}),
        ("rotating-pin", {"sigma": [0.5, 1.0]}, {"n": 2}),
    ],
)
def test_mujoco_sweep_matches_run_case(tmp_path, scene, grid, fixed):
    ds = run_sweep(
        scene, grid, fixed=fixed, numerics=FAST, duration=20, out=tmp_path / "m.nc", workers=1, progress=False
    )
    check_against_run_case(ds, scene, fixed, FAST, 20, "mujoco")
    if scene == "coupled-pair":
        assert ds["amplitude"].dims == ("kappa", "chain") and ds["frequency_mismatch"].dims == ("kappa",)
    if scene == "two-pinned":
        assert np.isfinite(ds["snap_amplitude"]).all()
        assert (ds["constraint_violation"] < 0.05).all()
    if scene == "rotating-pin":
        assert "rotation_rate" in ds


def test_resume_continues_without_recomputing(tmp_path):
    kw = dict(fixed={"n": 3}, numerics=FAST, duration=30, engine="reduced", progress=False, snapshot_interval=0)
    grid = {"sigma": [0.2, 0.5, 0.8], "seed": [0, 1]}
    whole = run_sweep("one-pinned", grid, out=tmp_path / "whole.nc", workers=1, **kw)

    out = tmp_path / "part.nc"
    seen = []

    def interrupt(coords, record):
        seen.append(coords)
        if len(seen) == 2:
            raise Stop

    with pytest.raises(Stop):
        run_sweep("one-pinned", grid, out=out, workers=2, on_point=interrupt, **kw)
    journal = tmp_path / "part.nc.journal"
    assert journal.exists()
    part = load(out)
    done = part["status"].values != "pending"
    assert done.sum() == 2 and part.attrs["complete"] == 0
    with open(journal, "a") as f:  # a line torn by a kill
        f.write('{"i": 5, "status": "ok", "resu')

    again = []
    resumed = run_sweep("one-pinned", grid, out=out, workers=1, on_point=lambda c, r: again.append(c), **kw)
    assert len(again) == 4 and not any(c in seen for c in again)  # only the missing points ran
    np.testing.assert_array_equal(resumed["finished_at"].values[done], part["finished_at"].values[done])
    xr.testing.assert_equal(resumed.drop_vars(VOLATILE), whole.drop_vars(VOLATILE))
    xr.testing.assert_identical(load(out), resumed)
    assert not journal.exists()

    rerun = []  # a finished sweep: nothing runs, nothing changes
    run_sweep("one-pinned", grid, out=out, on_point=lambda c, r: rerun.append(c), **kw)
    assert rerun == []
    xr.testing.assert_identical(load(out), resumed)


def test_resume_after_kill(tmp_path):
    """kill -9 of a running `elastoactive sweep` (2 local workers) loses nothing that was finished,
    leaves no worker holding the file, and re-running continues."""
    out = tmp_path / "k.nc"
    grid = ["--grid", "sigma=0.3:1.0:4", "--grid", "n=5,7"]
    args = [
        sys.executable,
        "-m",
        "elastoactive",
        "sweep",
        "one-pinned",
        *grid,
        "--duration",
        "150",
        "--out",
        str(out),
        "--workers",
        "2",
        "--quiet",
    ]
    journal = tmp_path / "k.nc.journal"
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and proc.poll() is None:
            if journal.exists() and journal.read_text().count("\n") >= 3:  # header + 2 points
                break
            time.sleep(0.05)
    finally:
        proc.kill()
        proc.wait()
    finished = {json.loads(line)["i"]: json.loads(line) for line in journal.read_text().splitlines()[1:]}
    assert len(finished) >= 2
    new = []
    ds = run_sweep(
        "one-pinned",
        parse_grid([g for g in grid if g != "--grid"]),
        duration=150,
        out=out,
        workers=1,
        progress=False,
        on_point=lambda c, r: new.append(c),
    )
    assert len(new) == 8 - len(finished) and (ds["status"] == "ok").all()
    times = ds["finished_at"].values.reshape(-1)
    for i, entry in finished.items():
        assert times[i] == np.datetime64(int(round(entry["finished_at"] * 1e9)), "ns")


def test_changed_sweep_is_refused(tmp_path):
    kw = dict(numerics=FAST, duration=20, engine="reduced", progress=False, workers=1)
    out = tmp_path / "s.nc"
    run_sweep("one-pinned", {"sigma": [0.3, 0.6]}, fixed={"n": 3}, out=out, **kw)
    before = out.read_bytes()
    for scene, grid, fixed, extra in [
        ("one-pinned", {"sigma": [0.3, 0.7]}, {"n": 3}, {}),
        ("one-pinned", {"sigma": [0.3, 0.6]}, {"n": 4}, {}),
        ("one-pinned", {"sigma": [0.3, 0.6], "seed": [0]}, {"n": 3}, {}),
        ("one-pinned", {"sigma": [0.3, 0.6]}, {"n": 3}, {"duration": 21}),
        ("one-pinned", {"sigma": [0.3, 0.6]}, {"n": 3}, {"engine": "mujoco"}),
        ("rotating-pin", {"sigma": [0.3, 0.6]}, {"n": 3}, {}),
    ]:
        with pytest.raises(SweepMismatch, match="holds a different sweep"):
            run_sweep(scene, grid, fixed=fixed, out=out, **{**kw, **extra})
    assert out.read_bytes() == before
    other = tmp_path / "other.nc"
    other.write_text("not a sweep")
    with pytest.raises(SweepMismatch, match="refusing to overwrite"):
        run_sweep("one-pinned", {"sigma": [0.3]}, out=other, **kw)
    with pytest.raises(ParameterError, match="both"):
        run_sweep("one-pinned", {"sigma": [0.3]}, fixed={"sigma": 1.0}, **kw)
    with pytest.raises(ParameterError, match="no effect"):
        run_sweep("one-pinned", {"kappa": [0.3]}, **kw)


def test_diverged_point_is_recorded_and_sweep_goes_on(tmp_path):
    # Euler treats the drag explicitly: stable for dt < 2 m / gamma = 0.02 at mass_ratio 0.01
    num = Numerics(integrator="Euler", mass_ratio=1e-2, dt=0.01, sample_dt=0.05)
    ds = run_sweep(
        "one-pinned",
        {"dt": [0.01, 0.05]},
        fixed={"n": 3},
        numerics=num,
        duration=5,
        out=tmp_path / "d.nc",
        workers=1,
        progress=False,
        timestep_check=False,
    )
    assert ds["status"].values.tolist() == ["ok", "error"]
    assert "diverged" in ds["error"].values[1] and ds["error"].values[0] == ""
    assert np.isfinite(ds["amplitude"].values[0]) and np.isnan(ds["amplitude"].values[1])
    checked = run_sweep(
        "one-pinned", {"dt": [0.01, 0.05]}, fixed={"n": 3}, numerics=num, duration=5, workers=1, progress=False
    )
    assert "stability limit" in checked["error"].values[1]


def test_dask_local_cluster(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    grid = {"kappa": [0.5, 1.5], "sigma": [0.6, 1.0]}
    kw = dict(fixed={"n": 3}, numerics=FAST, duration=20, progress=False)
    local = run_sweep("coupled-pair", grid, workers=1, **kw)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = run_sweep("coupled-pair", grid, scheduler=cluster.scheduler_address, out=tmp_path / "d.nc", **kw)
    xr.testing.assert_equal(remote.drop_vars(VOLATILE), local.drop_vars(VOLATILE))
    assert (remote["status"] == "ok").all()


def test_cli(tmp_path, capsys):
    out = tmp_path / "c.nc"
    args = [
        "sweep",
        "one-pinned",
        "--grid",
        "sigma=0.3:0.9:3",
        "--n",
        "3",
        "--engine",
        "reduced",
        "--preset",
        "fast",
        "--duration",
        "20",
        "--out",
        str(out),
        "--workers",
        "1",
        "--quiet",
    ]
    assert main(args) == 0
    assert "3 of 3 points" in capsys.readouterr().out
    ds = load(out)
    assert ds.attrs["fixed_n"] == 3 and ds.attrs["numerics_dt"] == 0.01
    assert json.loads(ds.attrs["sweep_spec"])["grid"] == [["sigma", np.linspace(0.3, 0.9, 3).tolist()]]
    assert main(args) == 0  # resumes a finished sweep: nothing to do
    assert main(args[:4] + ["--sigma", "1"] + args[4:]) == 2
    assert main([a.replace("0.3:0.9:3", "0.3:0.9:4") for a in args]) == 2
    assert "holds a different sweep" in capsys.readouterr().err


def test_sweep_outcome_is_what_the_dataset_says(tmp_path):
    """run_sweep_outcome (the command line's path, no xarray Dataset) runs the same points and writes the same
    file as run_sweep; its status, errors and counts are the Dataset's."""
    kw = dict(fixed={"n": 3}, numerics=FAST, duration=5, progress=False, workers=2)
    grid = {"sigma": [0.3, 0.8], "dt": [0.01, 0.05]}  # dt 0.05 is refused by the pre-flight check
    ds = run_sweep("one-pinned", grid, out=tmp_path / "d.nc", **kw)
    outcome = run_sweep_outcome("one-pinned", grid, out=tmp_path / "o.nc", **kw)
    np.testing.assert_array_equal(outcome.status, ds["status"].values.reshape(-1))
    np.testing.assert_array_equal(outcome.error, ds["error"].values.reshape(-1))
    assert (outcome.points_done, outcome.points_total) == (ds.attrs["points_done"], ds.attrs["points_total"]) == (4, 4)
    assert set(outcome.status) == {"ok", "error"}
    written = load(tmp_path / "o.nc")
    xr.testing.assert_equal(written.drop_vars(VOLATILE), ds.drop_vars(VOLATILE))
    assert {k: str(v) for k, v in written.attrs.items()} == {k: str(v) for k, v in ds.attrs.items()}


# ----------------------------------------------------------------------------- MuJoCo sweeps on mujoco.batch


def test_mujoco_sweep_resumed_after_an_interruption_gives_the_same_dataset(tmp_path):
    """Points run in batches (here 2 per batch on 2 threads, noise with different seeds): an interrupted
    sweep keeps what was journaled, the resume runs only the rest, and the dataset equals the
    uninterrupted sweep's, which equals run_case point by point."""
    grid = {"sigma": [0.3, 0.8, 1.5], "seed": [0, 1]}
    kw = dict(
        fixed={"n": 4, "noise": 0.05},
        numerics=FAST,
        duration=20,
        progress=False,
        snapshot_interval=0,
        workers=2,
        batch_size=2,
    )
    whole = run_sweep("one-pinned", grid, out=tmp_path / "whole.nc", **kw)
    check_against_run_case(whole, "one-pinned", {"n": 4, "noise": 0.05}, FAST, 20, "mujoco")

    out = tmp_path / "part.nc"
    seen = []

    def interrupt(coords, record):
        seen.append(coords)
        if len(seen) == 3:
            raise Stop

    with pytest.raises(Stop):
        run_sweep("one-pinned", grid, out=out, on_point=interrupt, **kw)
    part = load(out)
    done = int((part["status"].values != "pending").sum())  # the batches that ended: 2 points each
    assert done >= 3 and part.attrs["complete"] == int(done == 6)
    again = []
    resumed = run_sweep("one-pinned", grid, out=out, on_point=lambda c, r: again.append(c), **kw)
    assert len(again) == 6 - done and not any(c in seen for c in again)
    xr.testing.assert_equal(resumed.drop_vars(VOLATILE), whole.drop_vars(VOLATILE))
    xr.testing.assert_identical(load(out), resumed)
    assert not (tmp_path / "part.nc.journal").exists()


def test_a_diverging_point_of_a_batch_is_its_error_and_the_others_finish(tmp_path):
    # one model (Euler, n = 3) for every sigma: sigma = 100 blows up at dt = 0.01, the others do not
    num = Numerics(integrator="Euler", mass_ratio=1e-2, dt=0.01, sample_dt=0.05)
    ds = run_sweep(
        "one-pinned",
        {"sigma": [0.5, 100.0, 50.0]},
        fixed={"n": 3},
        numerics=num,
        duration=10,
        out=tmp_path / "d.nc",
        workers=2,
        progress=False,
        timestep_check=False,
    )
    assert ds["status"].values.tolist() == ["ok", "error", "ok"]
    assert "SimulationDiverged" in ds["error"].values[1] and "diverged by t = 5 tau" in ds["error"].values[1]
    assert np.isfinite(ds["amplitude"].values[[0, 2]]).all() and np.isnan(ds["amplitude"].values[1])
    expected = run_case(Case(Physics(n=3, sigma=50.0), num, 10), timestep=False).results
    assert ds["amplitude"].values[2] == expected.amplitude


def test_preflight_check_once_per_distinct_model(tmp_path, monkeypatch):
    from elastoactive.engines import timestep as diagnose

    calls = []
    original = diagnose.check_timestep

    def counted(physics, numerics, *args, **kwargs):
        if kwargs.get("suggest", True):  # not the checks of the setting a refusal suggests (suggest=False)
            calls.append((physics.sigma, numerics.seed))
        return original(physics, numerics, *args, **kwargs)

    monkeypatch.setattr(diagnose, "check_timestep", counted)
    # sigma = 5 at N = 5: dt = 0.01 does not resolve the fastest rate; refused while its batch runs
    ds = run_sweep(
        "one-pinned",
        {"sigma": [0.3, 0.8, 5.0], "seed": [0, 1, 2]},
        fixed={"n": 5},
        numerics=FAST,
        duration=10,
        workers=2,
        progress=False,
    )
    assert sorted(calls) == [(0.3, 0), (0.8, 0), (5.0, 0)]  # the seed changes nothing it checks (no noise)
    assert (ds["status"].values[:2] == "ok").all() and (ds["status"].values[2] == "error").all()
    refused = run_point(Case(Physics(n=5, sigma=5.0), FAST, 10))
    assert refused["status"] == "error" and "does not resolve" in refused["error"]
    assert (ds["error"].values[2] == refused["error"]).all() and np.isnan(ds["amplitude"].values[2]).all()


def test_periodicity_and_notes_are_stored(tmp_path):
    """Every scene's sweep stores periodic (1 / 0 / NaN), period_spread (per chain for the pair) and the
    notes of each point (text, '; '-joined), as run_case measures them, with attributes saying what
    they are."""
    out = tmp_path / "p.nc"
    grid = {"sigma": [0.5, 4.0], "noise": [0.0, 0.3]}
    ds = run_sweep(
        "one-pinned",
        grid,
        fixed={"n": 3},
        numerics=FAST,
        duration=60,
        out=out,
        workers=2,
        progress=False,
        timestep_check=False,
    )
    check_against_run_case(ds, "one-pinned", {"n": 3}, FAST, 60, "mujoco", timestep=False)
    disk = load(out)
    xr.testing.assert_identical(disk, ds)
    assert disk["periodic"].dims == ("sigma", "noise") and disk["period_spread"].dims == ("sigma", "noise")
    periodic = disk["periodic"].values
    assert periodic[0, 0] == 1 and periodic[1, 1] == 0  # at rest; an irregular, noisy beat
    assert np.isin(periodic[~np.isnan(periodic)], [0, 1]).all()
    notes = disk["notes"].values
    assert notes[0, 0] == "" and "not periodic" in notes[1, 1]
    attrs = disk["periodic"].attrs
    assert list(attrs["flag_values"]) == [1, 0] and attrs["flag_meanings"] == "periodic irregular"
    assert "NaN" in attrs["comment"] and "notes" in disk["notes"].attrs["long_name"]
    assert "periodic" in disk.attrs["measurements"]

    pair = run_sweep(
        "coupled-pair",
        {"noise": [0.0, 0.3]},
        fixed={"n": 3, "sigma": 4.0, "kappa": 0.5},
        numerics=FAST,
        duration=40,
        out=tmp_path / "pair.nc",
        workers=1,
        progress=False,
        timestep_check=False,
    )
    check_against_run_case(
        pair, "coupled-pair", {"n": 3, "sigma": 4.0, "kappa": 0.5}, FAST, 40, "mujoco", timestep=False
    )
    assert pair["period_spread"].dims == ("noise", "chain") and pair["periodic"].dims == ("noise",)
    assert pair["periodic"].values[1] == 0 and pair["notes"].values[1].count("chain ") == 2
    for scene in ("two-pinned", "rotating-pin"):  # present before any point is done
        ds = run_sweep(scene, {"sigma": [0.5]}, fixed={"n": 3}, numerics=FAST, duration=10, workers=1, progress=False)
        assert {"periodic", "period_spread", "notes"} <= set(ds.data_vars)


def test_journal_lines_with_bad_periodic_or_notes_are_run_again(tmp_path):
    grid = {"sigma": [0.2, 0.5, 0.8]}
    kw = {**REDUCED, "snapshot_interval": 1e9}
    out, journal = tmp_path / "q.nc", tmp_path / "q.nc.journal"

    def stop(coords, record):
        if coords["sigma"] == 0.8:
            raise Stop

    with pytest.raises(Stop):
        run_sweep("one-pinned", grid, out=out, on_point=stop, **kw)
    reference = load(out)
    out.unlink()
    header, *lines = journal.read_text().splitlines()
    entries = {e["i"]: e for e in map(json.loads, lines)}
    assert sorted(entries) == [0, 1, 2] and all(isinstance(e["notes"], str) for e in entries.values())
    entries[1]["results"]["periodic"] = 0.5
    entries[2]["notes"] = 3
    journal.write_text("\n".join([header, *(json.dumps(entries[i]) for i in range(3))]) + "\n")
    again = []
    with pytest.warns(UserWarning, match="discarded 2 journal line"):
        resumed = run_sweep("one-pinned", grid, out=out, on_point=lambda c, r: again.append(c["sigma"]), **kw)
    assert sorted(again) == [0.5, 0.8]
    xr.testing.assert_equal(resumed.drop_vars(VOLATILE), reference.drop_vars(VOLATILE))


def test_a_failing_batch_is_its_points_errors(tmp_path, monkeypatch):
    """Should a whole batch fail (not one simulation), its points are errors and the other batches go on."""
    from elastoactive.engines import mujoco_batch

    original = mujoco_batch.run_batch

    def fragile(sims, *args, **kwargs):
        if sims[0].run.physics.n == 4:
            raise RuntimeError("batch lost")
        return original(sims, *args, **kwargs)

    monkeypatch.setattr(mujoco_batch, "run_batch", fragile)
    ds = run_sweep(
        "one-pinned", {"n": [3, 4], "sigma": [0.5, 0.9]}, numerics=FAST, duration=10, workers=2, progress=False
    )
    assert ds["status"].values.tolist() == [["ok", "ok"], ["error", "error"]]
    assert (ds["error"].values[1] == "RuntimeError: batch lost").all()


def test_batch_size_must_be_at_least_one(tmp_path, capsys):
    with pytest.raises(ParameterError, match="batch_size must be"):
        run_sweep("one-pinned", {"sigma": [0.3]}, batch_size=0, progress=False)
    args = [
        "sweep",
        "one-pinned",
        "--grid",
        "sigma=0.3",
        "--out",
        str(tmp_path / "b.nc"),
        "--batch-size",
        "0",
        "--quiet",
    ]
    assert main(args) == 2 and "--batch-size must be >= 1" in capsys.readouterr().err
    assert not (tmp_path / "b.nc").exists()


def test_netcdf_writer_matches_xarrays(tmp_path):
    """outputs.write_netcdf (h5netcdf, without xarray's writer and its dask imports) writes what xarray's own
    to_netcdf writes, as xarray.open_dataset reads it back: floats with NaN, integers, text, times with NaT, a
    per-chain dimension, numpy and plain attributes."""
    from elastoactive.io.outputs import write_netcdf

    status = np.array([["ok", "error", "pending"], ["ok", "", "ok"]], dtype=object)
    finished = np.array(
        [["2026-11-22T17:56:44.8378", "NaT", "2026-01-01"], ["NaT", "NaT", "1970-01-01"]], dtype="datetime64[ns]"
    )
    amplitude = np.arange(12.0).reshape(2, 3, 2)
    amplitude[0, 1] = np.nan
    variables = {
        "amplitude": (("sigma", "n", "chain"), amplitude, {"units": "rad", "long_name": "amplitude"}),
        "periodic": (
            ("sigma", "n"),
            np.array([[1.0, 0.0, np.nan], [np.nan, 1.0, 0.0]]),
            {"flag_values": np.array([1.0, 0.0]), "flag_meanings": "periodic irregular"},
        ),
        "status": (("sigma", "n"), status, {"long_name": "status"}),
        "finished_at": (("sigma", "n"), finished, {"long_name": "when"}),
    }
    coords = {
        "sigma": (("sigma",), np.array([0.3, 1.0]), {"long_name": "sigma"}),
        "n": (("n",), np.array([5, 7, 9], dtype=np.int64), {"long_name": "N"}),
        "chain": (("chain",), np.arange(1, 3), {"long_name": "chain"}),
    }
    attrs = {
        "title": "t",
        "duration": 40.0,
        "points_total": 6,
        "complete": 0,
        "numerics_integrator": Numerics().integrator,
        "numerics_dt": Numerics().dt,
    }
    mine, theirs = tmp_path / "mine.nc", tmp_path / "xarray.nc"
    write_netcdf(mine, variables, coords, attrs)
    xr.Dataset(
        {k: (d, v, a) for k, (d, v, a) in variables.items()},
        coords={k: (d, v, a) for k, (d, v, a) in coords.items()},
        attrs={
            k: (str(v) if isinstance(v, str) else float(v) if isinstance(v, float) else v) for k, v in attrs.items()
        },
    ).to_netcdf(theirs, engine="h5netcdf")
    a, b = load(mine), load(theirs)
    xr.testing.assert_identical(a, b)
    assert a["finished_at"].dtype == np.dtype("datetime64[ns]") and np.isnat(a["finished_at"].values[0, 1])
    assert type(a.attrs["numerics_integrator"]) is str and a.attrs["numerics_dt"] == 0.0025
    with xr.open_dataset(mine) as default_engine:  # a valid netCDF-4 file for xarray's default engine too
        assert set(default_engine.data_vars) == set(variables)


def test_long_chain_sweep_says_its_numerics_are_automatic(tmp_path):
    ds = run_sweep(
        "one-pinned", {"sigma": [0.05]}, fixed={"n": 30}, duration=2, out=tmp_path / "l.nc", progress=False, workers=1
    )
    assert (ds["status"] == "ok").all() and "automatic long-chain numerics" in ds.attrs["numerics_automatic"]
    short = run_sweep("one-pinned", {"sigma": [0.8]}, duration=2, progress=False, workers=1)
    assert "numerics_automatic" not in short.attrs

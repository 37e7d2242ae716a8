"""`elastoactive sweep`: grid parsing, agreement with run_case, resume, refusal, Dask."""

import json
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr

from elastoactive.batch import Case, run_case
from elastoactive.cli import main
from elastoactive.params import Numerics, ParameterError, Physics
from elastoactive.sweep import SweepMismatch, normalize_grid, parse_grid, run_sweep

FAST = Numerics.preset("fast")
VOLATILE = ["wall_time_s", "finished_at"]


def load(path):
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


def check_against_run_case(ds, scene, fixed, numerics, duration, engine):
    dims = [d for d in ds["status"].dims]
    for index in np.ndindex(*ds["status"].shape):
        point = {d: ds[d].values[i].item() for d, i in zip(dims, index)}
        assert ds["status"].values[index] == "ok", ds["error"].values[index]
        phys = {k: v for k, v in point.items() if k != "seed"}
        num = numerics if "seed" not in point else Numerics(**{**numerics.__dict__, "seed": point["seed"]})
        expected = run_case(Case(Physics(scene=scene, **fixed, **phys), num, duration, engine))["results"]
        for name, value in expected.items():
            np.testing.assert_array_equal(ds[name].values[index], np.asarray(value, dtype=float), err_msg=f"{name} at {point}")


def test_parse_grid():
    grid = parse_grid(["sigma=0.2:1.0:5", "kappa=0.5,1,2", "n=3:7:3", "drag-ratio=2", "seed=0,1"])
    assert list(grid) == ["sigma", "kappa", "n", "drag_ratio", "seed"]
    np.testing.assert_array_equal(grid["sigma"], np.linspace(0.2, 1.0, 5))
    np.testing.assert_array_equal(grid["kappa"], [0.5, 1.0, 2.0])
    assert grid["n"].dtype.kind == "i" and grid["n"].tolist() == [3, 5, 7]
    assert grid["drag_ratio"].tolist() == [2.0] and grid["seed"].dtype.kind == "i"
    assert normalize_grid({"sigma": "0:1:3", "n": [5, 7.0]})["n"].tolist() == [5, 7]
    for bad in (["sigma"], ["sigma=1:2"], ["sigma=0:1:0"], ["sigma=0:1:2.5"], ["sigma=a,b"], ["sigma=1,,2"],
                ["sigma=1,1"], ["n=2.5"], ["nan=1"], ["scene=1"], ["sigma=1", "sigma=2"], ["sigma=inf"], []):
        with pytest.raises(ParameterError):
            parse_grid(bad)


def test_reduced_sweep_matches_run_case(tmp_path):
    out = tmp_path / "r.nc"
    ds = run_sweep("one-pinned", {"sigma": [0.3, 0.8], "n": [3, 4]}, numerics=FAST, duration=40, engine="reduced",
                   out=out, workers=2, progress=False)
    assert dict(ds.sizes) == {"sigma": 2, "n": 2}
    check_against_run_case(ds, "one-pinned", {}, FAST, 40, "reduced")
    disk = load(out)
    xr.testing.assert_identical(disk, ds)
    assert disk.attrs["scene"] == "one-pinned" and disk.attrs["engine"] == "reduced" and disk.attrs["duration"] == 40
    assert disk.attrs["complete"] == 1 and disk.attrs["fixed_drag_ratio"] == 1.0 and disk.attrs["numerics_dt"] == 0.01
    assert "package_version" in disk.attrs and not (tmp_path / "r.nc.journal").exists()


@pytest.mark.parametrize("scene, grid, fixed", [
    ("coupled-pair", {"kappa": [0.5, 2.0]}, {"n": 3}),
    ("two-pinned", {"n": [3, 4], "seed": [1]}, {"sigma": 2.0}),
    ("rotating-pin", {"sigma": [0.5, 1.0]}, {"n": 2}),
])
def test_mujoco_sweep_matches_run_case(tmp_path, scene, grid, fixed):
    ds = run_sweep(scene, grid, fixed=fixed, numerics=FAST, duration=20, out=tmp_path / "m.nc", workers=1,
                   progress=False)
    check_against_run_case(ds, scene, fixed, FAST, 20, "mujoco")
    if scene == "coupled-pair":
        assert ds["amplitude"].dims == ("kappa", "chain") and ds["frequency_mismatch"].dims == ("kappa",)
    if scene == "two-pinned":
        assert np.isfinite(ds["snap_amplitude"]).all()
        assert (ds["constraint_violation"] < 0.05).all()
    if scene == "rotating-pin":
        assert "rotation_rate" in ds


class Stop(Exception):
    pass


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
    args = [sys.executable, "-m", "elastoactive.cli", "sweep", "one-pinned", *grid, "--duration", "150",
            "--out", str(out), "--workers", "2", "--quiet"]
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
    ds = run_sweep("one-pinned", parse_grid([g for g in grid if g != "--grid"]), duration=150, out=out, workers=1,
                   progress=False, on_point=lambda c, r: new.append(c))
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
    ds = run_sweep("one-pinned", {"dt": [0.01, 0.05]}, fixed={"n": 3}, numerics=num, duration=5,
                   out=tmp_path / "d.nc", workers=1, progress=False, timestep_check=False)
    assert ds["status"].values.tolist() == ["ok", "error"]
    assert "diverged" in ds["error"].values[1] and ds["error"].values[0] == ""
    assert np.isfinite(ds["amplitude"].values[0]) and np.isnan(ds["amplitude"].values[1])
    checked = run_sweep("one-pinned", {"dt": [0.01, 0.05]}, fixed={"n": 3}, numerics=num, duration=5,
                        workers=1, progress=False)
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
    args = ["sweep", "one-pinned", "--grid", "sigma=0.3:0.9:3", "--n", "3", "--engine", "reduced", "--preset", "fast",
            "--duration", "20", "--out", str(out), "--workers", "1", "--quiet"]
    assert main(args) == 0
    assert "3 of 3 points" in capsys.readouterr().out
    ds = load(out)
    assert ds.attrs["fixed_n"] == 3 and ds.attrs["numerics_dt"] == 0.01
    assert json.loads(ds.attrs["sweep_spec"])["grid"] == [["sigma", np.linspace(0.3, 0.9, 3).tolist()]]
    assert main(args) == 0  # resumes a finished sweep: nothing to do
    assert main(args[:4] + ["--sigma", "1"] + args[4:]) == 2
    assert main([a.replace("0.3:0.9:3", "0.3:0.9:4") for a in args]) == 2
    assert "holds a different sweep" in capsys.readouterr().err

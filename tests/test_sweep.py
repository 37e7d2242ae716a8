"""`elastoactive sweep`: grid parsing, agreement with run_case, resume, refusal, Dask."""

import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

from elastoactive.batch import Case, run_case
from elastoactive.cli import main
from elastoactive.params import Numerics, ParameterError, Physics
from elastoactive import sweep as sweep_module
from elastoactive import sweep_netcdf
from elastoactive.sweep import SweepMismatch, make_sweep, normalize_grid, parse_grid, run_point, run_sweep

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
        expected = run_case(Case(Physics(scene=scene, **fixed, **phys), num, duration, engine)).results.as_dict()
        for name, value in expected.items():
            if name == "notes":  # text: one string per point
                assert ds["notes"].values[index] == "; ".join(value), point
                continue
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
    assert dict(ds.sizes) == {"sigma": 2, "n": 2, "harmonic": 5}  # harmonics: one value per harmonic
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
    args = [sys.executable, "-m", "elastoactive", "sweep", "one-pinned", *grid, "--duration", "150",
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


def test_sweep_outcome_is_what_the_dataset_says(tmp_path):
    """run_sweep_outcome (the command line's path, no xarray Dataset) runs the same points and writes the same
    file as run_sweep; its status, errors and counts are the Dataset's."""
    kw = dict(fixed={"n": 3}, numerics=FAST, duration=5, progress=False, workers=2)
    grid = {"sigma": [0.3, 0.8], "dt": [0.01, 0.05]}  # dt 0.05 is refused by the pre-flight check
    ds = run_sweep("one-pinned", grid, out=tmp_path / "d.nc", **kw)
    outcome = sweep_module.run_sweep_outcome("one-pinned", grid, out=tmp_path / "o.nc", **kw)
    np.testing.assert_array_equal(outcome.status, ds["status"].values.reshape(-1))
    np.testing.assert_array_equal(outcome.error, ds["error"].values.reshape(-1))
    assert (outcome.points_done, outcome.points_total) == (ds.attrs["points_done"], ds.attrs["points_total"]) == (4, 4)
    assert set(outcome.status) == {"ok", "error"}
    written = load(tmp_path / "o.nc")
    xr.testing.assert_equal(written.drop_vars(VOLATILE), ds.drop_vars(VOLATILE))
    assert {k: str(v) for k, v in written.attrs.items()} == {k: str(v) for k, v in ds.attrs.items()}


# ----------------------------------------------------------------------------- "Trustworthy runs"

REDUCED = dict(fixed={"n": 3}, numerics=FAST, duration=20, engine="reduced", progress=False, workers=1)


@pytest.mark.parametrize("how", ["signal", "exception"])
def test_ctrl_c_during_final_save_loses_nothing(tmp_path, monkeypatch, how):
    """Item 1: a Ctrl-C during the final save, and a second one during the save on the way out,
    neither delete the journal before the netCDF is on disk; re-running resumes."""
    grid = {"sigma": [0.3, 0.6, 0.9]}
    out, journal = tmp_path / "i.nc", tmp_path / "i.nc.journal"
    original = sweep_netcdf.write_netcdf  # every netCDF the sweep writes goes through it
    calls = []

    def interrupted(path, *args, **kwargs):
        calls.append(path)
        if len(calls) <= 2:
            if how == "signal":  # a real SIGINT (Ctrl-C) arriving as the write starts
                signal.raise_signal(signal.SIGINT)
            else:  # an interrupt that cannot be deferred
                raise KeyboardInterrupt
        return original(path, *args, **kwargs)

    monkeypatch.setattr(sweep_netcdf, "write_netcdf", interrupted)
    with pytest.raises(KeyboardInterrupt):
        run_sweep("one-pinned", grid, out=out, snapshot_interval=1e9, **REDUCED)
    monkeypatch.undo()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
    if how == "signal":  # deferred: the save completed, then the interrupt came
        assert len(calls) == 1 and load(out).attrs["complete"] == 1 and not journal.exists()
    else:  # no netCDF could be written: the journal keeps every point
        assert not out.exists() and len(journal.read_text().splitlines()) == 1 + 3
    again = []
    ds = run_sweep("one-pinned", grid, out=out, on_point=lambda c, r: again.append(c), **REDUCED)
    assert again == [] and (ds["status"] == "ok").all() and not journal.exists()
    xr.testing.assert_identical(load(out), ds)


@pytest.mark.skipif(not Path("/proc/self/fd").is_dir(), reason="needs /proc to name fsync'ed files")
def test_journal_goes_only_after_the_netcdf_is_durable(tmp_path, monkeypatch):
    """Item 1: the final netCDF is written to a temporary file, fsync'ed, renamed over `out` and the
    directory fsync'ed, all while the journal is still there; only then is the journal removed."""
    out, journal = tmp_path / "o.nc", tmp_path / "o.nc.journal"
    real_fsync, real_replace = os.fsync, os.replace
    events = []

    def fsync(fd):
        real_fsync(fd)
        events.append(("fsync", os.path.realpath(os.readlink(f"/proc/self/fd/{fd}")), journal.exists()))

    def replace(src, dst):
        real_replace(src, dst)
        events.append(("replace", os.path.realpath(dst), journal.exists()))

    monkeypatch.setattr(os, "fsync", fsync)
    monkeypatch.setattr(os, "replace", replace)
    run_sweep("one-pinned", {"sigma": [0.3, 0.6]}, out=out, snapshot_interval=1e9, **REDUCED)
    monkeypatch.undo()
    final = max(k for k, e in enumerate(events) if e[:2] == ("replace", os.path.realpath(out)))
    assert events[final - 1][0] == "fsync" and ".o.nc.tmp" in events[final - 1][1]  # the new file's data
    assert events[final + 1][:2] == ("fsync", os.path.realpath(tmp_path))  # the rename
    assert all(journal_there for *_, journal_there in events[: final + 2])
    assert not journal.exists() and load(out).attrs["complete"] == 1


def test_invalid_journal_lines_are_run_again(tmp_path):
    """Item 2: journal lines that are well-formed JSON but wrong (types, shapes, missing fields,
    non-finite values, unknown status, index or coordinates off the grid) are discarded with a
    warning and their points run again; valid lines are kept."""
    grid = {"sigma": [0.2, 0.5, 0.8], "seed": [0, 1, 2]}
    kw = {**REDUCED, "duration": 30, "snapshot_interval": 1e9}
    out, journal = tmp_path / "v.nc", tmp_path / "v.nc.journal"
    seen = []

    def stop_at_the_end(coords, record):
        seen.append(coords)
        if len(seen) == 9:
            raise Stop

    with pytest.raises(Stop):
        run_sweep("one-pinned", grid, out=out, on_point=stop_at_the_end, **kw)
    reference = load(out)  # every point, saved on the way out
    out.unlink()  # the journal alone now says what is done
    header, *lines = journal.read_text().splitlines()
    entries = {e["i"]: e for e in map(json.loads, lines)}
    assert sorted(entries) == list(range(9))

    def changed(point, **change):
        entry = json.loads(json.dumps(entries[point]))
        for key, value in change.items():
            if "." in key:
                outer, inner = key.split(".")
                if value is None:
                    del entry[outer][inner]
                else:
                    entry[outer][inner] = value
            else:
                entry[key] = value
        return json.dumps(entry)

    bad = [
        changed(1, **{"results.amplitude": "abc"}),
        changed(2, **{"results.amplitude": [0.1, 0.2]}),
        changed(3, **{"results.frequency": None}),  # missing
        changed(4, status="maybe"),
        changed(5, coords={"sigma": 0.2, "seed": 0}),
        changed(6, **{"results.amplitude": float("nan")}),
        changed(7, wall_time_s="fast"),
        changed(8, i=99),  # off the grid
        changed(8, i="8"),
    ]
    journal.write_text("\n".join([header, json.dumps(entries[0]), *bad, json.dumps(entries[8])]) + "\n")
    again = []
    with pytest.warns(UserWarning, match="discarded 9 journal line"):
        resumed = run_sweep("one-pinned", grid, out=out, on_point=lambda c, r: again.append(c), **kw)
    flat = [dict(zip(grid, (s, d))) for s in grid["sigma"] for d in grid["seed"]]
    assert sorted(flat.index(c) for c in again) == [1, 2, 3, 4, 5, 6, 7]
    assert (resumed["status"] == "ok").all() and not journal.exists()
    xr.testing.assert_equal(resumed.drop_vars(VOLATILE), reference.drop_vars(VOLATILE))


def test_full_disk_is_a_clear_error_and_the_sweep_resumes(tmp_path, monkeypatch):
    """Item 3: too little free space refuses the snapshot before any h5py write; ENOSPC while
    writing becomes the same clear error; the journal stays and the sweep resumes."""
    grid = {"sigma": [0.3, 0.6]}
    out, journal = tmp_path / "f.nc", tmp_path / "f.nc.journal"
    original = sweep_netcdf.write_netcdf
    writes = []

    def counted(path, *args, **kwargs):
        writes.append(path)
        return original(path, *args, **kwargs)

    monkeypatch.setattr(sweep_netcdf, "write_netcdf", counted)
    monkeypatch.setattr(shutil, "disk_usage", lambda path: SimpleNamespace(total=10**12, used=10**12 - 1000, free=1000))
    with pytest.raises(ParameterError, match="not enough free space") as info:
        run_sweep("one-pinned", grid, out=out, **REDUCED)
    message = str(info.value)
    assert str(out) in message and "MB needed" in message and journal.name in message and "resume" in message
    assert writes == [] and not out.exists()  # no h5py write started
    assert len(journal.read_text().splitlines()) == 1 + 2

    monkeypatch.undo()

    def full(path, *args, **kwargs):
        Path(path).write_bytes(b"\x89HDF partly")
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(sweep_netcdf, "write_netcdf", full)
    with pytest.raises(ParameterError, match="no space left") as info:
        run_sweep("one-pinned", grid, out=out, **REDUCED)
    assert str(out) in str(info.value) and "needed" in str(info.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == [journal.name]  # no partial file left
    assert len(journal.read_text().splitlines()) == 1 + 2
    assert main(["sweep", "one-pinned", "--grid", "sigma=0.3,0.6", "--n", "3", "--engine", "reduced", "--preset",
                 "fast", "--duration", "20", "--out", str(out), "--workers", "1", "--quiet"]) == 2

    monkeypatch.undo()  # space freed: the sweep resumes without running anything again
    again = []
    ds = run_sweep("one-pinned", grid, out=out, on_point=lambda c, r: again.append(c), **REDUCED)
    assert again == [] and (ds["status"] == "ok").all() and not journal.exists()
    xr.testing.assert_identical(load(out), ds)


def test_exit_status_when_points_fail(tmp_path, capsys):
    """Item 4: every point failed: exit 1 with the first error; some failed: exit 0, counted."""
    # Euler at mass_ratio 0.01 is stable for dt < 0.02: the timestep check refuses larger steps
    base = ["sweep", "one-pinned", "--n", "3", "--integrator", "Euler", "--mass-ratio", "0.01", "--sample-dt", "0.1",
            "--duration", "5", "--workers", "1", "--quiet"]
    assert main(base + ["--grid", "dt=0.05,0.1", "--out", str(tmp_path / "all.nc")]) == 1
    captured = capsys.readouterr()
    assert "2 failed" in captured.out
    assert "all 2 points of the sweep failed" in captured.err and "stability limit" in captured.err
    assert main(base + ["--grid", "dt=0.01,0.05", "--out", str(tmp_path / "some.nc")]) == 0
    captured = capsys.readouterr()
    assert "2 of 2 points" in captured.out and "1 failed" in captured.out and "stability limit" in captured.err


def test_corrupted_journal_header_names_the_journal(tmp_path, capsys):
    """Item 5: a corrupted journal header is reported as such (not as a bad .nc), naming the
    journal and how to proceed; removing it continues from the netCDF."""
    grid = {"sigma": [0.3, 0.6, 0.9]}
    out, journal = tmp_path / "h.nc", tmp_path / "h.nc.journal"
    seen = []

    def stop(coords, record):
        seen.append(coords)
        raise Stop

    with pytest.raises(Stop):
        run_sweep("one-pinned", grid, out=out, on_point=stop, **REDUCED)
    text = journal.read_text()
    corrupted = "\x00\x00garbage" + text[14:]
    journal.write_text(corrupted)
    with pytest.raises(ParameterError) as info:
        run_sweep("one-pinned", grid, out=out, **REDUCED)
    message = str(info.value)
    assert str(journal) in message and "corrupted" in message and "remove" in message and "restore" in message
    assert journal.read_text() == corrupted  # left as it was
    args = ["sweep", "one-pinned", "--grid", "sigma=0.3,0.6,0.9", "--n", "3", "--engine", "reduced", "--preset", "fast",
            "--duration", "20", "--out", str(out), "--workers", "1", "--quiet"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert journal.name in err and err.count("\n") == 1
    journal.unlink()  # as the message says: continue from the netCDF
    again = []
    ds = run_sweep("one-pinned", grid, out=out, on_point=lambda c, r: again.append(c), **REDUCED)
    assert len(again) == 2 and seen[0] not in again and (ds["status"] == "ok").all()


def test_workers_must_be_at_least_one(tmp_path, capsys):
    """Item 6: --workers 0 / -1 and run_sweep(workers=0 / -1) are refused, naming workers."""
    for workers in (0, -1):
        with pytest.raises(ParameterError, match="workers must be"):
            run_sweep("one-pinned", {"sigma": [0.3]}, **{**REDUCED, "workers": workers})
        args = ["sweep", "one-pinned", "--grid", "sigma=0.3", "--engine", "reduced", "--out", str(tmp_path / "w.nc"),
                "--workers", str(workers), "--quiet"]
        assert main(args) == 2
        err = capsys.readouterr().err
        assert "--workers must be >= 1" in err and err.count("\n") == 1
    assert not (tmp_path / "w.nc").exists() and not (tmp_path / "w.nc.journal").exists()


def test_mujoco_only_numerics_refused_with_reduced_engine(tmp_path, capsys):
    """Item 7: dt axes and --dt / --integrator options change nothing with the reduced engine (dt does when
    noise > 0: the noise step) and are refused. The mass ratio is physics since inertia became part of the
    reduced model (it decides the overdamped or inertial regime), so it may be swept with either engine."""
    kw = dict(duration=20, engine="reduced", progress=False, workers=1)
    with pytest.raises(ParameterError, match="dt only affects the MuJoCo engine"):
        run_sweep("one-pinned", {"dt": [0.01, 0.025]}, **kw)
    make_sweep("one-pinned", {"mass_ratio": [1e-4, 0.5]}, engine="reduced")
    make_sweep("one-pinned", {"dt": [0.01, 0.025]}, fixed={"noise": 0.1}, engine="reduced")  # Euler-Maruyama step
    make_sweep("one-pinned", {"dt": [0.01, 0.025], "noise": [0.0, 0.1]}, engine="reduced")
    make_sweep("one-pinned", {"dt": [0.01, 0.025], "mass_ratio": [1e-4, 1e-3]}, engine="mujoco")
    base = ["sweep", "one-pinned", "--grid", "sigma=0.3", "--engine", "reduced", "--out", str(tmp_path / "e.nc"),
            "--quiet"]
    for option, value in (("--dt", "0.001"), ("--integrator", "RK4")):
        assert main(base + [option, value]) == 2
        err = capsys.readouterr().err
        assert option in err and "only affects the MuJoCo engine" in err and err.count("\n") == 1
    assert main(base + ["--grid", "dt=0.01,0.025"]) == 2
    assert "grid dt: dt only affects the MuJoCo engine" in capsys.readouterr().err
    assert not (tmp_path / "e.nc").exists()


# ----------------------------------------------------------------------------- MuJoCo sweeps on mujoco.batch


def test_mujoco_sweep_resumed_after_an_interruption_gives_the_same_dataset(tmp_path):
    """Points run in batches (here 2 per batch on 2 threads, noise with different seeds): an interrupted
    sweep keeps what was journaled, the resume runs only the rest, and the dataset equals the
    uninterrupted sweep's, which equals run_case point by point."""
    grid = {"sigma": [0.3, 0.8, 1.5], "seed": [0, 1]}
    kw = dict(fixed={"n": 4, "noise": 0.05}, numerics=FAST, duration=20, progress=False, snapshot_interval=0,
              workers=2, batch_size=2)
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
    ds = run_sweep("one-pinned", {"sigma": [0.5, 100.0, 50.0]}, fixed={"n": 3}, numerics=num, duration=10,
                   out=tmp_path / "d.nc", workers=2, progress=False, timestep_check=False)
    assert ds["status"].values.tolist() == ["ok", "error", "ok"]
    assert "SimulationDiverged" in ds["error"].values[1] and "diverged at t = 5 tau" in ds["error"].values[1]
    assert np.isfinite(ds["amplitude"].values[[0, 2]]).all() and np.isnan(ds["amplitude"].values[1])
    expected = run_case(Case(Physics(n=3, sigma=50.0), num, 10)).results
    assert ds["amplitude"].values[2] == expected.amplitude


def test_preflight_check_once_per_distinct_model(tmp_path, monkeypatch):
    from elastoactive import diagnose

    calls = []
    original = diagnose.check_timestep

    def counted(physics, numerics, *args, **kwargs):
        if kwargs.get("suggest", True):  # not the checks of the setting a refusal suggests (suggest=False)
            calls.append((physics.sigma, numerics.seed))
        return original(physics, numerics, *args, **kwargs)

    monkeypatch.setattr(diagnose, "check_timestep", counted)
    # sigma = 5 at N = 5: dt = 0.01 does not resolve the fastest rate; refused while its batch runs
    ds = run_sweep("one-pinned", {"sigma": [0.3, 0.8, 5.0], "seed": [0, 1, 2]}, fixed={"n": 5}, numerics=FAST,
                   duration=10, workers=2, progress=False)
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
    ds = run_sweep("one-pinned", grid, fixed={"n": 3}, numerics=FAST, duration=60, out=out, workers=2,
                   progress=False, timestep_check=False)
    check_against_run_case(ds, "one-pinned", {"n": 3}, FAST, 60, "mujoco")
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

    pair = run_sweep("coupled-pair", {"noise": [0.0, 0.3]}, fixed={"n": 3, "sigma": 4.0, "kappa": 0.5},
                     numerics=FAST, duration=40, out=tmp_path / "pair.nc", workers=1, progress=False,
                     timestep_check=False)
    check_against_run_case(pair, "coupled-pair", {"n": 3, "sigma": 4.0, "kappa": 0.5}, FAST, 40, "mujoco")
    assert pair["period_spread"].dims == ("noise", "chain") and pair["periodic"].dims == ("noise",)
    assert pair["periodic"].values[1] == 0 and pair["notes"].values[1].count("chain ") == 2
    for scene in ("two-pinned", "rotating-pin"):  # present before any point is done
        ds = run_sweep(scene, {"sigma": [0.5]}, fixed={"n": 3}, numerics=FAST, duration=10, workers=1,
                       progress=False)
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
    ds = run_sweep("one-pinned", {"n": [3, 4], "sigma": [0.5, 0.9]}, numerics=FAST, duration=10, workers=2,
                   progress=False)
    assert ds["status"].values.tolist() == [["ok", "ok"], ["error", "error"]]
    assert (ds["error"].values[1] == "RuntimeError: batch lost").all()


def test_batch_size_must_be_at_least_one(tmp_path, capsys):
    with pytest.raises(ParameterError, match="batch_size must be"):
        run_sweep("one-pinned", {"sigma": [0.3]}, batch_size=0, progress=False)
    args = ["sweep", "one-pinned", "--grid", "sigma=0.3", "--out", str(tmp_path / "b.nc"), "--batch-size", "0",
            "--quiet"]
    assert main(args) == 2 and "--batch-size must be >= 1" in capsys.readouterr().err
    assert not (tmp_path / "b.nc").exists()


def test_netcdf_writer_matches_xarrays(tmp_path):
    """outputs.write_netcdf (h5netcdf, without xarray's writer and its dask imports) writes what xarray's own
    to_netcdf writes, as xarray.open_dataset reads it back: floats with NaN, integers, text, times with NaT, a
    per-chain dimension, numpy and plain attributes."""
    from elastoactive.outputs import write_netcdf

    status = np.array([["ok", "error", "pending"], ["ok", "", "ok"]], dtype=object)
    finished = np.array([["2026-11-22T17:56:44.8378", "NaT", "2026-01-01"], ["NaT", "NaT", "1970-01-01"]],
                        dtype="datetime64[ns]")
    amplitude = np.arange(12.0).reshape(2, 3, 2)
    amplitude[0, 1] = np.nan
    variables = {
        "amplitude": (("sigma", "n", "chain"), amplitude, {"units": "rad", "long_name": "amplitude"}),
        "periodic": (("sigma", "n"), np.array([[1.0, 0.0, np.nan], [np.nan, 1.0, 0.0]]),
                     {"flag_values": np.array([1.0, 0.0]), "flag_meanings": "periodic irregular"}),
        "status": (("sigma", "n"), status, {"long_name": "status"}),
        "finished_at": (("sigma", "n"), finished, {"long_name": "when"}),
    }
    coords = {"sigma": (("sigma",), np.array([0.3, 1.0]), {"long_name": "sigma"}),
              "n": (("n",), np.array([5, 7, 9], dtype=np.int64), {"long_name": "N"}),
              "chain": (("chain",), np.arange(1, 3), {"long_name": "chain"})}
    attrs = {"title": "t", "duration": 40.0, "points_total": 6, "complete": 0, "numerics_integrator":
             Numerics().integrator, "numerics_dt": Numerics().dt}
    mine, theirs = tmp_path / "mine.nc", tmp_path / "xarray.nc"
    write_netcdf(mine, variables, coords, attrs)
    xr.Dataset({k: (d, v, a) for k, (d, v, a) in variables.items()},
               coords={k: (d, v, a) for k, (d, v, a) in coords.items()},
               attrs={k: (str(v) if isinstance(v, str) else float(v) if isinstance(v, float) else v)
                      for k, v in attrs.items()}).to_netcdf(theirs, engine="h5netcdf")
    a, b = load(mine), load(theirs)
    xr.testing.assert_identical(a, b)
    assert a["finished_at"].dtype == np.dtype("datetime64[ns]") and np.isnat(a["finished_at"].values[0, 1])
    assert type(a.attrs["numerics_integrator"]) is str and a.attrs["numerics_dt"] == 0.0025
    with xr.open_dataset(mine) as default_engine:  # a valid netCDF-4 file for xarray's default engine too
        assert set(default_engine.data_vars) == set(variables)


def test_long_chain_sweep_says_its_numerics_are_automatic(tmp_path):
    ds = run_sweep("one-pinned", {"sigma": [0.05]}, fixed={"n": 30}, duration=2, out=tmp_path / "l.nc",
                   progress=False, workers=1)
    assert (ds["status"] == "ok").all() and "automatic long-chain numerics" in ds.attrs["numerics_automatic"]
    short = run_sweep("one-pinned", {"sigma": [0.8]}, duration=2, progress=False, workers=1)
    assert "numerics_automatic" not in short.attrs


# ----------------------------------------------------------------------------- where the output cannot go


def test_out_under_a_file_is_one_line(tmp_path, capsys):
    """An --out whose folder is a file (or cannot be written) is refused before anything runs, naming --out, as
    `run` does (it was a FileExistsError / PermissionError traceback)."""
    afile = tmp_path / "afile"
    afile.write_text("not a folder")
    args = ["sweep", "one-pinned", "--grid", "sigma=0.3", "--n", "3", "--engine", "reduced", "--preset", "fast",
            "--duration", "20", "--workers", "1", "--quiet", "--out", str(afile / "x.nc")]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--out" in err and "is a file" in err
    with pytest.raises(ParameterError, match="is a file"):
        run_sweep("one-pinned", {"sigma": [0.3]}, out=afile / "deeper" / "x.nc", **REDUCED)


def test_file_size_limit_is_one_line_before_h5py_writes(tmp_path):
    """Under a file-size limit (ulimit -f) too small for the netCDF, h5py failed write after write and the process
    crashed (exit 139). The limit is checked before any point runs and before any write: one line, the journal
    kept, no partial file."""
    import resource

    limit = 8 * 1024  # ulimit -f 8

    def limited():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    out = tmp_path / "x.nc"
    args = [sys.executable, "-m", "elastoactive", "sweep", "one-pinned", "--grid", "sigma=0.3:1.0:8", "--n", "3",
            "--engine", "reduced", "--preset", "fast", "--duration", "20", "--workers", "1", "--quiet", "--out", str(out)]
    done = subprocess.run(args, capture_output=True, text=True, preexec_fn=limited, timeout=120)
    assert done.returncode == 2, done.stderr[-2000:]
    assert done.stderr.count("\n") == 1 and "file-size limit" in done.stderr and str(out) in done.stderr
    assert not out.exists() and (tmp_path / "x.nc.journal").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.nc.journal"]


def test_unreachable_dask_scheduler_is_one_line(tmp_path, capsys, monkeypatch):
    """A scheduler address nobody answers at: one line naming it after a short wait (it was Dask's 30 s, then a
    69-line traceback), and nothing is written."""
    pytest.importorskip("dask.distributed")
    from elastoactive import sweep_runners

    monkeypatch.setattr(sweep_runners, "DASK_CONNECT_S", 1.0, raising=False)
    out = tmp_path / "d.nc"
    args = ["sweep", "two-pinned", "--grid", "delta=0:0.3:7", "--out", str(out), "--quiet",
            "--scheduler", "tcp://127.0.0.1:9"]
    start = time.monotonic()
    assert main(args) == 2
    assert time.monotonic() - start < 15
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in err
    assert list(tmp_path.iterdir()) == []

"""Sweeps that must not lose or misreport work: Ctrl-C during the save, the journal's durability and validation,
a full disk, exit codes, refused settings, and outputs that cannot be written (the sweep's storage and its one-line
refusals)."""

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

import pytest
import xarray as xr
from sweep_helpers import REDUCED, VOLATILE, Stop, load  # shared with test_sweep.py

from elastoactive.cli import main
from elastoactive.core.params import ParameterError
from elastoactive.sweep import make_sweep, run_sweep
from elastoactive.sweep import netcdf as sweep_netcdf

# ----------------------------------------------------------------------------- "Trustworthy runs"


@pytest.fixture
def terminal_ctrl_c():
    """SIGINT raising KeyboardInterrupt, as at a terminal, whatever the shell that started the tests left (a
    background job ignores it); the disposition found is restored after."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.mark.parametrize("how", ["signal", "exception"])
def test_ctrl_c_during_final_save_loses_nothing(tmp_path, monkeypatch, how, terminal_ctrl_c):
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
    assert (
        main(
            [
                "sweep",
                "one-pinned",
                "--grid",
                "sigma=0.3,0.6",
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
        )
        == 2
    )

    monkeypatch.undo()  # space freed: the sweep resumes without running anything again
    again = []
    ds = run_sweep("one-pinned", grid, out=out, on_point=lambda c, r: again.append(c), **REDUCED)
    assert again == [] and (ds["status"] == "ok").all() and not journal.exists()
    xr.testing.assert_identical(load(out), ds)


def test_exit_status_when_points_fail(tmp_path, capsys):
    """Every point refused before it runs: exit 2, nothing written; some failed: exit 0, counted."""
    # Euler at mass_ratio 0.01 is stable for dt < 0.02: the timestep check refuses larger steps
    base = [
        "sweep",
        "one-pinned",
        "--n",
        "3",
        "--integrator",
        "Euler",
        "--mass-ratio",
        "0.01",
        "--sample-dt",
        "0.1",
        "--duration",
        "5",
        "--workers",
        "1",
        "--quiet",
    ]
    assert main(base + ["--grid", "dt=0.05,0.1", "--out", str(tmp_path / "all.nc")]) == 2  # every point refused
    captured = capsys.readouterr()
    assert "refuses every point of the sweep (2)" in captured.err and "stability limit" in captured.err
    assert "dt <= " in captured.err.split("passes every point")[1] and not (tmp_path / "all.nc").exists()
    assert main(base + ["--grid", "dt=0.01,0.05", "--out", str(tmp_path / "some.nc")]) == 0
    captured = capsys.readouterr()
    assert "2 of 2 points" in captured.out and "1 failed" in captured.out and "stability limit" in captured.err


@pytest.mark.parametrize("engine", ["mujoco", "reduced"])
def test_a_refused_network_point_fails_at_once(tmp_path, capsys, engine):
    """A network point runs whole on its thread, where the pre-flight check running beside the batch cannot stop it:
    the sweep checks it first. A point whose units are too stiff (l_a = 1e-5: MuJoCo's automatic dt ~1e-8) is
    recorded as failed with the refusal in a second, not run for hours; the other point runs."""
    start = time.perf_counter()
    argv = [
        "sweep",
        "trapped-unit",
        "--grid",
        "alignment_length=1e-5,1",
        "--engine",
        engine,
        "--duration",
        "5",
        "--workers",
        "1",
        "--quiet",
        "--out",
        str(tmp_path / "s.nc"),
    ]
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert "2 of 2 points" in captured.out and "1 failed" in captured.out and "alignment_length >=" in captured.err
    assert time.perf_counter() - start < 30.0


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
    args = [
        "sweep",
        "one-pinned",
        "--grid",
        "sigma=0.3,0.6,0.9",
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
        args = [
            "sweep",
            "one-pinned",
            "--grid",
            "sigma=0.3",
            "--engine",
            "reduced",
            "--out",
            str(tmp_path / "w.nc"),
            "--workers",
            str(workers),
            "--quiet",
        ]
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
    base = [
        "sweep",
        "one-pinned",
        "--grid",
        "sigma=0.3",
        "--engine",
        "reduced",
        "--out",
        str(tmp_path / "e.nc"),
        "--quiet",
    ]
    for option, value in (("--dt", "0.001"), ("--integrator", "RK4")):
        assert main(base + [option, value]) == 2
        err = capsys.readouterr().err
        assert option in err and "only affects the MuJoCo engine" in err and err.count("\n") == 1
    assert main(base + ["--grid", "dt=0.01,0.025"]) == 2
    assert "grid dt: dt only affects the MuJoCo engine" in capsys.readouterr().err
    assert not (tmp_path / "e.nc").exists()


# ----------------------------------------------------------------------------- where the output cannot go


def test_out_under_a_file_is_one_line(tmp_path, capsys):
    """An --out whose folder is a file (or cannot be written) is refused before anything runs, naming --out, as
    `run` does (it was a FileExistsError / PermissionError traceback)."""
    afile = tmp_path / "afile"
    afile.write_text("not a folder")
    args = [
        "sweep",
        "one-pinned",
        "--grid",
        "sigma=0.3",
        "--n",
        "3",
        "--engine",
        "reduced",
        "--preset",
        "fast",
        "--duration",
        "20",
        "--workers",
        "1",
        "--quiet",
        "--out",
        str(afile / "x.nc"),
    ]
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
    args = [
        sys.executable,
        "-m",
        "elastoactive",
        "sweep",
        "one-pinned",
        "--grid",
        "sigma=0.3:1.0:8",
        "--n",
        "3",
        "--engine",
        "reduced",
        "--preset",
        "fast",
        "--duration",
        "20",
        "--workers",
        "1",
        "--quiet",
        "--out",
        str(out),
    ]
    done = subprocess.run(args, capture_output=True, text=True, preexec_fn=limited, timeout=120)
    assert done.returncode == 2, done.stderr[-2000:]
    assert done.stderr.count("\n") == 1 and "file-size limit" in done.stderr and str(out) in done.stderr
    assert not out.exists() and (tmp_path / "x.nc.journal").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.nc.journal"]


def test_unreachable_dask_scheduler_is_one_line(tmp_path, capsys, monkeypatch):
    """A scheduler address nobody answers at: one line naming it after a short wait (it was Dask's 30 s, then a
    69-line traceback), and nothing is written."""
    pytest.importorskip("dask.distributed")
    from elastoactive.sweep import runners as sweep_runners

    monkeypatch.setattr(sweep_runners, "DASK_CONNECT_S", 1.0, raising=False)
    out = tmp_path / "d.nc"
    args = [
        "sweep",
        "two-pinned",
        "--grid",
        "delta=0:0.3:7",
        "--out",
        str(out),
        "--quiet",
        "--scheduler",
        "tcp://127.0.0.1:9",
    ]
    start = time.monotonic()
    assert main(args) == 2
    assert time.monotonic() - start < 15
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in err
    assert list(tmp_path.iterdir()) == []


def test_a_sweep_whose_every_point_is_refused_is_refused_before_any_runs(tmp_path, capsys, monkeypatch):
    """A MuJoCo sweep the pre-flight check refuses at every point (dt = 0.01 does not resolve the N = 20 ring) is one
    line naming a setting that passes every point, before any point runs: no netCDF of failures, no journal. The
    setting it names then passes."""
    from elastoactive.sweep import points as sweep_points

    ran = []
    monkeypatch.setattr(sweep_points, "run_chunk", lambda *a, **k: ran.append(a), raising=False)
    out = tmp_path / "ring.nc"
    argv = [
        "sweep",
        "ring",
        "--n",
        "20",
        "--preset",
        "fast",
        "--grid",
        "sigma=0.5,0.8",
        "--duration",
        "1",
        "--workers",
        "1",
        "--quiet",
        "--out",
        str(out),
    ]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "refuses every point of the sweep (2)" in err and "does not resolve" in err
    assert not out.exists() and not (tmp_path / "ring.nc.journal").exists()
    setting = err.split("a setting that passes every point: ")[1].split()
    assert setting[:2] == ["--dt", "0.00625"]
    assert main(argv[:4] + setting + argv[4:]) == 0
    assert (load(out)["status"].values == "ok").all()


def test_a_refused_point_is_checked_again_by_a_rerun(tmp_path):
    """A point refused before it ran (its settings, not its simulation) is no result: a re-run checks it again, and
    runs it when the refusal no longer holds (here: without the timestep check). A failed simulation is kept."""
    from sweep_helpers import FAST

    out = tmp_path / "r.nc"
    kw = dict(fixed={"n": 5}, numerics=FAST, duration=2, progress=False, workers=1, out=out)
    ds = run_sweep("one-pinned", {"sigma": [0.3, 5.0]}, **kw)  # sigma = 5: dt 0.01 does not resolve it
    assert ds["status"].values.tolist() == ["ok", "error"] and "does not resolve" in ds["error"].values[1]
    again = []
    ds = run_sweep("one-pinned", {"sigma": [0.3, 5.0]}, on_point=lambda c, r: again.append(c), **kw)
    assert again == [{"sigma": 5.0}] and ds["status"].values.tolist() == ["ok", "error"]
    again.clear()
    ds = run_sweep(
        "one-pinned", {"sigma": [0.3, 5.0]}, on_point=lambda c, r: again.append(c), timestep_check=False, **kw
    )
    assert again == [{"sigma": 5.0}] and ds["status"].values.tolist() == ["ok", "ok"]
    again.clear()
    run_sweep("one-pinned", {"sigma": [0.3, 5.0]}, on_point=lambda c, r: again.append(c), **kw)
    assert again == []

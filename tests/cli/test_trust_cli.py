"""Trustworthy outputs from the command line: files others can read, no run replacing another unseen, no file
overwritten without --force, no edited record used, no fault (a full disk) ending in a traceback.

One test per mechanism; the helpers `refused` and `no_simulation` are those of test_trust.py.
"""

from __future__ import annotations

import fcntl
import json
import os
import resource
import subprocess
import sys

import numpy as np
import pytest
from conftest import refused  # the shared one-line-refusal check

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.records import load_trajectory, settings_digest

RUN = ["run", "one-pinned", *"--n 4 --sigma 1.2 --duration 60 --quiet --json --engine reduced".split()]


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A short reduced run written by `run --out`."""
    out = tmp_path_factory.mktemp("recorded") / "run"
    assert main(RUN + ["--out", str(out)]) == 0
    return out


def test_files_are_written_with_the_users_umask(tmp_path):
    from elastoactive.io.outputs import write_text

    old = os.umask(0o022)
    try:
        assert main(RUN + ["--out", str(tmp_path / "run")]) == 0
        write_text(tmp_path / "report.md", "text")
    finally:
        os.umask(old)
    for path in (tmp_path / "run" / "summary.json", tmp_path / "run" / "trajectory.npz", tmp_path / "report.md"):
        assert path.stat().st_mode & 0o777 == 0o644, (path, oct(path.stat().st_mode))


def test_a_second_run_into_a_folder_being_written_is_refused(tmp_path, capsys, no_simulation):
    out = tmp_path / "run"
    out.mkdir()
    fd = os.open(out, os.O_RDONLY)  # what a first run into --out holds from its check until its files are written
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        refused(capsys, RUN + ["--out", str(out)], "--out", "another run is writing")
    finally:
        os.close(fd)
    assert not list(out.iterdir())


def test_an_existing_video_or_still_is_not_replaced_without_force(recorded, tmp_path, capsys, no_simulation):
    video, still = tmp_path / "beat.mp4", tmp_path / "beat.png"
    video.write_bytes(b"the video of another run")
    still.write_bytes(b"a still")
    refused(capsys, ["render", str(recorded), "-o", str(video)], "--output", "exists", "--force")
    refused(capsys, ["render", str(recorded), "--still", str(still)], "--still", "exists", "--force")
    refused(capsys, RUN + ["--video", str(video)], "--video", "exists", "--force")
    assert video.read_bytes() == b"the video of another run" and still.read_bytes() == b"a still"


def test_a_video_of_absurdly_many_frames_is_refused_before_rendering(recorded, tmp_path, capsys, no_simulation):
    refused(capsys, ["render", str(recorded), "-o", str(tmp_path / "v.mp4"), "--rate", "1e-9"], "rate", "frames")
    refused(capsys, RUN + ["--video", str(tmp_path / "v.mp4"), "--rate", "1e-9"], "rate", "frames")
    assert not (tmp_path / "v.mp4").exists()


@pytest.mark.parametrize("tolerance", ["nan", "-1", "1e-9", "inf", "2"])
def test_validate_refuses_a_meaningless_tolerance(tolerance, capsys, monkeypatch):
    import elastoactive.checks.validate as validate

    def boom(*args, **kwargs):
        raise AssertionError("validated before --tolerance was checked")

    monkeypatch.setattr(validate, "compare", boom)
    monkeypatch.setattr(validate, "convergence", boom)
    refused(capsys, ["validate", "--tolerance", tolerance, "--quiet"], "--tolerance")


def test_an_edited_summary_is_refused(recorded, tmp_path, capsys, no_simulation):
    """The record's settings are checksummed, in the summary and in the trajectory: another sigma written into
    summary.json is not drawn, re-run or measured as if it had been simulated."""
    edited = tmp_path / "edited"
    edited.mkdir()
    (edited / "trajectory.npz").write_bytes((recorded / "trajectory.npz").read_bytes())
    summary = json.loads((recorded / "summary.json").read_text())
    summary["parameters"]["sigma"] = 0.5
    (edited / "summary.json").write_text(json.dumps(summary))
    png = str(tmp_path / "s.png")
    refused(capsys, ["render", str(edited), "--still", png], "summary.json", "changed after the run")
    refused(capsys, ["run", "--from", str(edited), "--out", str(tmp_path / "again")], "changed after the run")
    summary.pop("settings_sha256")  # its own checksum removed too: an edit all the same
    (edited / "summary.json").write_text(json.dumps(summary))
    with pytest.raises(ea.ParameterError, match="changed after the run"):
        load_trajectory(edited)
    refused(capsys, ["run", "--from", str(edited), "--out", str(tmp_path / "again")], "settings_sha256")
    (edited / "trajectory.npz").unlink()  # nor does a summary alone, without the trajectory that knows its digest
    refused(
        capsys,
        ["run", "--from", str(edited / "summary.json"), "--out", str(tmp_path / "again")],
        "settings_sha256",
        "changed after the run",
    )
    assert not (tmp_path / "again").exists()
    load_trajectory(recorded)  # the untouched record loads


@pytest.mark.parametrize(
    "command",
    [
        RUN + ["--out"],
        ["sweep", "one-pinned", "--grid", "sigma=1", "--out"],
        ["reproduce", "--tiny", "--out"],
        RUN + ["--video"],
    ],
)
@pytest.mark.parametrize("empty", ["", " "])
def test_an_empty_output_path_is_refused(tmp_path, capsys, no_simulation, monkeypatch, command, empty):
    """An empty output path is not the working folder (Path('') is '.'): one line naming the option, nothing
    written."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as info:  # argparse's own error (the option's type): exit 2
        main(command + [empty])
    err = capsys.readouterr().err.strip().splitlines()
    assert info.value.code == 2 and len(err) == 1 and err[0].startswith("elastoactive: error:"), err
    assert f"argument {command[-1]}: an empty path" in err[0]
    assert not list(tmp_path.iterdir())


def test_an_empty_output_path_is_refused_by_the_api(tmp_path, monkeypatch):
    from elastoactive.report.reproduce import reproduce

    monkeypatch.chdir(tmp_path)
    for empty in ("", "  "):
        with pytest.raises(ea.ParameterError, match="out: an empty path"):
            reproduce(empty, "tiny", only=["stability"], progress=False, log=lambda message: None)
    assert not list(tmp_path.iterdir())


def test_a_failed_write_names_the_file_and_the_cause_in_one_line(tmp_path, capsys, monkeypatch):
    def full_disk(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(np, "savez_compressed", full_disk)
    capsys.readouterr()
    assert main(RUN + ["--out", str(tmp_path / "run")]) == 1
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()  # the run's notes (warnings), then the failure in one line
    assert lines[-1].startswith("elastoactive: error:") and "Traceback" not in captured.err
    assert all(line.startswith("elastoactive: warning:") for line in lines[:-1])
    assert "trajectory.npz" in lines[-1] and "No space left on device" in lines[-1] and "Errno" not in lines[-1]
    assert json.loads(captured.out)["amplitude"] > 0  # the results are shown all the same


def _limited(limit_bytes: int):
    return lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, resource.RLIM_INFINITY))


def test_a_file_size_limit_gives_one_line_not_a_traceback(tmp_path):
    """`ulimit -f`: the trajectory cannot be written; run and run --force refuse before they simulate, render (a
    still, a video: its encoder is a separate process) fails, each in one line."""
    base = [sys.executable, "-m", "elastoactive"]
    small = RUN[:6] + ["--duration", "20"] + RUN[8:]
    out = tmp_path / "run"
    assert subprocess.run(base + small + ["--out", str(out)], capture_output=True, timeout=120).returncode == 0
    commands = (
        RUN + ["--duration", "2000", "--out", str(tmp_path / "big")],
        RUN + ["--duration", "2000", "--out", str(out), "--force"],
        ["render", str(out), "--still", str(tmp_path / "s.png"), "--width", "2048", "--height", "2048"],
        ["render", str(out), "-o", str(tmp_path / "v.mp4"), "--width", "512", "--height", "512", "--quiet"],
    )
    for argv in commands:
        if argv[0] == "render" and os.environ.get("MUJOCO_GL") == "disabled":
            continue
        result = subprocess.run(base + argv, capture_output=True, text=True, timeout=300, preexec_fn=_limited(20_000))
        lines = result.stderr.strip().splitlines()
        assert "Traceback" not in result.stderr and lines[-1].startswith("elastoactive:"), (argv, result.stderr)
        if argv[0] == "run":  # refused before the simulation: the trajectory would not fit under the limit
            assert result.returncode == 2 and len(lines) == 1, (argv, result.stderr)
            assert "--out" in lines[0] and "file-size limit" in lines[0] and "--sample-dt" in lines[0], lines
        else:
            assert result.returncode in (1, 4) and "File too large" in lines[-1], (argv, result.stderr)
    load_trajectory(out)  # the run --force was refused: the earlier run is whole
    assert not (tmp_path / "big").exists()


def test_a_run_whose_trajectory_cannot_be_stored_is_refused_before_it_simulates(
    tmp_path, capsys, monkeypatch, no_simulation
):
    """The trajectory's size is known before the run (samples x columns): a file-size limit or a free space below it
    is one line naming --out, before anything is simulated."""
    import shutil
    from types import SimpleNamespace

    from elastoactive.io import outputs

    out = tmp_path / "run"
    monkeypatch.setattr(outputs, "file_size_limit", lambda: 10_240)  # `ulimit -f 10`
    refused(capsys, RUN + ["--out", str(out)], "--out", "trajectory.npz", "file-size limit", "10240 bytes")
    monkeypatch.setattr(outputs, "file_size_limit", lambda: None)
    monkeypatch.setattr(shutil, "disk_usage", lambda path: SimpleNamespace(total=1e9, used=1e9, free=5_000))
    refused(capsys, RUN + ["--out", str(out)], "--out", "trajectory.npz", "free")
    assert not out.exists()


def test_a_trajectory_that_cannot_be_written_leaves_the_summary(tmp_path, capsys, monkeypatch):
    """A failure writing the large file (the trajectory) still writes the small one: summary.json with the results, its
    settings' checksum, no trajectory checksum and the error (an earlier run in the folder is kept whole instead:
    test_trust.py). The results are printed, the failure is one line, and the summary re-runs with --from."""
    out = tmp_path / "run"

    def too_large(*args, **kwargs):
        raise OSError(27, "File too large")

    with monkeypatch.context() as patch:
        patch.setattr(np, "savez_compressed", too_large)
        assert main(RUN + ["--out", str(out)]) == 1
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert err[-1].startswith("elastoactive: error:") and "trajectory.npz" in err[-1] and "File too large" in err[-1]
    assert "summary.json was written without it" in err[-1]
    summary = ea.records.read_summary(out)
    assert summary["numerics"]["duration"] == 60 and summary["trajectory_sha256"] is None
    assert "File too large" in summary["trajectory_error"]
    assert json.loads(captured.out)["amplitude"] == summary["results"]["amplitude"]
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"]
    assert main(["run", "--from", str(out), "--out", str(tmp_path / "again"), "--quiet"]) == 0
    assert load_trajectory(tmp_path / "again").t[-1] == pytest.approx(60)


def test_what_cannot_be_measured_is_refused_before_simulating(capsys, no_simulation):
    refused(
        capsys, ["run", "one-pinned", "--transient", "29.99", "--duration", "30", "--quiet"], "--transient", "sample(s)"
    )
    refused(capsys, ["run", "paraboloid", "--n", "1", "--duration", "20", "--quiet"], "n = 1", "curvature")
    with pytest.raises(ea.ParameterError, match="curvature"):
        ea.simulate(ea.Physics(scene="paraboloid", n=1), duration=20)


def test_the_front_door_takes_the_obvious_forms_or_names_the_argument():
    physics = ea.Physics(n=3)
    fast = ea.simulate(physics, "fast", duration=2)
    assert np.array_equal(fast.theta, ea.simulate(physics, ea.Numerics.preset("fast"), duration=2).theta)
    by_dict = ea.simulate(physics, {"sample_dt": 0.1}, duration=2, engine="reduced")
    assert by_dict.t[1] == pytest.approx(0.1)
    by_name = ea.simulate("one-pinned", duration=2, engine="reduced")
    assert by_name.physics == ea.Physics(scene="one-pinned")
    for call, argument in (
        (lambda: ea.simulate(physics, {"dt_": 0.01}, duration=2), "numerics"),
        (lambda: ea.simulate(7, duration=2), "physics"),
        (lambda: ea.measure(None), "trajectory"),
        (lambda: ea.measure(np.zeros((10, 7))), "trajectory"),
    ):
        with pytest.raises(TypeError, match=argument):
            call()
    with pytest.raises(ea.ParameterError, match="transient"):
        ea.measure(fast, transient=1.99)


def test_from_reruns_every_recorded_run_or_refuses(tmp_path, capsys):
    """The reduced engine's mass ratio is recorded (an inertial chain re-runs inertial); a record that lacks a setting
    the re-run needs (here an older summary without its duration) is refused, not filled with a default."""
    heavy, again = tmp_path / "heavy", tmp_path / "again"
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--n",
                "4",
                "--mass-ratio",
                "10",
                "--duration",
                "40",
                "--engine",
                "reduced",
                "--quiet",
                "--out",
                str(heavy),
            ]
        )
        == 0
    )
    assert json.loads((heavy / "summary.json").read_text())["numerics"]["mass_ratio"] == 10
    assert main(["run", "--from", str(heavy), "--out", str(again), "--quiet"]) == 0
    with np.load(heavy / "trajectory.npz") as a, np.load(again / "trajectory.npz") as b:
        np.testing.assert_array_equal(a["theta"], b["theta"])
    older = json.loads((heavy / "summary.json").read_text())
    older.pop("trajectory_sha256")
    older["numerics"]["duration"] = None
    older["numerics"].pop("mass_ratio")
    older["settings_sha256"] = settings_digest(older)  # a record of a version that did not write them
    (heavy / "summary.json").write_text(json.dumps(older))
    refused(capsys, ["run", "--from", str(heavy), "--quiet"], "duration", "mass_ratio", "--duration", "--mass-ratio")
    assert (
        main(
            [
                "run",
                "--from",
                str(heavy),
                "--duration",
                "40",
                "--mass-ratio",
                "10",
                "--out",
                str(tmp_path / "given"),
                "--quiet",
            ]
        )
        == 0
    )
    with np.load(heavy / "trajectory.npz") as a, np.load(tmp_path / "given" / "trajectory.npz") as b:
        np.testing.assert_array_equal(a["theta"], b["theta"])


def test_reading_the_git_commit_writes_nothing_into_the_checkout(tmp_path):
    """The provenance's git state is read without refreshing the index: under a full disk or a file-size limit a
    refresh would leave .git/index.lock behind, and it would race with the user's own git commands."""
    from elastoactive.io.outputs import git_commit

    def git(*args):
        subprocess.run(["git", "-C", str(tmp_path), *args], check=True, capture_output=True)

    git("init", "-q")
    (tmp_path / "a.txt").write_text("a")
    git("add", "a.txt")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "a")
    index = tmp_path / ".git" / "index"
    os.utime(tmp_path / "a.txt", (1e9, 1e9))  # the index's stat data is stale: a refresh would rewrite it
    before = (index.read_bytes(), index.stat().st_mtime_ns)
    assert git_commit(tmp_path) and not git_commit(tmp_path).endswith("+dirty")
    assert (index.read_bytes(), index.stat().st_mtime_ns) == before


def test_the_provenance_names_the_checkouts_commit():
    """Run from a checkout, the provenance records its commit (the package's folder's parent is the checkout)."""
    from elastoactive.io.outputs import PACKAGE_ROOT, git_commit, provenance

    assert (PACKAGE_ROOT / "elastoactive" / "io" / "outputs.py").is_file()
    if not (PACKAGE_ROOT / ".git").exists():
        pytest.skip("not run from a git checkout")
    head = subprocess.run(["git", "-C", str(PACKAGE_ROOT), "rev-parse", "HEAD"], capture_output=True, text=True)
    assert git_commit().split("+")[0] == head.stdout.strip()
    assert provenance()["git_commit"] == git_commit()

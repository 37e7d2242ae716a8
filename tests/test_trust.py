"""Trustworthy runs: nothing lost, nothing silently wrong, every run reproducible (run, render, reproduce).

Sweeps have their own such tests in test_sweep.py, the README's commands in test_readme.py, random inputs
in test_properties.py, the library's pre-flight check in test_front_door.py.
"""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest
from conftest import refused  # the shared one-line-refusal check

import elastoactive as ea
from elastoactive import records
from elastoactive.cli import main
from elastoactive.core.surface import command_line
from elastoactive.engines.timestep import check_timestep
from elastoactive.io import progress
from elastoactive.records import load_trajectory

RUN = ["run", "one-pinned", "--n", "4", "--sigma", "1.2", "--duration", "60", "--quiet"]


# ------------------------------------------------------------------------------- silently wrong


def test_short_window_gives_null_frequency_naming_the_fix(tmp_path, capsys):
    assert (
        main(["run", "one-pinned", "--duration", "50", "--engine", "reduced", "--quiet", "--out", str(tmp_path)]) == 0
    )
    captured = capsys.readouterr()
    results = json.loads((tmp_path / "summary.json").read_text())["results"]
    assert results["frequency"] is None and results["amplitude"] > 2  # clearly beating, but < 2 periods
    assert "--duration" in captured.err and "warning" in captured.err


def test_beat_regularity_is_reported():
    clean = ea.measure(ea.simulate(ea.Physics(), duration=400, engine="reduced"))
    assert clean.periodic is True and clean.period_spread < 1e-4 and not clean.notes
    noisy = ea.measure(ea.simulate(ea.Physics(noise=0.1), duration=400, engine="reduced"))
    assert noisy.periodic is False and noisy.period_spread > 0.01 and "not periodic" in noisy.notes[0]
    short = ea.measure(ea.simulate(ea.Physics(), duration=80, engine="reduced"))
    assert short.periodic is None and short.notes


def test_a_rigid_rotation_has_no_beat_frequency():
    """A chain that turns without bending (a rotating pin, an orbit in the dish) has a steady Theta: no beat, so its
    frequency is null with a note saying why, not 0.0 (which says the chain is at rest)."""
    from elastoactive.core.trajectory import Trajectory

    t = np.arange(0.0, 200.0, 0.05)
    shape = np.array([0.0, 0.3, 0.5])
    turning = Trajectory(
        t=t, theta=shape + 0.08 * t[:, None], physics=ea.Physics(scene="rotating-pin", n=3), engine="x"
    )
    res = ea.measure(turning)
    assert res.frequency is None and res.rotation_rate == pytest.approx(0.08)
    assert len(res.notes) == 1 and "no beat" in res.notes[0] and "rotation_rate" in res.notes[0]
    still = Trajectory(t=t, theta=np.broadcast_to(shape, (t.size, 3)), physics=turning.physics, engine="x")
    res = ea.measure(still)
    assert res.frequency == 0.0 and not res.notes


SUGGESTION_CASES = (
    (ea.Physics(scene="coupled-pair", kappa=1000), ea.Numerics(dt=0.0025)),
    (ea.Physics(n=30, sigma=100), ea.Numerics(dt=1e-4, sample_dt=0.05)),
    (ea.Physics(scene="two-pinned"), ea.Numerics(dt=0.04, sample_dt=0.04)),
    (ea.Physics(sigma=50), ea.Numerics()),
    (ea.Physics(sigma=500), ea.Numerics()),
    (ea.Physics(sigma=50, contact=True), ea.Numerics()),
    (ea.Physics(n=17, sigma=10, contact=True), ea.Numerics(sample_dt=0.1)),
)


@pytest.mark.parametrize("physics,numerics", SUGGESTION_CASES)
def test_suggested_settings_pass_every_check(physics, numerics):
    """A refusal's suggested setting, typed back as printed with the run's other settings (its sample_dt), is
    accepted: by Numerics (sample_dt a whole multiple of dt) and by the pre-flight check."""
    with command_line(), pytest.raises(ea.ParameterError) as err:  # worded as the options to type
        check_timestep(physics, numerics)
    words = str(err.value).split("a setting that passes every check: --dt ")[1].split()
    dt, mass, integrator = float(words[0]), float(words[2]), words[4].rstrip(")")
    check_timestep(physics, ea.Numerics(dt=dt, mass_ratio=mass, integrator=integrator, sample_dt=numerics.sample_dt))


def test_the_suggested_command_line_passes(capsys, no_simulation):
    argv = ["run", "one-pinned", "--sigma", "50", "--duration", "100", "--quiet"]
    line = refused(capsys, argv, "a setting that passes every check")
    suggestion = line.split("a setting that passes every check: ")[1].rstrip(")").split()
    with pytest.raises(AssertionError, match="simulated"):  # every check passed: it went on to simulate
        main(argv + suggestion)


# ------------------------------------------------------------------------------- nothing lost


def test_outputs_are_checked_before_simulating(tmp_path, capsys, no_simulation):
    afile = tmp_path / "afile"
    afile.write_text("x")
    refused(capsys, RUN + ["--out", str(afile)], "--out", "is a file")
    refused(capsys, RUN + ["--out", "/proc/elastoactive-test/run"], "--out", "cannot write")
    refused(capsys, RUN + ["--transient", "60"], "transient")
    refused(capsys, RUN + ["--video", str(tmp_path / "v.gif")], "--video", ".mp4")
    refused(capsys, RUN + ["--video", str(tmp_path / "v.mp4"), "--width", "100000"], "width")
    refused(capsys, RUN[:-5] + ["--duration", "1e9", "--quiet"], "duration", "MuJoCo steps")
    refused(capsys, RUN[:-5] + ["--duration", "1e9", "--sample-dt", "0.05", "--quiet"], "duration", "--sample-dt")
    refused(capsys, RUN[:-5] + ["--duration", "0.01", "--quiet"], "duration")
    refused(capsys, RUN + ["--sample-dt", "1e9"], "--sample-dt")


def test_a_failed_write_keeps_the_previous_run_whole(tmp_path, capsys, monkeypatch):
    out = tmp_path / "run"
    assert main(RUN + ["--out", str(out), "--engine", "reduced"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    def full_disk(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(np, "savez_compressed", full_disk)
    assert main(RUN + ["--out", str(out), "--engine", "reduced", "--force", "--sigma", "1.3"]) == 1
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before  # no temporary file left, nothing torn
    assert "nothing was replaced" in capsys.readouterr().err.strip().splitlines()[-1]
    load_trajectory(out)  # the pair still belongs together


def test_a_large_trajectory_is_written_uncompressed_and_reads_back(tmp_path, monkeypatch):
    """Above records.COMPRESS_BYTES the trajectory is stored, not deflated; it loads as a compressed one does."""
    runs = {}
    for name, limit in (("small", records.COMPRESS_BYTES), ("large", 0)):
        monkeypatch.setattr(records, "COMPRESS_BYTES", limit)
        assert main(RUN + ["--out", str(tmp_path / name), "--engine", "reduced"]) == 0
        with zipfile.ZipFile(tmp_path / name / "trajectory.npz") as archive:
            kinds = {info.compress_type for info in archive.infolist()}
        assert kinds == ({zipfile.ZIP_DEFLATED} if name == "small" else {zipfile.ZIP_STORED}), (name, kinds)
        runs[name] = load_trajectory(tmp_path / name)
    assert np.array_equal(runs["small"].theta, runs["large"].theta)
    assert np.array_equal(runs["small"].t, runs["large"].t)


def test_summary_and_trajectory_must_belong_together(tmp_path, capsys):
    for name, sigma in (("a", "1.2"), ("b", "1.3")):
        assert main(RUN + ["--out", str(tmp_path / name), "--engine", "reduced", "--sigma", sigma]) == 0
    (tmp_path / "a" / "trajectory.npz").write_bytes((tmp_path / "b" / "trajectory.npz").read_bytes())
    with pytest.raises(ea.ParameterError, match="checksum"):
        load_trajectory(tmp_path / "a")


def test_an_earlier_run_is_not_replaced_without_force(tmp_path, capsys):
    out = str(tmp_path / "run")
    assert main(RUN + ["--out", out, "--engine", "reduced"]) == 0
    assert main(RUN + ["--out", out, "--engine", "reduced"]) == 0  # the same run again: nothing is lost
    refused(capsys, RUN + ["--out", out, "--engine", "reduced", "--sigma", "1.3"], "--force", "parameters")
    assert main(RUN + ["--out", out, "--engine", "reduced", "--sigma", "1.3", "--force"]) == 0
    assert json.loads((tmp_path / "run" / "summary.json").read_text())["parameters"]["sigma"] == 1.3


# ------------------------------------------------------------------------------- clear messages


def test_render_refuses_bad_inputs_in_one_line(tmp_path, capsys):
    run = tmp_path / "run"
    assert main(RUN + ["--out", str(run), "--engine", "reduced"]) == 0
    capsys.readouterr()
    png = str(tmp_path / "s.png")
    refused(capsys, ["render", str(run), "--still", png, "--time", "nan"], "time")
    refused(capsys, ["render", str(run), "--still", png, "--width", "100000"], "width")
    refused(capsys, ["render", str(run)], "--output")
    truncated = tmp_path / "truncated" / "trajectory.npz"
    truncated.parent.mkdir()
    (truncated.parent / "summary.json").write_text((run / "summary.json").read_text())
    truncated.write_bytes((run / "trajectory.npz").read_bytes()[:500])
    refused(capsys, ["render", str(truncated), "--still", png], "truncated")
    wrong = tmp_path / "wrong"
    wrong.mkdir()
    summary = json.loads((run / "summary.json").read_text())
    summary.pop("trajectory_sha256")
    (wrong / "summary.json").write_text(json.dumps(summary))
    np.savez(wrong / "trajectory.npz", t=np.arange(5.0), theta=np.zeros((5, 3)))
    refused(capsys, ["render", str(wrong), "--still", png], "theta of shape")
    np.savez(wrong / "trajectory.npz", t=np.arange(5.0), angles=np.zeros((5, 4)))
    refused(capsys, ["render", str(wrong), "--still", png], "lacks the array")
    theta = np.zeros((5, 4))
    theta[3:] = np.nan
    np.savez(wrong / "trajectory.npz", t=np.arange(5.0), theta=theta)
    refused(capsys, ["render", str(wrong), "--still", png], "not finite", "t = 3")


def test_reproduce_and_accuracy_options_are_checked(capsys, tmp_path, no_simulation):
    refused(capsys, ["reproduce", "--only", "bogus", "--out", str(tmp_path)], "--only", "bogus", "hopf")
    refused(capsys, ["reproduce", "--only", "", "--out", str(tmp_path)], "--only")
    for command in ("reproduce", "accuracy"):
        for workers in ("0", "-1"):
            with pytest.raises(SystemExit) as exit_:
                main([command, "--workers", workers])
            assert exit_.value.code == 2 and "--workers" in capsys.readouterr().err


def test_progress_writes_lines_in_a_log(monkeypatch, capsys):
    monkeypatch.setattr(progress, "LOG_INTERVAL", 0.0)
    bar = progress.progress_bar(10, "mujoco one-pinned", "sample")  # stderr is not a terminal under pytest
    bar.update(5)
    bar.close()
    lines = capsys.readouterr().err.splitlines()
    assert lines[0] == "mujoco one-pinned: 50% (5/10 samples, 0 s)" and "\r" not in "".join(lines)


def test_progress_moves_within_a_run_of_slow_samples(monkeypatch):
    """A long chain takes seconds per checked block of samples: the bar moves by wall time, not every 100 samples."""
    from elastoactive.engines import mujoco as engine
    from elastoactive.engines import runner
    from elastoactive.io import progress

    updates = []
    monkeypatch.setattr(runner, "PROGRESS_EVERY", 0.0)
    with progress.observe(lambda event: updates.append(event) if event.kind == "update" else None):
        engine.simulate_mujoco(ea.Physics(n=3), ea.Numerics(), 2.0, progress=True)
    assert len(updates) >= 40 and updates[-1].done == pytest.approx(2.0)  # at least every sample, not every 100


# ------------------------------------------------------------------------------- reproducible


def test_summary_records_provenance(tmp_path):
    assert main(RUN + ["--out", str(tmp_path), "--engine", "reduced"]) == 0
    prov = json.loads((tmp_path / "summary.json").read_text())["provenance"]
    assert set(prov["versions"]) >= {"elastoactive", "mujoco", "numpy", "scipy", "numba", "python"}
    assert prov["command"] and prov["started_utc"].endswith("+00:00") and prov["wall_time_s"] > 0
    assert "platform" in prov and "git_commit" in prov


def test_from_reruns_a_recorded_mujoco_run_bit_identically(tmp_path):
    first, again = tmp_path / "first", tmp_path / "again"
    assert (
        main(
            [
                "run",
                "two-pinned",
                "--n",
                "5",
                "--sigma",
                "0.9",
                "--delta",
                "0.15",
                "--seed",
                "3",
                "--duration",
                "20",
                "--dt",
                "0.005",
                "--sample-dt",
                "0.05",
                "--quiet",
                "--out",
                str(first),
            ]
        )
        == 0
    )
    assert main(["run", "--from", str(first / "summary.json"), "--out", str(again), "--quiet"]) == 0
    with np.load(first / "trajectory.npz") as a, np.load(again / "trajectory.npz") as b:
        np.testing.assert_array_equal(a["theta"], b["theta"])
    s1, s2 = (json.loads((p / "summary.json").read_text()) for p in (first, again))
    assert s1["parameters"] == s2["parameters"] and s1["numerics"] == s2["numerics"] and s1["results"] == s2["results"]
    # an option beside --from overrides the record
    assert main(["run", "--from", str(first), "--duration", "30", "--out", str(tmp_path / "longer"), "--quiet"]) == 0
    assert json.loads((tmp_path / "longer" / "summary.json").read_text())["numerics"]["duration"] == 30


def test_reproduce_records_provenance(tmp_path):
    from elastoactive.report.reproduce import reproduce

    reproduce(tmp_path, "tiny", 1, ["stability"], progress=False, log=lambda *a: None)
    assert json.loads((tmp_path / "provenance.json").read_text())["versions"]["mujoco"]
    assert "## Provenance" in (tmp_path / "report.md").read_text()
    assert "provenance" in json.loads((tmp_path / "stability.json").read_text())


def test_engines_compare_irregular_beats_by_their_statistics():
    """With noise the beat is irregular: validate compares cycle statistics (z-scores), not single numbers."""
    from elastoactive.checks.validate import Z_AGREE, compare, format_table

    c = compare(ea.Physics(noise=0.1), ea.Numerics(), 400)
    assert c.mujoco.periodic is False and c.statistics is not None
    assert c.statistics["z"] <= Z_AGREE and c.worst() < 0.01
    assert "irregular beat" in format_table([c])
    regular = compare(ea.Physics(n=4, sigma=1.2), ea.Numerics(), 200)
    assert regular.statistics is None

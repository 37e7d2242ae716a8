"""`elastoactive run` and `validate` end to end: the files a user opens."""

import json

import numpy as np
import pytest

from elastoactive.cli import build_parser, main


@pytest.mark.parametrize(
    "scene,extra,keys",
    [
        ("one-pinned", [], {"amplitude", "frequency"}),
        ("two-pinned", ["--delta", "0.1"], {"amplitude", "frequency", "snap_amplitude"}),
        ("rotating-pin", [], {"amplitude", "frequency", "rotation_rate"}),
        ("coupled-pair", ["--kappa", "2"], {"amplitude", "frequency", "frequency_mismatch"}),
    ],
)
@pytest.mark.parametrize("engine", ["mujoco", "reduced"])
def test_run_writes_summary_and_trajectory(tmp_path, scene, extra, keys, engine):
    out = tmp_path / "run"
    argv = [
        "run",
        scene,
        "--n",
        "4",
        "--sigma",
        "1.2",
        "--duration",
        "30",
        "--engine",
        engine,
        "--out",
        str(out),
        "--quiet",
        *extra,
    ]
    assert main(argv) == 0
    summary = json.loads((out / "summary.json").read_text())
    irregular = {"sensitivity"} if summary["results"]["periodic"] is False else set()  # its numbers' errors
    assert set(summary["results"]) == keys | {"periodic", "period_spread", "notes", "harmonics"} | irregular
    assert summary["engine"] == engine and summary["wall_time_s"] > 0
    assert summary["parameters"]["n"] == 4 and summary["parameters"]["sigma"] == 1.2
    assert summary["numerics"]["duration"] == 30
    pair = scene == "coupled-pair"
    if pair:
        assert len(summary["results"]["amplitude"]) == 2 and summary["parameters"]["kappa"] == 2
    else:
        assert "kappa" not in summary["parameters"]  # only what the scene uses
    with np.load(out / "trajectory.npz") as f:
        t, theta = f["t"], f["theta"]
    assert t[0] == 0 and t[-1] == pytest.approx(30)
    assert theta.shape == (t.size, 8 if pair else 4)


def test_engines_agree_through_the_cli(tmp_path):
    results = {}
    for engine in ("mujoco", "reduced"):
        main(["run", "one-pinned", "--duration", "150", "--engine", engine, "--out", str(tmp_path / engine), "--quiet"])
        results[engine] = json.loads((tmp_path / engine / "summary.json").read_text())["results"]
    assert results["mujoco"]["amplitude"] == pytest.approx(results["reduced"]["amplitude"], rel=0.01)
    assert results["mujoco"]["frequency"] == pytest.approx(results["reduced"]["frequency"], rel=0.01)


def test_help_speaks_the_papers_language():
    text = build_parser()._subparsers._group_actions[0].choices["run"].format_help()
    for word in ("--n", "--sigma", "--delta", "--kappa", "--rho", "--duration", "--engine", "--seed", "tau"):
        assert word in text


def test_validate_one_scene(capsys):
    assert main(["validate", "rotating-pin", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "rotating-pin N=7" in out and "PASS" in out


def test_help_loads_no_heavy_library():
    """`elastoactive --help` (and the import of the CLI and every registered scene and term) must stay fast: none of
    scipy, numba, mujoco, matplotlib or xarray is loaded until a command runs. A plug-in that imports one at module
    level slows every command by tenths of a second (scipy.optimize alone is ~0.3 s)."""
    import subprocess
    import sys

    code = (
        "import sys, runpy; sys.argv = ['elastoactive', '--help']\n"
        "try:\n    runpy.run_module('elastoactive', run_name='__main__')\nexcept SystemExit:\n    pass\n"
        "heavy = [m for m in ('scipy', 'numba', 'mujoco', 'matplotlib', 'xarray') if m in sys.modules]\n"
        "print(','.join(heavy), file=sys.stderr)"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.stderr.strip().splitlines()[-1:] in ([], [""]), result.stderr


@pytest.mark.parametrize(
    "argv",
    [["run", "lattice", "--rings", "1.5"], ["run", "lattice", "--boundary", "foo"], ["validate", "bogus"], ["bogus"]],
)
def test_argument_errors_are_one_line(argv, capsys):
    """argparse's own errors (a number that is not one, an invalid choice) are one 'elastoactive: error:' line naming
    the command, like every other refusal (they had printed the whole usage block first)."""
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("elastoactive: error:") and "--help" in err[0], err

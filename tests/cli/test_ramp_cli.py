"""`elastoactive ramp`: from a saved run's last state, the ramped parameter not fixed beside it, one-line refusals."""

import json

from elastoactive.cli import main


def test_a_ramp_starts_from_a_saved_run(tmp_path, capsys):
    run = [
        "run",
        "trapped-unit",
        "--Pi",
        "2",
        "--alignment-length",
        "0.5",
        "--trap",
        "1",
        "--duration",
        "20",
        "--engine",
        "reduced",
    ]
    assert main([*run, "--out", str(tmp_path / "run"), "--quiet"]) == 0
    ramp = [
        "ramp",
        "trapped-unit",
        "--ramp",
        "Pi=1.5,2",
        "--alignment-length",
        "0.5",
        "--trap",
        "1",
        "--duration",
        "30",
    ]
    argv = [*ramp, "--start-from", str(tmp_path / "run"), "--out", str(tmp_path / "r.nc"), "--workers", "1"]
    assert main([*argv, "--quiet"]) == 0
    import xarray as xr

    with xr.open_dataset(tmp_path / "r.nc") as data:
        assert json.loads(data.attrs["ramp"])["start"] == f"{tmp_path / 'run'} at t = 20"
        assert (data.network_state.values == 1).all()  # collective from the first step: it started orbiting
    assert (tmp_path / "r.png").stat().st_size > 0


def test_refusals_are_one_line(tmp_path, capsys):
    base = ["ramp", "lattice", "--rings", "1", "--out", str(tmp_path / "r.nc")]
    for extra, words in (
        (["--ramp", "Pi=1,2", "--Pi", "1"], "is ramped"),
        (["--ramp", "Pi"], "NAME=VALUES"),
        (["--ramp", "Pi=1,2", "--seeds", "a"], "--seeds"),
        (["--ramp", "Pi=1,2", "--start-from", str(tmp_path)], "holds no saved run"),
        (["--ramp", "Pi=1,2", "--sigma", "0.1"], "give sigma or Pi, not both"),  # as `run` refuses it
        (["--ramp", "Pi=1,2", "--ramp", "alignment_length=0.1,0.2"], "--ramp given 2 times"),
    ):
        assert main([*base, *extra]) == 2
        err = capsys.readouterr().err
        assert words in err and err.count("\n") == 1, err


def test_run_starts_from_a_saved_run(tmp_path, capsys):
    import numpy as np

    import elastoactive as ea

    run = ["run", "lattice", "--rings", "1", "--Pi", "2", "--alignment-length", "0.1", "--engine", "reduced"]
    assert main([*run, "--duration", "10", "--out", str(tmp_path / "a"), "--quiet"]) == 0
    assert main([*run, "--duration", "10", "--start-from", str(tmp_path / "a"), "--out", str(tmp_path / "b")]) == 0
    first, then = ea.load(tmp_path / "a"), ea.load(tmp_path / "b")
    assert np.array_equal(then.nodes[0], first.nodes[-1]) and np.array_equal(then.polarity[0], first.polarity[-1])
    assert json.loads((tmp_path / "b" / "summary.json").read_text())["start"] == f"{tmp_path / 'a'} at t = 10"
    assert main([*run[:3], "3", *run[4:], "--duration", "10", "--start-from", str(tmp_path / "a")]) == 2
    assert (
        "--start-from: the run is of scene lattice (7 nodes, 1 unit), not lattice (37 nodes" in capsys.readouterr().err
    )

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
    ):
        assert main([*base, *extra]) == 2
        err = capsys.readouterr().err
        assert words in err and err.count("\n") == 1, err

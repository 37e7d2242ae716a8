"""`elastoactive ramp`: a step whose measuring fails is still a step run; its error is recorded and the ramp goes on
from its end."""

import numpy as np

from elastoactive import protocols
from elastoactive.cli import main

RAMP = ["ramp", "one-pinned", "--ramp", "sigma=0.5,0.8", "--n", "4", "--duration", "4", "--workers", "1", "--quiet"]


def test_a_step_whose_measuring_fails_is_recorded_as_its_error(tmp_path, monkeypatch, capsys):
    measure, calls = protocols.measure, []

    def fails_first(traj, transient=None):
        calls.append(traj.physics.sigma)
        if len(calls) == 1:
            raise IndexError("index 0 is out of bounds for axis 0 with size 0")
        return measure(traj, transient)

    monkeypatch.setattr(protocols, "measure", fails_first)
    assert main([*RAMP, "--out", str(tmp_path / "r.nc")]) == 0
    err = capsys.readouterr().err
    assert "4 steps run, 1 not measured" in err
    assert "not measured: IndexError: index 0 is out of bounds for axis 0 with size 0" in err
    import xarray as xr

    with xr.open_dataset(tmp_path / "r.nc") as data:
        up = data.sel(seed=0, direction="up")
        assert up.error.values.tolist() == ["IndexError: index 0 is out of bounds for axis 0 with size 0", ""]
        assert np.isnan(up.amplitude.values[0]) and np.isfinite(up.amplitude.values[1])
        assert (data.order.values >= 0).all()  # every step ran
    assert calls == [0.5, 0.8, 0.8, 0.5]


def test_a_ramp_none_of_whose_steps_is_measured_exits_1(tmp_path, monkeypatch, capsys):
    def fails(traj, transient=None):
        raise ValueError("no samples")

    monkeypatch.setattr(protocols, "measure", fails)
    assert main([*RAMP, "--out", str(tmp_path / "r.nc")]) == 1
    err = capsys.readouterr().err
    assert "4 not measured" in err and "not measured: ValueError: no samples" in err
    assert (tmp_path / "r.nc").is_file() and not (tmp_path / "r.png").exists()

"""`elastoactive sweep`: a point whose measuring fails is that point's error (its simulation's wall time kept); the
other points are measured and the sweep is a result."""

import math

from elastoactive import batch
from elastoactive.cli import main


def test_a_point_whose_measuring_fails_is_its_error(tmp_path, monkeypatch, capsys):
    measure = batch.measure

    def fails_at_half(traj, transient=None):
        if traj.physics.sigma == 0.5:
            raise IndexError("index 0 is out of bounds for axis 0 with size 0")
        return measure(traj, transient)

    monkeypatch.setattr(batch, "measure", fails_at_half)
    argv = ["sweep", "one-pinned", "--n", "4", "--grid", "sigma=0.5,0.8", "--duration", "4", "--engine", "reduced"]
    assert main([*argv, "--workers", "1", "--quiet", "--out", str(tmp_path / "s.nc")]) == 0
    assert "IndexError: index 0 is out of bounds" in capsys.readouterr().err
    import xarray as xr

    with xr.open_dataset(tmp_path / "s.nc") as data:
        assert data.status.values.tolist() == ["error", "ok"]
        assert data.error.values[0] == "IndexError: index 0 is out of bounds for axis 0 with size 0"
        assert math.isnan(float(data.amplitude.values[0])) and math.isfinite(float(data.amplitude.values[1]))
        assert float(data.wall_time_s.values[0]) > 0

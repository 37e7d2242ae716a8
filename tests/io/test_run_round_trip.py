"""A run's files read back bit for bit: a trajectory saved as `elastoactive run --out` writes it, read by `ea.load`
and by `render`, and re-run by `run --from`, gives the very arrays of the simulation (both engines are deterministic),
for a planar chain, a chain in three dimensions and a network read from a file."""

import json

import pytest

import elastoactive as ea
from elastoactive import records
from elastoactive.cli import main
from elastoactive.cli import render as render_cli

ARRAYS = ("t", "theta", "head", "polarity", "nodes")

NETWORK = {
    "nodes": [[0, 0], [1, 0], [0.5, 0.866], [1.5, 0.866], [1, 1.732]],
    "bonds": [[0, 1], [1, 2], [0, 2], [1, 3], [2, 3], [2, 4], [3, 4]],
    "pinned": [0, 1, 3],
}


def _same(a, b) -> None:
    for name in ARRAYS:
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), name


def _save(out, physics, numerics, duration, engine):
    """Simulate and save as `elastoactive run --out` does; returns the trajectory in memory."""
    physics = records.resolved_inputs(physics)
    inputs = records.run_inputs(physics)
    traj = ea.simulate(physics, numerics, duration=duration, engine=engine)
    record = records.summary(traj, numerics, duration, sensitivity=False)
    if inputs.as_dict():
        record["inputs"] = inputs.as_dict()
    records.write_run(out, traj, record, inputs.copies)
    return traj


@pytest.mark.parametrize(
    "physics, duration, engine",
    [
        (dict(scene="one-pinned", n=4, sigma=0.8), 5.0, "mujoco"),
        (dict(scene="clamped-3d", n=3, sigma=2.5), 3.0, "mujoco"),
        (dict(scene="network", geometry="net.json", sigma=0.2, alignment_length=0.1), 5.0, "reduced"),
    ],
    ids=["chain", "clamped-3d", "network-file"],
)
def test_save_load_render_and_run_from_are_bit_identical(tmp_path, monkeypatch, capsys, physics, duration, engine):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "net.json").write_text(json.dumps(NETWORK))
    numerics = ea.Numerics(sample_dt=0.05)
    traj = _save(tmp_path / "run", ea.Physics(**physics), numerics, duration, engine)
    loaded = ea.load(tmp_path / "run")
    _same(loaded, traj)
    assert loaded.physics == traj.physics
    drawn = {}
    monkeypatch.setattr(render_cli, "_render", lambda t, *args, **kwargs: drawn.setdefault("traj", t) and 0)
    assert main(["render", str(tmp_path / "run"), "--still", str(tmp_path / "still.png")]) == 0
    _same(drawn["traj"], traj)
    assert main(["run", "--from", str(tmp_path / "run"), "--quiet", "--out", str(tmp_path / "again")]) == 0
    _same(ea.load(tmp_path / "again"), traj)
    again = json.loads((tmp_path / "again" / "summary.json").read_text())
    first = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert again["parameters"] == first["parameters"] and again["numerics"] == first["numerics"]
    capsys.readouterr()

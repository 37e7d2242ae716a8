"""Turn a trajectory into the numbers a run reports, and write a run's files."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

from .analysis import observables as obs
from .params import Numerics, Physics
from .trajectory import Trajectory


def default_transient(duration: float) -> float:
    """Time discarded before measuring the steady state: half the run."""
    return 0.5 * duration


def measure(traj: Trajectory, transient: float | None = None) -> dict:
    """amplitude and frequency of Theta = theta_N - theta_1 (per chain for the pair, as lists),
    plus snap_amplitude (two-pinned), rotation_rate (rotating pin), frequency_mismatch (pair)."""
    t = traj.t
    transient = default_transient(t[-1] - t[0]) if transient is None else transient
    physics = traj.physics
    chains = [traj.chain(k) for k in range(physics.n_chains)]
    curvatures = [obs.curvature(c) for c in chains]
    amplitudes = [obs.amplitude(t, x, transient) for x in curvatures]
    frequencies = [obs.frequency(t, x, transient) if a > 1e-6 else 0.0 for a, x in zip(amplitudes, curvatures)]
    out: dict = {}
    if physics.n_chains == 1:
        out["amplitude"], out["frequency"] = amplitudes[0], frequencies[0]
    else:
        out["amplitude"], out["frequency"] = amplitudes, frequencies
        oscillating = all(a > 1e-3 for a in amplitudes)
        out["frequency_mismatch"] = (
            obs.frequency_mismatch(t, curvatures[0], curvatures[1], transient) if oscillating else float("nan")
        )
    if physics.scene == "two-pinned" and physics.n >= 3:
        out["snap_amplitude"] = obs.snap_amplitude(traj.theta, t, transient)
    if physics.scene == "rotating-pin":
        out["rotation_rate"] = obs.rotation_rate(t, traj.theta, transient)
    return out


def summary(traj: Trajectory, numerics: Numerics, duration: float, transient: float | None = None) -> dict:
    """Everything summary.json holds: parameters, numerical settings, wall time and results."""
    transient = default_transient(duration) if transient is None else transient
    settings = dataclasses.asdict(numerics)
    if traj.engine == "reduced":
        settings = {k: settings[k] for k in ("sample_dt", "perturbation", "seed")}
    return {
        "engine": traj.engine,
        "parameters": traj.physics.relevant(),
        "numerics": {**settings, "duration": duration, "transient": transient},
        "wall_time_s": traj.wall_time_s,
        "results": measure(traj, transient),
        "solver": traj.info,
    }


def _jsonable(value):
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return None if not np.isfinite(value) else float(value)
    if isinstance(value, np.integer):
        return int(value)
    return value


def write_run(out: Path, traj: Trajectory, summary_dict: dict) -> None:
    """summary.json and trajectory.npz (t in tau, theta: one column per particle)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.json").write_text(json.dumps(_jsonable(summary_dict), indent=2) + "\n")
    np.savez_compressed(out / "trajectory.npz", t=traj.t, theta=traj.theta, scene=traj.physics.scene, n=traj.physics.n)


def load_trajectory(path: Path, physics: Physics | None = None) -> Trajectory:
    """Read a trajectory.npz written by write_run (the physics from summary.json beside it)."""
    path = Path(path)
    if path.is_dir():
        path = path / "trajectory.npz"
    with np.load(path) as f:
        t, theta = f["t"], f["theta"]
    if physics is None:
        summary_file = path.with_name("summary.json")
        if not summary_file.exists():
            raise FileNotFoundError(f"{summary_file} not found: pass the physics explicitly")
        physics = Physics(**json.loads(summary_file.read_text())["parameters"])
    return Trajectory(t=t, theta=theta, physics=physics, engine="file")

"""A run's folder, written: summary.json and trajectory.npz with their checksums and provenance, the run's inputs
(RunInputs: its network file, plug-in files, start state) and their copies, as `elastoactive run --out` and `ea.save`
write it and `ea.load`, `run --from` and `render` read it.

The folder is checked before the run (`check_destination`, `trajectory_bytes`: a long run is never lost to an output
that cannot take it); after the run, `write_folder` writes the trajectory first, with a summary that says it is not
measured yet, then measures and replaces the summary by the measured one: a measuring failure is recorded in
summary.json (`measure_error`) and never loses the trajectory.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

from . import plugins
from .core.errors import ParameterError
from .core.params import Numerics, Physics, option
from .core.trajectory import Trajectory
from .io.outputs import provenance, utc_now
from .records import (
    RunInputs,
    RunWriteError,
    error_line,
    read_summary,
    rewrite_summary,
    run_inputs,
    summary,
    unmeasured_summary,
    write_run,
)
from .starts import Start


@dataclass(frozen=True)
class RunSettings:
    """How a trajectory was run, as its summary records it: the numerics as resolved for its duration (the gate's),
    the duration, the state it started from (None: the scene's seeded state) and the folder that state came from."""

    numerics: Numerics
    duration: float
    start: Start | None = None
    start_path: str | None = None


@dataclass(frozen=True)
class Written:
    """What `write_folder` did: the summary it wrote last (summary.json's record; its `results` null when measuring
    failed), the measuring failure in one line (None: measured), and the write's failure (None: both files written),
    for the caller to raise once the results are shown."""

    summary: dict
    measure_error: str | None = None
    write_error: OSError | None = None


def trajectory_bytes(physics: Physics, samples: int) -> int:
    """About the size of a run's trajectory.npz, uncompressed (compression gains ~10% on a moving chain): t and the
    scene's recorded columns per sample (Scene.record_columns: a chain's angles and moving pivot, a network's nodes and
    polarities), 8 bytes each."""
    return 8 * (1 + physics.scene_def.record_columns(physics)) * int(samples)


def check_destination(
    out: Path,
    physics: Physics,
    numerics: Numerics,
    engine: str,
    duration: float,
    transient: float,
    force: bool,
    name: str = "out",
) -> None:
    """Refuse, before simulating, a folder `out` (the caller's argument `name`) that holds a run with other settings,
    unless `force`."""
    if force or not (out / "summary.json").exists():
        return
    try:
        old = read_summary(out)
    except ParameterError:
        old = {}
    new_settings = {"engine": engine, "parameters": physics.relevant(), "duration": duration, "transient": transient}
    old_settings = {
        "engine": old.get("engine"),
        "parameters": old.get("parameters"),
        "duration": (old.get("numerics") or {}).get("duration"),
        "transient": (old.get("numerics") or {}).get("transient"),
    }
    old_numerics = {k: v for k, v in (old.get("numerics") or {}).items() if k not in ("duration", "transient")}
    new_numerics = {k: getattr(numerics, k) for k in old_numerics if hasattr(numerics, k)}
    differences = [k for k in new_settings if new_settings[k] != old_settings[k]]
    differences += [k for k in old_numerics if old_numerics[k] != new_numerics.get(k)]
    if differences:
        raise ParameterError(
            f"{option(name, str(out))} already holds a run with other settings ({', '.join(differences)} differ); "
            f"choose another folder, or pass {option('force')} to replace it"
        )


def write_folder(
    out: Path | None,
    traj: Trajectory,
    settings: RunSettings,
    transient: float,
    *,
    started: str | None = None,
    clock: float | None = None,
) -> Written:
    """Write the run `traj` (run with `settings`, measured after `transient`) into the folder `out` (None: measure
    only), with its provenance (`started`: the UTC time it started, `clock`: its perf_counter then; default now) and
    inputs (records.run_inputs). The folder must have been checked (check_destination) and be locked by the caller
    (io.outputs.folder_lock)."""
    started = utc_now() if started is None else started
    clock = time.perf_counter() if clock is None else clock
    physics, start = traj.physics, settings.start
    state = None if start is None else {name: getattr(start, name) for name in ("theta", "positions", "polarity")}
    inputs = run_inputs(physics, state, settings.start_path)
    numerics, duration = settings.numerics, settings.duration

    def extras(s: dict) -> dict:
        if start is not None:
            s["start"] = start.source
        s["provenance"] = provenance(started, time.perf_counter() - clock)
        if needed := plugins.needed(physics):  # what `run --from` and `render` of this run load first
            s["plugins"] = needed
        if inputs.as_dict():
            s["inputs"] = inputs.as_dict()
        return s

    # the trajectory first, with a summary that says it is not measured yet: measuring never loses a finished run
    written, failed = _write(out, traj, extras(unmeasured_summary(traj, numerics, duration, transient)), inputs)
    try:
        s = extras(summary(traj, numerics, duration, transient))
    except Exception as err:  # noqa: BLE001 (whatever measuring raised: recorded, and the trajectory kept)
        line = error_line(err)
        s = extras(unmeasured_summary(traj, numerics, duration, transient, error=line))
        if written:
            rewrite_summary(out, s)
        return Written(s, line, failed)
    if written:
        rewrite_summary(out, s)
    return Written(s, None, failed)


def _write(out: Path | None, traj: Trajectory, pending: dict, inputs: RunInputs) -> tuple[bool, OSError | None]:
    """Write the run's files (its summary not yet measured: `pending`) into `out`: (whether summary.json is this
    run's now, the write's failure to raise once the results are shown)."""
    if out is None:
        return False, None
    try:
        write_run(out, traj, pending, inputs.copies)
    except RunWriteError as err:  # the trajectory could not be written; the summary maybe alone
        return err.summary is not None, err
    except OSError as err:
        return False, err
    return True, None

"""`elastoactive run SCENE`: simulate one scene, write summary.json + trajectory.npz, optionally a video.

Everything that can be checked is checked before the simulation (parameters, run length, transient,
the output folder and the video file), so a long run is never lost to a bad option; the outputs are
written atomically, with a provenance record. `--from DIR` re-runs a recorded run.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..api import simulate
from ..core import registry
from ..core.errors import ParameterError
from ..core.params import Numerics, Physics, parameter_fields
from ..core.units import CHAIN, scene_units
from ..engines import ENGINES
from ..io import tables
from ..io.outputs import check_file, check_folder, check_space, folder_lock, output_path, utc_now
from ..records import (
    STATE_ARRAYS,
    RunInputs,
    StartInput,
    jsonable,
    read_run,
    read_summary,
    recorded_numerics,
    recorded_physics,
    resolved_inputs,
    state_digest,
)
from ..reduced.settings import METHODS
from ..results import check_transient
from ..saving import RunSettings, check_destination, trajectory_bytes, write_folder
from ..starts import Start, last_state, read_start
from .fields import add_fields, help_argument, scene_argument, scene_description
from .options import UNITS, scene_help
from .render import add_video_args, check_video_options, video_after_run

DEFAULT_DURATION = 300.0


def register(subparsers) -> None:
    run = subparsers.add_parser(
        "run",
        description="Simulate one scene. " + UNITS,
        epilog=scene_help(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        conflict_handler="resolve",  # its -h: fields.SceneHelp
    )
    help_argument(run, fill)
    fill(run, None)
    run.set_defaults(func=main)


def fill(run: argparse.ArgumentParser, scene: str | None) -> None:
    """The options of `run`: every scene's (scene None), or one scene's in its own units (`run SCENE --help`)."""
    units = scene_units(registry.get(scene)) if scene else CHAIN
    if scene:
        run.description = scene_description(scene)
    scene_argument(run, nargs="?")
    physics = "physics (the paper's dimensionless numbers)" if scene is None else f"physics of {scene}"
    add_fields(run.add_argument_group(physics), Physics, defaults=False, scene=scene)
    add_fields(run.add_argument_group("numerics"), Numerics, defaults=False, scene=scene)
    run.add_argument(
        "--duration",
        type=float,
        default=None,
        help=f"simulated time in {units.time_units} (default {DEFAULT_DURATION:g})",
    )
    run.add_argument(
        "--transient",
        type=float,
        default=None,
        help=f"time discarded before measuring, {units.time_units} (default: half the run)",
    )
    run.add_argument("--engine", choices=ENGINES, default=None, help="MuJoCo scene or the reduced ODE (default mujoco)")
    run.add_argument(
        "--method",
        choices=METHODS,
        default=None,
        help="the reduced engine's ODE method (default: chosen from the stiffness at the start: "
        "numba-DOP853, or the implicit LSODA for long chains near their onset); summary.json records it",
    )
    run.add_argument(
        "--rtol",
        type=float,
        default=None,
        help="the reduced engine's relative tolerance (atol = rtol / 100; default the scene's: a chain's 1e-9, a "
        "network's 1e-9, or 1e-6 above 1500 free coordinates); summary.json records it",
    )
    run.add_argument("--out", type=output_path, help="folder for summary.json and trajectory.npz")
    run.add_argument(
        "--force",
        action="store_true",
        help="replace a run with other settings already in --out, or an existing --video file",
    )
    run.add_argument(
        "--from",
        dest="source",
        type=Path,
        metavar="SUMMARY",
        help="re-run a recorded run (its folder or summary.json) with the same scene, parameters, numerics, "
        "engine and duration; options given beside it override the recorded ones",
    )
    run.add_argument(
        "--start-from",
        type=Path,
        metavar="RUN",
        help="start from the last state of a saved run (its folder) instead of the scene's seeded state (a network's "
        "nodes and polarities, a chain's angles); summary.json records it",
    )
    run.add_argument(
        "--quiet", action="store_true", help="no progress bar, and the results on one line (nothing else on stdout)"
    )
    run.add_argument(
        "--json",
        action="store_true",
        help="print the results as JSON (wall time, every observable, notes, harmonics) instead of a table",
    )
    run.add_argument("--video", type=output_path, help="also render the run to this MP4 (see `elastoactive render -h`)")
    add_video_args(run, time_units=units.time_units)


@dataclass(frozen=True)
class Recorded:
    """What --from re-runs: the recorded run's physics parameters (its network file as located: RunInputs), numerics,
    duration, transient, engine, the reduced engine's method and tolerances, the state it started from (None: the
    scene's seeded state), where that state came from, and one note per input that changed since the run."""

    physics: dict
    numerics: dict
    duration: float | None = None
    transient: float | None = None
    engine: str | None = None
    method: str | None = None
    rtol: float | None = None
    atol: float | None = None
    start: Start | None = None
    start_path: str | None = None
    notes: tuple[str, ...] = ()


NOTHING_RECORDED = Recorded(physics={}, numerics={})


def _recorded(path: Path) -> Recorded:
    """What --from re-runs of the record at `path` (a run's folder or its summary.json)."""
    path = Path(path)
    folder = path if path.is_dir() else path.parent
    what = f"run --from {path}"
    s = read_summary(path)
    physics, notes = recorded_physics(s, folder, what)
    parameters = dict(s["parameters"])
    if "geometry" in parameters:  # the network file the run read: the original, or the run's copy of it
        parameters["geometry"] = physics.geometry
    numerics = dict(s.get("numerics", {}))
    solver = s.get("solver") or {}
    method = solver.get("method")  # the reduced engine's ODE method, as it ran
    rtol, atol = (solver.get(k) for k in ("rtol", "atol"))  # and its tolerances
    start = RunInputs.of(s, f"{what}: summary.json").start
    return Recorded(
        physics=parameters,
        duration=numerics.pop("duration", None),
        transient=numerics.pop("transient", None),
        numerics=numerics,
        engine=s.get("engine", "mujoco"),
        method=method if method in METHODS else None,
        rtol=rtol if isinstance(rtol, (int, float)) else None,
        atol=atol if isinstance(rtol, (int, float)) and isinstance(atol, (int, float)) else None,
        start=None if start is None else _recorded_start(folder, start, s.get("start"), what),
        start_path=None if start is None else start.path,
        notes=tuple(notes),
    )


def _recorded_start(folder: Path, record: StartInput, source, what: str) -> Start:
    """The state a recorded run started from: its folder's copy, else the last state of the start run if that is
    still the same state (state_digest); refused otherwise."""
    source = source if isinstance(source, str) else record.path
    try:
        with np.load(folder / record.copy) as f:
            arrays = {name: np.asarray(f[name], dtype=float) for name in STATE_ARRAYS if name in f.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile):
        arrays = {}
    if arrays and state_digest(arrays) == record.state_sha256:
        return Start(**arrays, source=source)
    try:
        traj, _ = read_run(Path(record.path), what=what)
        start = last_state(traj, source=record.path)
    except ParameterError:
        start = None
    if start is not None and state_digest(_state_arrays(start)) == record.state_sha256:
        return dataclasses.replace(start, source=source)
    raise ParameterError(
        f"{what}: the state it started from (sha256 {record.state_sha256[:12]}) is neither in its "
        f"{record.copy} nor the last state of {record.path} now; give --start-from"
    )


def _state_arrays(start: Start) -> dict:
    return {name: getattr(start, name) for name in STATE_ARRAYS}


def settings_from(args, record: Recorded | None = None) -> tuple[Physics, Numerics, str, float, float | None]:
    """physics, numerics, engine, duration, transient: the recorded run's (--from; `record`, read from args.source
    when not given), overridden by options given. A network file is named by its absolute path."""
    base = record if record is not None else (_recorded(args.source) if args.source else NOTHING_RECORDED)
    recorded_physics_ = dict(base.physics)
    recorded_scene = recorded_physics_.pop("scene", None)
    scene = args.scene or recorded_scene
    if scene is None:
        raise ParameterError("give a SCENE (or --from a recorded run)")
    given = lambda cls: {
        f.name: getattr(args, f.name) for f in parameter_fields(cls) if getattr(args, f.name) is not None
    }
    # the recorded physics, then the options given (a value that stops acting, like contact_radius once --no-contact
    # is given, is dropped; one given where it does not act is refused)
    physics = Physics(scene=recorded_scene or scene, **recorded_physics_).replace(scene=scene, **given(Physics))
    physics.require_acting(given(Physics))  # an option typed where it does not act, even at its default
    physics = resolved_inputs(physics)
    engine = args.engine or base.engine or "mujoco"
    recorded_numerics_ = dict(base.numerics)
    if base.engine and engine != base.engine and engine in ENGINES:  # the record's settings the engine reads
        recorded_numerics_ = {k: v for k, v in recorded_numerics_.items() if k in recorded_numerics(engine, physics)}
    numerics = Numerics(**{**recorded_numerics_, **given(Numerics)})
    duration = args.duration if args.duration is not None else (base.duration or DEFAULT_DURATION)
    transient = args.transient if args.transient is not None else (base.transient if args.duration is None else None)
    # a large network's and a long run's automatic sample_dt, recorded as it ran
    numerics = physics.scene_def.record_numerics(physics, numerics, duration).for_duration(duration)
    return physics, numerics, engine, numerics.check_duration(duration), transient


def check_rerun(args, physics: Physics, engine: str) -> None:
    """`--from`: refuse a record that lacks a setting the re-run needs (and no option gives it), rather than fill
    it with a default that the recorded run may not have used."""
    s = read_summary(args.source)
    numerics = s.get("numerics") or {}
    needed = {
        "engine": s.get("engine") is None and args.engine is None,
        "duration": numerics.get("duration") is None and args.duration is None,
    }
    needed.update(
        {
            name: name not in s["parameters"] and getattr(args, name, None) is None
            for name in physics.relevant()
            if name != "scene"
        }
    )
    needed.update(
        {
            name: numerics.get(name) is None and getattr(args, name) is None
            for name in (recorded_numerics(engine, physics) if engine in ENGINES else ())
        }
    )
    missing = [name for name, lacking in needed.items() if lacking]
    if missing:
        options = " ".join(f"--{name.replace('_', '-')}" for name in missing)
        raise ParameterError(
            f"--from {args.source}: the record has no {', '.join(missing)}, so it cannot be re-run "
            f"exactly; give {options}"
        )


def main(args) -> int:
    if not args.out:
        return _run(args, None)
    check_folder(Path(args.out))  # a file or an unwritable place is named as such, before the lock creates it
    with folder_lock(Path(args.out)):  # the destination's check and the write, with no other run in between
        return _run(args, Path(args.out))


def _warn(note: str) -> None:
    print(f"elastoactive: warning: {note}", file=sys.stderr)


def _start(args, record: Recorded) -> tuple[Start | None, str | None]:
    """The state the run starts from and the folder it comes from (absolute): --start-from's last state, else the
    recorded run's start (--from), else None (the scene's seeded state)."""
    if args.start_from is None:
        return record.start, record.start_path
    folder = Path(args.start_from).expanduser().resolve()
    if not (folder / "trajectory.npz").is_file():
        read_start(folder)  # refuses in one line: not a saved run
    traj, notes = read_run(folder, what=f"--start-from {args.start_from}")
    for note in notes:
        _warn(note)
    return last_state(traj, source=str(folder)), str(folder)


def _run(args, out: Path | None) -> int:
    started, clock = utc_now(), time.perf_counter()
    record = _recorded(args.source) if args.source else NOTHING_RECORDED
    for note in record.notes:
        _warn(note)
    physics, numerics, engine, duration, transient = settings_from(args, record)
    if args.source:
        check_rerun(args, physics, engine)
    samples = numerics.sample_times(duration)
    transient = check_transient(duration, transient, samples)
    if out:
        check_destination(out, physics, numerics, engine, duration, transient, args.force, "out")
        check_space(
            out,
            trajectory_bytes(physics, samples.size),
            "trajectory.npz",
            advice=", or record fewer samples (--sample-dt, --duration)",
        )
    if args.video:
        check_file(args.video, "--video", (".mp4",), force=args.force)
        check_video_options(args, duration)
    # --from repeats the reduced engine's recorded method (the automatic choice would pick it again; a given one too)
    method = args.method or (record.method if args.source and engine == "reduced" else None)
    tolerances = {"rtol": args.rtol, "atol": None}  # given; else --from repeats the recorded run's, to the bit
    if args.rtol is None and args.source and engine == "reduced":
        tolerances = {"rtol": record.rtol, "atol": record.atol}
    start, start_path = _start(args, record)
    if start is not None:  # a state of this scene, refused naming the option that gave it (elastoactive.starts)
        start.checked(physics, "--start-from" if args.start_from else "--from")
    traj = simulate(
        physics,
        numerics,
        duration=duration,
        engine=engine,
        progress=not args.quiet,
        method=method,
        start=start,
        **tolerances,
    )
    settings = RunSettings(numerics, duration, start, start_path)
    written = write_folder(out, traj, settings, transient, started=started, clock=clock)  # as ea.save writes it
    s, failed = written.summary, written.write_error
    if written.measure_error is not None:
        if failed is not None:
            raise failed from None
        kept = f"; the trajectory is kept in {out / 'trajectory.npz'} and {out / 'summary.json'} records the error"
        print(
            f"elastoactive: error: measuring the run failed ({written.measure_error}){kept if out else ''}",
            file=sys.stderr,
        )
        if args.video:
            video_after_run(args, traj, numerics)
        return 1
    # the results first: shown even if the files cannot be written
    _print_results(args, s, engine, duration)
    for note in s["results"].get("notes", []):
        _warn(note)
    if failed is not None:
        raise failed
    if out and not args.quiet:  # stdout holds the results alone with --json
        print(
            f"wrote {out / 'summary.json'} and {out / 'trajectory.npz'}", file=sys.stderr if args.json else sys.stdout
        )
    if args.video:  # rendered from the recorded trajectory, after the simulation
        return video_after_run(args, traj, numerics)
    return 0


def _print_results(args, s: dict, engine: str, duration: float) -> None:
    """The run's results on stdout (io.tables): a table with units, one line with --quiet, the JSON with --json."""
    units = s.get("units") or {}
    wall = round(s["wall_time_s"], 3)
    title = f"{s['parameters']['scene']}, {engine}: {duration:g} {units.get('time', '')} in {wall:g} s of wall time"
    record = jsonable({"wall_time_s": wall, **s["results"]})
    text = tables.results_text(
        record, s["results"], units.get("results") or {}, as_json=args.json, quiet=args.quiet, title=title
    )
    if text:
        print(text)

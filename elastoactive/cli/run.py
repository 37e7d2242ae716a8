"""`elastoactive run SCENE`: simulate one scene, write summary.json + trajectory.npz, optionally a video.

Everything that can be checked is checked before the simulation (parameters, run length, transient,
the output folder and the video file), so a long run is never lost to a bad option; the outputs are
written atomically, with a provenance record. `--from DIR` re-runs a recorded run.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from .. import plugins
from ..api import simulate
from ..core import registry
from ..core.errors import ParameterError
from ..core.params import Numerics, Physics, parameter_fields
from ..core.units import CHAIN, scene_units
from ..engines import ENGINES
from ..io.outputs import check_file, check_folder, check_space, folder_lock, output_path, provenance, utc_now
from ..reduced.settings import METHODS
from ..results import check_transient, jsonable, read_summary, recorded_numerics, summary, write_run
from ..starts import read_start
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
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.add_argument("--video", type=output_path, help="also render the run to this MP4 (see `elastoactive render -h`)")
    add_video_args(run, time_units=units.time_units)


def _recorded(path: Path) -> dict:
    """What --from re-runs: scene, physics, numerics, engine, duration and transient of a summary.json."""
    s = read_summary(path)
    numerics = dict(s.get("numerics", {}))
    method = (s.get("solver") or {}).get("method")  # the reduced engine's ODE method, as it ran
    rtol, atol = ((s.get("solver") or {}).get(k) for k in ("rtol", "atol"))  # and its tolerances
    return {
        "physics": dict(s["parameters"]),
        "duration": numerics.pop("duration", None),
        "transient": numerics.pop("transient", None),
        "numerics": numerics,
        "engine": s.get("engine", "mujoco"),
        "method": method if method in METHODS else None,
        "rtol": rtol if isinstance(rtol, (int, float)) else None,
        "atol": atol if isinstance(rtol, (int, float)) and isinstance(atol, (int, float)) else None,
    }


def settings_from(args) -> tuple[Physics, Numerics, str, float, float | None]:
    """physics, numerics, engine, duration, transient: the recorded run's (--from), overridden by options given."""
    base = (
        _recorded(args.source)
        if args.source
        else {"physics": {}, "numerics": {}, "engine": None, "duration": None, "transient": None}
    )
    recorded_scene = base["physics"].pop("scene", None)
    scene = args.scene or recorded_scene
    if scene is None:
        raise ParameterError("give a SCENE (or --from a recorded run)")
    given = lambda cls: {
        f.name: getattr(args, f.name) for f in parameter_fields(cls) if getattr(args, f.name) is not None
    }
    # the recorded physics, then the options given (a value that stops acting, like contact_radius once --no-contact
    # is given, is dropped; one given where it does not act is refused)
    physics = Physics(scene=recorded_scene or scene, **base["physics"]).replace(scene=scene, **given(Physics))
    physics.require_acting(given(Physics))  # an option typed where it does not act, even at its default
    engine = args.engine or base["engine"] or "mujoco"
    if base["engine"] and engine != base["engine"] and engine in ENGINES:  # the record's settings the engine reads
        base["numerics"] = {k: v for k, v in base["numerics"].items() if k in recorded_numerics(engine, physics)}
    numerics = Numerics(**{**base["numerics"], **given(Numerics)})
    duration = args.duration if args.duration is not None else (base["duration"] or DEFAULT_DURATION)
    transient = args.transient if args.transient is not None else (base["transient"] if args.duration is None else None)
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


def _check_destination(
    out: Path, physics: Physics, numerics: Numerics, engine: str, duration: float, transient: float, force: bool
) -> None:
    """Refuse, before simulating, an --out that cannot be written or that holds another run."""
    check_folder(out)
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
            f"--out {out} already holds a run with other settings ({', '.join(differences)} differ); "
            "choose another folder, or pass --force to replace it"
        )


def trajectory_bytes(physics: Physics, samples: int) -> int:
    """About the size of a run's trajectory.npz, uncompressed (compression gains ~10% on a moving chain): t and the
    scene's recorded columns per sample (Scene.record_columns: a chain's angles and moving pivot, a network's nodes and
    polarities), 8 bytes each."""
    return 8 * (1 + physics.scene_def.record_columns(physics)) * int(samples)


def main(args) -> int:
    if not args.out:
        return _run(args, None)
    check_folder(Path(args.out))  # a file or an unwritable place is named as such, before the lock creates it
    with folder_lock(Path(args.out)):  # the destination's check and the write, with no other run in between
        return _run(args, Path(args.out))


def _run(args, out: Path | None) -> int:
    started, clock = utc_now(), time.perf_counter()
    physics, numerics, engine, duration, transient = settings_from(args)
    if args.source:
        check_rerun(args, physics, engine)
    samples = numerics.sample_times(duration)
    transient = check_transient(duration, transient, samples)
    if out:
        _check_destination(out, physics, numerics, engine, duration, transient, args.force)
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
    method = args.method or (_recorded(args.source)["method"] if args.source and engine == "reduced" else None)
    tolerances = {"rtol": args.rtol, "atol": None}  # given; else --from repeats the recorded run's, to the bit
    if args.rtol is None and args.source and engine == "reduced":
        tolerances = {k: _recorded(args.source)[k] for k in ("rtol", "atol")}
    start = read_start(args.start_from).checked(physics, "--start-from") if args.start_from else None
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
    s = summary(traj, numerics, duration, transient)
    if start is not None:
        s["start"] = start.source
    s["provenance"] = provenance(started, time.perf_counter() - clock)
    if needed := plugins.needed(physics):  # what `run --from` and `render` of this run load first
        s["plugins"] = needed
    # the results first: shown even if the files cannot be written
    print(json.dumps(jsonable({"wall_time_s": round(s["wall_time_s"], 3), **s["results"]}), indent=2))
    for note in s["results"].get("notes", []):
        print(f"elastoactive: warning: {note}", file=sys.stderr)
    if out:
        write_run(out, traj, s)
        print(f"wrote {out / 'summary.json'} and {out / 'trajectory.npz'}")
    if args.video:  # rendered from the recorded trajectory, after the simulation
        return video_after_run(args, traj, numerics)
    return 0

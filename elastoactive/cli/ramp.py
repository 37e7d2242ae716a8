"""`elastoactive ramp SCENE --ramp NAME=VALUES`: one parameter up and then down in steps, each step starting from the
previous step's end, for several seeds, into one netCDF file with the direction as a coordinate, and its figure
(elastoactive.protocols). Resumable: the same command again skips the finished steps.

Exit status: 0 when the ramp finished; 2 for invalid options, a run the pre-flight check refuses, or an --out that
holds another ramp; 3 when a step diverged (rerun to resume from the last finished step).

The ramp is `ea.ramp`'s (elastoactive.explore.ramp_outcome): this module parses the options into its arguments, draws
the figure and reports. The protocols (the ramp's runner and its process pool) are imported inside `main`, the
subcommand's boundary: `elastoactive --help` loads neither the sweep package nor the pools.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..core.errors import ParameterError
from ..core.params import Numerics, Physics, parameter_fields
from ..engines import ENGINES
from ..io.outputs import output_path
from .fields import add_fields, scene_argument
from .options import UNITS

EXAMPLES = """examples:
  elastoactive ramp lattice --rings 3 --alignment-length 0.1 --ramp Pi=0.55:0.8:6 --seeds 0,1,2 \\
      --duration 400 --out loop.nc
  elastoactive ramp network --geometry kagome --size 3 --alignment-length 0.1 --ramp Pi=0.3,0.5,0.7,0.9 --out kagome.nc
  elastoactive ramp lattice --rings 2 --alignment-length 0.1 --ramp Pi=1.2:1.6:5 --start-from results/lattice \\
      --out from_run.nc

Each seed runs the values upward, then back down (the top value twice: up, then continuing down), every step for
--duration from the last state of the one before; the first from the scene's state seeded by each of --seeds, or from a
saved run's last state (--start-from). The netCDF has dims seed, direction (up, down) and the ramped parameter; one
variable per observable (network runs: network_state, the named state, as an index with its names in flag_meanings;
unit_rate, each unit's |net turning rate|), order (when each step ran). Re-running the same command resumes it from
its journal (OUT.journal); the same --out with another ramp is refused. Results: xarray.open_dataset(OUT)."""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "ramp",
        description="Ramp one parameter up and then down in steps, each step starting from the previous step's end, "
        "for several seeds; write the measurements as one netCDF file with the direction as a coordinate (the "
        "hysteresis loop as data) and its figure; resumable. " + UNITS,
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    scene_argument(p)
    p.add_argument(
        "--ramp",
        required=True,
        action="append",
        metavar="NAME=VALUES",
        help="the parameter and its values upward: a comma list (Pi=0.6,0.7,0.8) or start:stop:num (Pi=0.6:0.8:5, "
        "ends included); NAME a real-valued physics parameter (Pi, the elasto-active coupling, on network scenes); "
        "once: a ramp steps one parameter",
    )
    p.add_argument("--seeds", default="0", help="seeds of the first step's initial state, a comma list (default 0)")
    p.add_argument(
        "--start-from",
        type=Path,
        metavar="RUN",
        help="start every seed's first step from the last state of a saved run (a folder of `elastoactive run --out`)",
    )
    add_fields(p.add_argument_group("fixed physics (defaults as in `run`)"), Physics, defaults=False)
    add_fields(p.add_argument_group("numerics"), Numerics, defaults=False)
    g = p.add_argument_group("run")
    g.add_argument("--engine", choices=ENGINES, default="reduced", help="(default %(default)s)")
    g.add_argument("--duration", type=float, default=300.0, help="simulated time per step (default %(default)s)")
    g.add_argument("--transient", type=float, help="time discarded before measuring each step (default: half)")
    g.add_argument("--out", type=output_path, required=True, help="netCDF file (resumed if it holds the same ramp)")
    g.add_argument("--figure", type=output_path, help="the loop's figure (PNG; default: OUT with .png)")
    g.add_argument(
        "--plot",
        metavar="OBSERVABLE",
        help="what the figure shows against the ramped parameter (default: polarity_speed where measured, else "
        "amplitude)",
    )
    g.add_argument("--workers", type=int, help="processes, one seed each (default: every core)")
    g.add_argument("--quiet", action="store_true", help="no progress lines")
    p.set_defaults(func=main)


def main(args) -> int:
    # the subcommand's boundary: the ramp's runner and the sweep package (see the module docstring)
    from .. import protocols
    from ..explore import ramp_outcome
    from ..starts import read_start

    if len(args.ramp) > 1:
        raise ParameterError(
            f"--ramp given {len(args.ramp)} times ({', '.join(args.ramp)}): a ramp steps one parameter; give one "
            "--ramp (another parameter: a ramp of its own, or a fixed value)"
        )
    ramp = args.ramp[0]
    name, _, text = ramp.partition("=")
    name = name.strip()
    if not name or not text:
        raise ParameterError(f"--ramp must be NAME=VALUES (e.g. Pi=0.6:0.8:5), got {ramp!r}")
    try:
        seeds = [int(s) for s in args.seeds.split(",")]
    except ValueError:
        raise ParameterError(f"--seeds must be a comma list of integers, got {args.seeds!r}") from None
    given = {f.name: getattr(args, f.name) for f in parameter_fields(Physics) if getattr(args, f.name) is not None}
    numerics = {f.name: getattr(args, f.name) for f in parameter_fields(Numerics) if getattr(args, f.name) is not None}
    start = read_start(args.start_from) if args.start_from else None
    if start is not None:  # refused naming the option (elastoactive.starts)
        start = start.checked(
            Physics(scene=args.scene, **{k: v for k, v in given.items() if k != name}), "--start-from"
        )
    outcome = ramp_outcome(
        {"scene": args.scene, **given},
        name,
        text,
        numerics,
        seeds=seeds,
        duration=args.duration,
        transient=args.transient,
        engine=args.engine,
        start=start,
        out=args.out,
        workers=args.workers,
        progress=not args.quiet,
    )
    none_measured = len(outcome.errors) == outcome.ran + outcome.kept  # every step's measuring failed: no loop to draw
    figure = args.figure or args.out.with_suffix(".png")
    if not none_measured:
        protocols.ramp_figure(outcome.path, figure, args.plot)
    kept = f", {outcome.kept} kept from the journal" if outcome.kept else ""
    failed = f", {len(outcome.errors)} not measured" if outcome.errors else ""
    drawn = "" if none_measured else f" and {figure}"
    steps = f"{outcome.ran} steps run{kept}{failed}, {outcome.wall_s:.1f} s"
    print(f"wrote {outcome.path} ({steps}){drawn}", file=sys.stderr)
    for err in list(dict.fromkeys(outcome.errors))[:3]:  # as a sweep's failed points: the ramp is still a result
        print(f"  not measured: {err}", file=sys.stderr)
    return 1 if none_measured else 0

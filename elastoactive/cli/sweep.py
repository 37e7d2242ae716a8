"""`elastoactive sweep SCENE --grid ...`: any grid of any scene into a resumable netCDF file.

Exit status: 0 when the sweep finished and at least one point succeeded (a partly failed sweep is a
result: its failed points are counted, their first errors shown, and `--retry-errors` runs them
again; a point refused before it ran is checked again by any re-run); 1 when every point failed (the first
error is shown); 2 for invalid options, settings the pre-flight check refuses at every point, an output that
holds another sweep or a corrupted journal, or an output that cannot be written (e.g. a full disk:
the journal is kept, re-run to resume).

The sweep is `ea.sweep`'s (elastoactive.sweep.verb.sweep_outcome): this module parses the options into its records
(a Physics, a Numerics: the verb then needs not the front door's conversions) and reports. elastoactive.sweep (its
runners, the batch and the process pool) is imported inside `fill` and `main`, the subcommand's boundary:
`elastoactive --help` does not load it.
"""

from __future__ import annotations

import argparse
import sys

from ..core import registry
from ..core.errors import ParameterError
from ..core.parameters import stochastic
from ..core.params import PRESETS, Numerics, Physics, option, parameter_fields, scene_parameters
from ..core.units import CHAIN, scene_units
from ..engines import ENGINES
from ..io.outputs import check_file, output_path
from .fields import add_fields, help_argument, scene_argument, scene_description
from .options import UNITS

EXAMPLES = """examples:
  elastoactive sweep one-pinned --grid sigma=0.2:1.0:9 --grid n=5,7,9 --duration 300 --out onset.nc
  elastoactive sweep coupled-pair --grid kappa=0:2:11 --grid rho=1,1.333 --preset fast --out pair.nc
  elastoactive sweep one-pinned --grid seed=0:9:10 --noise 0.1 --engine reduced --out noise.nc
  elastoactive sweep lattice --grid Pi=1:2:5 --alignment-length 0.1 --engine reduced --out pi.nc
  elastoactive sweep ... --scheduler tcp://10.0.0.5:8786      (run on a Dask cluster)

Grid values: a comma list (kappa=0.5,1,2) or start:stop:num (sigma=0.2:1.0:9, ends included).
MuJoCo points that share a model (e.g. along sigma, seed, noise, kappa) run together in one
mujoco.batch on every core's thread; each point also records whether its motion is periodic.
Re-running the same command continues an interrupted sweep (finished points are kept); the same
--out with a different grid or parameters is refused. Results: xarray.open_dataset(OUT).

Exit status: 0 if at least one point succeeded (failed points are counted and listed; rerun them
with --retry-errors; a point refused before it ran is checked again by any re-run), 1 if every point
failed, 2 for invalid options, settings the pre-flight check refuses at every point (before any
runs, naming a --dt that passes), or an unusable --out."""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "sweep",
        description="Run a scene at every point of a parameter grid and write the measurements (amplitude, "
        "frequency, ...) as an xarray Dataset to netCDF, point by point; resumable. " + UNITS,
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        conflict_handler="resolve",  # its -h: fields.SceneHelp
    )
    help_argument(p, fill)
    fill(p, None)
    p.set_defaults(func=main)


def fill(p: argparse.ArgumentParser, scene: str | None) -> None:
    """The options of `sweep`: every scene's (scene None), or one scene's in its own units (`sweep SCENE --help`)."""
    from ..sweep import NUMERICS_KEYS, grid_keys  # the subcommand's boundary (see the module docstring)

    units = scene_units(registry.get(scene)) if scene else CHAIN
    keys = grid_keys()
    if scene:
        p.description = scene_description(scene)
        own = scene_parameters(registry.get(scene))
        keys = tuple(k for k in keys if k in own or k in NUMERICS_KEYS)
    scene_argument(p)
    p.add_argument(
        "--grid",
        action="append",
        required=True,
        metavar="NAME=VALUES",
        help=f"a grid axis (repeat for more); NAME one of {', '.join(keys)}",
    )
    fixed = "fixed physics (off the grid; defaults as in `run`)"
    add_fields(p.add_argument_group(fixed), Physics, defaults=False, scene=scene)
    g = p.add_argument_group("numerics (default: the preset's; a given option overrides it)")
    g.add_argument(
        "--preset",
        choices=tuple(PRESETS),
        default="accurate",
        help="numerical settings (default %(default)s; fast: dt 0.01, ~4x quicker"
        + (", results within 0.3%% for the paper's N = 7 chains" if units is CHAIN else "")
        + "; stiffer structures need a smaller --dt, which a refusal names)",
    )
    add_fields(g, Numerics, defaults=False, scene=scene)
    g = p.add_argument_group("run")
    g.add_argument("--engine", choices=ENGINES, default="mujoco", help="(default %(default)s)")
    time = units.time_units
    g.add_argument(
        "--duration", type=float, default=300.0, help=f"simulated time per point, {time} (default %(default)s)"
    )
    g.add_argument("--transient", type=float, help=f"time discarded before measuring, {time} (default: half the run)")
    g.add_argument("--out", type=output_path, required=True, help="netCDF file (resumed if it holds the same sweep)")
    g.add_argument(
        "--workers",
        type=int,
        help="local threads (MuJoCo: mujoco.batch) or processes (reduced engine), >= 1 "
        "(default: every core; unused with --scheduler)",
    )
    g.add_argument(
        "--batch-size",
        type=int,
        metavar="POINTS",
        help="most MuJoCo points stepped together in one mujoco.batch (default: 8 per thread); a batch's "
        "points are saved when it ends, so an interrupted sweep loses at most the running batches",
    )
    g.add_argument(
        "--scheduler", metavar="ADDRESS", help="Dask scheduler address, e.g. tcp://host:8786 (default: this machine)"
    )
    g.add_argument("--retry-errors", action="store_true", help="when resuming, run failed points again")
    g.add_argument(
        "--no-timestep-check", action="store_true", help="run MuJoCo points beyond the linear stability limit of dt"
    )
    g.add_argument("--quiet", action="store_true", help="no progress bar")


def main(args) -> int:
    # the subcommand's boundary: the sweep package, its runners and pools (see the module docstring)
    from ..sweep import MUJOCO_ONLY, check_engine_numerics, parse_grid
    from ..sweep.verb import sweep_outcome

    if args.workers is not None and args.workers < 1:
        raise ParameterError(f"--workers must be >= 1, got {args.workers}")
    if args.batch_size is not None and args.batch_size < 1:
        raise ParameterError(f"--batch-size must be >= 1, got {args.batch_size}")
    check_file(args.out, "--out", ())  # a writable place, not under a file: one line naming --out
    grid = parse_grid(args.grid)
    fixed = {f.name: getattr(args, f.name) for f in parameter_fields(Physics) if getattr(args, f.name) is not None}
    overrides = {f.name: getattr(args, f.name) for f in parameter_fields(Numerics) if getattr(args, f.name) is not None}
    both = [k for k in grid if k in overrides or k in fixed]
    if both:
        raise ParameterError(f"{', '.join(option(k) for k in both)} given both fixed and on the grid")
    noisy = stochastic(fixed, grid)
    check_engine_numerics(args.engine, [k for k in overrides if k in MUJOCO_ONLY], noisy)
    # ea.sweep's work, without building the xarray Dataset (which would load xarray and pandas, ~0.4 s of CPU, for
    # three numbers and two texts): the options as the fields they set, the preset's numerics with those given
    outcome = sweep_outcome(
        Physics(scene=args.scene, **fixed),
        grid,
        Numerics.preset(args.preset, **overrides),
        duration=args.duration,
        engine=args.engine,
        transient=args.transient,
        out=args.out,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=not args.quiet,
        retry_errors=args.retry_errors,
        check=not args.no_timestep_check,
        batch_size=args.batch_size,
        dataset=False,
    )
    status, errors = outcome.status, outcome.error
    failed = status == "error"
    print(
        f"wrote {args.out}: {outcome.points_done} of {outcome.points_total} points over "
        f"{' x '.join(f'{k}[{v.size}]' for k, v in grid.items())}, {int(failed.sum())} failed"
    )
    if failed.size and failed.all():
        print(
            f"elastoactive: all {failed.size} points of the sweep failed; the first error: {errors[0]}", file=sys.stderr
        )
        return 1
    for err in list(dict.fromkeys(errors[failed]))[:3]:
        print(f"  failed: {err}", file=sys.stderr)
    return 0

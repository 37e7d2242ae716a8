"""Command line of the renderer: `elastoactive render RUN -o out.mp4` and `run ... --video out.mp4`.

Kept apart from elastoactive.render so that building the parser imports nothing heavy: the renderer (matplotlib,
MuJoCo and its GL set-up) and mujoco itself are imported inside the functions that render or check MUJOCO_GL, the
subcommand's boundary.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..core.errors import ParameterError
from ..io.outputs import check_file
from ..records import jsonable, read_run

RENDER_HELP = (
    "Frame k shows t = start + k * rate / fps (times in tau). The default rate makes one beat of "
    "Theta last about a second (rate = 1 / (f tau), measured on the trajectory), or one turn of a "
    "rotating chain; 10 tau/s when nothing oscillates. A chain in three dimensions is drawn in two views side by "
    "side, from the side (face on to the tip's path) and down the clamp axis, with the tip's trace. The GL back end "
    "is MUJOCO_GL if set, else egl, else osmesa."
)


def add_video_args(p: argparse.ArgumentParser, *, still: bool = False, time_units: str = "tau") -> None:
    """Options of the picture (shared by `run --video` and `render`); times in `time_units` (a scene's own help:
    units.Units.time_units)."""
    g = p.add_argument_group("video (off-screen rendering, MP4 via mediapy + imageio-ffmpeg)")
    g.add_argument("--fps", type=float, default=30.0, help="frames per second of video (default %(default)s)")
    g.add_argument(
        "--rate",
        type=float,
        default=None,
        help=f"{time_units} of simulated time per second of video (default: one beat per second)",
    )
    g.add_argument("--width", type=int, default=640, help="frame width in pixels, even (default %(default)s)")
    g.add_argument("--height", type=int, default=480, help="frame height in pixels, even (default %(default)s)")
    g.add_argument(
        "--trail",
        type=float,
        default=1.0,
        help="length of the particles' fading trails, in seconds of video; 0: none (default %(default)s)",
    )
    if still:
        g.add_argument(
            "--start", type=float, default=None, help="first time rendered, tau (default: start of the record)"
        )
        g.add_argument("--end", type=float, default=None, help="last time rendered, tau (default: end of the record)")
        g.add_argument("--still", type=Path, help="also (or instead) write one frame to this PNG")
        g.add_argument("--time", type=float, default=None, help="time of the still, tau (default: end of the record)")


def _render(traj, args, video: Path | None, still: Path | None, numerics=None) -> int:
    from ..render import RenderError, render_still, render_trajectory  # start-up time: matplotlib, MuJoCo, GL

    common = dict(
        rate=args.rate, fps=args.fps, width=args.width, height=args.height, trail=args.trail, numerics=numerics
    )
    try:
        if video is not None:
            out = render_trajectory(
                traj,
                video,
                start=getattr(args, "start", None),
                end=getattr(args, "end", None),
                progress=not args.quiet,
                **common,
            )
            out["wall_time_s"] = round(out["wall_time_s"], 2)
            print(json.dumps(jsonable(out)))
        if still is not None:
            print(json.dumps(jsonable(render_still(traj, still, time=getattr(args, "time", None), **common))))
    except RenderError as err:  # exit 4: this machine cannot render (bad options are exit 2, in cli.main)
        print(f"elastoactive: cannot render: {err}", file=sys.stderr)
        return 4
    return 0


def check_video_options(args, span: float | None = None) -> None:
    """Refuse bad picture options before anything is simulated or rendered (`span`: the tau the video shows)."""
    from ..render import check_picture  # start-up time: rendering loads matplotlib, MuJoCo and GL

    check_picture(fps=args.fps, rate=args.rate, width=args.width, height=args.height, trail=args.trail, span=span)


def video_after_run(args, traj, numerics=None) -> int:
    """`run ... --video PATH`: render the run's trajectory (after the simulation, from the record)."""
    return _render(traj, args, args.video, None, numerics)


def main(args) -> int:
    if args.output is None and args.still is None:
        raise ParameterError("give -o/--output (MP4) and/or --still (PNG)")
    check_video_options(args)
    if args.output is not None:
        check_file(args.output, "--output", (".mp4",), force=args.force)
    if args.still is not None:
        check_file(args.still, "--still", (".png",), force=args.force)
    traj, notes = read_run(args.run, what=f"render {args.run}")  # the run's own inputs (its copy of a changed network)
    for note in notes:
        print(f"elastoactive: warning: {note}", file=sys.stderr)
    return _render(traj, args, args.output, args.still)


def register(sub) -> None:
    p = sub.add_parser(
        "render",
        description="Render a saved run off-screen. The physics comes from summary.json beside "
        "trajectory.npz. " + RENDER_HELP,
    )
    p.add_argument(
        "run", type=Path, metavar="RUN_DIR_OR_NPZ", help="folder written by `run --out`, or its trajectory.npz"
    )
    p.add_argument("-o", "--output", type=Path, help="MP4 file to write")
    add_video_args(p, still=True)
    p.add_argument("--force", action="store_true", help="replace an existing video or still")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=main)

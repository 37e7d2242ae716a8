"""`elastoactive reproduce`: every claim of the paper, claim by claim, into one folder."""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import ParameterError
from .options import workers_argument


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "reproduce",
        help="regenerate the paper's figures, their data and report.md (claim by claim)",
        description="Run every study (linear stability, Hopf N = 7, N = 2 normal form, self-snapping, rotating pin, "
        "synchronisation, noise, anisotropic drag) with MuJoCo and the reduced model, and write PNG figures, NPZ/JSON "
        "data and report.md into one folder. The default (quick) size takes a few minutes on 2 cores.",
    )
    p.add_argument("--out", type=Path, default=Path("results/reproduction"), help="output folder (default %(default)s)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--full", action="store_true", help="publication resolution (finer grids, longer runs: much slower)")
    g.add_argument("--tiny", action="store_true", help="smallest grids and runs (a smoke test; numbers are rough)")
    workers_argument(p)
    p.add_argument("--only", default=None, help="comma-separated subset of studies, e.g. hopf,sync")
    p.add_argument("--quiet", action="store_true", help="no progress output")
    p.set_defaults(func=main)


def main(args) -> int:
    from ..outputs import check_folder  # start-up time: the studies load both engines, matplotlib and xarray
    from ..reproduce import reproduce
    from ..studies import STUDIES

    size = "full" if args.full else ("tiny" if args.tiny else "quick")
    only = None
    if args.only is not None:
        only = [name.strip() for name in args.only.split(",") if name.strip()]
        unknown = [name for name in only if name not in STUDIES]
        if not only or unknown:
            raise ParameterError(f"--only: {'unknown studies ' + ', '.join(map(repr, unknown)) if unknown else 'no study named'}"
                                 f"; choose from {', '.join(STUDIES)}")
    check_folder(args.out)
    reproduce(args.out, size, args.workers, only, progress=not args.quiet,
              log=(lambda *a: None) if args.quiet else (lambda msg: print(msg, file=sys.stderr, flush=True)))
    print(Path(args.out) / "report.md")
    return 0

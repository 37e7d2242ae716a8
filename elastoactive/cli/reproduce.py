"""`elastoactive reproduce`: every claim of the paper, claim by claim, into one folder.

The studies and their runner (report.reproduce) are imported inside `main`, the subcommand's boundary: the studies load
both engines, the runner the batch and its process pool.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..core.errors import ParameterError
from ..io.outputs import check_folder, output_path
from .options import workers_argument

DESCRIPTION = (
    "Run every study (linear stability, Hopf N = 7, N = 2 normal form, self-snapping, rotating pin, synchronisation, "
    "noise, anisotropic drag, inertia, the long chain, the dish; beyond the paper the skin effect, the response to a "
    "tip force, entrainment and the ring, the active solid's hysteresis, noise and disorder, the chain in 3D, cilia "
    "through the fluid) with MuJoCo and the reduced model, and write PNG figures, NPZ/JSON data and report.md into one"
    " folder. The default (quick) size takes about 4 min on an idle 2-core machine: each study declares the seconds "
    "its run may take (a test holds their sum), its figures are drawn beside the next study, and the"
    " log and report.md set each study's wall and CPU time against its budget and name the slowest (a loaded machine "
    "stretches the wall time; --tiny about 2 min). "
    "An existing folder is reproduced in place, never silently replaced: a study whose data there are complete and "
    "were made at the same size by the same code is kept (resume after Ctrl-C: rerun the same command); --only runs "
    "the named studies and merges them with the others of the folder, and report.md and provenance.json are rebuilt "
    "from every study present. A folder of another size is refused unless --force; --force also reruns studies "
    "that would be kept."
)


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "reproduce",
        description=DESCRIPTION,
    )
    p.add_argument(
        "--out", type=output_path, default=Path("results/reproduction"), help="output folder (default %(default)s)"
    )
    g = p.add_mutually_exclusive_group()
    g.add_argument("--full", action="store_true", help="publication resolution (finer grids, longer runs: much slower)")
    g.add_argument("--tiny", action="store_true", help="smallest grids and runs (a smoke test; numbers are rough)")
    workers_argument(p)
    p.add_argument(
        "--only",
        default=None,
        help="comma-separated subset of studies, e.g. hopf,sync (merged with the others already in --out)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="rerun studies whose data in --out would be kept, and replace a folder of another size",
    )
    p.add_argument("--quiet", action="store_true", help="no progress output")
    p.set_defaults(func=main)


def _only(text: str | None, known: tuple[str, ...]) -> list[str] | None:
    """The studies named by --only (None: all)."""
    if text is None:
        return None
    only = [name.strip() for name in text.split(",") if name.strip()]
    unknown = [name for name in only if name not in known]
    if not only or unknown:
        raise ParameterError(
            f"--only: {'unknown studies ' + ', '.join(map(repr, unknown)) if unknown else 'no study named'}"
            f"; choose from {', '.join(known)}"
        )
    return only


def main(args) -> int:
    from ..report.reproduce import reproduce  # the studies' runner
    from ..studies import registry  # the studies load both engines

    size = "full" if args.full else ("tiny" if args.tiny else "quick")
    only = _only(args.only, registry.names())
    check_folder(args.out)
    log = (lambda *a: None) if args.quiet else (lambda msg: print(msg, file=sys.stderr, flush=True))
    try:
        result = reproduce(args.out, size, args.workers, only, progress=not args.quiet, log=log, force=args.force)
    except KeyboardInterrupt as err:  # reproduce.Interrupted says which study stopped and what stays saved
        print(f"elastoactive: {err or 'interrupted'}", file=sys.stderr)
        return 130
    print(result.report)
    return 0

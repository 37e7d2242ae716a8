"""`elastoactive accuracy`: error against wall time of every engine setting on the paper's cases.

checks.accuracy is imported inside `main`, the subcommand's boundary: it loads both engines and matplotlib.
"""

from __future__ import annotations

from pathlib import Path

from ..io.outputs import check_file, check_folder
from .options import workers_argument


def main(args) -> int:
    # both engines, matplotlib and the process pool load only when the study runs
    from ..checks.accuracy import (
        OUTPUTS,
        format_defaults,
        format_recommendations,
        recommend,
        run_study,
        summarise,
        write_outputs,
    )

    check_folder(args.out)
    for name in OUTPUTS:  # a folder of results (of any size) is replaced only when asked
        check_file(args.out / name, "--out", (), force=args.force)
    size = "tiny" if args.tiny else "quick" if args.quick else "full"
    rows, meta = run_study(size, workers=args.workers, progress=not args.quiet)
    write_outputs(args.out, rows, meta)
    summary = summarise(rows)
    print(format_defaults(summary))
    print()
    print(format_recommendations(recommend(summary, key="worst"), "worst"))
    bad = [r for r in rows if r["status"] != "ok"]
    print(
        f"\n{len(rows)} runs in {meta['elapsed_s']:.0f} s ({len(bad)} refused/diverged/failed, recorded); "
        f"wrote {args.out / 'accuracy.md'}, accuracy.csv, accuracy.png, accuracy_steady.png"
    )
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "accuracy",
        description="Measure the error of MuJoCo (integrator, dt, mass ratio) and of the reduced model (method, "
        "tolerance) against a tight reduced-model solution (rtol 1e-11) on the paper's cases, with their wall "
        "time; write a log-log plot, tables (markdown + CSV) and the cheapest settings for 1%, 0.1%, 0.01%.",
    )
    p.add_argument("--out", type=Path, default=Path("results/accuracy"), help="output folder (default %(default)s)")
    size = p.add_mutually_exclusive_group()
    size.add_argument("--quick", action="store_true", help="coarser grid and shorter runs (about 2-2.5 min on 2 cores)")
    size.add_argument(
        "--tiny",
        action="store_true",
        help="one case, two settings per engine (a smoke test, a few seconds; numbers are rough)",
    )
    workers_argument(p, "processes (default: every core)")
    p.add_argument("--force", action="store_true", help="replace the results of a study already in --out")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=main)

"""`elastoactive validate [SCENE]`: both engines on every registered scene's validation cases, error table."""

from __future__ import annotations

import sys

from .. import registry
from .options import UNITS, numerics_args, numerics_from


def register(subparsers) -> None:
    val = subparsers.add_parser("validate", help="run MuJoCo and the reduced model on the paper's cases and tabulate the error",
                         description="Cross-validate the MuJoCo scenes against the reduced model on the paper's cases. " + UNITS)
    val.add_argument("scene", nargs="?", choices=registry.names(), metavar="SCENE", help="only this scene (default: all)")
    numerics_args(val)
    val.add_argument("--tolerance", type=float, default=0.01, help="largest acceptable relative error (default 0.01)")
    val.add_argument("--convergence", action="store_true", help="instead: tabulate the error as dt and the mass ratio shrink")
    val.add_argument("--quiet", action="store_true")
    val.set_defaults(func=main)


def main(args) -> int:
    # start-up time: both engines load only when a command runs, not for --help
    from ..validate import compare, convergence, format_convergence, format_table, validation_cases

    cases = validation_cases(args.scene)
    if args.convergence:
        for case in cases:
            if case.convergence:
                rows = convergence(case.physics, case.duration)
                print(f"\n{case.physics.scene}: error against the reduced model as dt shrinks (mass ratio "
                      f"{rows[0].numerics.mass_ratio:g}), then as the mass ratio shrinks (dt = {rows[-1].numerics.dt:g})\n")
                print(format_convergence(rows))
        return 0
    numerics = numerics_from(args)
    rows = []
    for case in cases:
        physics = case.physics
        rows.append(compare(physics, numerics, case.duration))
        if not args.quiet:
            print(f"  done {physics.scene} ({rows[-1].mujoco_wall_s:.2f} s MuJoCo, {rows[-1].reduced_wall_s:.2f} s reduced)",
                  file=sys.stderr)
    print(format_table(rows))
    worst = max(r.worst() for r in rows)
    verdict = "PASS" if worst <= args.tolerance else "FAIL"
    print(f"\nlargest relative error {100 * worst:.3f}% (tolerance {100 * args.tolerance:g}%): {verdict}")
    return 0 if verdict == "PASS" else 1

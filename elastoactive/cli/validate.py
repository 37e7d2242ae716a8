"""`elastoactive validate [SCENE]`: both engines on every registered scene's validation cases, error table.

checks.validate is imported inside `main`, the subcommand's boundary: it loads both engines.
"""

from __future__ import annotations

import math
import sys

from ..core import registry
from ..core.errors import ParameterError, SimulationDiverged
from ..core.params import Numerics
from .fields import numerics_args, numerics_from
from .options import UNITS

TOLERANCE_RANGE = (1e-4, 1.0)
"""Tolerances validate accepts: below 1e-4 (0.01%) no setting passes (the MuJoCo discretisation error alone is
larger: docs/generated/convergence.md), above 1 (100%) the comparison says nothing."""


def check_tolerance(tolerance: float) -> float:
    """The largest acceptable relative error, refused (naming --tolerance) outside TOLERANCE_RANGE."""
    low, high = TOLERANCE_RANGE
    if not (math.isfinite(tolerance) and low <= tolerance <= high):
        raise ParameterError(
            f"--tolerance (largest relative error, 0.01 = 1%) must lie in [{low:g}, {high:g}], got "
            f"{tolerance}: below {low:g} no setting passes (MuJoCo's discretisation error alone is "
            "larger), above 1 the comparison says nothing"
        )
    return float(tolerance)


def register(subparsers) -> None:
    val = subparsers.add_parser(
        "validate",
        description="Cross-validate the MuJoCo scenes against the reduced model on the paper's cases. " + UNITS,
    )
    val.add_argument(
        "scene", nargs="?", choices=registry.names(), metavar="SCENE", help="only this scene (default: all)"
    )
    numerics_args(val)
    val.add_argument(
        "--tolerance", type=float, default=0.01, help="largest acceptable relative error, in [1e-4, 1] (default 0.01)"
    )
    val.add_argument(
        "--convergence", action="store_true", help="instead: tabulate the error as dt and the mass ratio shrink"
    )
    val.add_argument(
        "--inertial",
        action="store_true",
        help="compare MuJoCo with the reduced model's inertial counterpart at the run's mass ratio "
        "(implied by a --mass-ratio other than the default; heavy chains run longer: x sqrt(mass "
        "ratio) above 1; a case the inertial model does not cover is listed as not run)",
    )
    val.add_argument("--quiet", action="store_true")
    val.set_defaults(func=main)


def main(args) -> int:
    # both engines load only when the command runs, not for --help
    from ..checks.validate import (
        compare,
        convergence,
        format_convergence,
        format_table,
        inertial_plan,
        not_run,
        validation_cases,
        verdict,
    )

    check_tolerance(args.tolerance)
    cases = validation_cases(args.scene)
    if args.convergence:
        for case in cases:
            if case.convergence:
                rows = convergence(case.physics, case.duration)
                print(
                    f"\n{case.physics.scene}: error against the reduced model as dt shrinks (mass ratio "
                    f"{rows[0].numerics.mass_ratio:g}), then as the mass ratio shrinks "
                    f"(dt = {rows[-1].numerics.dt:g})\n"
                )
                print(format_convergence(rows))
        return 0
    numerics = numerics_from(args)
    inertial = bool(getattr(args, "inertial", False)) or numerics.mass_ratio != Numerics().mass_ratio
    plan = [(case, "") for case in cases]
    if inertial:
        plan = inertial_plan(numerics.mass_ratio, args.scene)
        if all(gap for _, gap in plan):
            raise ParameterError(
                (
                    f"--inertial (mass ratio {numerics.mass_ratio:g})"
                    if numerics.mass_ratio == Numerics().mass_ratio
                    else f"--mass-ratio {numerics.mass_ratio:g}"
                )
                + ": no validation case "
                f"of {args.scene or 'any scene'} can run against the inertial reduced model ({plan[0][1]}); validate "
                "it at the default mass ratio, in the overdamped limit"
            )
        print(
            f"MuJoCo ({numerics.integrator}, dt = {numerics.dt:g}) against the inertial reduced model at mass ratio "
            f"{numerics.mass_ratio:g} (durations {', '.join(f'{c.duration:g}' for c, gap in plan if not gap)} tau)\n"
        )
    rows = []
    for case, gap in plan:
        physics = case.physics
        if gap:
            rows.append(not_run(case, numerics, gap))
            continue
        try:
            rows.append(compare(physics, numerics, case.duration, inertial=True if inertial else None))
        except (ParameterError, SimulationDiverged) as err:  # this case cannot run at this setting: a row saying so
            rows.append(not_run(case, numerics, str(err).split("\n")[0]))
        if not args.quiet:
            done = (
                f"({rows[-1].mujoco_wall_s:.2f} s MuJoCo, {rows[-1].reduced_wall_s:.2f} s reduced)"
                if rows[-1].ran
                else rows[-1].note
            )
            print(f"  done {physics.scene} {done}", file=sys.stderr)
    print(format_table(rows))
    line, passed = verdict(rows, args.tolerance)
    print(f"\n{line}")
    return 0 if passed else 1

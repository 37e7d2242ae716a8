"""`elastoactive whirl --S S`: the clamped filament's whirl in three dimensions as the limit of a ladder of chains.

Off the table the clamped filament under a follower load S = f L^3 / B above onset whirls: from an out-of-plane start
it turns as a rigid, non-planar shape about the clamp axis (docs/model3d.md, section 6). This command finds that whirl
on a ladder of N (default 10, 14, 20, 28, 40, 56) in the reduced 3D model at sigma = S / N^3: the coarsest rung settled
from a helix and refined by Newton's method as a shape turning rigidly, each next rung by Newton from the previous
rung's shape (analysis.whirl.continuum_whirl). It prints, rung by rung and extrapolated to N -> infinity in 1/N with
an error bar (analysis.filament.richardson), the angular rate N^4 |Omega| (units B / (zeta L^4)), the tip's distance
from the axis over the length R / L and the bend between the first and the last link, and each rung's largest growth
rate in the rotating frame (< 0: the whirl is stable). The ladder must resolve the bending length, as `filament`'s
(check_resolution).

The 3D model (numba) and the whirl's analysis (scipy) are imported inside main, the subcommand's boundary:
`elastoactive --help` and the other commands do not load them.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from dataclasses import asdict, dataclass

from ..core.errors import ParameterError
from .filament import check_resolution, converging
from .options import ladder_argument

RUNG_COST_POWER = 4
"""A rung's wall time grows like N^RUNG_COST_POWER (Newton's method on N links: its Jacobian by 2N evaluations of a
right-hand side that solves a dense 2N x 2N system): the rungs left are estimated from the last one found."""

DEFAULT_LADDER = (10, 14, 20, 28, 40, 56)
"""The ladder of N (a few seconds in all at S = 100: Newton's method, no long runs but the coarsest rung's)."""


@dataclass(frozen=True)
class WhirlRung:
    """One chain of the ladder."""

    n: int
    sigma: float
    omega: float
    """N^4 Omega, signed (> 0 turning from +y to +z), in B / (zeta L^4)."""
    radius: float
    """The tip's distance from the clamp axis over the length, R / L."""
    bend: float
    """The angle between the first and the last link (rad)."""
    growth: float
    """N^4 times the largest growth rate in the rotating frame (< 0: stable), in B / (zeta L^4)."""
    residual: float
    """Newton's largest residual (per tau)."""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "whirl",
        description="Find the whirl of the clamped chain in three dimensions (a rigid non-planar shape turning about "
        "the clamp axis) by Newton's method on chains of N particles at sigma = S / N^3 (reduced 3D model), and "
        "extrapolate its rate N^4 Omega (B / (zeta L^4)), tip radius R / L and bend to the continuum filament in 1/N "
        "(docs/model3d.md, section 6).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--S", dest="S", type=float, required=True, help="follower load f L^3 / B (onset 76.10)")
    ladder_argument(p, DEFAULT_LADDER, count=3, smallest=3)
    p.add_argument(
        "--drag-ratio",
        dest="gamma_l",
        metavar="RATIO",
        type=float,
        default=1.0,
        help="longitudinal over transverse drag gamma_L / gamma_T (default 1)",
    )
    p.add_argument("--json", action="store_true", help="print the result as JSON instead of a table")
    p.add_argument("--quiet", action="store_true", help="no wall-time line")
    p.set_defaults(func=main)


def _estimate(ns: list[int]):
    """on_rung for continuum_whirl: after each rung, the rungs left estimated from its wall time (RUNG_COST_POWER),
    announced once (io.progress.announce) when they come to engines.runner.ANNOUNCE_SECONDS or more."""
    from ..engines.runner import ANNOUNCE_SECONDS, duration_text  # start-up time: loaded with the command
    from ..io.progress import announce

    said = []

    def on_rung(n: int, seconds: float) -> None:
        left = [m for m in ns if m > n]
        estimate = sum(seconds * (m / n) ** RUNG_COST_POWER for m in left)
        if not said and estimate >= ANNOUNCE_SECONDS:
            said.append(n)
            rungs = ", ".join(str(m) for m in left)
            announce(
                f"whirl: the rungs N = {rungs} will take about {duration_text(estimate)} (N = {n} took "
                f"{seconds:.2g} s; a rung's time grows like N^{RUNG_COST_POWER})"
            )

    return on_rung


def main(args) -> int:
    from ..analysis.continuum import continuum_critical  # the continuum's onset (scipy)
    from ..analysis.whirl import NoWhirl, continuum_whirl  # the 3D model (numba) and Newton's method (scipy)

    if not (math.isfinite(args.S) and args.S > 0):
        raise ParameterError(f"S (follower load f L^3 / B) must be a positive number, got {args.S}")
    if not (math.isfinite(args.gamma_l) and args.gamma_l > 0):
        raise ParameterError(f"--drag-ratio (gamma_L / gamma_T) must be a positive number, got {args.gamma_l}")
    s_c, _ = continuum_critical()
    if args.S <= s_c:
        raise ParameterError(
            f"S = {args.S:g} is at or below the filament's onset S_c = {s_c:.2f}: the straight filament is stable "
            "and does not whirl; give --S above it"
        )
    check_resolution(args.S, args.ns)
    clock = time.perf_counter()
    try:
        result = continuum_whirl(args.S, args.ns, args.gamma_l, on_rung=_estimate(list(args.ns)))
    except NoWhirl as missed:
        raise ParameterError(f"no whirl found: {missed}; {_advice(args, missed.straight)}") from None
    wall = time.perf_counter() - clock
    rungs = [
        WhirlRung(s.n, s.sigma, s.omega * s.n**4, s.tip_radius / s.n, s.bend, s.growth * s.n**4, s.residual)
        for s in result.states
    ]
    parts = (("omega", result.omega), ("radius", result.radius), ("bend", result.bend))
    trend = {name: converging(x.values) for name, x in parts}
    if args.json:
        record = {name: {**x._asdict(), "converging": trend[name]} for name, x in parts}
        print(json.dumps({"S": args.S, "drag_ratio": args.gamma_l, "rungs": [asdict(r) for r in rungs], **record,
                          "wall_time_s": wall}, indent=2))  # fmt: skip
        return 0
    print(
        f"clamped filament in 3D at S = f L^3 / B = {args.S:g}, drag ratio {args.gamma_l:g}: the whirl of chains of N "
        "at sigma = S / N^3 (reduced 3D model, Newton's method)"
    )
    print(f"{'N':>6} {'sigma':>12} {'N^4 Omega':>12} {'R / L':>10} {'bend rad':>10} {'N^4 growth':>11}")
    for r in rungs:
        print(f"{r.n:>6} {r.sigma:>12.6g} {r.omega:>12.4f} {r.radius:>10.6f} {r.bend:>10.6f} {r.growth:>11.2f}")
    ns = ", ".join(str(r.n) for r in rungs)
    print(f"continuum (Richardson in 1/N over N = {ns}; sign of Omega: the start's sense of turning):")
    omega = result.omega
    print(f"  N^4 |Omega| = {abs(omega.value):.4f} +- {omega.error:.2g} B / (zeta L^4){_trend(trend['omega'])}")
    print(f"  R / L       = {result.radius.value:.6f} +- {result.radius.error:.2g}{_trend(trend['radius'])}")
    print(f"  bend        = {result.bend.value:.6f} +- {result.bend.error:.2g} rad{_trend(trend['bend'])}")
    stable = all(r.growth < 0 for r in rungs)
    worst = max(r.growth for r in rungs)
    print(f"  every rung's whirl {'stable' if stable else 'NOT stable'} (largest N^4 growth {worst:.2f})")
    if not args.quiet:
        print(f"wall time {wall:.1f} s")
    return 0


def _advice(args, straight: bool) -> str:
    """What to change among this command's options when no whirl was found."""
    drag = f" or a --drag-ratio nearer 1 (it is {args.gamma_l:g})" if args.gamma_l != 1 else ""
    if straight:
        return f"this load may not whirl from a helix: try a larger --S (it is {args.S:g}){drag}"
    return f"try a larger --S (it is {args.S:g}){drag}, or a ladder whose first N resolves the load better (--ns)"


def _trend(converges: bool) -> str:
    return "" if converges else "  [rungs not converging monotonically: not the 1/N regime, the error does not hold]"

"""The whirl's continuum limit: at each load S = N^3 sigma, the whirl of the reduced 3D chain along a ladder of N (found
by Newton's method as a shape turning rigidly, analysis.whirl), and its extrapolation in 1/N with an error bar.

    .venv/bin/python scripts/whirl_continuum.py [--loads 200,400] [--ns 7,10,14,20,28,40]

The first rung starts from a simulation: the reduced 3D chain at N = ns[0] run from a helix until it whirls
(analysis.whirl.settled_whirl), refined by Newton; each next rung starts from the previous one's shape
(analysis.whirl.continuum_whirl; `elastoactive whirl --S S` prints one load's limit with its error bars).
Prints a markdown table (docs/model3d.md, section 6): N^4 Omega (rad per filament time zeta L^4 / B), the tip's
distance from the axis over the length R / L, the bend between the first and the last link, and the largest growth
rate of a perturbation in the rotating frame (times N^4; < 0: the whirl is stable).
"""

from __future__ import annotations

import argparse

from elastoactive.analysis.whirl import continuum_whirl


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loads", default="200,400", help="loads S = N^3 sigma, comma separated")
    parser.add_argument("--ns", default="10,14,20,28,40,56", help="the ladder's N, increasing")
    args = parser.parse_args()
    ns = [int(n) for n in args.ns.split(",")]
    print("| S | N | N^4 Omega | R / L | bend (rad) | N^4 growth |")
    print("|---|---|---|---|---|---|")
    for load in (float(x) for x in args.loads.split(",")):
        result = continuum_whirl(load, ns)
        for state in result.states:
            n = state.n
            print(
                f"| {load:g} | {n} | {state.omega * n**4:.4f} | {state.tip_radius / n:.6f} | {state.bend:.6f} | "
                f"{state.growth * n**4:.2f} |"
            )
        print(
            f"| {load:g} | ∞ | {result.omega.value:.3f} ± {result.omega.error:.1e} | {result.radius.value:.5f} ± "
            f"{result.radius.error:.1e} | {result.bend.value:.5f} ± {result.bend.error:.1e} | |",
            flush=True,
        )


if __name__ == "__main__":
    main()

"""The whirl's continuum limit: at each load S = N^3 sigma, the whirl of the reduced 3D chain along a ladder of N (found
by Newton's method as a shape turning rigidly, analysis.whirl), and its extrapolation in 1/N with an error bar.

    .venv/bin/python scripts/whirl_continuum.py [--loads 200,400] [--ns 7,10,14,20,28,40]

The first rung starts from a simulation: the reduced 3D chain at N = ns[0] run from a helix until it whirls (RUN_TIME
natural times, the second half measured), refined by Newton; each next rung starts from the previous one's shape.
Prints a markdown table (docs/model3d.md, section 6): N^4 Omega (rad per filament time zeta L^4 / B), the tip's
distance from the axis over the length R / L, the bend between the first and the last link, and the largest growth
rate of a perturbation in the rotating frame (times N^4; < 0: the whirl is stable).
"""

from __future__ import annotations

import argparse

import numpy as np

from elastoactive.analysis.motion3d import measure3d
from elastoactive.analysis.whirl import find_whirl, ladder
from elastoactive.reduced.chain3d import Chain3D, solve3d

RUN_TIME = 6.0
"""Length of the first rung's settling run in units of N^4 tau / S (the load's natural time: several turns)."""


def settled_whirl(n: int, sigma: float):
    """The whirl of N links at sigma, from a helix run until it settles, then refined by Newton."""
    duration = RUN_TIME * n**4 / (sigma * n**3)
    ts = np.linspace(0.0, duration, 6001)
    s = np.arange(1, n + 1) / n
    t0 = np.column_stack([np.ones(n), 0.3 * s, 0.3 * s * s])
    path = solve3d(Chain3D(n=n, sigma=sigma), ts, t0 / np.linalg.norm(t0, axis=1)[:, None], rtol=1e-10, atol=1e-10)
    rate = measure3d(ts, path).whirl_rate
    return find_whirl(Chain3D(n=n, sigma=sigma), path[-1], 2 * np.pi * rate)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loads", default="200,400", help="loads S = N^3 sigma, comma separated")
    parser.add_argument("--ns", default="10,14,20,28,40,56", help="the ladder's N, increasing")
    args = parser.parse_args()
    ns = [int(n) for n in args.ns.split(",")]
    print("| S | N | N^4 Omega | R / L | bend (rad) | N^4 growth |")
    print("|---|---|---|---|---|---|")
    for load in (float(x) for x in args.loads.split(",")):
        first = settled_whirl(ns[0], load / ns[0] ** 3)
        result = ladder(load, ns, first.tangents, first.omega)
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

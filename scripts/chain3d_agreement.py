"""The clamped chain in 3D (scene clamped-3d) in both engines at their default numerics, as a user runs it: from the
scene's own seeded non-planar start (what `elastoactive run clamped-3d` does) and from a planar start (the same push
in y, none in z). For each case: the scene's frequency and amplitude (summary.json's) in both engines, MuJoCo's
relative differences, the state, the dt the automatic numerics chose, and each engine's wall time and tau per second.

    .venv/bin/python scripts/chain3d_agreement.py [--quick]

Prints a markdown table (docs/model3d.md, section 7). The second half of each run is measured (the default transient).
"""

from __future__ import annotations

import argparse

import numpy as np

import elastoactive as ea
from elastoactive.scenes.clamped3d import angles_of

CASES = ((7, 0.3, 600.0), (7, 0.8, 300.0), (20, 0.3, 600.0), (20, 0.8, 300.0))
"""(N, sigma, duration in tau): two loads above onset at N = 7 (sigma_c = 0.1575) and N = 20 (sigma_c = 0.0087)."""
STARTS = ("whirling", "planar")


def start_angles(physics: ea.Physics, start: str) -> np.ndarray | None:
    """None (the scene's seeded non-planar start) or the planar start: its azimuths, elevations 0."""
    if start == "whirling":
        return None
    theta = angles_of(physics.scene_def.initial_tangents(physics, ea.Numerics()))
    return np.concatenate([theta[: physics.n], np.zeros(physics.n)])


def row(n: int, sigma: float, duration: float, start: str) -> str:
    physics = ea.Physics(scene="clamped-3d", n=n, sigma=sigma)
    theta0 = start_angles(physics, start)
    runs = {e: ea.simulate(physics, duration=duration, engine=e, theta0=theta0) for e in ("reduced", "mujoco")}
    res = {e: ea.measure(t) for e, t in runs.items()}
    red, muj = res["reduced"], res["mujoco"]
    dt = runs["mujoco"].info.get("automatic_numerics", {}).get("dt", float(ea.Numerics().dt))

    def diff(a: float, b: float) -> str:
        return f"{100 * (a / b - 1):+.2f}%"

    walls = " / ".join(f"{runs[e].wall_time_s:.1f}" for e in ("reduced", "mujoco"))
    rates = " / ".join(f"{duration / runs[e].wall_time_s:.0f}" for e in ("reduced", "mujoco"))
    return (
        f"| {n} | {sigma:g} | {start} | {red.extra['motion_state']} / {muj.extra['motion_state']} | "
        f"{red.frequency:.5f} | {muj.frequency:.5f} | {diff(muj.frequency, red.frequency)} | {red.amplitude:.4f} | "
        f"{muj.amplitude:.4f} | {diff(muj.amplitude, red.amplitude)} | {dt:.3g} | {walls} | {rates} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 7 only")
    args = parser.parse_args()
    print(
        "| N | sigma | start | state (reduced / MuJoCo) | f tau, reduced | MuJoCo | diff | amplitude, reduced | MuJoCo "
        "| diff | MuJoCo dt | wall s (reduced / MuJoCo) | tau per s (reduced / MuJoCo) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n, sigma, duration in CASES:
        if args.quick and n != 7:
            continue
        for start in STARTS:
            print(row(n, sigma, duration, start), flush=True)


if __name__ == "__main__":
    main()

"""MuJoCo's error on the 3D whirl against dt (and the integrator): the measurement behind the scene clamped-3d's
automatic dt (scenes.clamped3d.STEP_ERROR).

Each case starts MuJoCo on Newton's whirl of the reduced model (analysis.whirl.settled_whirl), lets it settle for three
of the whirl's decay times (at least one period), and measures over the next two periods the tip's turning rate (the
slope of its azimuth about the clamp axis) and its distance from the axis, relative to Newton's. Ball joints at their
default twist inertia and damping (mjcf.chain3d).

    .venv/bin/python scripts/chain3d_timestep.py N SIGMA [DRAG_RATIO] [DT[:INTEGRATOR[:MASS_RATIO]] ...]

e.g. `scripts/chain3d_timestep.py 20 0.8 1 0.0025 0.005 0.0025:RK4:1e-3`. Prints one markdown row per setting
(docs/model3d.md, section 7).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from elastoactive.analysis.whirl import WhirlState, settled_whirl
from elastoactive.mjcf.chain3d import Chain3DModel, simulate3d

SAMPLE = 0.05
"""Spacing of the recorded samples (tau), rounded to whole steps."""


def whirl_error(whirl: WhirlState, dt: float, integrator: str, mass_ratio: float) -> str:
    period = 1.0 / abs(whirl.rate)
    settle = max(3.0 / abs(whirl.growth), period)
    sample = dt * max(1, round(SAMPLE / dt))
    ts = sample * np.arange(int((settle + 2 * period) / sample) + 1)
    chain = Chain3DModel(whirl.n, whirl.sigma, whirl.gamma_l, dt=dt, integrator=integrator, mass_ratio=mass_ratio)
    start = time.perf_counter()
    tip = simulate3d(chain, ts, whirl.tangents).sum(axis=1)
    wall = time.perf_counter() - start
    late = ts >= settle
    rate = np.polyfit(ts[late], np.unwrap(np.arctan2(tip[:, 2], tip[:, 1]))[late], 1)[0] / (2 * np.pi)
    radius = np.hypot(tip[late, 1], tip[late, 2]).mean()
    return (
        f"| {whirl.n} | {whirl.sigma:g} | {whirl.gamma_l:g} | {integrator} | {dt:g} | {mass_ratio:g} | "
        f"{rate / whirl.rate - 1:+.3%} | {radius / whirl.tip_radius - 1:+.3%} | {ts[-1] / wall:.1f} |"
    )


def main() -> None:
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    n, sigma = int(sys.argv[1]), float(sys.argv[2])
    ratio = float(sys.argv[3]) if len(sys.argv) > 3 else 1.0
    settings = sys.argv[4:] or ["0.0025", "0.005"]
    whirl = settled_whirl(n, sigma, ratio)
    print("| N | sigma | drag ratio | integrator | dt | mass ratio | rate | tip radius | tau per s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for setting in settings:
        parts = setting.split(":")
        dt, integrator, mass = parts + ["0.0025", "implicitfast", "1e-4"][len(parts) :]
        print(whirl_error(whirl, float(dt), integrator, float(mass)), flush=True)


if __name__ == "__main__":
    main()

"""Write the README's four images (docs/img/<scene>.png): one still of each scene at the paper's
parameters, after the transient, with a beat's worth of fading particle trails.

    .venv/bin/python scripts/make_readme_images.py [--out docs/img] [--width 640 --height 480]

Each run is simulated in MuJoCo (a fraction of a second), then rendered off-screen (GL back end
chosen as in elastoactive.render: MUJOCO_GL, else egl, else osmesa).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from elastoactive.params import Numerics, Physics
from elastoactive.render import default_rate, render_still
from elastoactive.simulate import simulate_mujoco

# (file name, physics, simulated time in tau): the paper's cases (elastoactive.validate.PAPER_CASES)
CASES = (
    ("one-pinned", Physics(scene="one-pinned", n=7, sigma=0.8), 300.0),
    ("two-pinned", Physics(scene="two-pinned", n=7, sigma=0.8, delta=0.1), 300.0),
    ("rotating-pin", Physics(scene="rotating-pin", n=7, sigma=0.8), 300.0),
    ("coupled-pair", Physics(scene="coupled-pair", n=7, sigma=0.8, rho=4 / 3, kappa=2.0), 600.0),
)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[1] / "docs" / "img")
    p.add_argument("--width", type=int, default=640)
    p.add_argument("--height", type=int, default=480)
    args = p.parse_args()
    for name, physics, duration in CASES:
        start = time.perf_counter()
        traj = simulate_mujoco(physics, Numerics(), duration)
        path = args.out / f"{name}.png"
        render_still(traj, path, rate=default_rate(traj), width=args.width, height=args.height)
        kib = path.stat().st_size / 1024
        print(f"{path}  {kib:.0f} KiB  ({time.perf_counter() - start:.1f} s)")


if __name__ == "__main__":
    main()

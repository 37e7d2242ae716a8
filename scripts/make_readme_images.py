"""Write the README's images (docs/img/<scene>.png): one still of each registered scene at its last
validation case (the paper's parameters), after the transient, with a beat's worth of fading trails; and the
videos of the two experiments beyond the paper and of the outlook's structures (docs/img/<name>.mp4 with a still
<name>.png): the N = 17 chain with self-contact, the chain in the dish, the beating N = 24 ring, the star of three
arms on a turning hub, the actuated active solid (a hexagon of 3 rings) and the chain in three dimensions whirling
(its validation case, drawn in two views).

    .venv/bin/python scripts/make_readme_images.py [--out docs/img] [--width 640 --height 480] [--only ring,star]

Each run is simulated in MuJoCo (a fraction of a second), then rendered off-screen (GL back end
chosen as in elastoactive.render: MUJOCO_GL, else egl, else osmesa).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import elastoactive as ea
from elastoactive.core.params import Numerics
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.render import default_rate, render_still, render_trajectory

# (file name, physics, simulated time in tau): each scene's last validation case (the pair: kappa = 2)
CASES = tuple((s.name, s.validation_cases()[-1].physics, s.validation_cases()[-1].duration) for s in ea.scenes.scenes())
# (file name, physics, simulated time, seconds of video, numerics): the supplement's two experiments and the outlook's
# structures, as videos (the ring's pin holds at dt = 0.001, as in the rings study)
VIDEOS = (
    ("long-chain-contact", ea.Physics(scene="one-pinned", n=17, sigma=0.8, contact=True), 400.0, 6.0, Numerics()),
    ("paraboloid", ea.Physics(scene="paraboloid", n=7, sigma=0.3, trap=0.1), 800.0, 6.0, Numerics()),
    ("ring", ea.Physics(scene="ring", n=24, sigma=0.5), 300.0, 8.0, Numerics(dt=0.001, sample_dt=0.1)),
    ("star", ea.Physics(scene="star", n=7, sigma=0.8, arms=3, hub_stiffness=1.0), 400.0, 8.0, Numerics()),
    ("lattice", ea.Physics(scene="lattice", rings=3, sigma=0.15, alignment_length=0.1), 100.0, 8.0, Numerics()),
    ("clamped-3d", ea.Physics(scene="clamped-3d", n=7, sigma=0.4), 300.0, 6.0, Numerics()),
)
VIDEO_SIZE = (480, 360)
VIDEO_FPS = 15.0


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[1] / "docs" / "img")
    p.add_argument("--width", type=int, default=640)
    p.add_argument("--height", type=int, default=480)
    p.add_argument(
        "--only",
        type=lambda text: set(text.split(",")),
        default=None,
        help="comma list of the images and videos to write (file names without suffix); default: all",
    )
    args = p.parse_args()
    videos = {name for name, *_ in VIDEOS}
    for name, physics, duration in CASES:
        if name in videos or (args.only is not None and name not in args.only):  # a video writes its own still
            continue
        start = time.perf_counter()
        traj = simulate_mujoco(physics, Numerics(), duration)
        path = args.out / f"{name}.png"
        render_still(traj, path, rate=default_rate(traj), width=args.width, height=args.height)
        kib = path.stat().st_size / 1024
        print(f"{path}  {kib:.0f} KiB  ({time.perf_counter() - start:.1f} s)")
    for name, physics, duration, seconds, numerics in VIDEOS:
        if args.only is not None and name not in args.only:
            continue
        start = time.perf_counter()
        traj = simulate_mujoco(physics, numerics, duration)
        rate = default_rate(traj)
        path = args.out / f"{name}.mp4"
        render_trajectory(
            traj,
            path,
            fps=VIDEO_FPS,
            rate=rate,
            start=max(duration / 2, duration - seconds * rate),
            width=VIDEO_SIZE[0],
            height=VIDEO_SIZE[1],
            progress=False,
        )
        render_still(traj, args.out / f"{name}.png", rate=rate, width=args.width, height=args.height)
        kib = path.stat().st_size / 1024
        print(f"{path}  {kib:.0f} KiB  ({time.perf_counter() - start:.1f} s)")


if __name__ == "__main__":
    main()

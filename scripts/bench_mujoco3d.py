#!/usr/bin/env python
"""MuJoCo's 3D chain (clamped-3d) against the planar chain (one-pinned) at the same N, side by side in one run.

  .venv/bin/python scripts/bench_mujoco3d.py [--before TREE] [--n 10 40 100] [--sigma 0.8] [--out FILE]

For each source tree (this checkout, and with --before a second one, e.g. `git worktree add --detach /tmp/base
<commit>` for the code before a change; a compiled controllers/_follower*.so must be copied in) and each N:

  engine only   one child process per scene builds the model the run would build (the automatic numerics: the planar
                Numerics.for_physics, the 3D Clamped3D.automatic_numerics) and times mj_step(nstep) in thread time,
                best of 3: microseconds per step and per degree-of-freedom-step (model.nv dofs: N planar, 3N with
                ball joints); the planar follower callback installed, as in a run
  whole process `python -m elastoactive run SCENE --n N --sigma S --duration D --quiet` (wall time, one run each): D =
                30 tau at N <= 40, 1 tau above (the 3D chain before the change takes ~40 ms a step at N = 100)

The ratios are 3D over planar in the same tree: per step, per dof-step and whole process. The machine's load is
printed; timings on a loaded machine are noisy: compare within one run (docs/performance.md).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent

CHILD = r"""
import json, sys, time
import mujoco
import elastoactive as ea
from elastoactive.controllers import follower_forces
scene, n, sigma = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
physics = ea.Physics(scene=scene, n=n, sigma=sigma)
if scene == "one-pinned":
    from elastoactive.mjcf.chain import prepare
    numerics = ea.Numerics().for_physics(physics)
    model, data = prepare(physics, numerics)
else:
    from elastoactive.mjcf.chain3d import Chain3DModel, prepare3d
    definition = physics.scene_def
    numerics = definition.automatic_numerics(physics, ea.Numerics())
    chain = Chain3DModel(n, sigma, mass_ratio=numerics.mass_ratio, dt=numerics.dt, integrator=numerics.integrator)
    model, data = prepare3d(chain, definition.initial_tangents(physics, ea.Numerics()))
steps = max(20, int(3e5 / model.nv**2))
best = float("inf")
with follower_forces():
    mujoco.mj_step(model, data, nstep=steps)  # warm
    for _ in range(3):
        start = time.thread_time()
        mujoco.mj_step(model, data, nstep=steps)
        best = min(best, time.thread_time() - start)
print(json.dumps({"us_step": 1e6 * best / steps, "nv": int(model.nv), "dt": float(model.opt.timestep),
                  "integrator": numerics.integrator, "mass_ratio": float(numerics.mass_ratio)}))
"""


def load() -> str:
    return " ".join(open("/proc/loadavg").read().split()[:3]) if os.path.exists("/proc/loadavg") else "?"


def env_for(tree: Path) -> dict:
    return {**os.environ, "PYTHONPATH": str(tree)}


def engine_only(tree: Path, scene: str, n: int, sigma: float) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, scene, str(n), str(sigma)], env=env_for(tree), cwd=tree,
                         check=True, capture_output=True, text=True)  # fmt: skip
    return json.loads(out.stdout.strip().splitlines()[-1])


def whole_process(tree: Path, scene: str, n: int, sigma: float, duration: float) -> float:
    cmd = [sys.executable, "-m", "elastoactive", "run", scene, "--n", str(n), "--sigma", str(sigma),
           "--duration", str(duration), "--quiet"]  # fmt: skip
    start = time.perf_counter()
    subprocess.run(cmd, env=env_for(tree), cwd=tree, check=True, capture_output=True)
    return time.perf_counter() - start


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", type=Path, help="a second source tree, measured first (the code before a change)")
    ap.add_argument("--n", type=int, nargs="+", default=[10, 40, 100])
    ap.add_argument("--sigma", type=float, default=0.8)
    ap.add_argument("--no-whole", action="store_true", help="engine-only figures only")
    ap.add_argument("--out", type=Path, help="also write the table here (markdown)")
    args = ap.parse_args(argv)
    trees = ([("before", args.before.resolve())] if args.before else []) + [("after", HERE)]
    lines = [
        f"load at start {load()}; sigma {args.sigma}; engine only: thread time, best of 3; whole process: wall, one "
        "run",
        "",
        "| code | N | scene | integrator, dt, mass | dofs | us/step | us/dof-step | 3D/planar per step | per dof-step "
        "| whole process (tau) | 3D/planar whole |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for label, tree in trees:
        for n in args.n:
            duration = 30.0 if n <= 40 else 1.0
            rows = {}
            for scene in ("one-pinned", "clamped-3d"):
                r = engine_only(tree, scene, n, args.sigma)
                r["whole"] = None if args.no_whole else whole_process(tree, scene, n, args.sigma, duration)
                rows[scene] = r
                print(f"[{time.strftime('%H:%M:%S')}] {label} N={n} {scene}: {r}", file=sys.stderr, flush=True)
            planar = rows["one-pinned"]
            for scene, r in rows.items():
                ratio = scene == "clamped-3d"
                per_step = f"{r['us_step'] / planar['us_step']:.2f}x" if ratio else ""
                per_dof = f"{(r['us_step'] / r['nv']) / (planar['us_step'] / planar['nv']):.2f}x" if ratio else ""
                whole = "" if r["whole"] is None else f"{r['whole']:.2f} s ({duration:g})"
                whole_ratio = f"{r['whole'] / planar['whole']:.2f}x" if ratio and r["whole"] is not None else ""
                lines.append(
                    f"| {label} | {n} | {scene} | {r['integrator']}, {r['dt']:.3g}, {r['mass_ratio']:.3g} | {r['nv']} "
                    f"| {r['us_step']:.1f} | {r['us_step'] / r['nv']:.2f} | {per_step} | {per_dof} | {whole} "
                    f"| {whole_ratio} |"
                )
    lines.append(f"\nload at end {load()}")
    text = "\n".join(lines)
    print(text)
    if args.out:
        args.out.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

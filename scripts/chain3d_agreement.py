"""The clamped chain in 3D in both engines from the same non-planar start: the state each reaches (beat, whirl), its
amplitude, frequency and whirl rate, their relative differences, and the wall time of each run.

    .venv/bin/python scripts/chain3d_agreement.py [--quick]

Prints a markdown table (docs/model3d.md, section 7). Reduced model: DOP853 at rtol = atol = 1e-10; MuJoCo: ball joints
(or pairs of hinges, `joints` column) at the default dt = 0.0025, mass ratio 1e-4, implicitfast. Start: the helix
t_k ~ (1, 0.3 s, 0.3 s^2), s = k / N; the record's second half is measured.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from elastoactive.analysis.motion3d import measure3d
from elastoactive.mjcf.chain3d import Chain3DModel, simulate3d
from elastoactive.reduced.chain3d import Chain3D, solve3d

CASES = ((7, 0.3, 600.0), (7, 0.8, 600.0), (20, 0.3, 800.0), (20, 0.8, 400.0))
"""(N, sigma, duration in tau): two loads above onset at N = 7 (sigma_c = 0.1575) and N = 20 (sigma_c ~ 0.0087)."""


def helix(n: int) -> np.ndarray:
    s = np.arange(1, n + 1) / n
    t = np.column_stack([np.ones(n), 0.3 * s, 0.3 * s * s])
    return t / np.linalg.norm(t, axis=1)[:, None]


def row(n: int, sigma: float, duration: float, joints: str = "ball", dt: float = 0.0025) -> str:
    ts = np.arange(0.0, duration + 1e-9, 0.05)
    t0 = helix(n)
    start = time.perf_counter()
    reduced = measure3d(ts, solve3d(Chain3D(n=n, sigma=sigma), ts, t0, rtol=1e-10, atol=1e-10))
    reduced_time = time.perf_counter() - start
    start = time.perf_counter()
    mujoco = measure3d(ts, simulate3d(Chain3DModel(n=n, sigma=sigma, joints=joints, dt=dt), ts, t0))
    mujoco_time = time.perf_counter() - start

    def diff(name: str) -> str:
        a, b = getattr(mujoco, name), getattr(reduced, name)
        return f"{100 * (a / b - 1):+.2f}%" if b else "-"

    return (
        f"| {n} | {sigma:g} | {joints} | {dt:g} | {reduced.state} / {mujoco.state} | {reduced.tip_amplitude:.4f} | "
        f"{diff('tip_amplitude')} | {reduced.frequency:.5f} | {diff('frequency')} | {reduced.whirl_rate:+.5f} | "
        f"{diff('whirl_rate')} | {reduced.tip_aspect:.3f} | {reduced_time:.1f} / {mujoco_time:.1f} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N = 7 only")
    args = parser.parse_args()
    print(
        "| N | sigma | joints | dt | state (reduced / MuJoCo) | tip amplitude | MuJoCo | f tau | MuJoCo | whirl rate "
        "| MuJoCo | tip aspect | wall s (reduced / MuJoCo) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    cases = [c for c in CASES if not args.quick or c[0] == 7]
    for n, sigma, duration in cases:
        print(row(n, sigma, duration), flush=True)
    n, sigma, duration = CASES[1]
    print(row(n, sigma, duration, joints="hinges"), flush=True)
    print(row(n, sigma, duration, dt=0.00125), flush=True)


if __name__ == "__main__":
    main()

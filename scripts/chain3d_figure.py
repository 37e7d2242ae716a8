"""The figure of docs/model3d.md: the N = 7 chain at sigma = 0.8 in three dimensions, both engines.

    .venv/bin/python scripts/chain3d_figure.py [OUT]   (default docs/img/chain3d_whirl.png)

Left: the whirling chain's shape at eight instants of one turn, seen in perspective (reduced model), with the tip's
path (reduced: line; MuJoCo, ball joints at the default numerics: dots). Middle: the tip's path across the clamp axis,
(y, z), both engines. Right: a settled planar beat kicked 1e-8 l out of its plane: the out-of-plane size max_k |z_k|
grows (log scale) until the chain whirls.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from elastoactive.analysis.motion3d import measure3d  # noqa: E402
from elastoactive.io.outputs import atomic_file  # noqa: E402
from elastoactive.mjcf.chain3d import Chain3DModel, simulate3d  # noqa: E402
from elastoactive.reduced.chain3d import Chain3D, positions, solve3d, tangents_of_angles  # noqa: E402

N, SIGMA = 7, 0.8


def main() -> None:
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "docs/img/chain3d_whirl.png")
    s = np.arange(1, N + 1) / N
    t0 = np.column_stack([np.ones(N), 0.3 * s, 0.3 * s * s])
    t0 /= np.linalg.norm(t0, axis=1)[:, None]
    ts = np.arange(0.0, 400.0 + 1e-9, 0.05)
    chain = Chain3D(n=N, sigma=SIGMA)
    reduced = solve3d(chain, ts, t0, rtol=1e-10, atol=1e-10)
    mujoco = simulate3d(Chain3DModel(n=N, sigma=SIGMA), ts, t0)
    period = 1.0 / measure3d(ts, reduced).frequency
    last = ts > ts[-1] - period

    fig = plt.figure(figsize=(13, 4.2))
    ax = fig.add_subplot(1, 3, 1, projection="3d")
    r = positions(reduced)
    for i in np.linspace(np.flatnonzero(last)[0], ts.size - 1, 8).astype(int):
        p = np.vstack([np.zeros(3), r[i]])
        ax.plot(p[:, 0], p[:, 1], p[:, 2], "-o", ms=2.5, lw=1, color="tab:blue", alpha=0.6)
    ax.plot(*r[last, -1].T, color="tab:orange", lw=1.5)
    ax.set(xlabel="x (l)", ylabel="y (l)", zlabel="z (l)", title=f"whirl, N = {N}, σ = {SIGMA}")

    ax = fig.add_subplot(1, 3, 2)
    tip_r, tip_m = r[last, -1], positions(mujoco)[last, -1]
    ax.plot(tip_r[:, 1], tip_r[:, 2], "-", label="reduced")
    ax.plot(tip_m[::10, 1], tip_m[::10, 2], ".", ms=4, label="MuJoCo (ball joints)")
    ax.set(xlabel="tip y (l)", ylabel="tip z (l)", aspect="equal", title="tip path across the clamp axis")
    ax.legend(fontsize="small")

    ax = fig.add_subplot(1, 3, 3)
    theta0 = 0.01 * np.sin(0.3 * np.arange(1, N + 1))
    beat = solve3d(chain, ts, tangents_of_angles(theta0), rtol=1e-10, atol=1e-10)
    kicked = beat[-1].copy()
    kicked[:, 2] += 1e-8 * s
    kicked /= np.linalg.norm(kicked, axis=1)[:, None]
    tk = np.arange(0.0, 150.0 + 1e-9, 0.05)
    path = solve3d(chain, tk, kicked, rtol=1e-11, atol=1e-13)
    ax.semilogy(tk, np.abs(path[..., 2]).max(axis=1))
    ax.set(xlabel="time after the kick (τ)", ylabel="max |z_k| (l)", title="planar beat kicked out of its plane")
    fig.tight_layout()
    with atomic_file(out) as tmp:
        fig.savefig(tmp, dpi=110)
    print(out)


if __name__ == "__main__":
    main()

"""Measurements of MuJoCo's hydrodynamic coupling (docs/hydrodynamics.md, "The MuJoCo engine"), from the project root:
.venv/bin/python scripts/hydro_mujoco_measure.py accuracy|cost|pair
"""

import sys
import time

import mujoco
import numpy as np

from elastoactive.controllers.hydro import flow_kernel
from elastoactive.mjcf.cilia import CiliaModel, lab_positions, prepare_cilia, simulate_cilia
from elastoactive.reduced.fluid import Beds, _arguments, eval_rhs_fluid, solve_fluid
from elastoactive.scenes.cilium import ROTATION


def start(chains, n, seed=0):
    rng = np.random.default_rng(seed)
    t = np.zeros((chains, n, 3))
    t[..., 0] = 1
    t[..., 1] = 0.05 * rng.standard_normal((chains, n))
    t[..., 2] = 0.02 * rng.standard_normal((chains, n))
    return t / np.linalg.norm(t, axis=-1)[..., None]


def whirl_rate(ts, path, t_from):
    """Mean angular rate of cilium 0's tip about its clamp axis over t >= t_from (rad / tau), and the tip radius."""
    tip = path[:, 0].sum(axis=1)
    keep = ts >= t_from
    phi = np.unwrap(np.arctan2(tip[keep, 2], tip[keep, 1]))
    slope = np.polyfit(ts[keep], phi, 1)[0]
    return slope, np.hypot(tip[keep, 1], tip[keep, 2]).mean()


def accuracy():
    n, sigma, a, h = 7, 1.0, 0.2, 0.5
    bases = np.array([[0.0, 0.0, h]])
    t0 = start(1, n)
    duration, t_from = 150.0, 100.0
    ts = np.arange(0, duration + 1e-9, 0.05)
    for label, beds, radius in (
        ("fluid (rpb)", Beds(n, sigma, bases, ROTATION, mobility="rpb", radius=a), a),
        ("lab-frame drag", Beds(n, sigma, bases, ROTATION), 0.0),
    ):
        s = time.perf_counter()
        ref = solve_fluid(beds, ts, t0, rtol=1e-10, atol=1e-12)
        w_ref, r_ref = whirl_rate(ts, ref, t_from)
        print(f"{label}: reduced whirl rate {w_ref:.6f}, tip radius {r_ref:.5f} ({time.perf_counter() - s:.1f} s)")
        for dt in (0.005, 0.0025, 0.00125, 0.000625):
            s = time.perf_counter()
            path = simulate_cilia(CiliaModel(n, sigma, bases, ROTATION, radius=radius, dt=dt), ts, t0)
            w, r = whirl_rate(ts, path, t_from)
            print(
                f"  dt {dt}: rate {w:.6f} ({(w / w_ref - 1) * 100:+.3f}%), radius {r:.5f} "
                f"({(r / r_ref - 1) * 100:+.3f}%)  [{time.perf_counter() - s:.1f} s]"
            )


def per_step(fn, repeats=5, min_time=0.2):
    """Least CPU time of this process per call (time.process_time: the machine's other load does not count)."""
    best = np.inf
    for _ in range(repeats):
        k, took = 0, 0.0
        s = time.process_time()
        while took < min_time:
            fn()
            k += 1
            took = time.process_time() - s
        best = min(best, took / k)
    return best


def cost():
    print("CPU us per step (process_time, least of 15):")
    print("beads B | cilia x N | mj_step us | coupled step us | flow alone us | ratio | reduced rhs us")
    for chains, n in ((1, 7), (2, 7), (4, 10), (16, 10), (64, 10)):
        bases = np.column_stack([3.0 * np.arange(chains), np.zeros(chains), np.full(chains, 0.5)])
        t0 = start(chains, n)
        plain = prepare_cilia(CiliaModel(n, 1.0, bases, ROTATION, dt=0.0025), t0)
        fluid = prepare_cilia(CiliaModel(n, 1.0, bases, ROTATION, radius=0.2, dt=0.0025), t0, settle=False)
        steps = 20 if chains * n > 100 else 200
        t_plain, t_fluid = np.inf, np.inf
        for _ in range(3):  # interleaved
            t_plain = min(t_plain, per_step(lambda: mujoco.mj_step(plain.model, plain.data, nstep=steps)) / steps)
            t_fluid = min(t_fluid, per_step(lambda: fluid.coupling(fluid.model, fluid.data, steps)) / steps)
        x = lab_positions(CiliaModel(n, 1.0, bases, ROTATION), t0).reshape(-1, 3)
        f, out = np.ones_like(x), np.empty_like(x)
        t_flow = per_step(lambda: flow_kernel(x, f, 0.2, 2, 1.0, out))
        beds = Beds(n, 1.0, bases, ROTATION, mobility="rpb", radius=0.2)
        y, o = t0.ravel().copy(), np.empty(t0.size)
        args = _arguments(beds)
        t_rhs = per_step(lambda: eval_rhs_fluid(y, *args, o))
        print(
            f"{chains * n:7d} | {chains:3d} x {n:2d} | {t_plain * 1e6:10.1f} | {t_fluid * 1e6:15.1f} | "
            f"{t_flow * 1e6:13.1f} | {t_fluid / t_plain:5.2f} | {t_rhs * 1e6:10.1f}"
        )


def pair():
    n, sigma, a, h, d = 7, 1.0, 0.2, 0.5, 2.0
    bases = np.array([[0.0, 0.0, h], [d, 0.0, h]])
    t0 = start(2, n, seed=1)
    duration = 200.0
    ts = np.arange(0, duration + 1e-9, 0.05)
    ref = solve_fluid(Beds(n, sigma, bases, ROTATION, mobility="rpb", radius=a), ts, t0, rtol=1e-10, atol=1e-12)

    def phases(path):
        tip = path.sum(axis=2)  # (T, C, 3) chain frame
        return np.unwrap(np.arctan2(tip[..., 2], tip[..., 1]), axis=0)

    keep = ts >= 150
    p_ref = phases(ref)
    lag_ref = np.angle(np.mean(np.exp(1j * (p_ref[keep, 1] - p_ref[keep, 0]))))
    rate_ref = np.polyfit(ts[keep], p_ref[keep, 0], 1)[0]
    print(f"reduced: lag {lag_ref:+.5f} rad, rate {rate_ref:.6f}")
    for dt in (0.0025, 0.00125):
        s = time.perf_counter()
        path = simulate_cilia(CiliaModel(n, sigma, bases, ROTATION, radius=a, dt=dt), ts, t0)
        p = phases(path)
        lag = np.angle(np.mean(np.exp(1j * (p[keep, 1] - p[keep, 0]))))
        rate = np.polyfit(ts[keep], p[keep, 0], 1)[0]
        print(
            f"  dt {dt}: lag {lag:+.5f} rad (diff {lag - lag_ref:+.5f}), rate {rate:.6f} "
            f"({(rate / rate_ref - 1) * 100:+.3f}%) [{time.perf_counter() - s:.1f} s]"
        )


if __name__ == "__main__":
    {"accuracy": accuracy, "cost": cost, "pair": pair}[sys.argv[1]]()

"""The cost of cilia through the fluid against the number of beads (reduced engine, elastoactive.reduced.fluid).

Rows of M cilia of N beads on the wall (cilia-row's geometry: bases (c d, 0, h), the Rotne-Prager-Blake mobility),
for each M: the cost of one right-hand-side evaluation (the dense mobility's O(B^2) build, B = M N beads, and the
links' tensions' B x B Cholesky, O(B^3)), and of the mobility alone; the evaluations DOP853 takes per tau (measured
by a compiled run where it is cheap, else bounded below by the straight row's fastest rate); the beat period (one
cilium's run); and so the projected wall time of 100 beats. The pair of N = 7 over 1000 tau is timed whole.

    .venv/bin/python scripts/bench_fluid.py                 # M = 1 .. 64, N = 10 (a few minutes)
    .venv/bin/python scripts/bench_fluid.py --quick         # M = 1 .. 16
    .venv/bin/python scripts/bench_fluid.py --out FILE.md   # also write the table

Timings are of one process on a shared machine: the load average is printed with the table.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from elastoactive.analysis.stability_fluid import linear_operator_fluid
from elastoactive.hydro.blake import rpb_kernel
from elastoactive.reduced import fluid
from elastoactive.scenes.cilium import FLUID_TOLERANCES, ROTATION

RADIUS = 0.1
HEIGHT = 0.5
SPACING = 3.0
SIGMA = 0.8
BEATS = 100
BUDGET = 600.0  # s: the "100 beats in 10 minutes"
MEASURED_UP_TO = 32  # cilia: the evaluations per tau are measured by a run up to here, scaled beyond


def row(m: int, n: int, sigma: float = SIGMA) -> fluid.Beds:
    c = np.arange(m, dtype=float)
    bases = np.stack([c * SPACING, np.zeros(m), np.full(m, HEIGHT)], axis=1)
    return fluid.Beds(n, sigma, bases, ROTATION, "rpb", RADIUS).checked()


def start(beds: fluid.Beds, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.zeros((beds.chains, beds.n, 3))
    t[..., 0] = 1.0
    t[..., 1:] = 0.05 * rng.normal(size=(beds.chains, beds.n, 2))
    return t / np.linalg.norm(t, axis=-1)[..., None]


def timed(f, least: float = 0.3) -> float:
    """Seconds per call of f (the best of repeats totalling `least` s)."""
    f()
    best, total = np.inf, 0.0
    while total < least:
        s = time.perf_counter()
        f()
        took = time.perf_counter() - s
        best, total = min(best, took), total + took
    return best


def period(n: int) -> float:
    """One cilium's beat period (tau): zero crossings of its tip's in-plane displacement over the second half of
    300 tau."""
    beds = row(1, n)
    ts = np.linspace(0.0, 300.0, 30001)
    path = fluid.solve_fluid(beds, ts, start(beds), rtol=FLUID_TOLERANCES[0], atol=FLUID_TOLERANCES[1])
    tip = path[:, 0, :, 1].sum(axis=-1)
    keep = ts > 150.0
    x, t = tip[keep] - tip[keep].mean(), ts[keep]
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    return float(np.mean(np.diff(t[up])))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10, help="beads per cilium (default 10)")
    ap.add_argument("--quick", action="store_true", help="M up to 16")
    ap.add_argument("--out", type=Path, default=None, help="also write the table (markdown) here")
    args = ap.parse_args(argv)
    n = args.n
    sizes = (1, 2, 4, 8, 16) if args.quick else (1, 2, 4, 8, 16, 32, 64)
    rtol, atol = FLUID_TOLERANCES
    lines = [f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; N = {n}, a / l = {RADIUS}, "
             f"h = {HEIGHT}, d = {SPACING}, sigma = {SIGMA}, rtol {rtol:g}, atol {atol:g}"]  # fmt: skip

    pair = row(2, 7)
    ts = np.linspace(0.0, 1000.0, 10001)
    fluid.solve_fluid(pair, ts[:11], start(pair), rtol=rtol, atol=atol)  # compiled (or loaded) first
    seconds = {}
    for method in fluid.METHODS:
        span = ts if method == "numba-DOP853" else ts[:2001]
        s = time.perf_counter()
        fluid.solve_fluid(pair, span, start(pair), rtol=rtol, atol=atol, method=method)
        seconds[method] = (time.perf_counter() - s) * 1000.0 / span[-1]
    lines.append(
        f"pair of N = 7 on the wall, 1000 tau: {seconds['numba-DOP853']:.2f} s compiled (numba-DOP853), "
        f"{seconds['DOP853']:.1f} s by scipy's DOP853 (200 tau timed, x 5)"
    )
    beat = period(n)
    lines.append(f"one cilium's beat period: {beat:.3f} tau; 100 beats = {BEATS * beat:.0f} tau")
    lines += [
        "",
        "| M | beads B | mobility build (ms) | evaluation (ms) | evals / tau | how | 100 beats (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    measured = (0.0, 1.0)
    largest = 0
    for m in sizes:
        beds = row(m, n)
        b = m * n
        y = np.ascontiguousarray(start(beds)).ravel()
        out = np.empty(y.size)
        args_ = fluid._arguments(beds)
        x = fluid.lab_positions(start(beds), beds).reshape(-1, 3)
        mob = np.empty((3 * b, 3 * b))
        t_mob = timed(lambda x=x, mob=mob: rpb_kernel(x, RADIUS, mob))
        t_eval = timed(lambda y=y, out=out, a=args_: fluid.eval_rhs_fluid(y, *a, out))
        rate = np.abs(np.linalg.eigvals(linear_operator_fluid(beds, SIGMA))).max()
        if m <= MEASURED_UP_TO:
            span = 50.0 if m <= 4 else 10.0
            run_ts = np.array([0.0, span])
            from elastoactive.reduced.dop853_loop import integrate

            run = integrate(fluid._dop853_fluid, args_, run_ts, y, rtol, atol)
            per_tau = run.nfev / span
            how = f"measured ({span:g} tau)"
            measured = (per_tau, rate)
        else:  # the last measured, scaled by the straight row's fastest rate (an explicit method's steps follow it)
            per_tau = measured[0] * rate / measured[1]
            how = f"M = {MEASURED_UP_TO}'s x fastest rate ratio"
        cost = BEATS * beat * per_tau * t_eval
        if cost <= BUDGET:
            largest = m
        lines.append(f"| {m} | {b} | {1e3 * t_mob:.3g} | {1e3 * t_eval:.3g} | {per_tau:.0f} | {how} | {cost:.3g} |")
        print(lines[-1], flush=True)
    lines.append("")
    lines.append(f"largest row that runs {BEATS} beats within {BUDGET:.0f} s: M = {largest} cilia of N = {n}")
    text = "\n".join(lines)
    print(text)
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

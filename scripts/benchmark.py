#!/usr/bin/env python
"""Performance benchmark, run on demand (not a test): every figure measured side by side in one run.

  .venv/bin/python scripts/benchmark.py [--out results/benchmark.md] [--repeats 7] [--quick]

1. force callback: mj_step(nstep) on the same N = 7 one-pinned model with the compiled C passive
   callback, with no callback (bare engine, no follower forces) and with the Python reference
   callback, per integrator (target: compiled / bare <= 1.3)
2. reduced model: simulate_reduced (numba-DOP853) against simulate_reference (scipy DOP853 on the
   plain-numpy right-hand side) at the same tolerance, per paper case (target >= 10x)
3. sweeps: batch.run_cases with 1 and 2 worker processes on the same MuJoCo cases (target >= 1.8x)
4. throughput: tau simulated per wall second on one core, N = 7 one-pinned chain, at the default
   settings and at the 'fast' preset, with their amplitude error against the reduced model (target
   >= 2000 tau/s at <= 1% amplitude error), plus where the time goes (engine steps vs the Python
   sampling loop of simulate_mujoco)

Timings are the best of N repeats (the machine is shared; the best is the least disturbed run).
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

import mujoco
import numpy as np

from elastoactive.batch import Case, run_cases
from elastoactive.controllers import compiled_passive, follower_forces, reference_passive
from elastoactive.engines.mujoco import prepare, simulate_mujoco
from elastoactive.engines.reduced import simulate_reduced, simulate_reference
from elastoactive.params import Numerics, Physics
from elastoactive.results import measure
from elastoactive.validate import validation_cases

CHAIN = Physics(n=7, sigma=0.8)  # one pinned end, the paper's beat


def best_of(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


# ------------------------------------------------------------------------------------------------
def bench_callback(repeats: int, nstep: int) -> list[dict]:
    """us per step with the compiled callback, without a callback and with the Python callback."""
    rows = []
    for integrator in ("implicitfast", "implicit", "discrete", "Euler", "RK4"):
        # Euler/RK4 treat the drag explicitly: dt must stay below 2 m / gamma
        numerics = Numerics(integrator=integrator, **({"mass_ratio": 1e-2} if integrator in ("Euler", "RK4") else {}))
        model, data = prepare(CHAIN, numerics)
        q0 = data.qpos.copy()
        results = {}
        variants = {"bare": None, "compiled": compiled_passive, "python": reference_passive}
        best = {k: np.inf for k in variants}
        for _ in range(repeats):  # interleaved, so that a slow spell hits all variants alike
            for name, cb in variants.items():
                n = nstep if name != "python" else max(nstep // 10, 200)
                mujoco.mj_resetData(model, data)
                data.qpos[:] = q0
                with follower_forces(cb):
                    t0 = time.perf_counter()
                    mujoco.mj_step(model, data, nstep=n)
                    best[name] = min(best[name], (time.perf_counter() - t0) / n)
        for name in variants:
            results[name] = 1e6 * best[name]
        rows.append({"integrator": integrator, "mass_ratio": numerics.mass_ratio, "dt": numerics.dt, **results,
                     "compiled_ratio": results["compiled"] / results["bare"],
                     "python_ratio": results["python"] / results["bare"]})
    return rows


# ------------------------------------------------------------------------------------------------
def bench_reduced(repeats: int, quick: bool) -> list[dict]:
    rows = []
    tol = dict(rtol=1e-9, atol=1e-11)
    simulate_reduced(CHAIN, Numerics(), 1.0)  # load the compiled kernels before timing
    for case in validation_cases():
        physics, duration = case.physics, case.duration / 3 if quick else case.duration
        numerics = Numerics()
        fast = best_of(lambda: simulate_reduced(physics, numerics, duration, method="numba-DOP853", **tol), repeats)
        a = simulate_reduced(physics, numerics, duration, method="numba-DOP853", **tol)
        ref_runs = []
        for _ in range(max(1, repeats // 3)):
            b = simulate_reference(physics, numerics, duration, method="DOP853", **tol)
            ref_runs.append(b.wall_time_s)
        slow = min(ref_runs)
        rows.append({"case": _case(physics), "duration": duration, "compiled_s": fast, "reference_s": slow,
                     "speedup": slow / fast, "max_diff": float(np.abs(a.theta - b.theta).max())})
    return rows


def _case(p: Physics) -> str:
    return p.scene_def.label(p)


# ------------------------------------------------------------------------------------------------
def bench_sweep(n_cases: int, duration: float, repeats: int) -> dict:
    cases = [Case(Physics(n=7, sigma=s), Numerics(), duration) for s in np.linspace(0.3, 1.5, n_cases)]
    run_cases(cases[:2], workers=2, progress=False)  # start-up costs (imports, numba cache) out of the way
    one, two = [], []
    for _ in range(repeats):  # interleaved, so that a busy spell of the shared machine hits both
        one.append(best_of(lambda: run_cases(cases, workers=1, progress=False), 1))
        two.append(best_of(lambda: run_cases(cases, workers=2, progress=False), 1))
    return {"cases": n_cases, "duration": duration, "one_s": min(one), "two_s": min(two),
            "speedup": min(one) / min(two), "one_all": one, "two_all": two}


# ------------------------------------------------------------------------------------------------
def bench_throughput(repeats: int, duration: float) -> list[dict]:
    ref = simulate_reduced(CHAIN, Numerics(), duration, rtol=1e-11, atol=1e-13)
    ref_amp = measure(ref).amplitude
    rows = []
    for name, numerics in (("default (accurate)", Numerics()), ("fast preset", Numerics.preset("fast")),
                           ("fast preset, sample_dt 0.1", Numerics.preset("fast", sample_dt=0.1))):
        runs = [simulate_mujoco(CHAIN, numerics, duration) for _ in range(repeats)]
        wall = min(r.wall_time_s for r in runs)
        if numerics.sample_dt != ref.t[1] - ref.t[0]:
            ref_n = simulate_reduced(CHAIN, numerics, duration, rtol=1e-11, atol=1e-13)
            amp_ref = measure(ref_n).amplitude
        else:
            amp_ref = ref_amp
        amp_err = abs(measure(runs[0]).amplitude - amp_ref) / amp_ref
        # the engine alone: the same number of steps in one C call (no sampling loop, no callback changes)
        steps = runs[0].info["steps"]
        model, data = prepare(CHAIN, numerics)
        q0 = data.qpos.copy()

        def engine_only():
            mujoco.mj_resetData(model, data)
            data.qpos[:] = q0
            with follower_forces():
                mujoco.mj_step(model, data, nstep=steps)

        engine = best_of(engine_only, repeats)
        rows.append({"setting": name, "dt": numerics.dt, "mass_ratio": numerics.mass_ratio,
                     "sample_dt": numerics.sample_dt, "wall_s": wall, "tau_per_s": duration / wall,
                     "engine_s": engine, "engine_tau_per_s": duration / engine, "loop_share": 1 - engine / wall,
                     "us_per_sample_loop": 1e6 * (wall - engine) / (runs[0].t.size - 1),
                     "amplitude_error": amp_err})
    return rows


# ------------------------------------------------------------------------------------------------
def report(cb, red, sweep, thr, meta) -> str:
    out = [f"# Benchmark ({meta['date']}, {meta['machine']})", "",
           f"Best of {meta['repeats']} repeats per figure; the 2 cores were shared with other jobs "
           f"(load average at start {meta['load']}), so figures carry tens of percent noise.", ""]
    out += ["## 1. Force callback vs bare engine step (N = 7 one-pinned, dt = 0.0025)", "",
            "| integrator | mass ratio | bare us/step | compiled callback us/step | Python callback us/step "
            "| compiled / bare (target <= 1.3) | Python / bare |", "|---|---|---|---|---|---|---|"]
    for r in cb:
        out.append(f"| {r['integrator']} | {r['mass_ratio']:g} | {r['bare']:.2f} | {r['compiled']:.2f} | {r['python']:.1f} "
                   f"| **{r['compiled_ratio']:.2f}x** | {r['python_ratio']:.1f}x |")
    out += ["", "## 2. Reduced model: compiled vs plain numpy/scipy (same DOP853 algorithm, rtol 1e-9, atol 1e-11)", "",
            "| case | duration tau | simulate_reduced s | simulate_reference s | speed-up (target >= 10) | max angle difference |",
            "|---|---|---|---|---|---|"]
    for r in red:
        out.append(f"| {r['case']} | {r['duration']:g} | {r['compiled_s']:.4f} | {r['reference_s']:.3f} "
                   f"| **{r['speedup']:.0f}x** | {r['max_diff']:.1e} |")
    out += ["", "## 3. Sweep on 2 cores vs 1 (batch.run_cases, process pool)", "",
            "| cases | tau per case | 1 worker s | 2 workers s | speed-up (target >= 1.8) |", "|---|---|---|---|---|",
            f"| {sweep['cases']} MuJoCo one-pinned N = 7 | {sweep['duration']:g} | {sweep['one_s']:.2f} | {sweep['two_s']:.2f} "
            f"| **{sweep['speedup']:.2f}x** |", "",
            "All repeats (s), 1 worker: " + ", ".join(f"{x:.2f}" for x in sweep["one_all"])
            + "; 2 workers: " + ", ".join(f"{x:.2f}" for x in sweep["two_all"]) + "."]
    out += ["", "## 4. Throughput on one core: N = 7 one-pinned chain", "",
            "| setting | dt | mass ratio | sample_dt | tau per wall s (target >= 2000) | amplitude error (target <= 1%) "
            "| engine alone, tau/s | share of time in the Python sampling loop | loop cost per sample, us |",
            "|---|---|---|---|---|---|---|---|---|"]
    for r in thr:
        out.append(f"| {r['setting']} | {r['dt']:g} | {r['mass_ratio']:g} | {r['sample_dt']:g} | **{r['tau_per_s']:.0f}** "
                   f"| {100 * r['amplitude_error']:.3f}% | {r['engine_tau_per_s']:.0f} | {100 * r['loop_share']:.0f}% "
                   f"| {r['us_per_sample_loop']:.1f} |")
    out.append("")
    return "\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("results/benchmark.md"))
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--quick", action="store_true", help="fewer steps and shorter runs (about 1 min)")
    args = ap.parse_args(argv)
    import os

    meta = {"date": time.strftime("%Y-%m-%d %H:%M"), "repeats": args.repeats,
            "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, MuJoCo {mujoco.__version__}",
            "load": " ".join(open("/proc/loadavg").read().split()[:3]) if os.path.exists("/proc/loadavg") else "?"}
    t0 = time.perf_counter()
    print("callback ...", file=sys.stderr)
    cb = bench_callback(args.repeats, 2000 if args.quick else 10000)
    print("reduced ...", file=sys.stderr)
    red = bench_reduced(args.repeats, args.quick)
    print("sweep ...", file=sys.stderr)
    sweep = bench_sweep(8 if args.quick else 12, 100.0 if args.quick else 200.0, 1 if args.quick else 3)
    print("throughput ...", file=sys.stderr)
    thr = bench_throughput(3 if args.quick else args.repeats, 100.0 if args.quick else 300.0)
    text = report(cb, red, sweep, thr, meta)
    text += f"\nBenchmark took {time.perf_counter() - t0:.0f} s. Rerun: `.venv/bin/python scripts/benchmark.py`.\n"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

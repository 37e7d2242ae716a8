"""Sections C, D (MuJoCo's rows) and E of scripts/benchmark.py: the MuJoCo sweep against the engine floor, long
chains in MuJoCo (tau per wall second, the step cost by N, the alternatives at N = 100) and the compiled force callback
against the bare step. benchmark.py runs them and writes their report."""

from __future__ import annotations

import statistics
import tempfile
import threading
import time
from pathlib import Path

import mujoco
import numpy as np
from bench_common import CLI, CORES, load, run_wall  # scripts/ is on sys.path when a script runs

from elastoactive.controllers import compiled_passive, follower_forces, reference_passive
from elastoactive.core.params import Numerics, Physics
from elastoactive.engines.mujoco import prepare, simulate_mujoco
from elastoactive.engines.reduced import regime, simulate_reduced


# ------------------------------------------------------------------------------------------------
# C. MuJoCo sweep against the engine floor
# ------------------------------------------------------------------------------------------------
def step_cost(physics: Physics, numerics: Numerics, nstep: int, repeats: int) -> float:
    model, data = prepare(physics, numerics)
    q0 = data.qpos.copy()
    best = np.inf
    with follower_forces(compiled_passive):
        for _ in range(repeats):
            mujoco.mj_resetData(model, data)
            data.qpos[:] = q0
            t0 = time.perf_counter()
            mujoco.mj_step(model, data, nstep=nstep)
            best = min(best, (time.perf_counter() - t0) / nstep)
    return best


def step_cost_pair(physics: tuple[Physics, Physics], numerics: Numerics, nstep: int, repeats: int) -> float:
    """The compiled step's cost with two threads stepping at once (one model each, as a sweep's two stepping
    threads do): the slower thread's time per step, best of `repeats`. Against step_cost it tells what sharing the
    cores costs the engine itself (memory, caches, clock), before any sweep machinery."""
    pairs = [prepare(p, numerics) for p in physics]
    starts = [data.qpos.copy() for _, data in pairs]
    best = np.inf
    with follower_forces(compiled_passive):
        for _ in range(repeats):
            gate = threading.Barrier(len(pairs))
            times = [0.0] * len(pairs)

            def run(k: int) -> None:
                model, data = pairs[k]
                mujoco.mj_resetData(model, data)
                data.qpos[:] = starts[k]
                gate.wait()
                t0 = time.perf_counter()
                mujoco.mj_step(model, data, nstep=nstep)  # releases the GIL
                times[k] = time.perf_counter() - t0

            threads = [threading.Thread(target=run, args=(k,)) for k in range(len(pairs))]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            best = min(best, max(times) / nstep)
    return best


def bench_sweep(points: int, duration: float, repeats: int) -> dict:
    """The sweep as a whole process against the engine floor, measured in pairs (the floor, then the sweep) so that
    each ratio compares the two at the same moment of a shared machine; the ratio reported is the median of the
    pairs'. The floor of a pair: the best of 5 x 4000 compiled steps (N = 7, the grid's first and last sigma, the
    cheaper) x the sweep's steps / cores; beside it the same with two threads stepping at once (step_cost_pair)."""
    numerics = Numerics()
    sigmas = np.linspace(0.3, 1.0, points)
    ends = (Physics(n=7, sigma=sigmas[0]), Physics(n=7, sigma=sigmas[-1]))
    steps = points * round(duration / numerics.dt)
    walls, floors, costs, pair_costs, loads = [], [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(repeats):
            cost = min(step_cost(p, numerics, 4000, 5) for p in ends)
            pair_costs.append(step_cost_pair(ends, numerics, 4000, 5))
            costs.append(cost)
            floors.append(cost * steps / CORES)
            out = Path(tmp) / f"sweep{k}.nc"
            command = [CLI, "sweep", "one-pinned", "--grid", f"sigma=0.3:1.0:{points}", "--duration", f"{duration:g}"]
            walls.append(run_wall([*command, "--out", str(out), "--quiet"], tmp))
            loads.append(load())
    ratios = [w / f for w, f in zip(walls, floors)]
    return {
        "points": points,
        "duration": duration,
        "steps": steps,
        "us_per_step": 1e6 * statistics.median(costs),
        "us_per_step_pair": 1e6 * statistics.median(pair_costs),
        "floor_s": statistics.median(floors),
        "walls": walls,
        "floors": floors,
        "ratios": ratios,
        "ratio": statistics.median(ratios),
        "loads": loads,
        "wall_s": statistics.median(walls),
        "best_s": min(walls),
    }


def sweep_report(sweep: dict) -> list[str]:
    """Section C's lines (scripts/benchmark.py, and alone with --sweep)."""
    pairs = ", ".join(f"{w:.2f} / {f:.2f}" for w, f in zip(sweep["walls"], sweep["floors"]))
    return [
        "## C. MuJoCo sweep against the engine floor (target a)",
        "",
        "| command | median s | engine floor s (median) | sweep / floor (median of the pairs) "
        "| pairs (sweep / floor s) |",
        "|---|---|---|---|---|",
        f"| `elastoactive sweep one-pinned --grid sigma=0.3:1.0:{sweep['points']} --duration {sweep['duration']:g} "
        f"--out TMP --quiet` | **{sweep['wall_s']:.2f}** | {sweep['floor_s']:.2f} | **{sweep['ratio']:.2f}x** "
        f"({min(sweep['ratios']):.2f}-{max(sweep['ratios']):.2f}) | {pairs} |",
        "",
        f"Floor = {sweep['us_per_step']:.2f} us per compiled step (mj_step with the C callback, N = 7, default "
        f"numerics, best of 5 x 4000 steps, measured just before each sweep) x {sweep['steps']} steps / {CORES} "
        f"cores. Two threads stepping at once cost {sweep['us_per_step_pair']:.2f} us per step each "
        f"({sweep['us_per_step_pair'] / sweep['us_per_step']:.2f}x): what sharing the cores costs the engine alone. "
        f"The whole process includes start-up, model compilation, pre-flight checks and writing the netCDF file. "
        f"Load average after each sweep: {'; '.join(sweep['loads'])}.",
    ]


# ------------------------------------------------------------------------------------------------
# D. long chains
# ------------------------------------------------------------------------------------------------
def bench_mujoco_long(cases: dict, repeats: int) -> dict:
    """simulate_mujoco with the default (automatic) numerics: tau per wall second, and the largest angle difference
    against the reduced (overdamped) model over the same run, relative to the largest angle."""
    rows = []
    for n, (sigma, duration) in cases.items():
        physics = Physics(n=n, sigma=sigma)
        used = Numerics().for_physics(physics)
        simulate_mujoco(physics, Numerics(), min(duration, 0.5))  # model compiled once
        runs = [simulate_mujoco(physics, Numerics(), duration) for _ in range(repeats)]
        best = min(runs, key=lambda r: r.wall_time_s)
        ref = simulate_reduced(physics, Numerics(), duration)
        err = float(np.abs(best.theta - ref.theta).max() / np.abs(ref.theta).max())
        rows.append(
            {
                "n": n,
                "sigma": sigma,
                "duration": duration,
                "wall_s": best.wall_time_s,
                "tau_per_s": duration / best.wall_time_s,
                "s_per_tau": best.wall_time_s / duration,
                "us_per_step": best.info["us_per_step"],
                "integrator": used.integrator,
                "dt": used.dt,
                "mass_ratio": used.mass_ratio,
                "err": err,
                "max_angle": float(np.abs(ref.theta).max()),
            }
        )
    long = [r for r in rows if r["n"] >= 30]
    x = np.log([r["n"] for r in long])
    fit = lambda key: float(np.polyfit(x, np.log([r[key] for r in long]), 1)[0]) if len(long) >= 2 else np.nan
    return {"rows": rows, "exponent_tau": fit("s_per_tau"), "exponent_step": fit("us_per_step")}


def _step_us(physics: Physics, numerics: Numerics, nstep: int, repeats: int) -> float:
    """Best thread time of mj_step(nstep) per step with the compiled callback, in us."""
    model, data = prepare(physics, numerics)
    best = np.inf
    with follower_forces(compiled_passive):
        for _ in range(repeats):
            t0 = time.thread_time()
            mujoco.mj_step(model, data, nstep=nstep)
            best = min(best, (time.thread_time() - t0) / nstep)
    return 1e6 * best


def bench_step_by_n(ns, repeats: int) -> list[dict]:
    """Step cost of implicitfast (the default below LONG_CHAIN) and of explicit drag (Euler, RK4) by N."""
    rows = []
    for n in ns:
        physics = Physics(n=n, sigma=0.05)
        nstep = max(20, int(200_000 / n**2))
        row = {"n": n}
        for name, numerics in (
            ("implicitfast", Numerics(integrator="implicitfast")),
            ("Euler", Numerics(integrator="Euler", mass_ratio=2e-3)),
            ("RK4", Numerics(integrator="RK4", mass_ratio=2e-3)),
        ):
            row[name] = _step_us(physics, numerics, nstep if name != "RK4" else max(10, nstep // 4), repeats)
        rows.append(row)
    return rows


ALTERNATIVES = (  # N = 100, sigma 0.05: what the automatic choice was picked from
    ("implicitfast dt 0.0025, m 1e-4 (the defaults below N = 30)", dict(integrator="implicitfast")),
    ("implicitfast dt 0.005, m 1e-3", dict(integrator="implicitfast", dt=0.005, mass_ratio=1e-3)),
    ("implicitfast dt 0.01, m 1e-3 ('fast' preset)", dict(integrator="implicitfast", dt=0.01, mass_ratio=1e-3)),
    ("Euler, automatic (Numerics() at N = 100)", None),
    ("Euler dt 0.0025, m 2e-3", dict(integrator="Euler", dt=0.0025, mass_ratio=2e-3)),
    ("Euler dt 0.005, m 4e-3", dict(integrator="Euler", dt=0.005, mass_ratio=4e-3)),
    ("RK4 dt 0.0025, m 2e-3", dict(integrator="RK4", dt=0.0025, mass_ratio=2e-3)),
    ("RK4 dt 0.005, m 4e-3", dict(integrator="RK4", dt=0.005, mass_ratio=4e-3)),
)


def bench_alternatives(n: int, duration: float) -> list[dict]:
    """Integrator, dt and mass at one long chain: tau per wall second and the angle error against the reduced
    model (one run each)."""
    physics = Physics(n=n, sigma=0.05)
    ref = simulate_reduced(physics, Numerics(), duration)
    rows = []
    for label, given in ALTERNATIVES:
        numerics = Numerics() if given is None else Numerics(**given)
        used = numerics.for_physics(physics)
        simulate_mujoco(physics, numerics, 0.2)
        traj = simulate_mujoco(physics, numerics, duration)
        rows.append(
            {
                "label": label,
                "integrator": used.integrator,
                "dt": used.dt,
                "mass_ratio": used.mass_ratio,
                "inertia_number": regime(physics, used).inertia_number,
                "us_per_step": traj.info["us_per_step"],
                "tau_per_s": duration / traj.wall_time_s,
                "err": float(np.abs(traj.theta - ref.theta).max() / np.abs(ref.theta).max()),
            }
        )
    return rows


# ------------------------------------------------------------------------------------------------
# E. callback vs bare step
# ------------------------------------------------------------------------------------------------
def bench_callback(repeats: int, nstep: int) -> list[dict]:
    chain = Physics(n=7, sigma=0.8)
    rows = []
    for integrator in ("implicitfast", "implicit", "discrete", "Euler", "RK4"):
        # Euler/RK4 treat the drag explicitly: dt must stay below 2 m / gamma
        numerics = Numerics(integrator=integrator, **({"mass_ratio": 1e-2} if integrator in ("Euler", "RK4") else {}))
        model, data = prepare(chain, numerics)
        q0 = data.qpos.copy()
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
        res = {k: 1e6 * v for k, v in best.items()}
        rows.append(
            {
                "integrator": integrator,
                "mass_ratio": numerics.mass_ratio,
                **res,
                "compiled_ratio": res["compiled"] / res["bare"],
                "python_ratio": res["python"] / res["bare"],
            }
        )
    return rows


# ------------------------------------------------------------------------------------------------

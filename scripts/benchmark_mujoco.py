"""Sections C, D (MuJoCo's rows) and E of scripts/benchmark.py: the MuJoCo sweep against the engine floor, long
chains in MuJoCo (tau per wall second, the step cost by N, the alternatives at N = 100) and the compiled force callback
against the bare step. benchmark.py runs them and writes their report."""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np
from bench_common import CLI, CORES, run_wall  # scripts/ is on sys.path when a script runs

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


def bench_sweep(points: int, duration: float, repeats: int) -> dict:
    numerics = Numerics()
    sigmas = np.linspace(0.3, 1.0, points)
    costs = [step_cost(Physics(n=7, sigma=s), numerics, 4000, 5) for s in (sigmas[0], sigmas[-1])]
    steps = points * round(duration / numerics.dt)
    floor = min(costs) * steps / CORES
    walls = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(repeats):
            out = Path(tmp) / f"sweep{k}.nc"
            walls.append(
                run_wall(
                    [
                        CLI,
                        "sweep",
                        "one-pinned",
                        "--grid",
                        f"sigma=0.3:1.0:{points}",
                        "--duration",
                        f"{duration:g}",
                        "--out",
                        str(out),
                        "--quiet",
                    ],
                    tmp,
                )
            )
    return {
        "points": points,
        "duration": duration,
        "steps": steps,
        "us_per_step": 1e6 * min(costs),
        "floor_s": floor,
        "walls": walls,
        "wall_s": statistics.median(walls),
        "best_s": min(walls),
    }


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

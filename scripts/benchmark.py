#!/usr/bin/env python
"""Performance benchmark, run on demand (not a test): every figure measured side by side in one run.

  .venv/bin/python scripts/benchmark.py [--quick] [--out docs/generated/benchmark.md]

A. reduced model, warm, at EQUAL ACCURACY (target e): the compiled default (simulate_reduced, rtol 1e-9)
   against plain scipy (solve_ivp with LSODA, Radau, BDF, RK45, DOP853 on the plain-numpy right-hand side
   rhs_reference). Accuracy = max |theta - theta_ref| over the run, theta_ref the compiled model at rtol 1e-12.
   Each scipy method gets the loosest rtol (atol = rtol / 100; ladder of decades, then one bisection step)
   whose error is <= 2 x the compiled run's error. A method is dropped as soon as one of its runs is slower
   than the best plain method found so far for that case (it cannot win), or exceeds a time cap.
   Cases: N = 7, every scene's validation case at 600 tau; N = 30 and 100, one-pinned, sigma 0.05, 100 tau.
B. whole process (target e, b): `elastoactive run one-pinned --engine reduced --duration 600 --quiet` against a
   plain script written to a temporary file (numpy + scipy LSODA, the same equations, at the rtol that matched
   in A, its imports included), median of 5 subprocess wall times each; `elastoactive --help` (target < 0.2 s).
C. MuJoCo sweep (target a): `elastoactive sweep one-pinned --grid sigma=0.3:1.0:16 --duration 100 --out TMP
   --quiet` as a whole process against the engine floor measured in the same run: the compiled step cost
   (best of several) x all steps / cores (C, D's MuJoCo rows and E: scripts/benchmark_mujoco.py).
D. long chains (targets c, d): MuJoCo tau per wall second at N = 7, 30, 100, 200 (simulate_mujoco with Numerics(),
   i.e. the automatic long-chain numerics from N = 30 on, Numerics.for_physics), with the angle error against the
   reduced model over the same run and the log-log growth exponents; the step cost of implicitfast, Euler and RK4
   by N; alternatives (integrator, dt, mass) at N = 100 over 20 tau; the reduced model's wall s per 100 tau at
   N = 7, 30, 100, 200 (sigma 0.05) and its log-log growth exponent.
E. the compiled force callback against the bare MuJoCo step (mj_step(nstep), N = 7, per integrator).
F. the filament (--filament runs this part alone; docs/generated/benchmark_filament.md): the clamped filament at
   S = 100 in PyElastica (the optional extra `bench`; its rows are skipped with a note without it) at 50 and 100
   elements, beside `elastoactive run --engine reduced` at N = 40, 80, 160 and the ladder `elastoactive filament`,
   every error against the ladder's extrapolated continuum, wall time per beat period (about 3 min).
G. the active lattice (--network runs this part alone; docs/generated/benchmark_network.md): the R = 6 patch (127
   nodes, 91 self-aligning units) for 1000 gamma / k in MuJoCo (default and 'fast' numerics), the reduced engine and a
   plain scipy solve_ivp script, the ODE solvers at the loosest rtol matching MuJoCo's error (about 3 min;
   scripts/benchmark_network.py).
H. the network's cost against its size (--network-scale runs this part alone; docs/generated/
   benchmark_network_scale.md): pinned triangular hexagons of 127 to 10 267 nodes, the reduced engine for 1000 gamma / k
   beside a plain numpy/scipy script of the same equations at equal accuracy and scipy's BDF, the lowest modes and
   the stability bracket, the whole process at 10 267 nodes, MuJoCo at 1027 nodes (scripts/benchmark_network_scale.py).
I. the clamped filament in 3D from an out-of-plane start (--elastica3d runs this part alone; docs/generated/
   benchmark_elastica3d.md): PyElastica (the optional extra `bench`) at 50, 100 and 200 elements beside the reduced 3D
   chain at N = 20 and 40 and the whirl's continuum limit (Newton's whirls along a ladder of N), S = 100: the state
   reached, its rate and tip radius against the continuum, wall times (scripts/bench_elastica3d.py; ~20 min loaded).

Timings are best of a few repeats unless said (the 2 cores are shared; the best is the least disturbed run);
whole-process figures are medians. --quick shortens every part (about 1 min). --sweep runs section C alone and
prints it (5 pairs of floor and sweep, about 1 min); --startup section B alone (about 30 s).
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np
from bench_common import CLI, CORES, load, log, run_wall  # scripts/ is on sys.path when a script runs
from bench_elastica3d import write_elastica3d
from benchmark_filament import bench_filament, filament_report
from benchmark_mujoco import (
    bench_alternatives,
    bench_callback,
    bench_mujoco_long,
    bench_step_by_n,
    bench_sweep,
    sweep_report,
)
from benchmark_network import bench_network, network_report
from benchmark_network_scale import bench_network_scale, scale_report

from elastoactive.checks.validate import validation_cases
from elastoactive.core.params import Numerics, Physics
from elastoactive.core.registry import initial_angles
from elastoactive.engines.reduced import rhs_reference, simulate_reduced, system_of

PLAIN_METHODS = ("LSODA", "DOP853", "RK45", "BDF", "Radau")  # LSODA first: the usual winner prunes the rest
MATCH = 2.0  # a plain method matches when its error is <= MATCH x the compiled run's error
REF_TOL = dict(rtol=1e-12, atol=1e-14)


# ------------------------------------------------------------------------------------------------
# A. reduced model, warm, equal accuracy
# ------------------------------------------------------------------------------------------------
class TooSlow(Exception):
    pass


def initial_state(physics: Physics, numerics: Numerics) -> np.ndarray:
    """The reduced model's initial state: the angles, then a moving pivot's position (the dish's centre)."""
    return np.concatenate([initial_angles(physics, numerics), np.zeros(physics.scene_def.head_coordinates)])


def plain_run(physics: Physics, duration: float, method: str, rtol: float, deadline_s: float):
    """solve_ivp(method) on rhs_reference, as a user would write it; stops (TooSlow) past deadline_s."""
    from scipy.integrate import solve_ivp

    numerics = Numerics()
    t = numerics.sample_times(duration)
    theta0 = initial_state(physics, numerics)
    f = rhs_reference(physics)
    t0 = time.perf_counter()
    stop = t0 + deadline_s

    def g(t_, y):
        if time.perf_counter() > stop:
            raise TooSlow
        return f(t_, y)

    sol = solve_ivp(g, (0.0, float(t[-1])), theta0, method=method, t_eval=t, rtol=rtol, atol=rtol * 1e-2)
    wall = time.perf_counter() - t0
    if not sol.success:
        raise TooSlow
    return sol.y.T[:, : physics.n_angles], wall  # the angles (compared with simulate_reduced's theta)


def match_method(physics, duration, method, ref, target, best_so_far, cap_s):
    """Loosest rtol of `method` with error <= target. Returns a dict (rtol, err, wall) or a reason string."""
    passed = None
    failed_rtol = None
    rtol = 1e-4
    while rtol >= 1e-13:
        limit = min(cap_s, best_so_far)
        try:
            theta, wall = plain_run(physics, duration, method, rtol, limit)
        except TooSlow:
            why = "slower than the best plain method" if best_so_far <= cap_s else f"over the {cap_s:g} s cap"
            return passed or f"{why} at rtol {rtol:.0e}"
        err = float(np.abs(theta - ref).max())
        if err <= target:
            passed = {"rtol": rtol, "err": err, "wall": wall}
            break
        failed_rtol = rtol
        rtol /= 10
    if passed is None:
        return "did not reach the accuracy"
    if failed_rtol is not None:  # one bisection step in log rtol: a looser rtol that still matches is cheaper
        mid = np.sqrt(passed["rtol"] * failed_rtol)
        try:
            theta, wall = plain_run(physics, duration, method, mid, min(cap_s, best_so_far))
            err = float(np.abs(theta - ref).max())
            if err <= target:
                passed = {"rtol": mid, "err": err, "wall": min(wall, passed["wall"])}
        except TooSlow:
            pass
    return passed


def plain_baseline_runs(physics: Physics) -> bool:
    """Whether the plain-numpy rhs_reference evaluates for this physics (a scene whose reduced model has parts the
    plain twin does not cover has no plain baseline here)."""
    try:
        value = rhs_reference(physics)(0.0, initial_state(physics, Numerics()))
        return bool(np.all(np.isfinite(value)))
    except Exception as err:  # noqa: BLE001 (reported: the case is left out of part A)
        log(f"part A leaves out {physics.scene}: the plain rhs_reference fails ({type(err).__name__}: {err})")
        return False


def bench_reduced(cases, repeats: int, cap_s: float) -> list[dict]:
    simulate_reduced(Physics(n=7, sigma=0.8), Numerics(), 1.0)  # compiled kernels loaded before timing
    rows = []
    for label, physics, duration in cases:
        log(f"reduced warm: {label}, {duration:g} tau (load {load()})")
        numerics = Numerics()
        ref = simulate_reduced(physics, numerics, duration, **REF_TOL).theta
        comp = simulate_reduced(physics, numerics, duration)  # also the warm-up (kernels compiled on first use)
        err_c = float(np.abs(comp.theta - ref).max())
        wall_c = min(simulate_reduced(physics, numerics, duration).wall_time_s for _ in range(repeats))
        target = MATCH * max(err_c, 1e-13)
        best = np.inf
        methods = {}
        for method in PLAIN_METHODS:
            r = match_method(physics, duration, method, ref, target, best, cap_s)
            methods[method] = r
            if isinstance(r, dict):
                best = min(best, r["wall"])
            log(f"  {method}: " + (r if isinstance(r, str) else _plain_cell(r)))
        winners = {m: r for m, r in methods.items() if isinstance(r, dict)}
        win = min(winners, key=lambda m: winners[m]["wall"]) if winners else None
        rows.append(
            {
                "case": label,
                "n": physics.n,
                "duration": duration,
                "compiled_s": wall_c,
                "compiled_err": err_c,
                "method": comp.info.get("method", "?"),
                "plain": methods,
                "best": win,
                "best_s": winners[win]["wall"] if win else np.nan,
                "speedup": winners[win]["wall"] / wall_c if win else np.nan,
                "bound": None if win else cap_s / wall_c,
            }
        )
    return rows


# ------------------------------------------------------------------------------------------------
# B. whole process
# ------------------------------------------------------------------------------------------------
PLAIN_SCRIPT = '''\
"""Plain numpy + scipy: the one-pinned chain (N = {n}, sigma = {sigma}), LSODA, {duration:g} tau."""
import sys
import numpy as np
from scipy.integrate import solve_ivp

n, sigma, c, gl, gt = {n}, {sigma!r}, 1.0, {gl!r}, {gt!r}
theta0 = np.array({theta0!r})
i = np.arange(n)
mask = (i[:, None, None] >= i[None, :, None]) & (i[:, None, None] >= i[None, None, :])  # i >= max(j, k)
upper = i[None, :] >= i[:, None]


def f(t, th):
    diff = th[:, None] - th[None, :]
    s, co = np.sin(diff), np.cos(diff)
    D = np.einsum("ijk,ij,ik->jk", mask, gl * s, s) + np.einsum("ijk,ij,ik->jk", mask, gt * co, co)
    Q = sigma * np.sum(upper * np.sin(diff), axis=1)
    grad = np.zeros(n)
    grad[0] += c * th[0]
    bend = np.diff(th)
    grad[:-1] -= c * bend
    grad[1:] += c * bend
    return np.linalg.solve(D, Q - grad)


t = np.arange({samples}) * {sample_dt!r}
sol = solve_ivp(f, (0.0, t[-1]), theta0, method="LSODA", t_eval=t, rtol={rtol!r}, atol={atol!r})
np.save(sys.argv[1], sol.y.T)
'''


def startup_rtol() -> float:
    """LSODA's rtol matching the compiled run in section A's first case (one-pinned, N = 7, sigma 0.8, 600 tau)."""
    physics, numerics = Physics(n=7, sigma=0.8), Numerics()
    ref = simulate_reduced(physics, numerics, 600.0, **REF_TOL).theta
    target = MATCH * max(float(np.abs(simulate_reduced(physics, numerics, 600.0).theta - ref).max()), 1e-13)
    lsoda = match_method(physics, 600.0, "LSODA", ref, target, np.inf, 10.0)
    return lsoda["rtol"] if isinstance(lsoda, dict) else 1e-10


def bench_process(lsoda_rtol: float, repeats: int) -> dict:
    physics, numerics, duration = Physics(n=7, sigma=0.8), Numerics(), 600.0
    system = system_of(physics)
    assert system.n_chains == 1 and system.clamped and not system.pinned
    t = numerics.sample_times(duration)
    ref = simulate_reduced(physics, numerics, duration, **REF_TOL).theta
    err_cli = float(np.abs(simulate_reduced(physics, numerics, duration).theta - ref).max())  # the CLI's path
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "plain_lsoda.py"
        script.write_text(
            PLAIN_SCRIPT.format(
                n=system.n,
                sigma=float(system.sigma),
                gl=float(system.gamma_l),
                gt=float(system.gamma_t),
                theta0=[float(x) for x in initial_angles(physics, numerics)],
                duration=duration,
                samples=t.size,
                sample_dt=float(numerics.sample_dt),
                rtol=float(lsoda_rtol),
                atol=float(lsoda_rtol) * 1e-2,
            )
        )
        out = Path(tmp) / "theta.npy"
        cli_cmd = [CLI, "run", "one-pinned", "--engine", "reduced", "--duration", "600", "--quiet"]
        plain_cmd = [sys.executable, str(script), str(out)]
        help_cmd = [CLI, "--help"]
        run_wall(cli_cmd, tmp), run_wall(plain_cmd, tmp)  # file caches warm, numba cache built
        cli, plain, hlp = [], [], []
        for _ in range(repeats):  # interleaved
            cli.append(run_wall(cli_cmd, tmp))
            plain.append(run_wall(plain_cmd, tmp))
            hlp.append(run_wall(help_cmd, tmp))
        err_plain = float(np.abs(np.load(out) - ref).max())
        imports = run_wall([sys.executable, "-c", "import numpy, scipy.integrate"], tmp)
    return {
        "cli": cli,
        "plain": plain,
        "help": hlp,
        "err_cli": err_cli,
        "err_plain": err_plain,
        "rtol": lsoda_rtol,
        "imports": imports,
        "cmd": " ".join(["elastoactive"] + cli_cmd[1:]),
    }


# ------------------------------------------------------------------------------------------------
# D. long chains: the reduced model's cost against N (MuJoCo's: scripts/benchmark_mujoco.py)
# ------------------------------------------------------------------------------------------------
def bench_reduced_long(ns, duration: float, repeats: int) -> dict:
    rows = []
    for n in ns:
        physics = Physics(n=n, sigma=0.05)
        simulate_reduced(physics, Numerics(), duration)  # warm-up: some kernels compile on first use, not at 1 tau
        runs = [simulate_reduced(physics, Numerics(), duration) for _ in range(repeats)]
        wall = min(r.wall_time_s for r in runs)
        rows.append(
            {
                "n": n,
                "duration": duration,
                "wall_s": wall,
                "per_100": wall * 100 / duration,
                "method": runs[0].info.get("method", "?"),
                "nfev": runs[0].info.get("nfev"),
            }
        )
    x, y = np.log([r["n"] for r in rows]), np.log([r["per_100"] for r in rows])
    big = [i for i, r in enumerate(rows) if r["n"] >= 30]
    slope_all = float(np.polyfit(x, y, 1)[0])
    slope_big = float(np.polyfit(x[big], y[big], 1)[0]) if len(big) >= 2 else np.nan
    return {"rows": rows, "exponent_all": slope_all, "exponent_long": slope_big}


SINGLE_BLAS = """
import json, sys
from elastoactive.engines.reduced import simulate_reduced
from elastoactive.core.params import Numerics, Physics
out = {}
for n in map(int, sys.argv[2:]):
    p = Physics(n=n, sigma=0.05)
    simulate_reduced(p, Numerics(), float(sys.argv[1]))
    out[n] = min(simulate_reduced(p, Numerics(), float(sys.argv[1])).wall_time_s for _ in range(2))
print(json.dumps(out))
"""


def bench_reduced_single_blas(ns, duration: float) -> dict:
    """The same reduced runs in a fresh process with OPENBLAS_NUM_THREADS=1 (BLAS threads vs a loaded machine)."""
    import json

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    res = subprocess.run(
        [sys.executable, "-c", SINGLE_BLAS, f"{duration:g}", *map(str, ns)],
        env=env,
        check=True,
        capture_output=True,
        text=True,
    )
    return {int(k): v * 100 / duration for k, v in json.loads(res.stdout.strip().splitlines()[-1]).items()}


def _plain_cell(r) -> str:
    if isinstance(r, dict):
        return f"{r['wall']:.3f} s (rtol {r['rtol']:.0e}, err {r['err']:.0e})"
    return "- (" + r + ")"


def process_report(proc: dict) -> list[str]:
    """Section B's lines (bench_process's figures)."""
    cli, plain, hlp = (statistics.median(proc[k]) for k in ("cli", "plain", "help"))
    return [
        "## B. Whole process (targets e, b): median of " + str(len(proc["cli"])) + " subprocess wall times",
        "",
        "| command | median s | all runs s | max angle error |",
        "|---|---|---|---|",
        f"| `{proc['cmd']}` | **{cli:.2f}** | {', '.join(f'{x:.2f}' for x in proc['cli'])} | {proc['err_cli']:.0e} |",
        f"| plain script: numpy + scipy LSODA, same equations, rtol {proc['rtol']:.0e} | **{plain:.2f}** | "
        f"{', '.join(f'{x:.2f}' for x in proc['plain'])} | {proc['err_plain']:.0e} |",
        f"| `elastoactive --help` (target < 0.2 s) | **{hlp:.3f}** | {', '.join(f'{x:.3f}' for x in proc['help'])} | |",
        "",
        f"Whole process, CLI / plain script: **{plain / cli:.2f}x** faster. For scale, "
        f"`python -c 'import numpy, scipy.integrate'` alone took {proc['imports']:.2f} s.",
    ]


def report(red, proc, sweep, mj, rl, cb, meta, steps=(), alt=(), alt_n=100, alt_tau=20.0) -> str:
    o = [
        f"# Benchmark ({meta['date']}, {meta['machine']})",
        "",
        f"One run of `scripts/benchmark.py{' --quick' if meta['quick'] else ''}`. Machine load (1/5/15 min): "
        f"{meta['load_start']} at the start, {meta['load_end']} at the end (2 shared cores; figures carry tens "
        f"of percent noise). Warm timings are best of {meta['repeats']}, whole-process timings medians. "
        f"{meta['bytecode']}",
        "",
    ]
    o += [
        "## A. Reduced model, warm, at equal accuracy (target e)",
        "",
        f"Error = max |theta - theta_ref| (rad) over the run; theta_ref = compiled model at rtol 1e-12. Each scipy "
        f"method (solve_ivp on the plain-numpy `rhs_reference`, atol = rtol/100) at the loosest rtol whose error "
        f"is <= {MATCH:g} x the compiled default's (ladder of decades, one bisection step). '-' = dropped: slower "
        f"than the best plain method already found (it cannot win) or over the time cap.",
        "",
        "| case | N | tau | compiled default s (err) | "
        + " | ".join(PLAIN_METHODS)
        + " | best plain | speed-up vs best plain |",
        "|---" * (6 + len(PLAIN_METHODS)) + "|",
    ]
    for r in red:
        o.append(
            f"| {r['case']} | {r['n']} | {r['duration']:g} | {r['compiled_s']:.4f} ({r['compiled_err']:.0e}) | "
            + " | ".join(_plain_cell(r["plain"][m]) for m in PLAIN_METHODS)
            + f" | {r['best'] or 'none within the cap'} | "
            + (f"**{r['speedup']:.0f}x** |" if r["best"] else f"**> {r['bound']:.0f}x** (cap / compiled) |")
        )
    if meta.get("skipped"):
        o += [
            "",
            "Left out (their plain-numpy rhs_reference does not evaluate, so there is no plain baseline): "
            + ", ".join(meta["skipped"])
            + ".",
        ]
    o += ["", *process_report(proc)]
    o += [
        "",
        *sweep_report(sweep),
    ]
    o += [
        "",
        "## D. Long chains (targets c, d)",
        "",
        "MuJoCo (`simulate_mujoco` with `Numerics()`, i.e. what `elastoactive run` and `ea.simulate` use without "
        "numerical options: implicitfast dt 0.0025, m 1e-4 below N = 30, the automatic long-chain numerics "
        "`Numerics.for_physics` from N = 30; the pre-flight check accepts every row), best of "
        f"{meta['mj_repeats']}. Angle error = max |theta - theta_reduced| / max |theta_reduced| over the same run "
        "(reduced model, overdamped, defaults):",
        "",
        "| N | sigma | numerics used | tau simulated | us per step | wall s | tau per wall s | angle error |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in mj["rows"]:
        o.append(
            f"| {r['n']} | {r['sigma']:g} | {r['integrator']} dt {r['dt']:.3g}, m {r['mass_ratio']:.2g} | "
            f"{r['duration']:g} | {r['us_per_step']:.1f} | {r['wall_s']:.3f} | **{r['tau_per_s']:.1f}** | "
            f"{100 * r['err']:.2f}% |"
        )
    o += [
        "",
        f"Growth over N = 30-{mj['rows'][-1]['n']} (log-log fit): wall s per tau ~ N^"
        f"**{mj['exponent_tau']:.2f}** (includes dt, which the automatic choice shrinks where the chain's fastest "
        f"rate grows: {mj['rows'][-1]['n']} particles take {mj['rows'][-1]['dt']:.2g}), us per step ~ N^"
        f"**{mj['exponent_step']:.2f}**.",
        "",
        "Step cost by N (us per step, thread time, best of 3; sigma 0.05; Euler and RK4 at m 2e-3): why "
        "implicitfast stays the default below N = 30 and explicit drag takes over above:",
        "",
        "| N | implicitfast | Euler | RK4 | implicitfast / Euler |",
        "|---|---|---|---|---|",
    ]
    for r in steps:
        o.append(
            f"| {r['n']} | {r['implicitfast']:.1f} | {r['Euler']:.1f} | {r['RK4']:.1f} | "
            f"{r['implicitfast'] / r['Euler']:.1f}x |"
        )
    o += [
        "",
        f"Alternatives at N = {alt_n}, sigma 0.05, {alt_tau:g} tau (one run each; m x rate: the inertia number "
        "of the regime criterion, overdamped below 0.1):",
        "",
        "| setting | us per step | tau per wall s | angle error vs reduced | m x rate |",
        "|---|---|---|---|---|",
    ]
    for r in alt:
        o.append(
            f"| {r['label']} | {r['us_per_step']:.0f} | {r['tau_per_s']:.1f} | {100 * r['err']:.2f}% | "
            f"{r['inertia_number']:.3f} |"
        )
    o += [
        "",
        f"Reduced model (simulate_reduced defaults, one-pinned, sigma 0.05), best of {meta['rl_repeats']}:",
        "",
        "| N | wall s per 100 tau | same, fresh process, OPENBLAS_NUM_THREADS=1 | method | RHS evaluations |",
        "|---|---|---|---|---|",
    ]
    for r in rl["rows"]:
        one = rl["single_blas"].get(r["n"])
        o.append(
            f"| {r['n']} | **{r['per_100']:.3f}** | {'' if one is None else f'{one:.3f}'} | {r['method']} "
            f"| {r['nfev']} |"
        )
    nmax = rl["rows"][-1]["n"]
    o += [
        "",
        f"Growth exponent (log-log fit of cost against N): **{rl['exponent_long']:.2f}** over N = 30-{nmax}, "
        f"{rl['exponent_all']:.2f} over N = 7-{nmax}. The exponent includes the number of steps, which grows "
        f"with the chain's fastest rate, not only the O(N) cost per evaluation.",
    ]
    o += [
        "",
        "## E. Force callback against the bare engine step (N = 7 one-pinned, dt 0.0025)",
        "",
        "| integrator | mass ratio | bare us/step | compiled callback us/step | Python callback us/step "
        "| compiled / bare (target <= 1.3) | Python / bare |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in cb:
        o.append(
            f"| {r['integrator']} | {r['mass_ratio']:g} | {r['bare']:.2f} | {r['compiled']:.2f} | "
            f"{r['python']:.1f} | **{r['compiled_ratio']:.2f}x** | {r['python_ratio']:.1f}x |"
        )
    o.append("")
    return "\n".join(o)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("docs/generated/benchmark.md"))
    ap.add_argument("--quick", action="store_true", help="shorter runs, fewer repeats (about 1 min)")
    ap.add_argument("--filament", action="store_true", help="only section F (the filament against PyElastica)")
    ap.add_argument("--filament-out", type=Path, default=Path("docs/generated/benchmark_filament.md"))
    ap.add_argument("--network", action="store_true", help="only section G (the active lattice)")
    ap.add_argument("--network-out", type=Path, default=Path("docs/generated/benchmark_network.md"))
    ap.add_argument("--network-scale", action="store_true", help="only section H (the network's cost against N)")
    ap.add_argument("--network-scale-out", type=Path, default=Path("docs/generated/benchmark_network_scale.md"))
    ap.add_argument("--elastica3d", action="store_true", help="only section I (the 3D filament against PyElastica)")
    ap.add_argument("--elastica3d-out", type=Path, default=Path("docs/generated/benchmark_elastica3d.md"))
    ap.add_argument("--startup", action="store_true", help="only section B (the whole process, --help)")
    ap.add_argument("--sweep", action="store_true", help="only section C (the MuJoCo sweep against the engine floor)")
    ap.add_argument("--fluid", action="store_true", help="only the cilia through the fluid (scripts/bench_fluid.py)")
    ap.add_argument("--mujoco3d", action="store_true", help="only MuJoCo's 3D chain against the planar one (per step, "
                    "per dof-step, whole process: scripts/bench_mujoco3d.py)")  # fmt: skip
    ap.add_argument("--reduced-paths", action="store_true", help="only the reduced engine's runs that the quick "
                    "reproduction leans on (scripts/bench_reduced_paths.py; --before there: two trees)")  # fmt: skip
    args = ap.parse_args(argv)
    q = args.quick
    if args.reduced_paths:
        from bench_reduced_paths import main as reduced_paths  # this folder's script

        return reduced_paths(["--repeats", "1" if q else "3"])
    if args.mujoco3d:
        from bench_mujoco3d import main as mujoco3d

        return mujoco3d([])
    if args.fluid:
        from bench_fluid import main as bench_fluid  # this folder's script: the cost table against the beads

        return bench_fluid(["--quick"] if q else [])
    if args.startup:
        log(f"whole process (load {load()})")
        print("\n".join(process_report(bench_process(startup_rtol(), 3 if q else 5))))
        return 0
    if args.sweep:
        log(f"sweep (load {load()})")
        print("\n".join(sweep_report(bench_sweep(8 if q else 16, 50.0 if q else 100.0, 2 if q else 5))))
        return 0
    if args.filament:
        return write_filament(args.filament_out, q)
    if args.network:
        text = network_report(bench_network(q))
        args.network_out.parent.mkdir(parents=True, exist_ok=True)
        args.network_out.write_text(text)
        print(text)
        return 0
    if args.elastica3d:
        return write_elastica3d(args.elastica3d_out, q)
    if args.network_scale:
        text = scale_report(bench_network_scale(q))
        args.network_scale_out.parent.mkdir(parents=True, exist_ok=True)
        args.network_scale_out.write_text(text)
        print(text)
        return 0
    meta = {
        "date": time.strftime("%Y-%m-%d %H:%M"),
        "quick": q,
        "load_start": load(),
        "machine": f"{platform.processor() or platform.machine()}, {CORES} cores, MuJoCo {mujoco.__version__}",
        "repeats": 2 if q else 3,
        "mj_repeats": 1 if q else 2,
        "rl_repeats": 2,
        "bytecode": "Bytecode caching was off (PYTHONDONTWRITEBYTECODE set): every whole-process run compiled "
        "the package's modules from source (about 0.04 s of a sweep's start-up)."
        if sys.flags.dont_write_bytecode
        else "Bytecode caching was on.",
    }
    t0 = time.perf_counter()
    scale = 0.25 if q else 1.0
    cases = [(c.physics.scene_def.label(c.physics), c.physics, 600.0 * scale) for c in validation_cases()]
    meta["skipped"] = [label for label, physics, _ in cases if not plain_baseline_runs(physics)]
    cases = [c for c in cases if c[0] not in meta["skipped"]]
    if q:
        cases = cases[:2]
    cases += [("one-pinned sigma=0.05", Physics(n=n, sigma=0.05), 100.0 * scale) for n in ((30,) if q else (30, 100))]
    red = bench_reduced(cases, meta["repeats"], cap_s=5.0 if q else 10.0)
    lsoda = red[0]["plain"]["LSODA"]
    lsoda_rtol = lsoda["rtol"] if isinstance(lsoda, dict) else 1e-10
    log(f"whole process (load {load()})")
    proc = bench_process(lsoda_rtol, 3 if q else 5)
    log(f"sweep (load {load()})")
    sweep = bench_sweep(8 if q else 16, 50.0 if q else 100.0, 1 if q else 3)
    log(f"long chains (load {load()})")
    mj = bench_mujoco_long(
        {
            7: (0.8, 10.0 if q else 40.0),
            30: (0.05, 5.0 if q else 20.0),
            100: (0.05, 5.0 if q else 20.0),
            200: (0.05, 1.0 if q else 4.0),
        },
        meta["mj_repeats"],
    )
    steps = bench_step_by_n((7, 30, 100) if q else (7, 15, 30, 60, 100, 200), 3)
    alt_tau = 5.0 if q else 20.0
    alt = bench_alternatives(100, alt_tau)
    ns = (7, 30, 100) if q else (7, 30, 100, 200)
    rl = bench_reduced_long(ns, 25.0 if q else 100.0, meta["rl_repeats"])
    rl["single_blas"] = bench_reduced_single_blas(ns, 25.0 if q else 100.0)
    log(f"callback (load {load()})")
    cb = bench_callback(3 if q else 5, 2000 if q else 8000)
    meta["load_end"] = load()
    text = report(red, proc, sweep, mj, rl, cb, meta, steps, alt, 100, alt_tau)
    text += f"\nBenchmark took {time.perf_counter() - t0:.0f} s.\n"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    print(text)
    return write_filament(args.filament_out, q)


def write_filament(out: Path, quick: bool) -> int:
    text = filament_report(bench_filament(quick))
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Section H of scripts/benchmark.py: the network's cost against its size, 100 to 10 000 nodes (docs/performance.md).

  .venv/bin/python scripts/benchmark.py --network-scale [--quick] [--network-scale-out docs/generated/...md]

Pinned triangular hexagons of R rings (1 + 3R(R+1) nodes) at sigma = 0.2, l_a = 0.1 (Pi = 2), seeded start:

- the reduced engine (simulate_network_reduced: DOP853 compiled with the O(N) right-hand side, at a large network's
  automatic tolerance, LARGE_TOLERANCES, at every size) for DURATION gamma / k, its wall time, right-hand sides and
  cost per evaluation;
- beside it, a plain numpy/scipy script of the same equations (benchmark_network.plain_rhs, solve_ivp DOP853 at the
  same rtol and atol: the same method and tolerances, so the same accuracy; the largest difference between the two
  runs' node positions over the span is reported) over SPAN gamma / k, scaled to DURATION;
- an implicit method from a library (scipy's BDF with the analytic Jacobian, sparse above 1500 free coordinates, the
  same rtol) over IMPLICIT_SPAN, up to IMPLICIT_NODES nodes, scaled;
- the lowest modes (normal_modes) and the stability bracket [lambda_1, ceiling] (analysis.network.stability: softest
  and coupling_ceiling), dense up to reduced.network.DENSE_MODES free coordinates, sparse above;
- at the largest size, the whole process `elastoactive run network ... --duration DURATION` with the default
  settings (its wall and CPU time: start-up, the gate, the run, the observables, the files; its record's spacing is
  the large network's automatic one);
- MuJoCo on the 1027-node patch (R = 18): its step cost and the automatic step.

The log-log slope of the cost per evaluation and of the run against the node count is printed (1: linear).
"""

from __future__ import annotations

import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np
from bench_common import CLI, CORES, load, log
from benchmark_network import plain_rhs

from elastoactive.scenes.network_kind import LARGE_TOLERANCES

SIGMA, ALIGNMENT_LENGTH = 0.2, 0.1
RINGS = (6, 10, 18, 31, 58)
"""127, 331, 1027, 2977 and 10 267 nodes."""
DURATION = 1000.0
SPAN = 20.0
"""gamma / k over which the plain script and the implicit method run (scaled to DURATION)."""
RTOL, ATOL = LARGE_TOLERANCES
MUJOCO_RINGS, MUJOCO_TAU = 18, 1.0
PARTIAL = Path(tempfile.gettempdir()) / "benchmark_network_scale_rows.json"
"""The rows measured so far (written after each size)."""
IMPLICIT_NODES, IMPLICIT_SPAN = 1100, 2.0
"""The implicit method runs up to this many nodes, over this span (it is some 50-300 times slower than DOP853)."""


def _physics(rings: int):
    from elastoactive.core.params import Physics

    return Physics(scene="network", geometry="triangular", size=rings, sigma=SIGMA, alignment_length=ALIGNMENT_LENGTH)


def _slope(x, y) -> float:
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def bench_network_scale(quick: bool) -> dict:
    from elastoactive.reduced.blas import one_blas_thread

    with one_blas_thread():  # one thread throughout (a loaded machine's BLAS threads thrash the dense algebra)
        return _bench(quick)


def _bench(quick: bool) -> dict:
    from scipy.integrate import solve_ivp

    from elastoactive.analysis.network import stability
    from elastoactive.core.params import Numerics
    from elastoactive.engines.network_reduced import simulate_network_reduced, system_of
    from elastoactive.reduced import network as model

    rings = RINGS[:3] if quick else RINGS
    duration = 100.0 if quick else DURATION
    span = 5.0 if quick else SPAN
    numerics = Numerics(sample_dt=0.5)
    simulate_network_reduced(_physics(2), numerics, 1.0)  # the kernels compiled (numba's cache)
    rows = []
    for r in rings:
        physics = _physics(r)
        network = physics.scene_def.network(physics)
        log(f"network scale: R = {r}, {network.n_nodes} nodes (load {load()})")
        start = time.perf_counter()
        values, _ = model.normal_modes(network, None if not model.is_large(network) else model.LOWEST_MODES)
        bracket = (stability.softest(network), stability.coupling_ceiling(network))
        algebra = time.perf_counter() - start
        cpu = time.process_time()
        run = simulate_network_reduced(physics, numerics, duration, rtol=RTOL, atol=ATOL)
        cpu = time.process_time() - cpu
        short = simulate_network_reduced(physics, numerics, span, rtol=RTOL, atol=ATOL)
        system = system_of(physics)
        f, free, count = plain_rhs(network, SIGMA, ALIGNMENT_LENGTH)
        y0 = model.pack(system, physics.scene_def.initial_network(physics, numerics))
        t0 = time.perf_counter()
        plain = solve_ivp(f, (0.0, span), y0, method="DOP853", t_eval=short.t, rtol=RTOL, atol=ATOL)
        plain_wall = time.perf_counter() - t0
        difference = float(np.abs(model.unpack(system, plain.y.T).positions - short.nodes).max())
        implicit_wall, implicit_difference, implicit_nfev = float("nan"), float("nan"), 0
        if network.n_nodes <= IMPLICIT_NODES:
            keep = short.t <= IMPLICIT_SPAN + 1e-9
            t0 = time.perf_counter()
            implicit = model.solve(system, short.t[keep], y0, rtol=RTOL, atol=ATOL, method="BDF")
            implicit_wall = (time.perf_counter() - t0) * span / IMPLICIT_SPAN
            implicit_nfev = implicit.nfev
            implicit_difference = float(np.abs(model.unpack(system, implicit.y).positions - short.nodes[keep]).max())
        rows.append(
            {
                "rings": r,
                "nodes": network.n_nodes,
                "bonds": network.n_bonds,
                "units": int(network.active.sum()),
                "wall_s": run.wall_time_s,
                "cpu_s": cpu,
                "nfev": run.info["nfev"],
                "us_per_eval": 1e6 * run.wall_time_s / run.info["nfev"],
                "plain_s": plain_wall * duration / span,
                "plain_nfev": int(plain.nfev),
                "ratio": plain_wall / short.wall_time_s,
                "difference": difference,
                "implicit_s": implicit_wall * duration / span,
                "implicit_nfev": implicit_nfev,
                "implicit_difference": implicit_difference,
                "algebra_s": algebra,
                "modes": int(values.size),
                "lambda_1": bracket[0],
                "ceiling": bracket[1],
            }
        )
        log(f"  {rows[-1]}")
        PARTIAL.write_text(json.dumps(rows))  # kept if a later part fails
    whole = None
    if not quick:
        largest = rings[-1]
        with tempfile.TemporaryDirectory() as tmp:
            command = [
                CLI,
                "run",
                "network",
                "--geometry",
                "triangular",
                "--size",
                str(largest),
                "--sigma",
                str(SIGMA),
                "--alignment-length",
                str(ALIGNMENT_LENGTH),
                "--engine",
                "reduced",
                "--duration",
                f"{duration:g}",
                "--out",
                os.path.join(tmp, "run"),
                "--quiet",
            ]
            log(f"network scale: whole process at R = {largest} (load {load()})")
            t0 = time.perf_counter()
            cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run(command, check=True, capture_output=True)
            cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            whole = {
                "rings": largest,
                "wall_s": time.perf_counter() - t0,
                "cpu_s": cpu1.ru_utime + cpu1.ru_stime - cpu0.ru_utime - cpu0.ru_stime,
                "command": "elastoactive " + " ".join(command[1:-3]) + " --out RUN --quiet",
            }
            log(f"  {whole}")
    log(f"network scale: MuJoCo R = {MUJOCO_RINGS} (load {load()})")
    from elastoactive.engines.network_mujoco import simulate_network_mujoco

    physics = _physics(MUJOCO_RINGS)
    t0 = time.perf_counter()
    traj = simulate_network_mujoco(physics, Numerics(), MUJOCO_TAU)
    mj = {
        "nodes": physics.scene_def.network(physics).n_nodes,
        "tau": MUJOCO_TAU,
        "total_s": time.perf_counter() - t0,
        "wall_s": traj.wall_time_s,
        "us_per_step": traj.info["us_per_step"],
        "dt": traj.info.get("automatic_numerics", {}).get("dt"),
    }
    return {"rows": rows, "whole": whole, "mujoco": mj, "duration": duration, "span": span, "quick": quick}


def scale_report(result: dict) -> str:
    rows = result["rows"]
    meta = (
        f"{platform.processor() or platform.machine()}, {CORES} cores, MuJoCo {mujoco.__version__}, Python "
        f"{sys.version.split()[0]}; {time.strftime('%Y-%m-%d %H:%M')}, load {load()}"
    )
    duration, span = result["duration"], result["span"]
    lines = [
        "## H. The network's cost against its size",
        "",
        f"Pinned triangular hexagons, sigma = {SIGMA}, l_a = {ALIGNMENT_LENGTH} (Pi = 2), seeded start, one thread "
        f"({meta}). Reduced engine: {duration:g} gamma / k, DOP853 compiled, rtol {RTOL:g}. Plain script: numpy "
        f"right-hand side, scipy solve_ivp DOP853 at the same rtol and atol (the same method: equal accuracy), over "
        f"{span:g} gamma / k, scaled; 'differs by': its largest node difference from the engine's run over that span. "
        f"Implicit: scipy's BDF with the analytic Jacobian, same rtol, over {IMPLICIT_SPAN:g}, scaled (to "
        f"{IMPLICIT_NODES} nodes). Modes + bracket: "
        "the lowest normal modes and [lambda_1, ceiling] (dense to 1500 free coordinates, sparse above).",
        "",
        "| R | nodes | bonds | reduced s (CPU s) | right-hand sides | us per evaluation (wall) | "
        "plain scipy s (scaled) | plain / reduced (same span) | differs by (a) | BDF s (scaled) | "
        "modes + bracket s | lambda_1 | ceiling |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        implicit = "-" if r["implicit_nfev"] == 0 else f"{r['implicit_s']:.3g}"
        lines.append(
            f"| {r['rings']} | {r['nodes']} | {r['bonds']} | {r['wall_s']:.3g} ({r['cpu_s']:.3g}) | {r['nfev']} | "
            f"{r['us_per_eval']:.3g} | "
            f"{r['plain_s']:.3g} | {r['ratio']:.2g} | "
            f"{r['difference']:.1e} | {implicit} | {r['algebra_s']:.2g} | {r['lambda_1']:.4g} | "
            f"{r['ceiling']:.4g} |"
        )
    nodes = [r["nodes"] for r in rows]
    if len(rows) > 1:
        per_evaluation = _slope(nodes, [r["us_per_eval"] for r in rows])
        lines += [
            "",
            f"Log-log slope against the nodes: cost per evaluation {per_evaluation:.2f}, "
            f"run {_slope(nodes, [r['wall_s'] for r in rows]):.2f}, plain script "
            f"{_slope(nodes, [r['plain_s'] for r in rows]):.2f}, modes + bracket "
            f"{_slope(nodes, [r['algebra_s'] for r in rows]):.2f} (1: linear).",
        ]
    if result["whole"]:
        w = result["whole"]
        lines += [
            "",
            f"Whole process at R = {w['rings']}: `{w['command']}`: {w['wall_s']:.1f} s wall, {w['cpu_s']:.1f} s of "
            "CPU (user + system).",
        ]
    mj = result["mujoco"]
    lines += [
        "",
        f"MuJoCo, {mj['nodes']} nodes (R = {MUJOCO_RINGS}), automatic numerics (dt {mj['dt']}): "
        f"{mj['us_per_step']:.0f} us per step, {mj['wall_s']:.2f} s for {mj['tau']:g} gamma / k "
        f"({mj['total_s']:.2f} s with building the model and the pre-flight checks).",
    ]
    return "\n".join(lines) + "\n"

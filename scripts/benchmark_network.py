"""Section G of scripts/benchmark.py: the active lattice (elastic network of self-aligning units), MuJoCo beside the
reduced engine and a plain scipy script, at equal accuracy (docs/performance.md).

  .venv/bin/python scripts/benchmark.py --network [--quick] [--network-out docs/generated/benchmark_network.md]

The case: the hexagonal patch of R = 6 rings (127 nodes, the outer ring of 36 pinned, 91 self-aligning units) at
sigma = 0.2, l_a = 0.1 (collective actuation: the units keep turning), for DURATION gamma / k (1000 relaxation
times; --quick: 100).

Accuracy: the largest node displacement error max |x - x_ref| over the window [0, WINDOW] (the lattice's dynamics is
sensitive to its state: trajectories part after ~10 gamma / k however accurate, as the validate window of the
chains), relative to the largest displacement from rest in the reference over the same window; x_ref = the reduced
engine at rtol 1e-11. MuJoCo runs Euler (the drag implicit) at dt 0.0025, at its automatic dt (0.00125 / Pi =
0.000625 here, Pi = sigma / l_a; timed over AUTO_TAU and scaled) and at the 'fast' preset's dt 0.01. The reduced
engine (compiled right-hand side, DOP853) and the plain script (solve_ivp on a numpy right-hand side written as a
user would: DOP853, RK45, LSODA) each get the loosest rtol (atol = rtol / 100, a ladder of decades) whose window
error is at most the dt 0.0025 run's. Wall times: one run each of the whole duration, single thread; a plain run is
stopped after PLAIN_CAP_S.
"""

from __future__ import annotations

import platform
import time

import mujoco
import numpy as np
from bench_common import CORES, load, log

RINGS, SIGMA, ALIGNMENT_LENGTH = 6, 0.2, 0.1
DURATION = 1000.0
WINDOW = 5.0
PLAIN_METHODS = ("DOP853", "RK45", "LSODA")
RTOLS = tuple(10.0**-k for k in range(3, 12))
REF_RTOL = 1e-11
AUTO_TAU = 100.0
"""gamma / k the automatic MuJoCo row is timed over (its wall time is scaled to the whole duration: 4 min otherwise)."""
PLAIN_CAP_S = 120.0
"""Wall seconds after which a plain solve_ivp run of the whole duration is abandoned (reported as slower)."""


class TooSlow(Exception):
    pass


def _physics():
    from elastoactive.core.params import Physics

    return Physics(scene="lattice", rings=RINGS, sigma=SIGMA, alignment_length=ALIGNMENT_LENGTH)


def plain_rhs(network, sigma: float, alignment_length: float):
    """The lattice's equations in plain numpy, as a user would write them: y = (free nodes' x, y interleaved, then
    the units' psi); gamma = 1, the springs summed with np.add.at."""
    free = np.flatnonzero(~network.pinned)
    active = np.flatnonzero(network.active)
    slot = np.full(len(network.positions), -1)
    slot[free] = np.arange(free.size)
    unit_slot = slot[active]
    i, j = network.bonds[:, 0], network.bonds[:, 1]
    k, a = network.stiffness, network.rest_lengths
    rest, anchors, trap = network.positions, network.anchors, network.trap
    count = 2 * free.size

    def f(t, y):
        x = rest.copy()
        x[free] = y[:count].reshape(-1, 2)
        psi = y[count:]
        r = x[j] - x[i]
        length = np.sqrt((r * r).sum(axis=1))
        fb = (k * (length - a) / length)[:, None] * r
        force = np.zeros_like(x)
        np.add.at(force, i, fb)
        np.add.at(force, j, -fb)
        force -= trap * (x - anchors)
        force[active] += sigma * np.column_stack([np.cos(psi), np.sin(psi)])
        v = force[free]
        vu = v[unit_slot]
        return np.concatenate([v.ravel(), (-vu[:, 0] * np.sin(psi) + vu[:, 1] * np.cos(psi)) / alignment_length])

    return f, free, count


def _window_error(nodes: np.ndarray, ref_nodes: np.ndarray, t: np.ndarray) -> float:
    keep = t <= WINDOW + 1e-9
    scale = np.abs(ref_nodes[keep] - ref_nodes[0]).max()
    return float(np.abs(nodes[keep] - ref_nodes[keep]).max() / scale)


def bench_network(quick: bool) -> dict:
    from scipy.integrate import solve_ivp

    from elastoactive.core.params import Numerics
    from elastoactive.engines.network_mujoco import simulate_network_mujoco
    from elastoactive.engines.network_reduced import simulate_network_reduced

    physics = _physics()
    network = physics.scene_def.network(physics)
    duration = 100.0 if quick else DURATION
    numerics = Numerics()
    log(f"network: reference (load {load()})")
    ref = simulate_network_reduced(physics, numerics, WINDOW, rtol=REF_RTOL, atol=REF_RTOL * 1e-2)
    t = ref.t
    rows = []
    settings = (
        ("MuJoCo, dt 0.0025 (Euler, m 1e-4)", Numerics(dt=0.0025, integrator="Euler"), duration),
        ("MuJoCo automatic (Euler, dt 0.000625 = 0.00125 / Pi)", Numerics(), min(duration, AUTO_TAU)),
        ("MuJoCo 'fast' preset (dt 0.01, m 1e-3)", Numerics.preset("fast", integrator="Euler"), duration),
    )
    for label, num, span in settings:
        log(f"network: {label} (load {load()})")
        short = simulate_network_mujoco(physics, num, WINDOW)
        run = simulate_network_mujoco(physics, num, span)
        rows.append(
            {
                "engine": label,
                "error": _window_error(short.nodes, ref.nodes, t),
                "wall_s": run.wall_time_s * duration / span,
                "us_per_step": run.info["us_per_step"],
                "setting": f"dt {run.info.get('automatic_numerics', {}).get('dt', num.dt):g}"
                + (f" (timed over {span:g}, scaled)" if span < duration else ""),
            }
        )
    target = rows[0]["error"]

    def loosest(solve):
        for rtol in RTOLS:
            error = solve(rtol)
            if error <= target:
                return rtol, error
        return None, None

    log(f"network: reduced engine (load {load()})")
    simulate_network_reduced(physics, numerics, 1.0)  # compile the kernels

    def reduced(rtol, span=WINDOW):
        return simulate_network_reduced(physics, numerics, span, rtol=rtol, atol=rtol * 1e-2)

    rtol, error = loosest(lambda r: _window_error(reduced(r).nodes, ref.nodes, t))
    run = reduced(rtol, duration)
    rows.append(
        {
            "engine": "reduced engine (compiled, DOP853)",
            "error": error,
            "wall_s": run.wall_time_s,
            "setting": f"rtol {rtol:g}",
            "nfev": run.info["nfev"],
        }
    )

    f, free, count = plain_rhs(network, SIGMA, ALIGNMENT_LENGTH)
    start = physics.scene_def.initial_network(physics, numerics)
    y0 = np.concatenate([start.positions[free].ravel(), start.polarity])

    def plain(method, rtol, span=WINDOW):
        times = numerics.sample_times(span)
        t0 = time.perf_counter()

        def timed(t, y):
            if time.perf_counter() - t0 > PLAIN_CAP_S:
                raise TooSlow
            return f(t, y)

        sol = solve_ivp(timed, (0.0, times[-1]), y0, method=method, t_eval=times, rtol=rtol, atol=rtol * 1e-2)
        wall = time.perf_counter() - t0
        nodes = np.broadcast_to(network.positions, (times.size,) + network.positions.shape).copy()
        nodes[:, free] = sol.y[:count].T.reshape(times.size, -1, 2)
        return nodes, wall, sol.nfev

    for method in PLAIN_METHODS:
        log(f"network: plain scipy {method} (load {load()})")
        rtol, error = loosest(lambda r: _window_error(plain(method, r)[0], ref.nodes, t))
        if rtol is None:
            rows.append(
                {"engine": f"plain scipy {method}", "error": None, "wall_s": None, "setting": "no rtol matched"}
            )
            continue
        try:
            _, wall, nfev = plain(method, rtol, duration)
        except TooSlow:
            rows.append(
                {
                    "engine": f"plain scipy solve_ivp {method}",
                    "error": error,
                    "wall_s": None,
                    "setting": f"rtol {rtol:g}: > {PLAIN_CAP_S:g} s, stopped",
                }
            )
            continue
        rows.append(
            {
                "engine": f"plain scipy solve_ivp {method}",
                "error": error,
                "wall_s": wall,
                "setting": f"rtol {rtol:g}",
                "nfev": nfev,
            }
        )
    return {
        "rows": rows,
        "duration": duration,
        "nodes": len(network.positions),
        "units": int(network.active.sum()),
        "quick": quick,
    }


def network_report(result: dict) -> str:
    meta = (
        f"{platform.processor() or platform.machine()}, {CORES} cores, MuJoCo {mujoco.__version__}; "
        f"{time.strftime('%Y-%m-%d %H:%M')}, load {load()}"
    )
    lines = [
        "## G. The active lattice: MuJoCo, the reduced engine and plain scipy at equal accuracy",
        "",
        f"Hexagonal patch R = {RINGS} ({result['nodes']} nodes, {result['units']} self-aligning units, outer ring "
        f"pinned), sigma = {SIGMA}, l_a = {ALIGNMENT_LENGTH}, {result['duration']:g} gamma / k, one thread "
        f"({meta}). Error: largest node error over [0, {WINDOW:g}] against the reduced engine at rtol "
        f"{REF_RTOL:g}, relative to the largest displacement; the ODE solvers at the loosest rtol matching MuJoCo's "
        "at dt 0.0025.",
        "",
        "| engine | setting | window error | wall s | us per step | right-hand sides |",
        "|---|---|---|---|---|---|",
    ]
    for r in result["rows"]:
        err = "-" if r["error"] is None else f"{100 * r['error']:.3g}%"
        wall = "-" if r["wall_s"] is None else f"{r['wall_s']:.3g}"
        us = f"{r['us_per_step']:.0f}" if "us_per_step" in r else "-"
        lines.append(f"| {r['engine']} | {r['setting']} | {err} | {wall} | {us} | {r.get('nfev', '-')} |")
    return "\n".join(lines) + "\n"

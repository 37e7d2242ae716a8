"""The cost of cilia through the fluid against the number of beads (reduced engine, elastoactive.reduced.fluid).

Rows of M cilia of N beads on the wall (cilia-row's geometry: bases (c d, 0, h), the Rotne-Prager-Blake mobility),
for each M: the CPU time of one right-hand-side evaluation, exact (every chain pair's mobility; the tensions by
Cholesky up to fluid.DIRECT_UP_TO links, by conjugate gradients beyond) and with the far field left out beyond
CUTOFF (Beds.cutoff); the evaluations DOP853 takes per tau on a beating row (counted, `evaluations_per_tau`);
one cilium's beat period; and so the projected time of 100 beats at two tolerances. The default route (Beds'
interaction "auto": the chains' interaction extrapolated over each step beyond fluid.EXACT_UP_TO links) is timed on
a whole run of DEFAULT_SPAN tau from the seeded start, scaled to 100 beats. With --against REV the kernel of git
revision REV is timed in the same run, side by side. The pair of N = 7 over 1000 tau is timed whole.

With --errors M1 M2 ..., instead: each row run 300 tau by the exact and the extrapolated interaction at the scenes'
tolerances, and the observables compared over tau 150..300 (`observe`): cilium 1's beat period, the neighbours'
phase lags (analysis.cilia.metachronal_wave, in cycles), the pumped flux (Blake's, over whole beats of cilium 1).

    .venv/bin/python scripts/bench_fluid.py                         # M = 1 .. 64, N = 10
    .venv/bin/python scripts/bench_fluid.py --against 90fa836       # and the kernel before, side by side
    .venv/bin/python scripts/bench_fluid.py --quick                 # M = 1 .. 16
    .venv/bin/python scripts/bench_fluid.py --out FILE.md           # also write the table
    .venv/bin/python scripts/bench_fluid.py --errors 8 16 24        # the extrapolated interaction's error
    .venv/bin/python scripts/bench_fluid.py --default --sizes 8 16 24 32 48 64   # the default route only

Times are CPU seconds of this process (time.process_time, the best of repeats): on a shared machine they rise less
with the load than wall time does; the load average is printed with the table.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from elastoactive.analysis import cilia as cilia_analysis
from elastoactive.reduced import fluid
from elastoactive.scenes.cilium import FLUID_TOLERANCES, ROTATION

RADIUS = 0.1
HEIGHT = 0.5
SPACING = 3.0
SIGMA = 0.8
BEATS = 100
BUDGET = 600.0  # s: the "100 beats in 10 minutes"
CUTOFF = 8.5 * SPACING  # l: each cilium interacts with its 8 nearest neighbours on either side
LOOSE = (1e-4, 1e-6)  # (rtol, atol) where a row's period and lags stay within 1e-6 of FLUID_TOLERANCES' (perf notes)
COUNTED_UP_TO = 32  # cilia: the evaluations per tau are counted up to here (by the cutoff kernel beyond EXACT_COUNT)
EXACT_COUNT = 8  # cilia: the evaluations per tau are counted on the exact kernel up to here
DEFAULT_SPAN = 60.0  # tau: the default route is timed over a whole run this long from the seeded start
ERROR_SPAN = 300.0  # tau: --errors' runs; the observables over its second half
ROOT = Path(__file__).resolve().parents[1]


def row(m: int, n: int, sigma: float = SIGMA, cutoff: float = np.inf) -> fluid.Beds:
    c = np.arange(m, dtype=float)
    bases = np.stack([c * SPACING, np.zeros(m), np.full(m, HEIGHT)], axis=1)
    return fluid.Beds(n, sigma, bases, ROTATION, "rpb", RADIUS, cutoff=cutoff).checked()


def start(beds: fluid.Beds, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.zeros((beds.chains, beds.n, 3))
    t[..., 0] = 1.0
    t[..., 1:] = 0.05 * rng.normal(size=(beds.chains, beds.n, 2))
    return t / np.linalg.norm(t, axis=-1)[..., None]


def timed(f, least: float = 0.3) -> float:
    """CPU seconds per call of f (the best of repeats totalling `least` s)."""
    f()
    best, total = np.inf, 0.0
    while total < least:
        s = time.process_time()
        f()
        took = time.process_time() - s
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


def evaluations_per_tau(beds: fluid.Beds, tolerances: tuple[float, float], span: float = 150.0) -> float:
    """DOP853's evaluations per tau on the beating row: over [span, 2 span] after a run from the start to span."""
    exact = beds._replace(interaction="exact")
    first = fluid.integrate_compiled(exact, np.array([0.0, span]), start(beds).ravel(), *tolerances)
    run = fluid.integrate_compiled(exact, np.array([span, 2 * span]), first.y[-1], *tolerances)
    return run.nfev / span


def default_run(beds: fluid.Beds, ts: np.ndarray, tolerances: tuple[float, float]):
    """solve_fluid's compiled run of the row from the seeded start (its route: Beds.interaction), as dop853_loop's
    Integrated (with its evaluations counted)."""
    return fluid.integrate_compiled(beds, ts, start(beds).ravel(), *tolerances)


def default_cost(beds: fluid.Beds, span: float = DEFAULT_SPAN) -> tuple[float, float]:
    """(CPU seconds per tau, evaluations per tau) of the default route over a whole run of `span` tau from the start,
    at the scenes' tolerances (compiled first on a short run)."""
    default_run(beds, np.array([0.0, 0.5]), FLUID_TOLERANCES)
    s = time.process_time()
    run = default_run(beds, np.array([0.0, span]), FLUID_TOLERANCES)
    return (time.process_time() - s) / span, run.nfev / span


def observe(beds: fluid.Beds, ts: np.ndarray, y: np.ndarray, transient: float) -> tuple[float, np.ndarray, float]:
    """(cilium 1's beat period, the neighbours' phase lags in cycles, the mean pumped flux) of a run's samples y
    (len(ts), 3 C N) after `transient`: the period from the upward zero crossings of the tips' in-plane signal, the
    lags by analysis.cilia.metachronal_wave, the flux Blake's 6 a sum F_x h integrated over whole beats of cilium 1
    between its first and last crossing (its swing is ~100 times its mean: a ragged window would move it)."""
    path = y.reshape(len(ts), beds.chains, beds.n, 3)
    u = path / np.linalg.norm(path, axis=-1, keepdims=True)
    positions = fluid.lab_positions(u, beds)
    signals = cilia_analysis.tip_signals(positions)
    keep = np.flatnonzero(ts >= transient)
    x, t = signals[0, keep], ts[keep]
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    crossings = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    beat = float(np.mean(np.diff(crossings)))
    lags = cilia_analysis.metachronal_wave(ts, signals, SPACING, transient=transient).lags / (2 * math.pi)
    forces = np.stack([fluid.fluid_forces(u[i], beds) for i in keep])
    flux = cilia_analysis.blake_flux(forces[..., 0], positions[keep][..., 2], beds.radius)
    a, b = crossings[0], crossings[-1]
    inside = (t > a) & (t < b)
    tt = np.concatenate([[a], t[inside], [b]])
    ff = np.concatenate([[np.interp(a, t, flux)], flux[inside], [np.interp(b, t, flux)]])
    return beat, lags, float(np.trapezoid(ff, tt) / (b - a))


def errors(sizes, n: int) -> list[str]:
    """The extrapolated interaction against the exact, row by row (module docstring, --errors)."""
    ts = np.linspace(0.0, ERROR_SPAN, int(10 * ERROR_SPAN) + 1)
    lines = [
        f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; N = {n}, a / l = {RADIUS}, h = {HEIGHT}, "
        f"d = {SPACING}, sigma = {SIGMA}; tolerances {FLUID_TOLERANCES[0]:g}/{FLUID_TOLERANCES[1]:g}; "
        f"{ERROR_SPAN:g} tau from the seeded start, observables over tau {ERROR_SPAN / 2:g}..{ERROR_SPAN:g}",
        "",
        "| M | CPU exact (s) | CPU extrapolated (s) | period (tau) | period, rel. error | lags (cycles) | "
        "max lag error (cycles) | flux (l^3/tau) | flux, rel. error |",
        "|---" * 9 + "|",
    ]
    for m in sizes:
        found = {}
        for interaction in ("exact", "extrapolated"):
            beds = row(m, n)._replace(interaction=interaction)
            default_run(beds, np.array([0.0, 0.5]), FLUID_TOLERANCES)  # compiled first
            s = time.process_time()
            run = default_run(beds, ts, FLUID_TOLERANCES)
            found[interaction] = (time.process_time() - s, *observe(beds, ts, run.y, ERROR_SPAN / 2))
        (c0, p0, l0, q0), (c1, p1, l1, q1) = found["exact"], found["extrapolated"]
        lag_error = np.abs((l1 - l0 + 0.5) % 1.0 - 0.5).max()
        lines.append(
            f"| {m} | {c0:.1f} | {c1:.1f} | {p0:.4f} | {(p1 - p0) / p0:.1e} | {l0.min():.3f} .. {l0.max():.3f} | "
            f"{lag_error:.1e} | {q0:.4f} | {(q1 - q0) / abs(q0):.1e} |"
        )
        print(lines[-1], flush=True)
    return lines


def default_table(sizes, n: int) -> list[str]:
    """The default route's CPU for 100 beats, row by row: a whole run of DEFAULT_SPAN tau from the seeded start,
    scaled to 100 of one cilium's beats."""
    beat = period(n)
    lines = [
        f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; N = {n}, a / l = {RADIUS}, h = {HEIGHT}, "
        f"d = {SPACING}, sigma = {SIGMA}; tolerances {FLUID_TOLERANCES[0]:g}/{FLUID_TOLERANCES[1]:g}; one cilium's "
        f"beat {beat:.3f} tau; CPU of a whole run of {DEFAULT_SPAN:g} tau from the seeded start, scaled",
        "",
        "| M | beads B | interaction | evaluations / tau | CPU per tau (s) | 100 beats (s of CPU) |",
        "|---" * 6 + "|",
    ]
    for m in sizes:
        beds = row(m, n)
        per_tau, rate = default_cost(beds)
        route = "extrapolated" if beds.extrapolated else "exact"
        lines.append(f"| {m} | {m * n} | {route} | {rate:.0f} | {per_tau:.3g} | {BEATS * beat * per_tau:.3g} |")
        print(lines[-1], flush=True)
    return lines


def kernel_of(revision: str):
    """reduced/fluid.py of a git revision as a module (its relative imports made absolute): its eval_rhs_fluid and
    _arguments, to time against today's."""
    show = ["git", "show", f"{revision}:elastoactive/reduced/fluid.py"]
    text = subprocess.run(show, cwd=ROOT, check=True, capture_output=True, text=True).stdout
    text = re.sub(r"^from \.\.(\w[\w.]*) import", r"from elastoactive.\1 import", text, flags=re.M)
    text = re.sub(r"^from \.(\w+) import", r"from elastoactive.reduced.\1 import", text, flags=re.M)
    folder = Path(tempfile.mkdtemp(prefix="fluid_before_"))
    path = folder / f"fluid_{revision}.py"
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[path.stem] = module
    spec.loader.exec_module(module)
    return module


def evaluation(module, beds: fluid.Beds) -> float:
    """CPU seconds of one evaluation of `module`'s kernel (fluid or an earlier revision's) on the row's start."""
    fields = [f for f in module.Beds._fields if f in beds._fields]
    b = module.Beds(**{f: getattr(beds, f) for f in fields})
    y = np.ascontiguousarray(start(beds)).ravel()
    out = np.empty(y.size)
    args = module._arguments(b)
    return timed(lambda: module.eval_rhs_fluid(y, *args, out))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10, help="beads per cilium (default 10)")
    ap.add_argument("--quick", action="store_true", help="M up to 16")
    ap.add_argument("--sizes", type=int, nargs="+", default=None, help="the M to time (default 1 2 4 ... 64)")
    ap.add_argument("--against", default=None, help="also time the kernel of this git revision, side by side")
    ap.add_argument("--before-up-to", type=int, default=64, help="time --against's kernel up to this M")
    ap.add_argument("--out", type=Path, default=None, help="also write the table (markdown) here")
    ap.add_argument("--default", action="store_true", help="only the default route's cost (no kernels timed)")
    ap.add_argument("--errors", type=int, nargs="+", default=None, help="instead: the extrapolated interaction's "
                    "error against the exact on rows of these M")  # fmt: skip
    args = ap.parse_args(argv)
    n = args.n
    if args.errors:
        text = "\n".join(errors(args.errors, n))
        print(text)
        if args.out:
            args.out.write_text(text + "\n")
        return 0
    sizes = args.sizes or ((1, 2, 4, 8, 16) if args.quick else (1, 2, 4, 8, 16, 24, 32, 48, 64, 96, 128))
    if args.default:
        text = "\n".join(default_table(sizes, n))
        print(text)
        if args.out:
            args.out.write_text(text + "\n")
        return 0
    before = kernel_of(args.against) if args.against else None
    rtol, atol = FLUID_TOLERANCES
    lines = [f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; N = {n}, a / l = {RADIUS}, "
             f"h = {HEIGHT}, d = {SPACING}, sigma = {SIGMA}; tolerances {rtol:g}/{atol:g} and {LOOSE[0]:g}/"
             f"{LOOSE[1]:g}; cutoff {CUTOFF:g} l; CPU times"]  # fmt: skip

    pair = row(2, 7)
    ts = np.linspace(0.0, 1000.0, 10001)
    fluid.solve_fluid(pair, ts[:11], start(pair), rtol=rtol, atol=atol)  # compiled (or loaded) first
    s = time.process_time()
    fluid.solve_fluid(pair, ts, start(pair), rtol=rtol, atol=atol)
    lines.append(f"pair of N = 7 on the wall, 1000 tau: {time.process_time() - s:.2f} s CPU (numba-DOP853)")
    beat = period(n)
    lines.append(f"one cilium's beat period: {beat:.3f} tau; 100 beats = {BEATS * beat:.0f} tau")
    rates = {}
    for m in sorted({min(m, COUNTED_UP_TO) for m in sizes}):
        beds = row(m, n, cutoff=np.inf if m <= EXACT_COUNT else CUTOFF)
        rates[m] = tuple(evaluations_per_tau(beds, tol) for tol in (FLUID_TOLERANCES, LOOSE))
    lines.append(
        f"evaluations per tau on the beating row (tau 150..300; counted on the cutoff kernel for M > {EXACT_COUNT}, "
        f"M > {COUNTED_UP_TO} take M = {COUNTED_UP_TO}'s), tight / loose: "
        + ", ".join(f"M = {m}: {a:.0f} / {b:.0f}" for m, (a, b) in rates.items())
    )
    head = "| M | beads B | before (ms) |" if before else "| M | beads B |"
    lines += [
        "",
        head + " exact (ms) | cutoff (ms) | 100 beats exact (s) | exact, loose (s) | cutoff, loose (s) | "
        "default: evaluations / tau | default: 100 beats (s) |",
        "|---" * (head.count("|") - 1 + 7) + "|",
    ]
    largest = {"exact": 0, "exact, loose": 0, "cutoff, loose": 0, "default": 0}
    for m in sizes:
        beds = row(m, n)
        t_exact = evaluation(fluid, beds)
        t_cut = evaluation(fluid, beds._replace(cutoff=CUTOFF))
        tight, loose = rates[min(m, COUNTED_UP_TO)]
        per_tau, default_rate = default_cost(beds)
        cost = {
            "exact": BEATS * beat * tight * t_exact,
            "exact, loose": BEATS * beat * loose * t_exact,
            "cutoff, loose": BEATS * beat * loose * t_cut,
            "default": BEATS * beat * per_tau,
        }
        for key, value in cost.items():
            if value <= BUDGET:
                largest[key] = m
        cells = [str(m), str(m * n)]
        if before:
            cells.append(f"{1e3 * evaluation(before, beds):.3g}" if m <= args.before_up_to else "")
        cells += [f"{1e3 * t_exact:.3g}", f"{1e3 * t_cut:.3g}"] + [f"{v:.3g}" for v in list(cost.values())[:3]]
        cells += [f"{default_rate:.0f}", f"{cost['default']:.3g}"]
        lines.append("| " + " | ".join(cells) + " |")
        print(lines[-1], flush=True)
    lines.append("")
    lines.append(
        f"largest row that runs {BEATS} beats within {BUDGET:.0f} s CPU (of the sizes timed; default: its whole run "
        f"of {DEFAULT_SPAN:g} tau from the start scaled), N = {n}: "
        + ", ".join(f"{key} M = {m}" for key, m in largest.items())
    )
    text = "\n".join(lines)
    print(text)
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

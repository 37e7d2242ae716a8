"""The cost of cilia through the fluid against the number of beads (reduced engine, elastoactive.reduced.fluid).

Rows of M cilia of N beads on the wall (cilia-row's geometry: bases (c d, 0, h), the Rotne-Prager-Blake mobility),
for each M: the CPU time of one right-hand-side evaluation, exact (every chain pair's mobility; the tensions by
Cholesky up to fluid.DIRECT_UP_TO links, by conjugate gradients beyond) and with the far field left out beyond
CUTOFF (Beds.cutoff); the evaluations DOP853 takes per tau on a beating row (counted, `evaluations_per_tau`);
one cilium's beat period; and so the projected time of 100 beats at two tolerances. With --against REV the kernel of
git revision REV is timed in the same run, side by side. The pair of N = 7 over 1000 tau is timed whole.

    .venv/bin/python scripts/bench_fluid.py                         # M = 1 .. 64, N = 10
    .venv/bin/python scripts/bench_fluid.py --against 90fa836       # and the kernel before, side by side
    .venv/bin/python scripts/bench_fluid.py --quick                 # M = 1 .. 16
    .venv/bin/python scripts/bench_fluid.py --out FILE.md           # also write the table

Times are CPU seconds of this process (time.process_time, the best of repeats): on a shared machine they rise less
with the load than wall time does; the load average is printed with the table.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from elastoactive.reduced import fluid
from elastoactive.reduced.dop853_loop import integrate
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
    args = fluid._arguments(beds)
    rtol, atol = tolerances
    first = integrate(fluid._dop853_fluid, args, np.array([0.0, span]), start(beds).ravel(), rtol, atol)
    run = integrate(fluid._dop853_fluid, args, np.array([span, 2 * span]), first.y[-1], rtol, atol)
    return run.nfev / span


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
    args = ap.parse_args(argv)
    n = args.n
    sizes = args.sizes or ((1, 2, 4, 8, 16) if args.quick else (1, 2, 4, 8, 16, 24, 32, 48, 64, 96, 128))
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
        head + " exact (ms) | cutoff (ms) | 100 beats exact (s) | exact, loose (s) | cutoff, loose (s) |",
        "|---" * (head.count("|") - 1 + 5) + "|",
    ]
    largest = {"exact": 0, "exact, loose": 0, "cutoff, loose": 0}
    for m in sizes:
        beds = row(m, n)
        t_exact = evaluation(fluid, beds)
        t_cut = evaluation(fluid, beds._replace(cutoff=CUTOFF))
        tight, loose = rates[min(m, COUNTED_UP_TO)]
        cost = {
            "exact": BEATS * beat * tight * t_exact,
            "exact, loose": BEATS * beat * loose * t_exact,
            "cutoff, loose": BEATS * beat * loose * t_cut,
        }
        for key, value in cost.items():
            if value <= BUDGET:
                largest[key] = m
        cells = [str(m), str(m * n)]
        if before:
            cells.append(f"{1e3 * evaluation(before, beds):.3g}" if m <= args.before_up_to else "")
        cells += [f"{1e3 * t_exact:.3g}", f"{1e3 * t_cut:.3g}"] + [f"{v:.3g}" for v in cost.values()]
        lines.append("| " + " | ".join(cells) + " |")
        print(lines[-1], flush=True)
    lines.append("")
    lines.append(
        f"largest row that runs {BEATS} beats within {BUDGET:.0f} s CPU (of the sizes timed), N = {n}: "
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

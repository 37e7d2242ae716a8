#!/usr/bin/env python
"""The reduced engine's runs that the quick reproduction leans on, side by side for one or two source trees.

  .venv/bin/python scripts/bench_reduced_paths.py [--before TREE] [--repeats 3]

For each source tree (this checkout, and with --before a second one, e.g. `git worktree add --detach /tmp/base
<commit>` for the code before a change; a compiled controllers/_follower*.so must be copied in), one child process on
that tree's `PYTHONPATH` warms each run once and then times it, best of --repeats (wall time, quiet machine wanted):

  tip drive, N = 2, 500 tau      entrainment's runs (a PeriodicForce on the tip: reduced.node_kernels)
  tip drive, N = 7, 1000 tau     the response's
  pair, N = 7, 1000 tau          the paper's coupled pair (sync, tongue)
  one-pinned, N = 7, 1000 tau    the Hopf chain
  what-if pair, 600 tau          sync's pair with chain 2's force x 0.75 (studies.sync._alt_pair_run)

Each tree's kernels should be in numba's cache first (`python -m elastoactive.cli.warm` on that tree): a compilation
is not what is measured. docs/performance.md, section 17, has a run of it.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent

CHILD = r"""
import json, sys, time
from elastoactive.core.params import Numerics
from elastoactive.engines.reduced import simulate_reduced
from elastoactive.scenes import coupled_pair, one_pinned
from elastoactive.studies.base import fast
from elastoactive.studies.sync import _alt_pair_run
repeats = int(sys.argv[1])
drive2 = one_pinned.SCENE.physics(n=2, sigma=1.0, drive_amplitude=0.1, drive_frequency=0.05)
drive7 = one_pinned.SCENE.physics(n=7, sigma=0.1, drive_amplitude=0.01, drive_frequency=0.01)
pair = coupled_pair.SCENE.physics(n=7, sigma=0.8, rho=4 / 3, kappa=0.07)
chain = one_pinned.SCENE.physics(n=7, sigma=0.8)
runs = {
    "tip drive, N = 2, 500 tau": lambda: simulate_reduced(drive2, Numerics(sample_dt=0.05), 500.0),
    "tip drive, N = 7, 1000 tau": lambda: simulate_reduced(drive7, Numerics(sample_dt=0.1), 1000.0),
    "pair, N = 7, 1000 tau": lambda: simulate_reduced(pair, fast(perturbation=0.3, sample_dt=0.1), 1000.0),
    "one-pinned, N = 7, 1000 tau": lambda: simulate_reduced(chain, fast(perturbation=0.1, sample_dt=0.1), 1000.0),
    "what-if pair, 600 tau": lambda: _alt_pair_run((7, 0.8, 0.75, 0.6, 600.0, 300.0)),
}
best = {}
for name, run in runs.items():
    run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    best[name] = min(times)
print(json.dumps(best))
"""


def measure(tree: Path, repeats: int) -> dict[str, float]:
    """Best wall time of each run, in a child process on `tree`'s PYTHONPATH (run from /tmp: the checkout's folder
    would shadow it)."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(repeats)], cwd="/tmp", env=env, capture_output=True, text=True, check=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", type=Path, help="a second source tree, measured first (the code before a change)")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs of each, the best kept (default 3)")
    args = ap.parse_args(argv)
    trees = ([args.before.resolve()] if args.before else []) + [HERE]
    print(f"load average {', '.join(f'{x:.2f}' for x in os.getloadavg())}")
    results = [measure(tree, args.repeats) for tree in trees]
    head = " | ".join(str(tree) for tree in trees)
    print(f"| run | {head} |" + (" ratio |" if args.before else ""))
    print("|---|" + "---|" * (len(trees) + bool(args.before)))
    for name in results[-1]:
        cells = " | ".join(f"{r[name]:.3f} s" for r in results)
        ratio = f" {results[0][name] / results[-1][name]:.1f}x |" if args.before else ""
        print(f"| {name} | {cells} |{ratio}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

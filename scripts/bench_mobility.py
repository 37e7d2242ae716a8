"""The mobilities' cost against the number of beads: building the dense (3n, 3n) matrix (rpy_into, rpb_into), its
Cholesky factorisation and one solve (scipy.linalg.cho_factor / cho_solve), and the matrix-free product (apply).

    .venv/bin/python scripts/bench_mobility.py [--sizes 14 70 140 640] [--repeats 5]

Prints a Markdown table (best of `repeats`, milliseconds, one BLAS thread) and the machine's load; the
configurations are cilia: upright chains of 7 beads on the wall at link spacing l = 1 on a square lattice of
spacing 2 l, radius a / l = 0.1 (the free-space build uses the same positions).
"""

from __future__ import annotations

import argparse

import numpy as np
from bench_common import best_of, load, log
from scipy.linalg import cho_factor, cho_solve

from elastoactive.hydro import apply, rpb_into, rpy_into
from elastoactive.reduced.blas import one_blas_thread

RADIUS = 0.1
BEADS_PER_CILIUM = 7


def cilia(n: int) -> np.ndarray:
    """n beads as ceil(n / 7) upright chains on a square lattice of spacing 2 l, the first bead at height 1 l."""
    count = -(-n // BEADS_PER_CILIUM)
    side = int(np.ceil(np.sqrt(count)))
    x = [(2.0 * (c % side), 2.0 * (c // side), 1.0 + k) for c in range(count) for k in range(BEADS_PER_CILIUM)]
    return np.array(x[:n], dtype=float)


def measure(n: int, repeats: int) -> dict[str, float]:
    x = cilia(n)
    out = np.empty((3 * n, 3 * n))
    forces = np.random.default_rng(0).normal(size=(n, 3))
    rpy_into(x, RADIUS, out)  # compiled (or loaded from numba's cache) before timing
    rpb_into(x, RADIUS, out)
    apply(x, RADIUS, forces, wall=True)
    row = {
        "rpy_into": best_of(lambda: rpy_into(x, RADIUS, out), repeats),
        "rpb_into": best_of(lambda: rpb_into(x, RADIUS, out), repeats),
    }
    rpb_into(x, RADIUS, out)
    row["cholesky"] = best_of(lambda: cho_factor(out.copy(), lower=True, overwrite_a=True), repeats)
    factor = cho_factor(out, lower=True)
    row["solve"] = best_of(lambda: cho_solve(factor, forces.ravel()), repeats)
    row["apply (wall)"] = best_of(lambda: apply(x, RADIUS, forces, wall=True), repeats)
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[14, 70, 140, 640])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    log(f"load before: {load()}")
    rows = {}
    for n in args.sizes:
        with one_blas_thread():  # a multi-threaded OpenBLAS spins on a shared machine (elastoactive.reduced.blas)
            rows[n] = measure(n, args.repeats)
        log(f"n = {n}: " + ", ".join(f"{k} {v * 1e3:.3g} ms" for k, v in rows[n].items()))
    columns = list(next(iter(rows.values())))
    print("| beads n | 3n | " + " | ".join(f"{c} (ms)" for c in columns) + " |")
    print("|---:|---:|" + "---:|" * len(columns))
    for n, row in rows.items():
        print(f"| {n} | {3 * n} | " + " | ".join(f"{row[c] * 1e3:.3g}" for c in columns) + " |")
    log(f"load after: {load()}")


if __name__ == "__main__":
    main()

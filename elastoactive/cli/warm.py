"""Compile the reduced model's kernels into numba's on-disk cache, so that the first run after an install does not.

The kernels are compiled with cache=True: the first process that needs one compiles it (about 3 min of CPU for the whole
set, 106 s of wall with the two groups side by side on 2 cores) and every later process loads it (about 3 s).
`scripts/setup.sh` runs this module after an install, and again when a source has changed since, so a fresh machine's
first `elastoactive reproduce` (or any first run) loads the kernels instead of compiling them. It runs, for a tau each
in the reduced engine, every registered scene's and term's validation case (which reach the numba-DOP853 loop with every
right-hand side, the network model, the periodic point forces), and the paths those do not: noise (Ito, Stratonovich,
coloured; a network's polarities), the inertial model with and without noise, a long chain, the implicit methods with
the analytic Jacobian, and chains through the fluid (on a wall, in free space, a row beyond the exact interaction's
size).

    .venv/bin/python -m elastoactive.cli.warm        # prints one line: what it ran and how long it took
"""

from __future__ import annotations

import time

from ..checks.validate import validation_cases
from ..core.params import Numerics, Physics
from ..engines.reduced import simulate_reduced
from ..io.executor import default_workers, forks, imap
from ..scenes import cilia_row, cilium, clamped3d, lattice

DURATION = 1.0
"""tau of each run: a few steps of every loop."""


Run = tuple[Physics, Numerics, dict]
"""(physics, numerics, simulate_reduced's keywords) of one warm-up run."""


def groups() -> tuple[list[Run], list[Run]]:
    """The warm-up's runs in two groups that share no compiled kernel, so that two cores compile them side by side:
    the scenes' validation cases and the chain's other paths; the chains through the fluid and a network's noise."""
    sampled = Numerics(sample_dt=0.1)
    chain = Physics(n=7, sigma=0.8)
    first = [(case.physics, sampled, {}) for case in validation_cases()]
    first += [
        (Physics(n=7, sigma=0.8, noise=0.1), sampled, {}),
        (Physics(n=7, sigma=0.8, noise=0.1, noise_calculus="stratonovich"), sampled, {}),
        (Physics(n=7, sigma=0.8, noise=0.1, noise_correlation=0.5), sampled, {}),
        (chain, Numerics(sample_dt=0.1, mass_ratio=0.5), {"inertial": True}),
        (Physics(n=7, sigma=0.8, noise=0.1), Numerics(sample_dt=0.1, mass_ratio=0.5), {"inertial": True}),
        (Physics(n=24, sigma=0.8), sampled, {}),
        (Physics(n=24, sigma=0.8), sampled, {"method": "LSODA"}),
        (chain, sampled, {"method": "Radau"}),
    ]
    first += [
        (case.physics, sampled, {"method": "BDF"})
        for case in validation_cases()  # the pinned constraints'
        if case.physics.scene_def.pinned and "BDF" in case.physics.scene_def.reduced_methods()
    ][:1]  # Jacobian
    network = lattice.SCENE.physics(rings=2, boundary="pinned", alignment_length=0.1, rotational_diffusion=0.03)
    second = [
        # through the fluid (a scene's validation case has the local drag): on the wall (Rotne-Prager-Blake), in free
        # space (Rotne-Prager-Yamakawa) and a row beyond fluid.EXACT_UP_TO links (the extrapolated interaction)
        (cilium.SCENE.physics(n=7, sigma=0.4, bead_radius=0.1), sampled, {}),
        (clamped3d.SCENE.physics(n=5, sigma=0.4, bead_radius=0.1), sampled, {}),
        (cilia_row.SCENE.physics(n=10, sigma=0.6, cilia=11, bead_radius=0.1), sampled, {}),
        (network, sampled, {}),  # a network's noisy polarities (Euler-Maruyama)
    ]
    return first, second


def runs() -> list[Run]:
    """Every run the warm-up makes."""
    first, second = groups()
    return first + second


def _run_all(todo: list[Run]) -> int:
    """Run each for DURATION; the number that failed (a scene this build refuses is skipped)."""
    failed = 0
    for physics, numerics, keywords in todo:
        try:
            simulate_reduced(physics, numerics, DURATION, **keywords)
        except Exception:  # noqa: BLE001 (warming only: the run itself will say what is wrong)
            failed += 1
    return failed


def warm() -> tuple[int, int, float]:
    """Run every warm-up run, the two groups side by side where there are two cores and pools fork; (runs, failed,
    seconds)."""
    start = time.perf_counter()
    parts = groups()
    if default_workers() > 1 and forks():
        failed = sum(count for _, count in imap(_run_all, parts, 2))
    else:
        failed = sum(_run_all(part) for part in parts)
    return sum(len(part) for part in parts), failed, time.perf_counter() - start


def main() -> None:
    count, failed, seconds = warm()
    note = f" ({failed} could not run)" if failed else ""
    print(
        f"elastoactive: the reduced model's kernels compiled into numba's cache: {count} short runs{note}, "
        f"{seconds:.0f} s"
    )


if __name__ == "__main__":
    main()

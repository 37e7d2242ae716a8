"""Run many independent cases on every core: one case = one simulation + its measurements.

MuJoCo cases run together with `mujoco.batch` (engines.mujoco_batch): the cases that share one
compiled model step in one batch on `workers` C threads of this process, bit for bit what
`run_case` gives. Reduced-engine cases run on a process pool (executor): their compiled kernels
hold the GIL, so threads would not help (processes gave 1.84x on 2 cores); the kernels are loaded
once in this process before the workers fork (load_engine), not again in every worker of every
batch. A list of both runs them at once: the reduced cases are handed to the pool first (its workers fork
before any MuJoCo thread starts) and run beside the MuJoCo threads, so that neither engine's last cases
leave a core idle while the other's wait (the cores are shared: each run's own wall time is then longer).
Results come back in input order; with `on_result` each is handed over (in this thread) as soon as it is done, so a
caller can write it out before the rest finish. A failed case (e.g. SimulationDiverged) raises, once
the others have finished: the first failure in input order. Every case passes the gate (gate.preflight) before
any of them runs, its MuJoCo timestep checked once per distinct model of the batch.

engines.mujoco_batch is imported inside _run_mujoco, the MuJoCo engine's boundary: it loads mujoco, which a batch of
reduced-engine cases does not need.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import time
from collections.abc import Callable, Iterable
from concurrent.futures import as_completed
from dataclasses import dataclass, field

from .core.params import Numerics, Physics
from .core.trajectory import Trajectory
from .engines import check_engine, run_engine
from .gate import TimestepChecks, preflight
from .io.executor import default_workers, imap, process_pool
from .io.progress import progress_bar
from .results import Results, measure


@dataclass(frozen=True)
class Case:
    physics: Physics
    numerics: Numerics = field(default_factory=Numerics)
    duration: float = 300.0
    engine: str = "mujoco"  # or "reduced"
    transient: float | None = None

    def __post_init__(self):
        check_engine(self.engine)


@dataclass
class CaseResult:
    """One finished case: its measurements, the simulation's wall time and solver info, and (if
    kept) the trajectory. batch_wall_s is the wall time of the whole batch it ran in."""

    results: Results | None
    """None when the batch ran with measured=False (the caller measures the trajectory itself)."""
    wall_time_s: float
    info: dict
    trajectory: Trajectory | None = None
    batch_wall_s: float = 0.0


def checked(case: Case, timestep: bool = True, checks: TimestepChecks | None = None) -> Case:
    """The case as it runs, once it has passed the gate (gate.preflight: its numerics resolved for its duration), or
    the gate's ParameterError."""
    run = preflight(
        case.physics, case.numerics, case.duration, case.engine, timestep=timestep, checks=checks, given=False
    )
    if run.numerics == case.numerics and run.duration == case.duration:
        return case
    return dataclasses.replace(case, numerics=run.numerics, duration=run.duration)


def run_case(
    case: Case,
    keep_trajectory: bool = False,
    measured: bool = True,
    *,
    timestep: bool = True,
    checks: TimestepChecks | None = None,
) -> CaseResult:
    """Simulate one case, once it has passed the gate (`checked`), and measure it (results.measure; not with
    measured=False)."""
    return _run_checked(checked(case, timestep, checks), keep_trajectory, measured)


def _run_checked(case: Case, keep_trajectory: bool = False, measured: bool = True) -> CaseResult:
    """Simulate and measure a case that has passed the gate already (`checked`'s result)."""
    traj = run_engine(case.engine, case.physics, case.numerics, case.duration)
    return CaseResult(
        measure(traj, case.transient) if measured else None,
        traj.wall_time_s,
        traj.info,
        traj if keep_trajectory else None,
    )


def load_engine(case: Case) -> None:
    """Run `case` for a few samples and discard them: loads what its engine needs (the reduced model's
    compiled kernels), so that pool workers forked afterwards start with it."""
    run_engine(case.engine, case.physics, case.numerics, min(case.duration, 4 * case.numerics.sample_dt))


def run_cases(
    cases: Iterable[Case],
    workers: int | None = None,
    progress: bool = True,
    keep_trajectory: bool = False,
    on_result: Callable[[int, CaseResult], None] | None = None,
    desc: str = "cases",
    measured: bool = True,
) -> list[CaseResult]:
    """Run the cases on `workers` threads (MuJoCo) or processes (reduced; default: every core);
    results in input order. measured=False skips results.measure (its harmonic fits cost several times a
    short reduced run): for a caller that keeps the trajectories and measures them its own way."""
    cases = list(cases)
    workers = default_workers() if workers is None else workers
    results: list[CaseResult | None] = [None] * len(cases)
    errors: dict[int, BaseException] = {}
    bar = None
    if progress:
        bar = progress_bar(len(cases), desc, "case")
    start = time.perf_counter()

    def finished(i: int, result: CaseResult) -> None:
        results[i] = result
        if on_result:
            on_result(i, result)
        if bar:
            bar.update()

    checks = TimestepChecks()  # one check per distinct model of the batch
    for i, case in enumerate(cases):  # the gate, before anything runs: a refused case is its own error
        try:
            cases[i] = checked(case, checks=checks)
        except Exception as err:  # noqa: BLE001 (raised below, after the others, as a failed run would be)
            errors[i] = err
    try:
        simulated = [i for i, case in enumerate(cases) if case.engine == "mujoco" and i not in errors]
        reduced = [i for i, case in enumerate(cases) if case.engine != "mujoco" and i not in errors]
        task = functools.partial(_run_checked, keep_trajectory=keep_trajectory, measured=measured)
        with contextlib.ExitStack() as stack:
            pending = {}
            if simulated and workers > 1 and len(reduced) > 1:  # both engines at once (see the module's docstring)
                pool = stack.enter_context(
                    process_pool(min(workers, len(reduced)), warm=functools.partial(load_engine, cases[reduced[0]]))
                )
                pending = {pool.submit(task, cases[i]): i for i in reduced}  # the workers fork now, before any C thread
                reduced = []
            _run_mujoco(cases, simulated, workers, measured, keep_trajectory, errors, finished)
            for future in as_completed(pending):
                error = future.exception()
                if error is not None:
                    errors[pending[future]] = error
                else:
                    finished(pending[future], future.result())
        if workers <= 1 or len(reduced) <= 1:
            for i in reduced:
                finished(i, _run_checked(cases[i], keep_trajectory, measured))
        elif reduced:
            runs = imap(
                task,
                [cases[i] for i in reduced],
                workers,
                completed=True,
                errors=True,
                warm=functools.partial(load_engine, cases[reduced[0]]),
            )
            for j, outcome in runs:
                if isinstance(outcome, BaseException):
                    errors[reduced[j]] = outcome
                else:
                    finished(reduced[j], outcome)
    finally:
        if bar:
            bar.close()
    if errors:
        raise errors[min(errors)]
    elapsed = time.perf_counter() - start
    for r in results:
        r.batch_wall_s = elapsed
    return results  # type: ignore[return-value]


def _run_mujoco(
    cases: list[Case],
    simulated: list[int],
    workers: int,
    measured: bool,
    keep_trajectory: bool,
    errors: dict,
    finished: Callable[[int, CaseResult], None],
) -> None:
    """The MuJoCo cases (indices `simulated`) in mujoco.batch batches on `workers` threads; each result to finished(i,
    result), each failure into errors[i]."""
    if simulated:
        from .engines.mujoco_batch import iter_mujoco_batch  # start-up time: loads mujoco

        runs = [cases[i] for i in simulated]
        for j, outcome in iter_mujoco_batch(runs, threads=max(1, workers)):
            i = simulated[j]
            if isinstance(outcome, BaseException):
                errors[i] = outcome
                continue
            try:
                res = measure(outcome, cases[i].transient) if measured else None
            except Exception as err:  # noqa: BLE001 (raised below, as run_case would)
                errors[i] = err
                continue
            finished(i, CaseResult(res, outcome.wall_time_s, outcome.info, outcome if keep_trajectory else None))

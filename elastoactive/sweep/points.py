"""Running grid points: one point on its own (`run_point`, for the process pool and Dask), or MuJoCo points
together in one mujoco.batch (`run_points`). Every point passes the gate (gate.preflight, through batch.checked);
a batch's timestep checks (engines.timestep.check_timestep) are computed once per distinct model on a thread of their
own while the batch steps (gate.TimestepChecks).

A point never raises for a failed simulation: its record holds the error text. A record is what the
journal stores: status, error, measurements (numbers; None as NaN, a bool as 0 or 1), notes and wall time.

The MuJoCo engine (engines.mujoco_batch, engines.timestep, the follower callback) and dask.distributed are imported
inside the functions that run MuJoCo points or Dask tasks, the engines' boundary: a reduced-engine sweep never loads
MuJoCo, a local one never Dask.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import threading
import time
from collections.abc import Callable, Sequence

import numpy as np

from ..batch import Case, checked, run_case
from ..core import observables, surface
from ..core.errors import ParameterError
from ..gate import TimestepChecks
from ..io.jsonio import to_jsonable
from ..results import measure

BATCH_POINTS_PER_THREAD = 8
"""Default size of a local MuJoCo batch: this many points per thread (a killed sweep loses at most the
batches that are running; a larger batch gains little once every thread has several simulations)."""


_TASK_LOCK = threading.Lock()
"""One batch task at a time per Dask worker process: each uses all the worker's threads, and the
follower callback is global to the process."""


def run_point(case: Case, timestep_check: bool = True) -> dict:
    """One grid point: never raises for a failed simulation, returns its error text instead."""
    start = time.perf_counter()
    try:
        out = run_case(case, timestep=timestep_check)  # through the gate
        record = _ok_record(out.results, out.info, out.wall_time_s)
    except Exception as err:  # a diverged or refused point is recorded and the sweep goes on
        record = error_record(err, time.perf_counter() - start)
    record["finished_at"] = time.time()
    return record


def _ok_record(results, info: dict, wall_time_s: float) -> dict:
    """A successful point's record: its numeric measurements, its notes as one text, its wall time."""
    values = results.as_dict()
    if "constraint_violation" in info:
        values["constraint_violation"] = info["constraint_violation"]
    notes = "; ".join(str(note) for note in (results.notes or ()))
    return {
        "status": "ok",
        "error": "",
        "results": _measurements(values),
        "notes": notes,
        "wall_time_s": float(wall_time_s),
    }


def error_record(err: BaseException, wall_time_s: float) -> dict:
    return {
        "status": "error",
        "error": f"{type(err).__name__}: {err}",
        "results": {},
        "notes": "",
        "wall_time_s": float(wall_time_s),
    }


def run_points(
    cases: Sequence[Case],
    timestep_check: bool = True,
    threads: int = 1,
    *,
    on_record: Callable[[int, dict], None] | None = None,
    cancel: threading.Event | None = None,
    checks: TimestepChecks | None = None,
    on_start: Callable[[], None] | None = None,
) -> list[dict]:
    """MuJoCo grid points run together (engines.mujoco_batch, `threads` C threads); returns each point's
    record as run_point would (never raises for a failed point). on_record(j, record) is called as each
    is known: a point that fails at once, the others when their batch ends, all of that batch's together once
    they are measured (the sweep saves them with one fsync). The follower callback must be installed by the
    caller (mujoco_batch.run_chunks does).

    The pre-flight checks (diagnose.check_timestep, once per distinct model) run on a thread of their
    own while the batch steps: a refused point is dropped from its batch at its next chunk of samples
    and recorded with the refusal, as if it had never run; a point is recorded only once its check is
    done."""
    from ..engines.mujoco_batch import Cancelled, as_runs, run_chunk, runs_alone  # start-up time: loads mujoco

    start = time.perf_counter()
    records: list[dict | None] = [None] * len(cases)
    checks = checks if checks is not None else TimestepChecks()
    stepping, finished = threading.Event(), threading.Event()

    held: list[int] = []  # measured points of the running batch, handed to on_record when it ends (release)

    def put(j: int, record: dict, hold: bool = False) -> None:
        record["finished_at"] = time.time()
        records[j] = record
        if hold:
            held.append(j)
        elif on_record is not None:
            on_record(j, record)

    def release() -> None:
        while held:
            j = held.pop(0)
            if on_record is not None:
                on_record(j, records[j])

    def drop(j: int) -> BaseException | None:
        return checks.known_refusal(cases[j].physics, cases[j].numerics)

    def done(j: int, outcome) -> None:
        refused = checks.refusal(cases[j].physics, cases[j].numerics) if timestep_check else None
        if refused is not None:  # the check's verdict comes first, whatever the simulation did
            outcome = refused
        if isinstance(outcome, BaseException):
            put(j, error_record(outcome, time.perf_counter() - start))
            return
        try:  # a finished simulation: its batch is ending, the record is handed over with the batch's (release)
            put(j, _ok_record(measure(outcome, cases[j].transient), outcome.info, outcome.wall_time_s), hold=True)
        except Exception as err:  # measuring failed: the point's error, as in run_point
            put(j, error_record(err, time.perf_counter() - start), hold=True)

    def check_all() -> None:
        # after the stepping has started: the checks need the GIL, which preparing the models needs too
        while not (stepping.wait(0.05) or finished.is_set()):
            pass
        for j in order:
            if finished.is_set() or (cancel is not None and cancel.is_set()):
                return
            with contextlib.suppress(Exception):
                checks.refusal(cases[j].physics, cases[j].numerics)

    def started() -> None:
        stepping.set()
        if on_start is not None:
            on_start()

    cases = list(cases)
    order = list(range(len(cases)))
    for j in list(order):  # the gate, but for the timestep check, which runs beside the batch (check_all)
        try:
            cases[j] = checked(cases[j], timestep=False)
        except Exception as err:  # refused: the point's error, as in run_point
            put(j, error_record(err, time.perf_counter() - start))
            order.remove(j)
    runs = as_runs(cases)
    if timestep_check:  # a run alone (a network) runs whole on its thread, where a refusal cannot stop it: check first
        for j in [j for j in order if runs_alone(runs[j])]:
            refused = checks.refusal(cases[j].physics, cases[j].numerics)
            if refused is not None:
                put(j, error_record(refused, time.perf_counter() - start))
                order.remove(j)
    checker = threading.Thread(target=check_all, name="elastoactive-checks", daemon=True) if timestep_check else None
    if checker is not None:
        checker.start()
    try:
        offer = (lambda j, model: checks.offer(cases[j].physics, cases[j].numerics, model)) if timestep_check else None
        run_chunk(runs, order, threads, done, cancel, started, drop if timestep_check else None, offer, release)
        release()
    except Cancelled:
        raise
    except Exception as err:  # the batch itself failed: its unfinished points are errors, the sweep goes on
        release()
        for j, record in enumerate(records):
            if record is None:
                put(j, error_record(err, time.perf_counter() - start))
    finally:
        finished.set()
        if checker is not None:
            checker.join()
    return records  # type: ignore[return-value]


def run_points_task(cases: Sequence[Case], timestep_check: bool = True) -> list[dict]:
    """A Dask task: one batch of MuJoCo points (run_points) on every thread of the worker that runs it;
    tasks of one worker process take turns."""
    threads = 1
    with contextlib.suppress(Exception):
        from dask.distributed import get_worker  # optional dependency, loaded on Dask workers only

        threads = max(1, int(get_worker().state.nthreads))
    from ..controllers import follower_forces  # start-up time: loads mujoco

    with _TASK_LOCK, follower_forces():
        return run_points(cases, timestep_check, threads)


def _measurements(results: dict) -> dict:
    """The numeric measurements of Results.as_dict(), as JSON-ready numbers: a number, or one per chain
    (a list). None ("could not be measured") becomes NaN, a bool 0 or 1, a categorical observable's value (its
    spec's categories, elastoactive.core.observables: e.g. dish_state) its index; other text (the notes) is left out: it
    is stored as the record's `notes`."""
    specs = {name: observables.find(name) for name in results}
    coded = {
        name: float(specs[name].categories.index(value))
        for name, value in results.items()
        if specs[name] is not None and value in specs[name].categories
    }
    return {
        name: _coded(to_jsonable(value, nonfinite="keep"))
        for name, value in {**results, **coded}.items()
        if _numeric(value)
    }


def _numeric(value, depth: int = 2) -> bool:
    """A number, or a non-empty list of them, or (VECTORS per chain) a list of such lists."""
    scalar = (int, float, np.integer, np.floating, np.bool_, type(None))
    if isinstance(value, (list, tuple, np.ndarray)):
        return depth > 0 and len(value) > 0 and all(_numeric(v, depth - 1) for v in value)
    return isinstance(value, scalar)


def _coded(value):
    """A measurement (JSON values: a number or lists of them) as numbers: None as NaN, a bool as 0.0 or 1.0."""
    if isinstance(value, list):
        return [_coded(v) for v in value]
    return math.nan if value is None else (float(value) if isinstance(value, bool) else value)


REFUSAL = "ParameterError: "
"""How a point's error text starts when the point was refused before it ran (its settings, as the pre-flight check or
the engine read them): nothing was simulated, so a re-run checks it again (a re-run with --no-timestep-check runs it)
instead of keeping the refusal as the point's result."""


def refused(error: str) -> bool:
    """A point's error text is a refusal of its settings (REFUSAL), not a failed simulation."""
    return isinstance(error, str) and error.startswith(REFUSAL)


def refuse_if_all_refused(cases: Sequence[Case], checks: TimestepChecks, grid_keys: Sequence[str] = ()) -> None:
    """Raise one ParameterError before any point runs when the pre-flight check (diagnose.check_timestep) refuses
    every one of `cases` (the MuJoCo points to run, none of the sweep's done): a sweep of refusals is no result.
    The line gives the first refusal and a setting that passes every point (the smallest of the points' passing dt
    at their mass ratio and integrator, checked). The first case is checked alone first: when it passes, nothing more
    runs here (the other checks are made beside the batches). The outcomes are kept in `checks` for the run."""
    if not cases or checks.refusal(cases[0].physics, cases[0].numerics) is None:
        return
    refusals = [checks.refusal(case.physics, case.numerics) for case in cases]
    if not all(isinstance(err, ParameterError) for err in refusals):
        return  # some point passes (or its check failed otherwise: that point's own error)
    from ..engines.timestep import check_timestep, passing_setting, stability_limits  # start-up time: loads mujoco

    first = cases[0]
    try:
        check_timestep(first.physics, first.numerics, suggest=False)
        text = str(refusals[0])
    except ParameterError as err:
        text = str(err)
    settings = []
    for case in {TimestepChecks.key(c.physics, c.numerics): c for c in cases}.values():
        numerics = case.numerics.for_physics(case.physics)
        try:
            settings.append(
                (passing_setting(case.physics, stability_limits(case.physics, numerics), numerics), numerics)
            )
        except Exception:
            settings.append((None, numerics))
    advice = ""
    if all(setting is not None for setting, _ in settings):
        dt = min(setting[0] for setting, _ in settings)
        tried = [dataclasses.replace(case.numerics, dt=dt) for case in cases]
        try:
            for case, numerics in zip(cases, tried):
                check_timestep(case.physics, numerics, suggest=False)
        except Exception:
            dt = None
        if dt is not None:
            masses = {setting[1] for setting, _ in settings}
            integrators = {numerics.integrator for _, numerics in settings}
            given = {} if "dt" in grid_keys else {"dt": dt}
            if len(masses) == 1 and "mass_ratio" not in grid_keys:
                given["mass_ratio"] = masses.pop()
            if len(integrators) == 1:
                given["integrator"] = integrators.pop()
            parts = [f"dt <= {dt:g} on the grid"] if "dt" in grid_keys else []
            parts += [surface.settings("Numerics", **given)] if given else []
            advice = f"; a setting that passes every point: {' '.join(parts)}"
    raise ParameterError(
        f"the pre-flight check refuses every point of the sweep ({len(cases)}), so none runs; "
        f"the first: {text.rstrip('.')}{advice}"
    )

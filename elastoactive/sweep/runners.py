"""Where a sweep's points run; each runner yields (flat index, record) as points finish.

* MuJoCo points run in batches (`engines.mujoco_batch`): points that share one compiled model (same
  N, mass ratio, integrator, dt and sampling; sigma, seed, noise, kappa, rho, drag ratio, delta and
  perturbation are per-simulation fields or states of it) step together in one `mujoco.batch` on
  `workers` C threads of this process: no Python per step, bit for bit what `elastoactive run` gives.
  A batch holds at most `batch_size` points (default 8 per thread). Its points are journaled when it
  ends (together: one fsync); a point that fails at once (diverged early, or refused by the pre-flight
  check, diagnose.check_timestep, computed once per distinct model while the batch steps) as soon as
  it does. A diverged point is its own error; the others of its batch go on. A kill loses at most
  the running batches.
* Reduced-engine points run on a local process pool (executor; its compiled kernels hold the GIL).
* On a Dask cluster (`scheduler="tcp://host:port"`) each task is one MuJoCo batch (on every thread of
  the worker that runs it, whose tasks take turns; at least one batch per worker), or one reduced point.
  Every worker of the cluster needs elastoactive (same version) installed; the batches (or reduced
  points) are submitted with client.map and collected as they complete, as locally.

engines.mujoco_batch (mujoco), dask.distributed, h5netcdf and xarray are imported inside the runners that use them,
the engines' and the storage's boundary: a reduced-engine sweep loads no MuJoCo, a local one no Dask.
"""

from __future__ import annotations

import contextlib
import functools
import threading
import time
from collections.abc import Iterator

import numpy as np

from ..core.errors import ParameterError
from ..gate import TimestepChecks
from ..io.executor import imap
from .grid import Sweep
from .netcdf import package_version
from .points import (
    BATCH_POINTS_PER_THREAD,
    error_record,
    run_point,
    run_points,
    run_points_task,
)


def run_local(todo: list[int], sweep: Sweep, workers: int, check: bool) -> Iterator[tuple[int, dict]]:
    """Reduced-engine points on a process pool (its compiled kernels hold the GIL: threads would not help)."""
    if workers <= 1 or len(todo) <= 1:
        for i in todo:
            yield i, run_point(sweep.case(i), check)
        return

    task = functools.partial(run_point, timestep_check=check)
    for j, record in imap(task, [sweep.case(i) for i in todo], workers, completed=True):
        yield todo[j], record


def _chunks(todo: list[int], sweep: Sweep, max_points: int, min_chunks: int = 1) -> tuple[dict, list[list[int]]]:
    """The todo points' cases and their batches (flat indices), as engines.mujoco_batch.plan forms them."""
    from ..engines.mujoco_batch import plan  # start-up time: loads mujoco

    cases = {i: sweep.case(i) for i in todo}
    chunks = plan([cases[i] for i in todo], max_points, min_chunks)
    return cases, [[todo[j] for j in chunk] for chunk in chunks]


def run_local_mujoco(
    todo: list[int],
    sweep: Sweep,
    workers: int,
    check: bool,
    batch_size: int | None,
    preload_xarray: bool = True,
    checks: TimestepChecks | None = None,
) -> Iterator[tuple[int, dict]]:
    """MuJoCo points in mujoco.batch batches on `workers` threads of this process; each point's record is
    yielded (in this thread) as soon as it is known, so a killed sweep loses at most the running batches."""
    from ..engines.mujoco_batch import run_chunks  # start-up time: loads mujoco

    cases, chunks = _chunks(todo, sweep, batch_size or BATCH_POINTS_PER_THREAD * workers)
    checks = TimestepChecks() if checks is None else checks  # the pre-flight's outcomes (sweep.refuse_if_all_refused)
    started, stop = threading.Event(), threading.Event()
    # what the netCDF snapshots and the returned Dataset need (h5netcdf; xarray only if a Dataset is returned:
    # preload_xarray) is loaded while the C threads step, instead of after them; the loading waits until the
    # stepping has started (it needs the GIL, which the pre-flight checks and the preparation of the models need
    # too). It shares the cores with the stepping threads, so only what will be used is loaded
    preload = threading.Thread(
        target=_preload_storage, args=(started, stop, preload_xarray), name="elastoactive-preload", daemon=True
    )
    preload.start()

    def task(chunk, threads, emit, cancel):
        run_points(
            [cases[i] for i in chunk],
            check,
            threads,
            cancel=cancel,
            checks=checks,
            on_start=started.set,
            on_record=lambda j, record: emit((chunk[j], record)),
        )

    try:
        yield from run_chunks(chunks, workers, task, idle=FLUSH)
    finally:
        stop.set()
        started.set()
        preload.join()


FLUSH = object()
"""Yielded by a runner when no record is waiting: the records before it are written out together."""


def _preload_storage(started: threading.Event, stop: threading.Event, dataset: bool = True) -> None:
    started.wait()
    if stop.is_set():
        return
    # (measuring a point, results.measure, needs nothing more: its harmonics no longer load scipy.optimize)
    with contextlib.suppress(Exception):
        # start-up time: loaded in the background, see run_local_mujoco. Snapshots need h5netcdf (and h5py)
        import h5netcdf  # noqa: F401

        package_version()  # reads the package's metadata
    if not dataset or stop.is_set():
        return
    with contextlib.suppress(Exception):
        # the Dataset run_sweep returns needs xarray (and pandas), and the index of a coordinate loads the
        # little of dask (dask.base) xarray asks whether it is a dask array; not dask.array (Store.dataset)
        import xarray

        xarray.Dataset(coords={"p": xarray.Variable(("p",), np.zeros(1), fastpath=True)})  # as Store.dataset


DASK_CONNECT_S = 10.0
"""How long to try to reach a Dask scheduler before giving up (Dask's own default waits 30 s)."""


def connect(scheduler):
    """A dask.distributed.Client of `scheduler` (an address such as 'tcp://host:8786', or a Client, returned as
    it is). An address that cannot be reached within DASK_CONNECT_S is one ParameterError naming it."""
    from dask.distributed import Client  # start-up time: dask (~1 s) loads only for --scheduler

    if isinstance(scheduler, Client):
        return scheduler
    try:
        return Client(scheduler, timeout=DASK_CONNECT_S)
    except (OSError, TimeoutError, ValueError, TypeError) as err:
        reason = str(err).splitlines()[0] if str(err) else type(err).__name__
        raise ParameterError(
            f"cannot reach the Dask scheduler at {scheduler} ({reason}); check the address and "
            "that the scheduler is running"
        ) from None


def run_dask(
    todo: list[int], sweep: Sweep, client, check: bool, batch_size: int | None = None
) -> Iterator[tuple[int, dict]]:
    """Points on a Dask cluster (`client`, from `connect`): MuJoCo points one batch per task (run_points_task,
    on all the threads of the worker that runs it), at least one batch per worker; reduced-engine points one
    per task."""
    from dask.distributed import as_completed as dask_completed  # start-up time: dask loads only for --scheduler

    futures = {}
    try:
        if sweep.engine == "mujoco":
            # a task runs on every thread of its worker, and a worker's tasks take turns: at least one
            # batch per worker, and batches of at most BATCH_POINTS_PER_THREAD points per worker thread
            nthreads = list(client.nthreads().values()) or [1]
            cases, chunks = _chunks(
                todo, sweep, batch_size or BATCH_POINTS_PER_THREAD * max(nthreads), min_chunks=len(nthreads)
            )
            futures = dict(
                zip(
                    client.map(
                        run_points_task,
                        [[cases[i] for i in chunk] for chunk in chunks],
                        [check] * len(chunks),
                        pure=False,
                    ),
                    chunks,
                )
            )
        else:
            futures = dict(
                zip(
                    client.map(run_point, [sweep.case(i) for i in todo], [check] * len(todo), pure=False),
                    [[i] for i in todo],
                )
            )
        for future in dask_completed(futures):
            chunk = futures[future]
            try:
                records = future.result()
                if isinstance(records, dict):
                    records = [records]
            except Exception as err:  # e.g. KilledWorker: the task took its worker down
                records = [{**error_record(err, float("nan")), "finished_at": time.time()} for _ in chunk]
            yield from zip(chunk, records)
    finally:
        if futures:
            client.cancel(list(futures))

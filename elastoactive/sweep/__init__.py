"""Parameter sweeps: any grid of physics parameters (and seed / numerics) of any scene.

    elastoactive sweep one-pinned --grid sigma=0.2:1.0:9 --grid n=5,7 --duration 300 --out s.nc
    ea.sweep(physics, {"sigma": np.linspace(0.2, 1.0, 9)}, duration=300)

The package is the front door's verb too: called, `elastoactive.sweep(physics, grid, ...)` is
elastoactive.sweep.verb.sweep (its signature and documentation), which returns the labelled Dataset the command
writes; its names are the runners that verb and the command are built on.

Each grid point is one `batch.Case`, measured by `results.measure`. The result is an xarray Dataset
whose dimensions are the grid parameters (plus `chain` for the pair), written to netCDF (h5netcdf
engine).

Each finished point is journaled at once and the netCDF rewritten atomically now and then; re-running
the same sweep with the same `out` continues it: the finished points are read from the netCDF and the
journal (the journal wins) and only the others run. Finished means status "ok" or "error" (a diverged
point keeps its error text; `retry_errors=True` runs those again; a point refused before it ran, its error
a ParameterError, is checked again by every re-run). The sweep's specification (scene,
grid with its order, the scene's fixed physics, numerics, engine, duration, transient) is stored in both
files; a different one is refused with the differences listed.

The modules, by concern (this one runs a sweep and holds their public names):

  sweep_grid     what can be swept, parsing the grid, the Sweep and its specification, variable names
  sweep_points   running points: one alone, or MuJoCo points together with the pre-flight checks
  sweep_runners  where points run: local threads (MuJoCo), a local process pool (reduced), Dask
  sweep_store    the results while the sweep runs: arrays, the fsynced journal, Ctrl-C during the save
  sweep_netcdf   the netCDF file: its contents and its atomic, durable write

The engine a sweep runs (mujoco, or the reduced engine's kernels) is imported inside _run_sweep, the
engines' boundary: the command line imports this module to build its parser, and forked pool workers start with
what the sweep loaded before them.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import types
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np

from ..batch import default_workers
from ..core.errors import ParameterError
from ..core.params import Numerics
from ..gate import TimestepChecks
from ..io.outputs import check_file
from ..io.progress import progress_bar
from .grid import (
    DIMENSION_ATTRS,
    FORMAT,
    MUJOCO_ONLY,
    NUMERICS_KEYS,
    VARIABLE_ATTRS,
    VECTORS,
    Sweep,
    SweepMismatch,
    SweepStorageError,
    check_engine_numerics,
    coordinate_attrs,
    grid_keys,
    make_sweep,
    normalize_grid,
    parse_grid,
    parse_values,
    physics_keys,
    scene_variables,
)
from .netcdf import SNAPSHOT_MARGIN
from .points import (
    BATCH_POINTS_PER_THREAD,
    refuse_if_all_refused,
    refused,
    run_point,
    run_points,
    run_points_task,
)
from .runners import FLUSH, connect, run_dask, run_local, run_local_mujoco
from .store import MUST_BE_FINITE, STATUSES, TEXT_VARIABLES, Store, SweepJournalWarning, sigint_deferred

__all__ = [
    "BATCH_POINTS_PER_THREAD",
    "DIMENSION_ATTRS",
    "FLUSH",
    "FORMAT",
    "MUJOCO_ONLY",
    "MUST_BE_FINITE",
    "NUMERICS_KEYS",
    "SNAPSHOT_MARGIN",
    "STATUSES",
    "Sweep",
    "SweepJournalWarning",
    "SweepMismatch",
    "SweepOutcome",
    "SweepStorageError",
    "TEXT_VARIABLES",
    "VARIABLE_ATTRS",
    "VECTORS",
    "check_engine_numerics",
    "coordinate_attrs",
    "grid_keys",
    "make_sweep",
    "normalize_grid",
    "parse_grid",
    "parse_values",
    "physics_keys",
    "run_point",
    "run_points",
    "run_points_task",
    "run_sweep",
    "run_sweep_outcome",
    "scene_variables",
]


def run_sweep(
    scene: str,
    grid: Mapping[str, Sequence],
    *,
    fixed: Mapping | None = None,
    numerics: Numerics | str = "accurate",
    duration: float = 300.0,
    engine: str = "mujoco",
    transient: float | None = None,
    out: str | os.PathLike | None = None,
    workers: int | None = None,
    scheduler=None,
    progress: bool = True,
    retry_errors: bool = False,
    timestep_check: bool = True,
    snapshot_interval: float = 10.0,
    on_point: Callable[[dict, dict], None] | None = None,
    batch_size: int | None = None,
):
    """Run `scene` at every point of `grid` ({name: values}; names from grid_keys()) and return an
    xarray.Dataset (dims: the grid parameters in the given order, plus `chain` for the pair).

    fixed      physics values off the grid (others: Physics defaults)
    numerics   a Numerics or a preset name ('accurate', 'fast'); seed/dt/... may be on the grid
    out        netCDF file written as the sweep goes (see the module docstring); re-running with
               the same arguments resumes, different arguments for an existing file are refused
    workers    local threads (MuJoCo: mujoco.batch's C threads) or processes (reduced engine), >= 1
               (default: every core); ignored when `scheduler` is given
    scheduler  Dask scheduler address ('tcp://host:port') or a dask.distributed.Client
    batch_size most MuJoCo points per mujoco.batch batch (default: 8 per local thread; 8 per Dask task):
               the points of a batch are journaled when it ends, so a kill loses at most the running batches
    on_point   called as on_point(coords, record) in this process after each point is stored
    timestep_check  refuse (record as an error) MuJoCo points whose dt is beyond the linear
               stability limit, as `elastoactive run` does; when it refuses every point (and none of the
               sweep is done), a ParameterError is raised before any runs, naming a dt that passes every point

    Raises ParameterError for invalid arguments (e.g. workers < 1, dt or mass_ratio on the grid of a
    reduced-engine sweep where they change nothing), SweepMismatch when `out` or its journal holds
    another sweep or is corrupted, SweepStorageError when `out` cannot be written (full disk: the
    journal is kept, re-run to resume). A failed point is not an exception: its status is "error".
    """
    return _run_sweep(
        scene,
        grid,
        fixed=fixed,
        numerics=numerics,
        duration=duration,
        engine=engine,
        transient=transient,
        out=out,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
        retry_errors=retry_errors,
        timestep_check=timestep_check,
        snapshot_interval=snapshot_interval,
        on_point=on_point,
        batch_size=batch_size,
    ).dataset()


@dataclasses.dataclass(frozen=True)
class SweepOutcome:
    """What the command line reports of a finished sweep, without building the xarray Dataset (xarray and
    pandas are ~0.4 s of import, and ~600 modules more to tear down at exit): the flat status and error
    texts of every point, and how many are done."""

    status: np.ndarray
    error: np.ndarray
    points_done: int
    points_total: int


def run_sweep_outcome(scene: str, grid: Mapping[str, Sequence], **kwargs) -> SweepOutcome:
    """run_sweep (same arguments), returning a SweepOutcome instead of the Dataset: the same points run,
    the same files are written (the netCDF does not need xarray: outputs.write_netcdf)."""
    store = _run_sweep(scene, grid, dataset=False, **kwargs)
    status = store.arrays["status"].reshape(-1).copy()
    return SweepOutcome(status, store.arrays["error"].reshape(-1).copy(), int(store.done().sum()), store.sweep.size)


def _run_sweep(
    scene: str,
    grid: Mapping[str, Sequence],
    *,
    fixed: Mapping | None = None,
    numerics: Numerics | str = "accurate",
    duration: float = 300.0,
    engine: str = "mujoco",
    transient: float | None = None,
    out: str | os.PathLike | None = None,
    workers: int | None = None,
    scheduler=None,
    progress: bool = True,
    retry_errors: bool = False,
    timestep_check: bool = True,
    snapshot_interval: float = 10.0,
    on_point: Callable[[dict, dict], None] | None = None,
    batch_size: int | None = None,
    dataset: bool = True,
) -> Store:
    """run_sweep's work; returns the closed store. `dataset`: the caller builds the xarray Dataset from it
    (then xarray is loaded in the background while MuJoCo points step)."""
    if workers is not None and (not isinstance(workers, (int, np.integer)) or isinstance(workers, bool) or workers < 1):
        raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
    if batch_size is not None and (
        not isinstance(batch_size, (int, np.integer)) or isinstance(batch_size, bool) or batch_size < 1
    ):
        raise ParameterError(f"batch_size must be an integer >= 1, got {batch_size!r}")
    sweep = make_sweep(
        scene, grid, fixed=fixed, numerics=numerics, duration=duration, engine=engine, transient=transient
    )
    for i in range(sweep.size):  # refuse an invalid point before starting
        sweep.case(i)
    # a file in a writable folder (created if need be), not under a file: one clear line, as for `run --out`
    out_path = None if out is None else check_file(Path(out), "out", ())
    if out_path is not None:
        out_path.parent.mkdir(parents=True, exist_ok=True)
    client = None if scheduler is None else connect(scheduler)
    # import what a point needs here (not at the top: the CLI imports this module for its parser):
    # forked pool workers then start with it loaded (saves ~1 s each)
    from ..engines import timestep as diagnose  # noqa: F401

    if engine == "mujoco":
        from ..engines import mujoco, mujoco_batch  # noqa: F401
    else:
        from ..engines import reduced  # noqa: F401
    store = Store(sweep, out_path)
    fresh = out_path is None or not (out_path.exists() or store.journal_path.exists())  # nothing of it on disk yet
    checks = TimestepChecks()
    try:
        store.open()
        store.check_file_size()  # before any point runs: the limit does not change while this process runs
        status, errors = store.arrays["status"].reshape(-1), store.arrays["error"].reshape(-1)
        # a refused point (nothing simulated) is checked again: its settings' refusal is no result
        todo = [
            i
            for i in range(sweep.size)
            if status[i] == "pending" or (status[i] == "error" and (retry_errors or refused(errors[i])))
        ]
        if todo and timestep_check and engine == "mujoco" and not (status == "ok").any():
            refuse_if_all_refused([sweep.case(i) for i in todo], checks, tuple(sweep.grid))
    except BaseException as err:
        # a sweep refused before any point ran leaves nothing behind (a new journal goes)
        store.close(
            complete=fresh
            and isinstance(err, ParameterError)
            and not isinstance(err, (SweepMismatch, SweepStorageError))
        )
        if client is not None and client is not scheduler:
            client.close()
        raise
    saved = False  # the final netCDF is on disk
    try:
        bar = None
        if progress:  # through io.progress: its observers see the sweep's points too
            bar = progress_bar(sweep.size, f"sweep {scene}", "point")
            if sweep.size > len(todo):  # the points a journal already holds
                bar.update(sweep.size - len(todo))
        if todo:
            local = default_workers() if workers is None else int(workers)
            runner_flushes = scheduler is None and engine == "mujoco"  # yields FLUSH between groups of records
            if scheduler is not None:
                runner = run_dask(todo, sweep, client, timestep_check, batch_size)
            elif engine == "mujoco":
                runner = run_local_mujoco(
                    todo, sweep, local, timestep_check, batch_size, preload_xarray=dataset, checks=checks
                )
            else:
                runner = run_local(todo, sweep, local, timestep_check)
            try:
                written: list[tuple[int, dict]] = []  # journaled, not yet fsync'ed nor reported

                def report() -> None:
                    store.sync()
                    store.snapshot(snapshot_interval)
                    while written:
                        flat, record = written.pop(0)
                        if bar is not None:
                            bar.update()
                            if record["status"] != "ok":
                                bar.set_postfix(failed=int((store.arrays["status"] == "error").sum()))
                        if on_point is not None:
                            on_point(sweep.coords(flat), record)

                for item in runner:
                    if item is FLUSH:  # the records that arrived together (a batch's) share one fsync
                        report()
                        continue
                    flat, record = item
                    written.append((flat, store.record(flat, record, sync=False)))
                    if runner_flushes is False:
                        report()
                report()
            finally:
                runner.close()
                if bar is not None:
                    bar.close()
        elif bar is not None:
            bar.close()
        # the final save: a Ctrl-C now waits until the netCDF is on disk (and the journal, if every
        # point is done, removed), then interrupts; the journal goes only after the netCDF is durable
        with sigint_deferred():
            if todo or store.stale or not (out_path and out_path.exists()):
                store.snapshot(None)
            saved = True
            store.close(complete=bool(store.done().all()))
    except BaseException as err:
        if not saved and not isinstance(err, SweepStorageError):
            with sigint_deferred():
                try:
                    store.snapshot(None)  # keep what is done readable; the journal has it anyway
                except Exception:
                    pass
        raise
    finally:
        store.close(complete=False)  # keeps the journal (a no-op if already closed above)
        if client is not None and client is not scheduler:
            client.close()
    return store


class _Sweep(types.ModuleType):
    """This package, callable: `ea.sweep(...)` runs elastoactive.sweep.verb.sweep, so that the name means one thing, the
    sweep (the package of its runners, and the verb that returns its Dataset)."""

    def __call__(self, *args, **kwargs):
        from .verb import sweep  # the verb's module loads the front door's records (api), once it is called

        return sweep(*args, **kwargs)

    @property
    def __wrapped__(self):
        """The verb, for inspect.signature and editors (`ea.sweep?` shows its parameters)."""
        from .verb import sweep  # as __call__

        return sweep


sys.modules[__name__].__class__ = _Sweep

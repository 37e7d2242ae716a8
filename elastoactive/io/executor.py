"""The package's one maker of process pools: every pool of worker processes is created here.

Reduced-model runs and studies run on processes (their compiled kernels hold the GIL: threads would
not help). Every pool made here behaves the same way:

* Workers are forked where the platform does (Linux): they start with what the parent has loaded.
  `warm`, called in the parent before the pool starts, loads what every task needs once (e.g. the
  reduced model's compiled kernels: ~2 s of loading per process, paid again by every worker of every
  new pool when the parent has not loaded them).
* Workers ignore Ctrl-C (SIGINT goes to the whole foreground process group) and end with the parent,
  even after a kill -9 of it (Linux): the parent alone handles an interrupt. When the block that
  uses the pool ends by an exception (KeyboardInterrupt included) or a generator using it is closed,
  the tasks not started are cancelled and the running workers terminated at once, so an interrupt
  stops promptly, with no KeyboardInterrupt traceback printed by a worker.

multiprocessing and ProcessPoolExecutor are imported where a pool starts (forks, process_pool), the pools' boundary:
they cost ~30 ms, and every command imports this module.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import as_completed
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # typing only: the pools' modules load when a pool starts (every command imports this one)
    from concurrent.futures import Future, ProcessPoolExecutor

__all__ = ["default_workers", "process_pool", "imap"]


def default_workers() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def forks() -> bool:
    """Whether pool workers are forked from the parent (and so inherit what it has loaded)."""
    import multiprocessing  # start-up time: only a pool needs it

    return multiprocessing.get_start_method() == "fork"


@contextlib.contextmanager
def process_pool(
    workers: int, initializer: Callable | None = None, initargs: tuple = (), warm: Callable[[], object] | None = None
) -> Iterator[ProcessPoolExecutor]:
    """A ProcessPoolExecutor of `workers` processes (see the module docstring). `initializer(*initargs)`
    runs in every worker as it starts; `warm()` once in the parent before the workers fork (a failure
    of it only means the workers load what it would have)."""
    from concurrent.futures import ProcessPoolExecutor  # start-up time: only a pool needs it

    if warm is not None and forks():
        with contextlib.suppress(Exception):
            warm()
    pool = ProcessPoolExecutor(
        max_workers=workers, initializer=_worker_start, initargs=(os.getpid(), initializer, initargs)
    )
    try:
        yield pool
    except BaseException:
        _stop(pool)
        raise
    pool.shutdown(wait=True)


def imap(
    fn: Callable,
    items: Iterable,
    workers: int,
    *,
    completed: bool = False,
    errors: bool = False,
    initializer: Callable | None = None,
    initargs: tuple = (),
    warm: Callable[[], object] | None = None,
) -> Iterator[tuple[int, object]]:
    """(index, fn(item)) for every item, computed on a process_pool of `workers` processes: in input order,
    or with `completed=True` as each finishes. `errors=True`: a task's exception is yielded as its result
    (the others go on) instead of raised. Closing the iterator early stops the pool at once."""
    items = list(items)
    with process_pool(min(workers, max(1, len(items))), initializer, initargs, warm) as pool:
        futures = {pool.submit(fn, item): i for i, item in enumerate(items)}
        for future in as_completed(futures) if completed else futures:
            yield futures[future], _outcome(future, errors)


def _outcome(future: Future, errors: bool):
    if not errors:
        return future.result()
    try:
        return future.result()
    except Exception as err:  # noqa: BLE001 (handed to the caller as the task's result)
        return err


def _worker_start(parent: int, initializer: Callable | None, initargs: tuple) -> None:
    """Every worker's start: ignore Ctrl-C (the parent handles it), end with the parent, then the caller's
    initializer."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent(parent)
    if initializer is not None:
        initializer(*initargs)


def _die_with_parent(parent: int) -> None:
    """End this worker when the parent process ends (Linux: PR_SET_PDEATHSIG), even after a kill -9 of it,
    instead of computing what nobody will receive."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(1)


def _stop(pool: ProcessPoolExecutor) -> None:
    """Cancel the tasks not started and terminate the workers now (shutdown alone waits for running tasks)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())  # the executor keeps no public list
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.terminate()
    for process in processes:
        with contextlib.suppress(Exception):
            process.join(timeout=5)

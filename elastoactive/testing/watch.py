"""Run a simulation under a watch: what it said about itself (elastoactive.io.progress's events) and how much CPU it
took before it was refused, stopped, finished or found silent.

The run goes on a thread of its own; the watch measures that thread's CPU time (a loaded machine's waits do not
count against it) and stops the run by raising `Stopped` from the progress observer once it has seen what it waits
for. A run that stays silent past the limit cannot be stopped from outside: its thread is left to end by itself
(daemon) and the outcome says it was silent.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

from ..core.errors import ParameterError
from ..io import progress

WALL_LIMIT_FACTOR = 20.0
"""The wall time a watch waits, as a multiple of its CPU limit (a loaded machine runs a thread far slower)."""
POLL_SECONDS = 0.02


class Stopped(BaseException):
    """Raised by the watch's observer to end a run once it has shown what was asked (a BaseException, so that no
    `except Exception` of the engines takes it for the run's own failure)."""


@dataclass
class Outcome:
    """What a watched run did: `refusal` (its one-line ParameterError), `error` (anything else it raised), `stopped`
    (the watch ended it), `finished` (it returned), or none of these (still silent at the limit); the CPU seconds at
    its first announcement and first progress update (None: never), and at its end."""

    refusal: ParameterError | None = None
    error: BaseException | None = None
    stopped: bool = False
    finished: bool = False
    announced: float | None = None
    updated: float | None = None
    cpu: float = 0.0
    events: list = field(default_factory=list)

    @property
    def silent(self) -> bool:
        return not (self.refusal or self.error or self.stopped or self.finished)


def _thread_cpu(thread: threading.Thread) -> float:
    """CPU seconds the thread has used so far (0 before it runs or after it ended)."""
    try:
        return time.clock_gettime(time.pthread_getcpuclockid(thread.ident))
    except (OSError, TypeError, AttributeError):
        return 0.0


def watched(run: Callable[[], object], limit: float, until: Callable[[Outcome], bool]) -> Outcome:
    """Run `run()` on a thread under a progress observer until `until(outcome)` holds after an event (then the run is
    stopped), the run ends, or it has used `limit` seconds of CPU (WALL_LIMIT_FACTOR x limit of wall time at most)."""
    outcome = Outcome()
    clock = {"thread": None}

    def cpu() -> float:
        return time.thread_time() if clock["thread"] is None else _thread_cpu(clock["thread"])

    def observer(event: progress.Event) -> None:
        if threading.current_thread() is not clock["thread"]:
            return
        now = time.thread_time()
        outcome.events.append(event)
        if event.kind == "announce" and outcome.announced is None:
            outcome.announced = now
        if event.kind == "update" and outcome.updated is None:
            outcome.updated = now
        if until(outcome) or now > limit:
            raise Stopped

    def target() -> None:
        try:
            with progress.observe(observer):
                run()
            outcome.finished = True
        except Stopped:
            outcome.stopped = True
        except ParameterError as err:
            outcome.refusal = err
        except BaseException as err:  # noqa: BLE001  (whatever the run raised is the outcome)
            outcome.error = err
        finally:
            outcome.cpu = time.thread_time()

    thread = threading.Thread(target=target, name="elastoactive-watch", daemon=True)
    clock["thread"] = thread
    start = time.monotonic()
    thread.start()
    while thread.is_alive():
        thread.join(POLL_SECONDS)
        if _thread_cpu(thread) > limit or time.monotonic() - start > WALL_LIMIT_FACTOR * limit:
            return replace(outcome, cpu=max(outcome.cpu, _thread_cpu(thread)), events=list(outcome.events))
    return outcome

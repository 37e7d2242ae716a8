"""Progress on long work: a live bar on a terminal, a line now and then in a log, and one seam that observes both.

tqdm redraws its bar with carriage returns, which fill a log file with hundreds of lines; when
stderr is not a terminal, `progress_bar` writes one plain line every LOG_INTERVAL seconds instead. tqdm is imported
inside progress_bar, where a bar is first shown on a terminal: a run without one does not load it.

Every word a run says about its own progress passes through this module: `announce` (a line before work that takes a
while: its estimated cost) and `progress_bar` (its bar or lines). Observers installed with `observe` see each of
them as an `Event`, whatever stderr is; an observer may raise (a BaseException such as elastoactive.testing's
`Stopped`) to end the run at that point: the conformance kit (elastoactive.testing) holds every engine path to
announcing and showing progress through this seam.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import NamedTuple

LOG_INTERVAL = 10.0  # seconds between lines when stderr is not a terminal
PREFIX = "elastoactive: "
"""What begins every line the package says on stderr about a run (announce)."""


class Event(NamedTuple):
    """What an observer of progress sees: `kind` is "announce" (`text`: the line said), "start" (a bar of `total`
    items named `desc` appears), "update" (`done` of `total` items), or "close"."""

    kind: str
    desc: str = ""
    done: float = 0.0
    total: float = 0.0
    text: str = ""


_OBSERVERS: list[Callable[[Event], None]] = []
_LOCK = threading.Lock()


@contextmanager
def observe(callback: Callable[[Event], None]) -> Iterator[None]:
    """Call `callback(event)` on every announcement and progress update made inside the block (any thread)."""
    with _LOCK:
        _OBSERVERS.append(callback)
    try:
        yield
    finally:
        with _LOCK:
            _OBSERVERS.remove(callback)


def notify(event: Event) -> None:
    """Hand `event` to every observer (what an observer raises propagates: it may stop the run)."""
    if not _OBSERVERS:
        return
    with _LOCK:
        observers = list(_OBSERVERS)
    for callback in observers:
        callback(event)


def announce(text: str, show: bool = True) -> None:
    """Say `text` on stderr as one line beginning PREFIX (when `show`), and tell the observers."""
    if show:
        print(f"{PREFIX}{text}", file=sys.stderr, flush=True)
    notify(Event("announce", text=text))


class LineProgress:
    """The tqdm calls the package uses (update, close), as a line every LOG_INTERVAL seconds."""

    def __init__(self, total: int, desc: str, unit: str):
        self.total, self.desc, self.unit = total, desc, unit
        self.n = 0
        self.start = self.last = time.monotonic()

    def update(self, n: int = 1) -> None:
        self.n += n
        now = time.monotonic()
        if now - self.last >= LOG_INTERVAL:
            self.last = now
            share = f"{100 * self.n / self.total:.0f}% " if self.total else ""
            print(
                f"{self.desc}: {share}({self.n}/{self.total} {self.unit}s, {now - self.start:.0f} s)",
                file=sys.stderr,
                flush=True,
            )

    def set_postfix(self, *args, **kwargs) -> None:
        """tqdm's trailing note: a log line has none."""

    def close(self) -> None:
        """The closing line, only when every item finished: close also runs on an error or Ctrl-C, whose own
        one line says what happened."""
        if self.n >= self.total and time.monotonic() - self.start >= LOG_INTERVAL:
            print(
                f"{self.desc}: done ({self.n} {self.unit}s in {time.monotonic() - self.start:.0f} s)",
                file=sys.stderr,
                flush=True,
            )


class Observed:
    """A bar (tqdm or LineProgress) whose start, updates and close are also handed to the observers."""

    def __init__(self, bar, total: float, desc: str):
        self.bar, self.total, self.desc, self.done = bar, total, desc, 0.0
        notify(Event("start", desc, 0.0, total))

    def update(self, n: float = 1) -> None:
        self.done += n
        self.bar.update(n)
        notify(Event("update", self.desc, self.done, self.total))

    def set_postfix(self, *args, **kwargs) -> None:
        self.bar.set_postfix(*args, **kwargs)

    def close(self) -> None:
        self.bar.close()
        notify(Event("close", self.desc, self.done, self.total))

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def progress_bar(total: int, desc: str, unit: str = "it") -> Observed:
    """A progress bar on stderr (tqdm on a terminal, LineProgress otherwise), seen by the observers."""
    if sys.stderr.isatty():
        from tqdm.auto import tqdm  # start-up time: tqdm loads only when a bar is shown

        bar = tqdm(total=total, desc=desc, unit=unit, mininterval=0.5, file=sys.stderr)
    else:
        bar = LineProgress(total, desc, unit)
    return Observed(bar, total, desc)

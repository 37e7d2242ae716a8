"""Progress on long work: a live bar on a terminal, a line now and then in a log.

tqdm redraws its bar with carriage returns, which fill a log file with hundreds of lines; when
stderr is not a terminal, `progress_bar` writes one plain line every LOG_INTERVAL seconds instead. tqdm is imported
inside progress_bar, where a bar is first shown on a terminal: a run without one does not load it.
"""

from __future__ import annotations

import sys
import time

LOG_INTERVAL = 10.0  # seconds between lines when stderr is not a terminal


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

    def close(self) -> None:
        """The closing line, only when every item finished: close also runs on an error or Ctrl-C, whose own
        one line says what happened."""
        if self.n >= self.total and time.monotonic() - self.start >= LOG_INTERVAL:
            print(
                f"{self.desc}: done ({self.n} {self.unit}s in {time.monotonic() - self.start:.0f} s)",
                file=sys.stderr,
                flush=True,
            )


def progress_bar(total: int, desc: str, unit: str = "it"):
    """A progress bar on stderr (tqdm on a terminal, LineProgress otherwise)."""
    if sys.stderr.isatty():
        from tqdm.auto import tqdm  # start-up time: tqdm loads only when a bar is shown

        return tqdm(total=total, desc=desc, unit=unit, mininterval=0.5, file=sys.stderr)
    return LineProgress(total, desc, unit)

"""A sweep's results while it runs: numpy arrays, the journal, and the netCDF snapshots (sweep_netcdf).

* `<out>.journal` is an append-only JSON-lines file: a header with the sweep's specification,
  then one line per finished point (its flat grid index, coordinates, status, error text,
  measurements, notes, wall time, finish time), flushed and fsync'ed as soon as the point is done.
  Appending one line is O(1) per point and a kill -9 can at worst leave a torn last line, which
  is skipped on reading; nothing already written can be damaged.
* Every journal line is validated when read: status "ok" or "error", index inside the grid,
  coordinates equal to the grid's at that index, the scene's measurements present (for "ok")
  with the right shape (one number per chain for the pair's per-chain values) and finite where
  they always are (NaN is allowed for snap_amplitude and frequency_mismatch, and for
  measurements this module does not know), periodic 1, 0 or NaN, notes a text, wall time a number. A line that
  fails is discarded with a SweepJournalWarning naming the count, and its point runs again. A point's record that
  would fail this check is stored as an error ("invalid result: ..."), so what is written reads back.
* `<out>` (netCDF) is the Dataset: rewritten atomically and durably (temporary file, fsync,
  os.replace, fsync of the directory) at most every `snapshot_interval` seconds while the sweep
  runs, so it can be opened at any time, and once more at the end (also on an error or Ctrl-C).
  When every point is done the journal is deleted, but only after the final netCDF is on disk:
  the netCDF alone is the result. A Ctrl-C during that final save waits until it is done (main
  thread, sigint_deferred), so the journal is never lost. Unfinished points have status "pending".
* Before each snapshot the free space is checked (twice the arrays' size plus 1 MB): if it is
  short, or a write fails (ENOSPC ...), a SweepStorageError names the file and the space needed,
  nothing more is written and the journal stays, so the sweep resumes once space is freed.
* A lock on the journal refuses a second sweep writing the same file. A journal whose header is
  corrupted is refused, naming it: restore it, or remove it to continue from the netCDF alone.

xarray is imported inside _read_netcdf, the netCDF reader's boundary: it loads pandas (about half a second), and the
command line imports this module to build its parser.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import math
import os
import signal
import threading
import time
import warnings
from pathlib import Path

import numpy as np

from ..core import observables, registry
from . import netcdf as sweep_netcdf
from .grid import (
    VECTORS,
    Sweep,
    SweepMismatch,
    SweepStorageError,
    check_spec,
    journal_path,
    scene_variables,
    spec_differences,
    spec_text,
)
from .netcdf import fsync_path, os_reason

STATUSES = ("ok", "error")


TEXT_VARIABLES = ("status", "error", "notes")
"""Variables that hold text per point (the others are numbers, and finished_at a time)."""
"""Status of a finished point; an unfinished one is "pending"."""


MUST_BE_FINITE = ("amplitude", "rotation_rate", "constraint_violation")
"""Measurements that are always finite. The other declared ones (elastoactive.core.observables: frequency,
snap_amplitude, frequency_mismatch, ...) are NaN when they cannot be measured, never infinite; measurements nothing
declares may be any number."""


def _per_chain(name: str) -> bool:
    """Whether a declared observable has one value per chain (Observable.per_chain; False for any other name)."""
    spec = observables.find(name)
    return spec is not None and spec.per_chain


class SweepJournalWarning(UserWarning):
    """Lines of the journal failed validation and were discarded: their points run again."""


class Store:
    """The sweep's results as numpy arrays, the journal and the netCDF snapshots."""

    def __init__(self, sweep: Sweep, out: Path | None):
        self.sweep, self.out = sweep, out
        self.spec = sweep.spec()
        shape = sweep.shape
        self.chains = sweep.chains
        self.required = ("amplitude", "frequency") + (
            ("constraint_violation",) if registry.get(sweep.scene).pinned else ()
        )
        self.arrays: dict[str, np.ndarray] = {}
        for name in scene_variables(sweep.scene):
            self._allocate(name, per_chain=self.chains > 1 and _per_chain(name))
        self.arrays["wall_time_s"] = np.full(shape, np.nan)
        self.arrays["finished_at"] = np.full(shape, np.datetime64("NaT"), dtype="datetime64[ns]")
        self.arrays["status"] = np.full(shape, "pending", dtype=object)
        self.arrays["error"] = np.full(shape, "", dtype=object)
        self.arrays["notes"] = np.full(shape, "", dtype=object)
        self.journal = None
        self.unsynced = False  # journal lines written but not yet fsync'ed (record(sync=False))
        self.stale = False  # the netCDF may lack points the journal holds: rewrite it even if nothing runs
        self.last_snapshot = time.monotonic()

    def _allocate(self, name: str, per_chain: bool) -> None:
        vector = (VECTORS[name][1],) if name in VECTORS else ()
        shape = self.sweep.shape + ((self.chains,) if per_chain else ()) + vector
        self.arrays[name] = np.full(shape, np.nan)

    @property
    def journal_path(self) -> Path:
        return journal_path(self.out)

    # -- reading
    def open(self) -> None:
        """Lock the journal, then read what the netCDF and the journal hold."""
        if self.out is None:
            return
        if self.out.exists():
            self._read_netcdf()
        path = self.journal_path
        try:
            # errors="replace": a damaged byte makes its line fail validation instead of the whole read
            self.journal = open(path, "a+", encoding="utf-8", errors="replace")
        except OSError as err:
            raise SweepStorageError(f"cannot write the journal {path}: {os_reason(err)}") from None
        try:
            # a POSIX record lock: unlike flock, not inherited by the forked pool workers, so
            # workers orphaned by a kill -9 of this process do not block the resume
            fcntl.lockf(self.journal, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self.journal.close()
            self.journal = None
            raise SweepMismatch(f"another sweep is writing {self.out} (its journal {path.name} is locked)") from None
        try:
            self._read_journal()
        except BaseException:
            self.close(complete=False)
            raise

    def _read_journal(self) -> None:
        path = self.journal_path
        self.journal.seek(0)
        text = self.journal.read()
        lines = text.split("\n")
        if lines and lines[-1] == "":
            lines.pop()
        if len(lines) == 1 and not text.endswith("\n") and _header(lines[0]) is None:
            lines = []  # a header torn by a kill as the sweep started: nothing was recorded yet
            self.journal.truncate(0)
        if not lines:
            self._append(json.dumps({"sweep_spec": self.spec}) + "\n")
            self._sync()
            return
        self.stale = True
        header = _header(lines[0])
        if header is None:
            raise SweepMismatch(
                f"the journal {path} is corrupted (its first line is not a sweep header), so the points recorded "
                f"in it cannot be trusted. To proceed, restore {path.name} from a backup and re-run, or remove it "
                f"to continue from {self.out.name if self.out.exists() else 'scratch'} (the points recorded only "
                "in the journal then run again)."
            )
        if spec_text(self.spec) != spec_text(header):
            diff = "; ".join(spec_differences(self.spec, header)) or "format"
            raise SweepMismatch(
                f"the journal {path} holds a different sweep ({diff}). To resume it, repeat its exact grid and "
                f"parameters; to start a new sweep, choose another --out or remove {path.name} (and {self.out.name} "
                "if present)."
            )
        discarded: list[str] = []
        for line in lines[1:]:
            if not line.strip():
                continue  # the newline added after a torn line
            try:
                entry = json.loads(line)
            except ValueError:
                discarded.append("not valid JSON (e.g. torn by a kill)")
                continue
            problem = self.problem(entry)
            if problem is None:
                self.set(entry["i"], entry)
                continue
            discarded.append(problem)
            i = entry.get("i") if isinstance(entry, dict) else None
            if _is_int(i) and 0 <= i < self.sweep.size:
                self.reset(i)  # its newest record is unusable: run the point again
        if discarded:
            warnings.warn(
                f"{path.name}: discarded {len(discarded)} journal line(s) that failed validation "
                f"(first: {discarded[0]}); the grid points they name run again",
                SweepJournalWarning,
                stacklevel=4,
            )
        if not text.endswith("\n"):
            self._append("\n")
            self._sync()

    def _read_netcdf(self) -> None:
        import xarray as xr  # start-up time: the CLI imports this module for its parser

        try:
            with xr.open_dataset(self.out, engine="h5netcdf") as ds:
                ds = ds.load()
        except Exception as err:
            raise SweepMismatch(
                f"{self.out} exists but cannot be read as netCDF ({err}); refusing to overwrite it. "
                "Choose another --out or remove the file."
            ) from None
        spec = ds.attrs.get("sweep_spec")
        try:
            spec = json.loads(spec) if isinstance(spec, str) else None
        except ValueError:
            spec = None
        check_spec(self.out, self.spec, spec)
        dims = tuple(self.sweep.grid)
        for name, var in ds.data_vars.items():
            if var.dims[: len(dims)] != dims:
                continue
            if name not in self.arrays:
                self._allocate(name, per_chain="chain" in var.dims)
            values = var.values
            if name == "finished_at":
                values = values.astype("datetime64[ns]")
            elif name in TEXT_VARIABLES:
                values = np.where(values == None, "", values).astype(object)  # noqa: E711
            self.arrays[name][...] = values
        status = self.arrays["status"]
        for flat in np.flatnonzero(~np.isin(status.reshape(-1), STATUSES)):
            self.reset(int(flat))  # "pending", or anything else: not finished

    def problem(self, entry) -> str | None:
        """Why a journal line (parsed) cannot be trusted, or None if it is a valid record of its point."""
        if not isinstance(entry, dict):
            return "not a JSON object"
        i = entry.get("i")
        if not _is_int(i):
            return f"index i={i!r} is not an integer"
        if not 0 <= i < self.sweep.size:
            return f"index i={i} outside the grid (0 to {self.sweep.size - 1})"
        coords, expected = entry.get("coords"), self.sweep.coords(i)
        if not (
            isinstance(coords, dict)
            and set(coords) == set(expected)
            and all(_is_number(coords[k]) and coords[k] == v for k, v in expected.items())
        ):
            return f"point {i}: coordinates {coords!r} do not match the grid's {expected}"
        status = entry.get("status")
        if status not in STATUSES:
            return f"point {i}: status {status!r} is not one of {', '.join(STATUSES)}"
        if not isinstance(entry.get("error", ""), str):
            return f"point {i}: error is not a text"
        if not isinstance(entry.get("notes", ""), str):
            return f"point {i}: notes is not a text"
        wall = entry.get("wall_time_s")
        if not _is_number(wall) or math.isinf(wall) or wall < 0:  # NaN: unknown (a worker lost on Dask)
            return f"point {i}: wall_time_s {wall!r} is not a number >= 0"
        finished = entry.get("finished_at")
        if not _is_number(finished) or not 0 <= finished < 9e9:  # datetime64[ns] ends in 2262
            return f"point {i}: finished_at {finished!r} is not a time"
        results = entry.get("results")
        if not isinstance(results, dict):
            return f"point {i}: results is not an object"
        if status == "ok":
            missing = [k for k in self.required if k not in results]
            if missing:
                return f"point {i}: results lack {', '.join(missing)}"
        for name, value in results.items():
            problem = self._value_problem(name, value)
            if problem:
                return f"point {i}: {name} {problem}"
        return None

    def _value_problem(self, name: str, value) -> str | None:
        if name in (*TEXT_VARIABLES, "finished_at", "wall_time_s"):
            return "is not a measurement"
        if name in VECTORS:
            return self._vector_problem(name, value)
        if name in self.arrays:
            per_chain = self.arrays[name].ndim > len(self.sweep.shape)
        elif observables.known(name):
            per_chain = self.chains > 1 and _per_chain(name)
        else:  # a measurement this module does not know: either shape, but one value per chain
            per_chain = self.chains > 1 and isinstance(value, list)
        if per_chain:
            if not (isinstance(value, list) and len(value) == self.chains):
                return f"= {value!r} is not a list of {self.chains} numbers (one per chain)"
            values = value
        else:
            if isinstance(value, list):
                return f"= {value!r} is a list where one number is expected"
            values = [value]
        for v in values:
            if not _is_number(v):
                return f"= {value!r} is not a number"
            if name in MUST_BE_FINITE and not math.isfinite(v):
                return f"= {value!r} is not finite"
            if (observables.known(name) or name in MUST_BE_FINITE) and math.isinf(v):
                return f"= {value!r} is infinite"
            if name == "periodic" and not (math.isnan(v) or v in (0, 1)):
                return f"= {value!r} is not 1, 0 or NaN"
        return None

    def _vector_problem(self, name: str, value) -> str | None:
        """A VECTORS measurement: a list of its size (one per chain for the pair), numbers or NaN."""
        size = VECTORS[name][1]
        per_chain = self.chains > 1 and _per_chain(name)
        rows = value if per_chain and isinstance(value, list) else [value]
        if per_chain and len(rows) != self.chains:
            return f"= {value!r} is not a list of {self.chains} lists (one per chain)"
        for row in rows:
            if not (isinstance(row, list) and len(row) == size):
                return f"= {value!r} is not a list of {size} numbers" + (" per chain" if per_chain else "")
            for v in row:
                if not _is_number(v):
                    return f"= {value!r} is not a list of numbers"
                if math.isinf(v):
                    return f"= {value!r} is infinite"
        return None

    # -- writing
    def reset(self, flat: int) -> None:
        """Mark a point as not run (pending), with no measurements."""
        index = np.unravel_index(flat, self.sweep.shape)
        for name, values in self.arrays.items():
            if name not in (*TEXT_VARIABLES, "finished_at"):
                values[index] = np.nan
        self.arrays["status"][index] = "pending"
        self.arrays["error"][index] = ""
        self.arrays["notes"][index] = ""
        self.arrays["finished_at"][index] = np.datetime64("NaT")

    def set(self, flat: int, entry: dict) -> None:
        """Store a record (validated: see `problem`)."""
        self.reset(flat)
        index = np.unravel_index(flat, self.sweep.shape)
        for name, value in entry.get("results", {}).items():
            if name not in self.arrays:
                per_chain = _per_chain(name) if name in VECTORS else isinstance(value, list)
                self._allocate(name, per_chain=self.chains > 1 and per_chain)
            self.arrays[name][index] = value
        self.arrays["status"][index] = entry["status"]
        self.arrays["error"][index] = entry.get("error", "")
        self.arrays["notes"][index] = entry.get("notes", "")
        self.arrays["wall_time_s"][index] = entry["wall_time_s"]
        self.arrays["finished_at"][index] = np.datetime64(int(round(entry["finished_at"] * 1e9)), "ns")

    def record(self, flat: int, entry: dict, sync: bool = True) -> dict:
        """Store a finished point and append it to the journal (fsync'ed, or with sync=False left for
        `sync`); returns the record stored. A record that would not pass the journal's validation is
        stored as an error instead, so that everything written can be read back."""
        line = {"i": flat, "coords": self.sweep.coords(flat), **entry}
        problem = self.problem(line)
        if problem is not None:
            entry = {
                "status": "error",
                "error": f"invalid result: {problem}",
                "results": {},
                "notes": "",
                "wall_time_s": _number_or_nan(entry.get("wall_time_s")),
                "finished_at": _number_or_nan(entry.get("finished_at"), time.time()),
            }
            line = {"i": flat, "coords": self.sweep.coords(flat), **entry}
        self.set(flat, entry)
        if self.journal is not None:
            self._append(json.dumps(line) + "\n")
            self.unsynced = True
            if sync:
                self.sync()
        return entry

    def sync(self) -> None:
        """Flush and fsync the journal lines written since the last time."""
        if self.journal is None or not self.unsynced:
            return
        self._sync()
        self.unsynced = False

    def _journal_error(self, err: OSError) -> SweepStorageError:
        return SweepStorageError(
            f"cannot append to the journal {self.journal_path}: {os_reason(err)}. The points recorded "
            "before are kept in it: fix this (e.g. free some space) and re-run the same sweep to resume."
        )

    def _append(self, text: str) -> None:
        """Write `text` to the journal (buffered until `_sync`); every write to it goes through here or `_sync`, and a
        failure is a SweepStorageError naming the journal."""
        try:
            self.journal.write(text)
        except OSError as err:
            raise self._journal_error(err) from err

    def _sync(self) -> None:
        """Flush and fsync the journal; a failure is a SweepStorageError naming it."""
        try:
            self.journal.flush()
            os.fsync(self.journal.fileno())
        except OSError as err:
            raise self._journal_error(err) from err

    def bytes_needed(self) -> int:
        """Free space asked for before writing a snapshot: twice the arrays' size, plus a margin."""
        return sweep_netcdf.bytes_needed(self.sweep.grid, self.arrays)

    def check_file_size(self) -> None:
        """Refuse a sweep whose netCDF this process may not write (the file-size limit, sweep_netcdf)."""
        if self.out is not None:
            sweep_netcdf.check_file_size(self.out, self.bytes_needed(), self._kept())

    def snapshot(self, interval: float | None) -> None:
        """Rewrite the netCDF (sweep_netcdf.write: atomically and durably, refused before h5py is called when
        the space is short) if `interval` seconds passed since the last time (None: now)."""
        if self.out is None or (interval is not None and time.monotonic() - self.last_snapshot < interval):
            return
        sweep_netcdf.write(self.out, self.contents, self.bytes_needed(), self._kept())
        self.last_snapshot = time.monotonic()

    def _kept(self) -> str:
        return (
            f"the journal {self.journal_path} keeps every finished point: free some space (or fix the cause) "
            "and re-run the same sweep to resume"
        )

    def close(self, complete: bool) -> None:
        """Release the journal; `complete`: remove it (only once the final netCDF is on disk)."""
        if self.journal is None:
            return
        if not complete:
            with contextlib.suppress(OSError, SweepStorageError):
                self.sync()
        if complete:
            self.journal_path.unlink(missing_ok=True)
            with contextlib.suppress(OSError):
                fsync_path(self.out.parent)
        # releases the lock; lines a failed sync left in the buffer fail again here, and were reported by then
        with contextlib.suppress(OSError):
            self.journal.close()
        self.journal = None

    # -- the Dataset
    def done(self) -> np.ndarray:
        return np.isin(self.arrays["status"], STATUSES)

    def dataset(self):
        """The sweep as an xarray.Dataset (what the netCDF file holds)."""
        return sweep_netcdf.dataset(self.contents())

    def contents(self) -> tuple[dict, dict, dict]:
        """(data variables, coordinates, attributes) of the Dataset (sweep_netcdf.contents)."""
        return sweep_netcdf.contents(self.sweep, self.arrays, self.spec, self.done())


def _header(line: str) -> dict | None:
    """The sweep specification in a journal's first line, or None if it is not a sweep header."""
    try:
        spec = json.loads(line)["sweep_spec"]
    except (ValueError, KeyError, TypeError, IndexError):
        return None
    return spec if isinstance(spec, dict) else None


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _number_or_nan(value, default: float = float("nan")) -> float:
    return float(value) if _is_number(value) and math.isfinite(value) else default


@contextlib.contextmanager
def sigint_deferred():
    """Hold a Ctrl-C (SIGINT) back until the block is done, then deliver it (KeyboardInterrupt by
    default). Only in the main thread (the only one Python delivers signals to), and only if SIGINT is
    handled from Python; elsewhere the block runs unprotected."""
    previous = signal.getsignal(signal.SIGINT) if threading.current_thread() is threading.main_thread() else None
    if previous is None or previous is signal.SIG_IGN:
        yield
        return
    caught = []
    signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        if caught:
            signal.raise_signal(signal.SIGINT)  # to the restored handler

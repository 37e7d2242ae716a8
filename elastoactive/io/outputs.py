"""Writing what a user computed: destinations checked before the work, files written atomically, and
a record of what made them (provenance).

Every writer in the package goes through here:
- `check_folder` / `check_file` run before a simulation, so that a run is never lost to a bad --out;
- `atomic_file` writes into a temporary file beside the target, fsyncs it and renames it into place,
  so a target is either the old file or the complete new one, never a torn one;
- `write_files` writes a set of files that belong together (a run's summary and trajectory) the
  same way, the trajectory before the summary that names its checksum;
- `provenance` records versions, command line, start time and wall time;
- `InputFile` records a file a run read (its absolute path, its SHA-256, the name of the run folder's copy) and finds
  the bytes the run read again (`InputFile.locate`).

Files are created with the permissions the user's umask gives (0666 & ~umask), as `open` would, not the
0600 of a bare temporary file. A write that fails (a full disk, a file-size limit) raises an OSError
naming the target file, which the command line reports in one line.

h5netcdf and h5py are imported inside write_netcdf, the netCDF writer's boundary: h5py costs a large part of a second,
and every command imports this module for its checks.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as _dt
import errno as _errno
import fcntl
import hashlib
import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

from ..core.errors import ParameterError

PACKAGES = ("elastoactive", "mujoco", "numpy", "scipy", "numba")
"""Whose versions a provenance record names (plus Python and the platform)."""


def utc_now() -> str:
    return _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")


def _version(name: str) -> str | None:
    try:
        return version(name)
    except PackageNotFoundError:
        return None


PACKAGE_ROOT = Path(__file__).resolve().parents[2]
"""The folder holding the elastoactive package (this module is elastoactive/io/outputs.py): a checkout's root."""


def git_commit(root: Path | None = None) -> str | None:
    """The checkout's commit (with '+dirty' if it has uncommitted changes), when run from a git checkout (default:
    the package's own)."""
    root = PACKAGE_ROOT if root is None else Path(root)
    if not (root / ".git").exists():
        return None
    try:
        head = subprocess.run(
            ["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True, text=True, timeout=5, check=True
        ).stdout.strip()
        # --no-optional-locks: reading the state must not write the index (a full disk or a file-size limit would
        # leave .git/index.lock behind, and a concurrent git command in the checkout would find it locked)
        dirty = subprocess.run(
            ["git", "-C", str(root), "--no-optional-locks", "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            timeout=5,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return head + ("+dirty" if dirty else "")


def provenance(started: str | None = None, wall_time_s: float | None = None, command: list[str] | None = None) -> dict:
    """What made an output: versions, git commit, platform, command line, UTC start time, wall time."""
    return {
        "versions": {**{name: _version(name) for name in PACKAGES}, "python": platform.python_version()},
        "git_commit": git_commit(),
        "platform": platform.platform(),
        "command": list(sys.argv if command is None else command),
        "started_utc": started or utc_now(),
        "wall_time_s": wall_time_s,
    }


# ------------------------------------------------------------------------------------------------ checks


def _writable_ancestor(path: Path, option: str, start: Path | None = None) -> Path:
    """The nearest existing ancestor of `start` (default: path); refuses when it is not a folder we can write in."""
    ancestor = path if start is None else start
    while not ancestor.exists():
        if ancestor.parent == ancestor:
            break
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise ParameterError(f"{option} {path}: {ancestor} is a file, not a folder")
    try:  # a real probe: os.access says yes to root on a read-only file system
        fd, probe = tempfile.mkstemp(prefix=".elastoactive-probe-", dir=ancestor)
        os.close(fd)
        os.unlink(probe)
    except OSError as err:
        raise ParameterError(f"{option} {path}: cannot write in {ancestor} ({err.strerror or err})") from None
    return ancestor


def output_path(text: str) -> Path:
    """An output path as typed on the command line (an argparse `type`): an empty one is refused, naming the option
    (Path('') would be the working folder, where the outputs would land unasked)."""
    if not text.strip():
        raise argparse.ArgumentTypeError(f"an empty path ({text!r}); give a folder or file name (. for this folder)")
    return Path(text)


def check_folder(path: Path, option: str = "--out") -> Path:
    """A folder we will write into: it may not exist yet, but must not be a file, and its nearest
    existing ancestor must be writable."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ParameterError(f"{option} {path} is a file; give a folder")
    _writable_ancestor(path, option, path if path.exists() else path.parent)
    return path


def check_file(path: Path, option: str, suffixes: tuple[str, ...], *, force: bool = True) -> Path:
    """A file we will write: the right suffix, not a folder, in a writable place; with force=False, not an
    existing file (replacing one takes --force)."""
    path = Path(path)
    if suffixes and path.suffix.lower() not in suffixes:
        raise ParameterError(f"{option} {path}: the file name must end in {' or '.join(suffixes)}")
    if path.is_dir():
        raise ParameterError(f"{option} {path} is a folder; give a file name")
    if not force and path.exists():
        raise ParameterError(f"{option} {path} exists already; choose another name, or pass --force to replace it")
    if path.exists() and not os.access(path, os.W_OK):
        raise ParameterError(f"{option} {path}: cannot overwrite it (permission denied)")
    _writable_ancestor(path, option, path.parent)
    return path


def file_size_limit() -> int | None:
    """The largest file this process may write, in bytes (RLIMIT_FSIZE: `ulimit -f`), or None if unlimited."""
    soft, _ = resource.getrlimit(resource.RLIMIT_FSIZE)
    return None if soft == resource.RLIM_INFINITY else int(soft)


def check_space(folder: Path, needed: int, what: str, option: str = "--out", advice: str = "") -> None:
    """Refuse (ParameterError naming `option`), before the work that makes it, a file `what` of about `needed`
    bytes that this process could not write into `folder`: above the file-size limit (ulimit -f), or more than the
    free space there. `advice` ends the line (how to need less)."""
    folder = Path(folder)
    limit = file_size_limit()
    size = f"{needed / 1e6:.2g} MB" if needed >= 1e5 else f"{needed} bytes"
    if limit is not None and limit < needed:
        raise ParameterError(
            f"{option} {folder}: {what} takes about {size}, and this process may not write files over "
            f"{limit} bytes (the file-size limit, ulimit -f); raise the limit{advice}"
        )
    existing = folder
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    try:
        free = shutil.disk_usage(existing).free
    except OSError:
        return
    if free < needed:
        raise ParameterError(
            f"{option} {folder}: {what} takes about {size} and only {free / 1e6:.2g} MB are free "
            f"there; free some space or choose another folder{advice}"
        )


@contextlib.contextmanager
def folder_lock(folder: Path, option: str = "--out") -> Iterator[Path]:
    """Hold an exclusive lock on `folder` (created if need be) for the duration of the block: a second writer
    into the same folder is refused at once (ParameterError naming `option`) instead of replacing the first
    one's files. The check that a folder may be written and the writing itself go inside one such block. A
    folder this call created is removed again if the block fails before anything was written into it."""
    folder = Path(folder)
    created = not folder.exists()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd = os.open(folder, os.O_RDONLY)
    except OSError as err:
        raise ParameterError(f"{option} {folder}: cannot create or open it ({err.strerror or err})") from None
    try:
        try:  # flock on the folder itself: nothing is left behind, and the lock goes with the process
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            if err.errno in (_errno.EWOULDBLOCK, _errno.EAGAIN, _errno.EACCES):
                raise ParameterError(
                    f"{option} {folder}: another run is writing into it right now; wait for it to "
                    "finish or choose another folder"
                ) from None
            raise
        try:
            yield folder
        except BaseException:
            if created:
                with contextlib.suppress(OSError):
                    folder.rmdir()  # only if still empty
            raise
    finally:
        os.close(fd)  # releases the lock


@contextlib.contextmanager
def lock_file(path: Path, what: str, option: str = "--out") -> Iterator[Path]:
    """Hold an exclusive lock on the file `path` (created if need be; removed when the block ends) while `what`
    writes: a second one is refused at once (ParameterError naming `option`, the holder's pid and start). The lock is
    a POSIX record lock (fcntl.lockf): the system drops it when its process ends, however it ends, and forked workers
    do not inherit it, so a file left by a killed run is stale and simply taken over, never waited for."""
    path = Path(path)
    while True:
        try:
            handle = open(path, "a+", encoding="utf-8")
        except OSError as err:
            raise ParameterError(
                f"{option} {path.parent}: cannot create the lock file {path.name} ({err.strerror or err})"
            ) from None
        try:
            fcntl.lockf(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            handle.seek(0)
            holder = handle.read().strip() or "unknown"
            handle.close()
            if err.errno in (_errno.EACCES, _errno.EAGAIN):
                raise ParameterError(
                    f"{option} {path.parent}: another {what} is writing into it right now ({holder}); "
                    f"wait for it to finish or choose another folder"
                ) from None
            raise
        try:  # the holder before us may have removed the file between our open and our lock: lock the one there now
            same = os.path.samestat(os.fstat(handle.fileno()), os.stat(path))
        except FileNotFoundError:
            same = False
        if same:
            break
        handle.close()
    try:
        try:
            handle.seek(0)
            handle.truncate()
            handle.write(f"pid {os.getpid()} on {platform.node()}, started {utc_now()}\n")
            handle.flush()
        except OSError as err:
            raise _naming(err, path) from None
        yield path
    finally:
        with contextlib.suppress(OSError):
            path.unlink()  # while still locked: the next one opens a new file
        with contextlib.suppress(OSError):  # a line a full disk kept in the buffer fails again, named above
            handle.close()


# ------------------------------------------------------------------------------------------------ writing


def _umask() -> int:
    """The process's umask (read without changing it where /proc says it)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _new_file_mode(path: Path) -> None:
    """Give a temporary file (mkstemp: 0600) the mode a newly created file gets: 0666 & ~umask."""
    os.chmod(path, 0o666 & ~_umask())


def _naming(err: OSError, target: Path) -> OSError:
    """err as an OSError that names the file being written (a failed write() names none)."""
    return OSError(err.errno, f"cannot write it ({err.strerror or err})", str(target))


def _fsync_dir(folder: Path) -> None:
    with contextlib.suppress(OSError):  # not every file system lets a folder be fsync'ed
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


@contextlib.contextmanager
def atomic_file(path: Path) -> Iterator[Path]:
    """Yield a temporary path beside `path` (same suffix) to write to; on success it is fsynced and
    renamed onto `path`, on failure removed. The target is never seen half-written."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
    except OSError as err:
        raise _naming(err, path) from None
    os.close(fd)
    tmp = Path(tmp)
    try:
        try:
            yield tmp
            _new_file_mode(tmp)
            with open(tmp, "rb+") as f:
                os.fsync(f.fileno())
            os.replace(tmp, path)
        except OSError as err:
            raise _naming(err, path) from None
        _fsync_dir(path.parent)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()


def write_text(path: Path, text: str) -> Path:
    with atomic_file(path) as tmp:
        tmp.write_text(text)
    return Path(path)


def write_files(folder: Path, writers: dict[str, Callable[[Path], None]]) -> list[Path]:
    """Write several files of one output into `folder`: each writer(tmp_path) fills its temporary
    file; only when all succeeded are they renamed into place, in the order given (put the file that
    names the others' checksums last)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    temporaries: list[tuple[Path, Path]] = []
    try:
        for name, writer in writers.items():
            try:
                fd, tmp = tempfile.mkstemp(prefix=f".{Path(name).stem}.", suffix=Path(name).suffix, dir=folder)
                os.close(fd)
                temporaries.append((Path(tmp), folder / name))
                writer(Path(tmp))
                _new_file_mode(Path(tmp))
                with open(tmp, "rb+") as f:
                    os.fsync(f.fileno())
            except OSError as err:
                raise _naming(err, folder / name) from None
        for tmp, target in temporaries:
            try:
                os.replace(tmp, target)
            except OSError as err:
                raise _naming(err, target) from None
        _fsync_dir(folder)
    finally:
        for tmp, _ in temporaries:
            with contextlib.suppress(FileNotFoundError):
                tmp.unlink()
    return [target for _, target in temporaries]


def sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _sha256_or_none(path: Path) -> str | None:
    """The file's SHA-256, or None when it is not a readable file."""
    try:
        return sha256(path) if path.is_file() else None
    except OSError:
        return None


@dataclass(frozen=True)
class InputFile:
    """A file a run read: `path`, absolute and resolved, where it was; `sha256`, the digest of the bytes read; `copy`,
    the name of the file in the run's folder that holds those same bytes (None: not copied)."""

    path: str
    sha256: str
    copy: str | None = None

    @classmethod
    def of(cls, path: str | os.PathLike, copy: str | None = None) -> tuple[InputFile, bytes]:
        """The record of the file at `path` as it is now, and its bytes (what a copy holds)."""
        path = Path(path).expanduser().resolve()
        data = path.read_bytes()
        return cls(str(path), hashlib.sha256(data).hexdigest(), copy), data

    def locate(self, folder: Path, what: str) -> tuple[Path | None, str | None]:
        """Where the bytes the run read are now, and a note when that is not the original: the original path when it
        still holds them; else the copy in the run's `folder` (when it does), with a note naming the change; else
        None, with a note saying neither holds them. `what` names the file in the notes ("network file")."""
        original = Path(self.path)
        now = _sha256_or_none(original)
        if now == self.sha256:
            return original, None
        change = "is gone" if now is None else f"changed since the run (sha256 {self.sha256[:12]} then, {now[:12]} now)"
        copy = Path(folder) / self.copy if self.copy else None
        if copy is not None and _sha256_or_none(copy) == self.sha256:
            return copy.resolve(), f"{what} {self.path} {change}; using the run's copy {self.copy}"
        kept = f"the run's copy {self.copy} is missing or changed too" if self.copy else "the run kept no copy"
        return None, f"{what} {self.path} {change}, and {kept}"


def provenance_line(record: dict, sidecar: str = "provenance.json") -> str:
    """One line naming what made an output (elastoactive.io.outputs.provenance)."""
    versions = ", ".join(f"{k} {v}" for k, v in record.get("versions", {}).items() if v)
    commit = f", git {record['git_commit']}" if record.get("git_commit") else ""
    return (
        f"Made by `{' '.join(record.get('command', []))}` on {record.get('platform')} at {record.get('started_utc')} "
        f"UTC ({versions}{commit}); also in {sidecar}."
    )


# ------------------------------------------------------------------------------------------------ netCDF

NETCDF_TIME_UNITS = "nanoseconds since 1970-01-01"


def write_netcdf(path: Path, variables: dict, coords: dict, attrs: dict) -> None:
    """Write a netCDF-4 file of plain arrays with h5netcdf, encoded as xarray's CF encoder encodes them, so that
    `xarray.open_dataset(path)` gives back the Dataset of these variables (values, dims, attributes), without
    loading xarray: its writer costs ~0.6 s of CPU at start-up (dask.array, distributed, scipy). `variables` and
    `coords` map a name to (dims, array, attrs); a coordinate's dims are its own name. Arrays may be float
    (missing: NaN, stored with _FillValue NaN), integer, text (object arrays of str: variable-length strings) or
    datetime64[ns] (int64 nanoseconds since 1970-01-01, NaT as int64's minimum, as xarray writes it)."""
    import h5netcdf  # start-up time: h5py, only when a file is written
    import h5py

    with h5netcdf.File(path, "w") as f:
        f.dimensions = {name: np.asarray(values).shape[0] for name, (dims, values, _) in coords.items()}
        for name, (dims, values, var_attrs) in {**coords, **variables}.items():
            values = np.asarray(values)
            extra: dict = {}
            kwargs: dict = {}
            if values.dtype.kind == "M":
                extra = {"units": NETCDF_TIME_UNITS, "calendar": "proleptic_gregorian"}
                values = values.astype("datetime64[ns]").view(np.int64)
            elif values.dtype.kind == "O" or values.dtype.kind == "U":
                kwargs["dtype"] = h5py.string_dtype()  # variable-length UTF-8, as xarray writes text
                values = np.array([str(v) for v in values.reshape(-1)], dtype=object).reshape(values.shape)
            elif values.dtype.kind == "f":
                kwargs["fillvalue"] = np.nan
            var = f.create_variable(name, tuple(dims), data=values, **kwargs)
            for key, value in {**var_attrs, **extra}.items():
                var.attrs[key] = _attribute(value)
        for key, value in attrs.items():
            f.attrs[key] = _attribute(value)


def _attribute(value):
    """An attribute value as h5py stores it like xarray: subclasses of str, int and float (e.g. Numerics'
    marked defaults) as the plain type."""
    for kind in (str, bool, int, float):
        if isinstance(value, kind) and type(value) is not kind:
            return kind(value) if kind is not str else str.__str__(value)
    return value

"""Writing what a user computed: destinations checked before the work, files written atomically, and
a record of what made them (provenance).

Every writer in the package goes through here:
- `check_folder` / `check_file` run before a simulation, so that a run is never lost to a bad --out;
- `atomic_file` writes into a temporary file beside the target, fsyncs it and renames it into place,
  so a target is either the old file or the complete new one, never a torn one;
- `write_files` writes a set of files that belong together (a run's summary and trajectory) the
  same way, the trajectory before the summary that names its checksum;
- `provenance` records versions, command line, start time and wall time.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import hashlib
import os
import platform
import subprocess
import sys
import tempfile
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Callable, Iterator

import numpy as np

from .errors import ParameterError

PACKAGES = ("elastoactive", "mujoco", "numpy", "scipy", "numba")
"""Whose versions a provenance record names (plus Python and the platform)."""


def utc_now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")


def _version(name: str) -> str | None:
    try:
        return version(name)
    except PackageNotFoundError:
        return None


def git_commit() -> str | None:
    """The checkout's commit (with '+dirty' if it has uncommitted changes), when run from a git checkout."""
    root = Path(__file__).resolve().parents[1]
    if not (root / ".git").exists():
        return None
    try:
        head = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True, text=True,
                              timeout=5, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=5).stdout.strip()
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


def check_folder(path: Path, option: str = "--out") -> Path:
    """A folder we will write into: it may not exist yet, but must not be a file, and its nearest
    existing ancestor must be writable."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ParameterError(f"{option} {path} is a file; give a folder")
    _writable_ancestor(path, option, path if path.exists() else path.parent)
    return path


def check_file(path: Path, option: str, suffixes: tuple[str, ...]) -> Path:
    """A file we will (over)write: the right suffix, not a folder, in a writable place."""
    path = Path(path)
    if suffixes and path.suffix.lower() not in suffixes:
        raise ParameterError(f"{option} {path}: the file name must end in {' or '.join(suffixes)}")
    if path.is_dir():
        raise ParameterError(f"{option} {path} is a folder; give a file name")
    if path.exists() and not os.access(path, os.W_OK):
        raise ParameterError(f"{option} {path}: cannot overwrite it (permission denied)")
    _writable_ancestor(path, option, path.parent)
    return path


# ------------------------------------------------------------------------------------------------ writing


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
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    try:
        yield tmp
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.replace(tmp, path)
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
            fd, tmp = tempfile.mkstemp(prefix=f".{Path(name).stem}.", suffix=Path(name).suffix, dir=folder)
            os.close(fd)
            temporaries.append((Path(tmp), folder / name))
            writer(Path(tmp))
            with open(tmp, "rb+") as f:
                os.fsync(f.fileno())
        for tmp, target in temporaries:
            os.replace(tmp, target)
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


def provenance_line(record: dict, sidecar: str = "provenance.json") -> str:
    """One line naming what made an output (elastoactive.outputs.provenance)."""
    versions = ", ".join(f"{k} {v}" for k, v in record.get("versions", {}).items() if v)
    commit = f", git {record['git_commit']}" if record.get("git_commit") else ""
    return (f"Made by `{' '.join(record.get('command', []))}` on {record.get('platform')} at {record.get('started_utc')} "
            f"UTC ({versions}{commit}); also in {sidecar}.")


# ------------------------------------------------------------------------------------------------ netCDF

NETCDF_TIME_UNITS = "nanoseconds since 1970-01-01"
_NAT = np.iinfo(np.int64).min


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

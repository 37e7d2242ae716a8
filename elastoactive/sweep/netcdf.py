"""A sweep's netCDF file: its contents (an xarray Dataset: one dimension per grid parameter, plus `chain`
for the pair and `harmonic` for the harmonics), and writing it atomically and durably, refused before
h5py is called when the space is short (a full disk can crash h5py).

Why not rewrite the netCDF after every point: that costs O(size of the file) per point, i.e.
O(points^2) for the sweep; and zarr region writes would add a dependency and leave a directory
rather than the single self-describing file asked for.

mujoco (for its version, already loaded by a MuJoCo sweep) and xarray are imported inside the functions that
need them, the engine's and the reader's boundary: the command line imports the sweep to build its parser.
"""

from __future__ import annotations

import errno
import functools
import json
import os
import shutil
from collections.abc import Callable
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

from ..core import observables, parameters
from ..core.params import LONG_CHAIN, Numerics, Physics, has_coupling, parameter_fields
from ..core.units import beat_signal, scene_units
from ..io.outputs import file_size_limit, write_netcdf
from ..wording import field_help, observable
from .grid import VECTORS, SweepStorageError, coordinate_attrs, spec_text, variable_attrs

SNAPSHOT_MARGIN = 1 << 20
"""Bytes of free space asked for beyond twice the arrays' size before writing a snapshot."""


def megabytes(size: int) -> str:
    return f"{size / 1e6:.1f} MB"


def is_disk_full(err: OSError) -> bool:
    return err.errno in (errno.ENOSPC, errno.EDQUOT) or "no space left" in str(err).lower()


def os_reason(err: OSError) -> str:
    return "no space left on the device" if is_disk_full(err) else (err.strerror or str(err))


def fsync_path(path: Path) -> None:
    """fsync a file or a directory (the latter makes a rename or removal in it durable)."""
    fd = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if path.is_dir() else 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


@functools.cache
def package_version() -> str:
    try:
        return version("elastoactive")
    except PackageNotFoundError:
        return "unknown"


def bytes_needed(grid: dict, arrays: dict) -> int:
    """Bytes asked for before writing a snapshot of a sweep over `grid` holding `arrays`: twice the
    arrays' size, plus a margin."""
    size = sum(len(json.dumps(v.tolist())) for v in grid.values())
    for values in arrays.values():
        if values.dtype == object:  # status and error texts: most are short or empty
            size += 24 * values.size + 4 * sum(len(v) for v in values.flat if isinstance(v, str) and len(v) > 8)
        else:
            size += values.nbytes
    return 2 * size + SNAPSHOT_MARGIN


def check_file_size(out: Path, needed: int, kept: str) -> None:
    """Refuse (SweepStorageError) a netCDF file for which `needed` bytes are asked when this process may not
    write a file that large (`ulimit -f`): h5py, stopped by the limit part-way, fails over and over and can
    crash the process. The limit does not change while the process runs, so a sweep checks it before any
    point runs, and again before every write."""
    limit = file_size_limit()
    if limit is not None and limit < needed:
        raise SweepStorageError(
            f"cannot write {out}: this process may not write files over {limit} bytes (the file-size limit, "
            f"ulimit -f), and about {megabytes(needed)} are asked for to write it. Nothing was written; raise the "
            f"limit (ulimit -f unlimited); {kept}"
        )


def write(out: Path, contents: Callable[[], tuple[dict, dict, dict]], needed: int, kept: str) -> None:
    """Write the netCDF file `out` atomically and durably from `contents()`, asking for `needed` bytes of free
    space (and of file-size limit) first; `kept` (what the journal keeps) ends every error message.

    The new file is written beside the old one, fsync'ed, renamed over it (os.replace) and the
    directory fsync'ed: after a crash either the old or the new file is there, complete. No write
    starts without enough free space or below the file-size limit (SweepStorageError, before h5py is
    called: a full disk or a file cut by the limit can crash it)."""
    check_file_size(out, needed, kept)
    try:
        free = shutil.disk_usage(out.parent).free
    except OSError:
        free = None
    if free is not None and free < needed:
        raise SweepStorageError(
            f"not enough free space to write {out}: about {megabytes(needed)} needed, {megabytes(free)} "
            f"free in {out.parent}. Nothing was written; {kept}"
        )
    tmp = out.with_name(f".{out.name}.tmp-{os.getpid()}")
    try:
        write_netcdf(tmp, *contents())
        fsync_path(tmp)
        os.replace(tmp, out)
        fsync_path(out.parent)
    except OSError as err:
        if is_disk_full(err):
            raise SweepStorageError(
                f"no space left on the device to write {out} (about {megabytes(needed)} needed); {kept}"
            ) from err
        raise SweepStorageError(f"cannot write {out}: {os_reason(err)}; {kept}") from err
    finally:
        if tmp.exists():
            tmp.unlink()


def scene_coordinate_attrs(name: str, physics: Physics) -> dict:
    """A grid coordinate's netCDF attributes on the sweep's scene: a physics parameter's help and units in the scene's
    units (Parameter.help_in, units_in), a numerical setting's help in them (wording.field_help), a dimension's as
    they are (grid.coordinate_attrs)."""
    units = scene_units(physics.scene_def)
    if parameters.known(name):
        spec = parameters.get(name)
        return {"long_name": spec.help_in(units), "units": spec.units_in(units)}
    for field in parameter_fields(Numerics):
        if field.name == name:
            return {"long_name": field_help(field, units)}
    return coordinate_attrs(name)


def scene_variable_attrs(name: str, physics: Physics) -> dict:
    """A recorded variable's netCDF attributes on the sweep's scene: a declared observable's units and long name as
    the scene reports it (wording.observable: a network's amplitude in a, its frequency in k/gamma), the others'
    (grid.variable_attrs) with their units in the scene's symbols."""
    attrs = dict(variable_attrs(name))
    if observables.known(name):
        spec = observable(name, physics)
        attrs.update(units=spec.units, long_name=spec.long_name)
    elif "units" in attrs:
        attrs["units"] = scene_units(physics.scene_def).of(attrs["units"])
    return attrs


def contents(sweep, arrays: dict, spec: dict, done: np.ndarray) -> tuple[dict, dict, dict]:
    """(data variables, coordinates, attributes) of the Dataset of a sweep (sweep_grid.Sweep) whose results are `arrays`
    ({name: array}), specification `spec` and finished points `done` (a boolean array of the grid's shape):
    {name: (dims, array, attrs)}, {...}, {...} (outputs.write_netcdf writes them; `dataset` makes them an
    xarray.Dataset)."""
    chains = sweep.chains
    dims = tuple(sweep.grid)
    physics = sweep.physics
    units, signal = scene_units(physics.scene_def), beat_signal(physics)
    coords = {k: ((k,), v, scene_coordinate_attrs(k, physics)) for k, v in sweep.grid.items()}
    if chains > 1:
        coords["chain"] = (("chain",), np.arange(1, chains + 1), coordinate_attrs("chain"))
    data = {}
    for name, values in arrays.items():
        vector = (VECTORS[name][0],) if name in VECTORS else ()
        var_dims = dims + (("chain",) if values.ndim > len(dims) + len(vector) else ()) + vector
        data[name] = (var_dims, values.copy(), scene_variable_attrs(name, physics))
        if vector:
            dim, size = VECTORS[name]
            coords[dim] = ((dim,), np.arange(1, size + 1), coordinate_attrs(dim))
        attrs = {
            "title": f"elastoactive sweep: {sweep.scene} over {', '.join(dims)}",
            "scene": sweep.scene,
            "engine": sweep.engine,
            "duration": sweep.duration,
            "transient": sweep.transient if sweep.transient is not None else 0.5 * sweep.duration,
            "grid": " ".join(dims),
            **{f"fixed_{k}": v for k, v in sweep.fixed.items()},
            **{f"numerics_{k}": v for k, v in sweep.fixed_numerics.items()},
            "package_version": package_version(),
            "points_total": sweep.size,
            "points_done": int(done.sum()),
            "points_failed": int((arrays["status"] == "error").sum()),
            "complete": int(done.all()),
            "sweep_spec": spec_text(spec),
            "units": units.text,
            "beat_signal": f"{signal.text} ({units.of(signal.units)})",
            "measurements": f"per point, after the transient: amplitude and frequency of {signal.symbol}; "
            "periodic (1: periodic, 0: irregular, NaN: too few cycles to tell or failed) with "
            "period_spread (std / mean of the cycle periods; per chain for the pair); notes (text: "
            "what to know about the numbers, '; '-separated); the scene's observables",
        }
    if has_coupling(physics.scene_def):  # the coupling Pi, which a grid or a fixed value may give in place of sigma
        attrs["coupling"] = f"Pi = {physics.scene_def.coupling_formula}"
    if sweep.engine == "mujoco":
        import mujoco  # start-up time: loaded by now only for MuJoCo sweeps

        attrs["mujoco_version"] = mujoco.__version__
        longest = int(np.max(sweep.grid["n"])) if "n" in sweep.grid else sweep.physics.n
        if longest >= LONG_CHAIN and sweep.numerics.automatic and not set(sweep.grid) & {"dt", "mass_ratio"}:
            attrs["numerics_automatic"] = (
                f"points with n >= {LONG_CHAIN} run with the automatic long-chain numerics (Numerics.for_physics: "
                "integrator Euler with a matched mass ratio and dt, where cheaper), not with the numerics_* "
                "values, which are the defaults they replace"
            )
    return data, coords, attrs


def dataset(contents: tuple[dict, dict, dict]):
    """An xarray.Dataset of `contents` (what `contents` returns; what the netCDF file holds)."""
    import xarray as xr  # start-up time: the CLI imports the sweep for its parser

    data, coords, attrs = contents
    # fastpath: the arrays are numpy arrays of the final dtypes already; the checks it skips would load
    # dask.array (~0.3 s of CPU) to ask whether they are dask arrays
    return xr.Dataset(
        {k: xr.Variable(d, v, a, fastpath=True) for k, (d, v, a) in data.items()},
        coords={k: xr.Variable(d, v, a, fastpath=True) for k, (d, v, a) in coords.items()},
        attrs=attrs,
    )

"""Parameter sweeps: any grid of physics parameters (and seed / numerics) of any scene.

    elastoactive sweep one-pinned --grid sigma=0.2:1.0:9 --grid n=5,7 --duration 300 --out s.nc

Each grid point is one `batch.Case`, run on every core (a local process pool, the default) or on
a Dask cluster (`scheduler="tcp://host:port"`), and measured by `results.measure`. The result is
an xarray Dataset whose dimensions are the grid parameters (plus `chain` for the pair), written
to netCDF (h5netcdf engine).

Storage and resume
------------------
* `<out>.journal` is an append-only JSON-lines file: a header with the sweep's specification,
  then one line per finished point (its flat grid index, coordinates, status, error text,
  measurements, wall time, finish time), flushed and fsync'ed as soon as the point is done.
  Appending one line is O(1) per point and a kill -9 can at worst leave a torn last line, which
  is skipped on reading; nothing already written can be damaged.
* `<out>` (netCDF) is the Dataset: rewritten atomically (temporary file + os.replace) at most
  every `snapshot_interval` seconds while the sweep runs, so it can be opened at any time, and
  once more at the end (also on an error or Ctrl-C). When every point is done the journal is
  deleted: the netCDF alone is the result. Unfinished points have status "pending".
* Re-running the same sweep with the same `out` continues it: the finished points are read from
  the netCDF and the journal (the journal wins) and only the others run. Finished means status
  "ok" or "error" (a diverged point keeps its error text; `retry_errors=True` runs those again).
  The sweep's specification (scene, grid with its order, the scene's fixed physics, numerics,
  engine, duration, transient) is stored in both files; a different one is refused with the
  differences listed. A lock on the journal refuses a second sweep writing the same file.

Dask: every worker of the cluster needs elastoactive (same version) installed; the points are
submitted with client.map and collected as they complete, exactly as with the local pool.

Why not rewrite the netCDF after every point: that costs O(size of the file) per point, i.e.
O(points^2) for the sweep; and zarr region writes would add a dependency and leave a directory
rather than the single self-describing file asked for.
"""

from __future__ import annotations

import dataclasses
import fcntl
import json
import math
import os
import time
from pathlib import Path
from typing import Callable, Iterator, Mapping, Sequence

import numpy as np

from .batch import Case, default_workers, run_case
from .params import PRESETS, SCENES, Numerics, ParameterError, Physics

PHYSICS_KEYS = ("n", "sigma", "delta", "kappa", "rho", "drag_ratio", "noise")
NUMERICS_KEYS = ("seed", "dt", "mass_ratio", "perturbation", "sample_dt")
GRID_KEYS = PHYSICS_KEYS + NUMERICS_KEYS
INTEGER_KEYS = ("n", "seed")
FORMAT = 1

# measured variables of each scene (results.measure), present even before any point is done
SCENE_VARIABLES = {
    "one-pinned": ("amplitude", "frequency"),
    "two-pinned": ("amplitude", "frequency", "snap_amplitude", "constraint_violation"),
    "rotating-pin": ("amplitude", "frequency", "rotation_rate"),
    "coupled-pair": ("amplitude", "frequency", "frequency_mismatch"),
}
PER_CHAIN = ("amplitude", "frequency")  # lists of one value per chain for the pair

VARIABLE_ATTRS = {
    "amplitude": dict(units="rad", long_name="amplitude of Theta = theta_N - theta_1 (half peak-to-peak)"),
    "frequency": dict(units="1/tau", long_name="oscillation frequency f*tau of Theta"),
    "frequency_mismatch": dict(units="1/tau", long_name="f_2 - f_1 from the Hilbert phases (NaN unless both oscillate)"),
    "snap_amplitude": dict(units="rad", long_name="standard deviation of theta_3 (self-snapping; NaN for n < 3)"),
    "rotation_rate": dict(units="rad/tau", long_name="mean d theta_1 / dt"),
    "constraint_violation": dict(units="l", long_name="largest distance of the last particle from its pin"),
    "wall_time_s": dict(units="s", long_name="wall time of the simulation (without measuring)"),
    "finished_at": dict(long_name="when the point finished"),
    "status": dict(long_name="ok, error (see error) or pending (not run yet)"),
    "error": dict(long_name="error text of a failed point (empty if ok)"),
}
COORD_ATTRS = {
    "n": "particles per chain N", "sigma": "elasto-active number F_a l / C1", "delta": "compression of the two-pinned chain",
    "kappa": "coupling stiffness K l^2 / C1", "rho": "stiffness ratio C2 / C1", "drag_ratio": "gamma_L / gamma_T",
    "noise": "noise amplitude a", "seed": "random seed", "dt": "timestep (tau)", "mass_ratio": "m / (gamma tau)",
    "perturbation": "initial kick (rad)", "sample_dt": "sampling interval (tau)", "chain": "chain (1: C1, 2: C2 = rho C1)",
}


class SweepMismatch(ParameterError):
    """The output file holds a different sweep (or is not a sweep file)."""


# ----------------------------------------------------------------------------- the grid


def parse_values(name: str, text: str) -> np.ndarray:
    """'a,b,c' (a list) or 'start:stop:num' (num evenly spaced values, both ends included)."""
    text = text.strip()
    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise ValueError
            start, stop, num = float(parts[0]), float(parts[1]), parts[2].strip()
            if not num.isdigit() or int(num) < 1:
                raise ValueError
            values = np.linspace(start, stop, int(num))
        else:
            items = [v.strip() for v in text.split(",")]
            if not all(items):
                raise ValueError
            values = np.array([float(v) for v in items])
    except ValueError:
        raise ParameterError(
            f"grid {name}={text!r}: expected a comma list (e.g. {name}=0.5,1,2) or start:stop:num "
            f"(e.g. {name}=0.2:1.0:9)"
        ) from None
    return _axis(name, values)


def _axis(name: str, values) -> np.ndarray:
    values = np.atleast_1d(np.asarray(values, dtype=float))
    if values.ndim != 1 or values.size == 0:
        raise ParameterError(f"grid {name}: needs at least one value")
    if not np.all(np.isfinite(values)):
        raise ParameterError(f"grid {name}: values must be finite, got {values.tolist()}")
    if name in INTEGER_KEYS:
        if not np.all(values == np.round(values)):
            raise ParameterError(f"grid {name}: values must be integers, got {values.tolist()}")
        values = values.astype(np.int64)
    if np.unique(values).size != values.size:
        raise ParameterError(f"grid {name}: repeated values {values.tolist()}")
    return values


def _key(name: str) -> str:
    key = name.strip().replace("-", "_")
    if key not in GRID_KEYS:
        raise ParameterError(f"grid: unknown parameter {name!r}; choose from {', '.join(GRID_KEYS)}")
    return key


def parse_grid(specs: Sequence[str]) -> dict[str, np.ndarray]:
    """['sigma=0.2:1.0:9', 'kappa=0.5,1,2'] -> {'sigma': array(9), 'kappa': array(3)}, in order."""
    grid: dict[str, np.ndarray] = {}
    for spec in specs:
        name, sep, text = spec.partition("=")
        if not sep:
            raise ParameterError(f"grid {spec!r}: expected NAME=VALUES, e.g. sigma=0.2:1.0:9 or kappa=0.5,1,2")
        key = _key(name)
        if key in grid:
            raise ParameterError(f"grid: {key} given twice")
        grid[key] = parse_values(key, text)
    if not grid:
        raise ParameterError("grid: give at least one parameter, e.g. --grid sigma=0.2:1.0:9")
    return grid


def normalize_grid(grid: Mapping[str, Sequence]) -> dict[str, np.ndarray]:
    """A grid given as {name: values} (values a sequence, or a string in the --grid syntax)."""
    out: dict[str, np.ndarray] = {}
    for name, values in grid.items():
        key = _key(name)
        if key in out:
            raise ParameterError(f"grid: {key} given twice")
        out[key] = parse_values(key, values) if isinstance(values, str) else _axis(key, values)
    if not out:
        raise ParameterError("grid: give at least one parameter")
    return out


# ----------------------------------------------------------------------------- the specification


@dataclasses.dataclass
class Sweep:
    """A sweep's cases and its specification (what must match to resume)."""

    scene: str
    grid: dict[str, np.ndarray]
    physics: Physics  # the fixed values (grid parameters take their first value)
    numerics: Numerics
    duration: float
    engine: str
    transient: float | None

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(v.size for v in self.grid.values())

    @property
    def size(self) -> int:
        return math.prod(self.shape)

    @property
    def fixed(self) -> dict:
        """The scene's physics parameters that are not on the grid."""
        return {k: v for k, v in self.physics.relevant().items() if k != "scene" and k not in self.grid}

    @property
    def fixed_numerics(self) -> dict:
        return {k: v for k, v in dataclasses.asdict(self.numerics).items() if k not in self.grid}

    def spec(self) -> dict:
        return {
            "format": FORMAT,
            "scene": self.scene,
            "engine": self.engine,
            "duration": float(self.duration),
            "transient": None if self.transient is None else float(self.transient),
            "grid": [[k, v.tolist()] for k, v in self.grid.items()],
            "fixed": self.fixed,
            "numerics": self.fixed_numerics,
        }

    def coords(self, flat: int) -> dict:
        index = np.unravel_index(flat, self.shape)
        return {k: v[i].item() for (k, v), i in zip(self.grid.items(), index)}

    def case(self, flat: int) -> Case:
        point = self.coords(flat)
        try:
            physics = dataclasses.replace(self.physics, **{k: v for k, v in point.items() if k in PHYSICS_KEYS})
            numerics = dataclasses.replace(self.numerics, **{k: v for k, v in point.items() if k in NUMERICS_KEYS})
        except ParameterError as err:
            raise ParameterError(f"grid point {point}: {err}") from None
        return Case(physics, numerics, self.duration, self.engine, self.transient)


def make_sweep(
    scene: str,
    grid: Mapping[str, Sequence],
    *,
    fixed: Mapping | None = None,
    numerics: Numerics | str = "accurate",
    duration: float = 300.0,
    engine: str = "mujoco",
    transient: float | None = None,
) -> Sweep:
    if scene not in SCENES:
        raise ParameterError(f"scene must be one of {', '.join(SCENES)}; got {scene!r}")
    if engine not in ("mujoco", "reduced"):
        raise ParameterError(f"engine must be 'mujoco' or 'reduced', got {engine!r}")
    duration = float(duration)
    if not math.isfinite(duration) or duration <= 0:
        raise ParameterError(f"duration (in tau) must be a positive number, got {duration}")
    if transient is not None and not 0 <= float(transient) < duration:
        raise ParameterError(f"transient must lie in [0, duration), got {transient}")
    grid = normalize_grid(grid)
    fixed = dict(fixed or {})
    if isinstance(numerics, str):
        numerics = Numerics.preset(numerics)
    bad = sorted(set(fixed) - set(PHYSICS_KEYS))
    if bad:
        raise ParameterError(f"fixed: unknown physics parameter(s) {', '.join(bad)}; choose from {', '.join(PHYSICS_KEYS)} "
                             "(numerical settings go in numerics)")
    both = [k for k in grid if k in fixed]
    if both:
        raise ParameterError(f"{', '.join(both)} given both as a fixed value and on the grid")
    used = set(Physics(scene=scene).relevant())
    unused = [k for k in grid if k in PHYSICS_KEYS and k not in used]
    if unused:
        raise ParameterError(f"grid: {', '.join(unused)} has no effect on scene {scene} "
                             f"(its parameters: {', '.join(sorted(used - {'scene'}))})")
    first = {k: v[0].item() for k, v in grid.items()}
    try:
        physics = Physics(scene=scene, **fixed, **{k: v for k, v in first.items() if k in PHYSICS_KEYS})
        numerics = dataclasses.replace(numerics, **{k: v for k, v in first.items() if k in NUMERICS_KEYS})
    except ParameterError as err:
        raise ParameterError(f"grid point {first}: {err}") from None
    return Sweep(scene, grid, physics, numerics, duration, engine, None if transient is None else float(transient))


def _spec_text(spec: dict) -> str:
    return json.dumps(spec, sort_keys=True)


def _differences(mine: dict, theirs: dict) -> list[str]:
    out = []
    for key in sorted(set(mine) | set(theirs)):
        a, b = mine.get(key), theirs.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            out += [f"{key}.{d}" for d in _differences(a, b)]
        elif key == "grid" and isinstance(a, list) and isinstance(b, list):
            da, db = dict((k, v) for k, v in a), dict((k, v) for k, v in b)
            if [k for k, _ in a] != [k for k, _ in b]:
                out.append(f"grid parameters: {[k for k, _ in a]} here, {[k for k, _ in b]} in the file")
            for k in sorted(set(da) & set(db)):
                if da[k] != db[k]:
                    out.append(f"grid {k}: {da[k]} here, {db[k]} in the file")
        elif _spec_text({"v": a}) != _spec_text({"v": b}):
            out.append(f"{key}: {a!r} here, {b!r} in the file")
    return out


def _check_spec(path: Path, mine: dict, theirs: dict | None) -> None:
    if theirs is None:
        raise SweepMismatch(f"{path} exists but is not an elastoactive sweep file; refusing to overwrite it. "
                            "Choose another --out or remove the file.")
    if _spec_text(mine) != _spec_text(theirs):
        diff = "; ".join(_differences(mine, theirs)) or "format"
        raise SweepMismatch(f"{path} holds a different sweep ({diff}). To resume it, repeat its exact grid and "
                            "parameters; to start a new sweep, choose another --out or remove the file "
                            f"(and {_journal_path(path).name} if present).")


# ----------------------------------------------------------------------------- running one point


def run_point(case: Case, timestep_check: bool = True) -> dict:
    """One grid point: never raises for a failed simulation, returns its error text instead."""
    start = time.perf_counter()
    try:
        if timestep_check and case.engine == "mujoco":
            from .diagnose import check_timestep

            check_timestep(case.physics, case.numerics)
        out = run_case(case)
        results = dict(out["results"])
        if "constraint_violation" in out["info"]:
            results["constraint_violation"] = out["info"]["constraint_violation"]
        record = {"status": "ok", "error": "", "results": _plain(results), "wall_time_s": float(out["wall_time_s"])}
    except Exception as err:  # a diverged or refused point is recorded and the sweep goes on
        record = {"status": "error", "error": f"{type(err).__name__}: {err}", "results": {},
                  "wall_time_s": time.perf_counter() - start}
    record["finished_at"] = time.time()
    return record


def _plain(value):
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.integer, int)) and not isinstance(value, bool):
        return int(value)
    return float(value)


def _local(todo: list[int], sweep: Sweep, workers: int, check: bool) -> Iterator[tuple[int, dict]]:
    if workers <= 1 or len(todo) <= 1:
        for i in todo:
            yield i, run_point(sweep.case(i), check)
        return
    from concurrent.futures import ProcessPoolExecutor, as_completed

    pool = ProcessPoolExecutor(max_workers=min(workers, len(todo)), initializer=_die_with_parent,
                               initargs=(os.getpid(),))
    try:
        futures = {pool.submit(run_point, sweep.case(i), check): i for i in todo}
        for future in as_completed(futures):
            yield futures[future], future.result()
    finally:
        pool.shutdown(wait=False, cancel_futures=True)


def _die_with_parent(parent: int) -> None:
    """Pool worker initializer (Linux): end with the sweep's process, even after a kill -9 of it,
    instead of computing points nobody will record."""
    try:
        import ctypes
        import signal

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(1)


def _dask(todo: list[int], sweep: Sweep, scheduler, check: bool) -> Iterator[tuple[int, dict]]:
    from dask.distributed import Client, as_completed

    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    futures = {}
    try:
        futures = dict(zip(client.map(run_point, [sweep.case(i) for i in todo], [check] * len(todo), pure=False), todo))
        for future in as_completed(futures):
            try:
                record = future.result()
            except Exception as err:  # e.g. KilledWorker: the point took its worker down
                record = {"status": "error", "error": f"{type(err).__name__}: {err}", "results": {},
                          "wall_time_s": float("nan"), "finished_at": time.time()}
            yield futures[future], record
    finally:
        if futures:
            client.cancel(list(futures))
        if own:
            client.close()


# ----------------------------------------------------------------------------- the store


def _journal_path(out: Path) -> Path:
    return out.with_name(out.name + ".journal")


class _Store:
    """The sweep's results as numpy arrays, the journal and the netCDF snapshots."""

    def __init__(self, sweep: Sweep, out: Path | None):
        self.sweep, self.out = sweep, out
        self.spec = sweep.spec()
        shape = sweep.shape
        self.chains = Physics(scene=sweep.scene).n_chains
        self.arrays: dict[str, np.ndarray] = {}
        for name in SCENE_VARIABLES[sweep.scene]:
            self._allocate(name, per_chain=self.chains > 1 and name in PER_CHAIN)
        self.arrays["wall_time_s"] = np.full(shape, np.nan)
        self.arrays["finished_at"] = np.full(shape, np.datetime64("NaT"), dtype="datetime64[ns]")
        self.arrays["status"] = np.full(shape, "pending", dtype=object)
        self.arrays["error"] = np.full(shape, "", dtype=object)
        self.journal = None
        self.last_snapshot = time.monotonic()

    def _allocate(self, name: str, per_chain: bool) -> None:
        shape = self.sweep.shape + ((self.chains,) if per_chain else ())
        self.arrays[name] = np.full(shape, np.nan)

    # -- reading
    def open(self) -> None:
        """Lock the journal, then read what the netCDF and the journal hold."""
        if self.out is None:
            return
        if self.out.exists():
            self._read_netcdf()
        path = _journal_path(self.out)
        self.journal = open(path, "a+", encoding="utf-8")
        try:
            # a POSIX record lock: unlike flock, not inherited by the forked pool workers, so
            # workers orphaned by a kill -9 of this process do not block the resume
            fcntl.lockf(self.journal, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self.journal.close()
            self.journal = None
            raise SweepMismatch(f"another sweep is writing {self.out} (its journal {path.name} is locked)") from None
        self.journal.seek(0)
        text = self.journal.read()
        lines = text.splitlines()
        if lines:
            try:
                header = json.loads(lines[0])["sweep_spec"]
            except (ValueError, KeyError, TypeError):
                header = None
            try:
                _check_spec(self.out, self.spec, header)
            except SweepMismatch:
                self.close(complete=False)
                raise
            for line in lines[1:]:
                try:
                    entry = json.loads(line)
                    self.set(int(entry["i"]), entry)
                except (ValueError, KeyError, TypeError, IndexError):
                    continue  # a line torn by a kill
            if not text.endswith("\n"):
                self.journal.write("\n")
        else:
            self.journal.write(json.dumps({"sweep_spec": self.spec}) + "\n")
        self._sync()

    def _read_netcdf(self) -> None:
        import xarray as xr

        try:
            with xr.open_dataset(self.out, engine="h5netcdf") as ds:
                ds = ds.load()
        except Exception as err:
            raise SweepMismatch(f"{self.out} exists but cannot be read as netCDF ({err}); refusing to overwrite it. "
                                "Choose another --out or remove the file.") from None
        spec = ds.attrs.get("sweep_spec")
        _check_spec(self.out, self.spec, json.loads(spec) if isinstance(spec, str) else None)
        dims = tuple(self.sweep.grid)
        for name, var in ds.data_vars.items():
            if var.dims[: len(dims)] != dims:
                continue
            if name not in self.arrays:
                self._allocate(name, per_chain="chain" in var.dims)
            values = var.values
            if name == "finished_at":
                values = values.astype("datetime64[ns]")
            elif name in ("status", "error"):
                values = np.where(values == None, "", values).astype(object)  # noqa: E711
            self.arrays[name][...] = values

    # -- writing
    def set(self, flat: int, entry: dict) -> None:
        index = np.unravel_index(flat, self.sweep.shape)
        for name in list(self.arrays):
            if name not in ("status", "error", "finished_at", "wall_time_s"):
                self.arrays[name][index] = np.nan
        for name, value in entry.get("results", {}).items():
            per_chain = isinstance(value, list)
            if name not in self.arrays:
                self._allocate(name, per_chain)
            self.arrays[name][index] = np.nan if value is None else value
        self.arrays["status"][index] = entry["status"]
        self.arrays["error"][index] = entry.get("error", "")
        self.arrays["wall_time_s"][index] = entry.get("wall_time_s", np.nan)
        self.arrays["finished_at"][index] = np.datetime64(int(round(entry["finished_at"] * 1e9)), "ns")

    def record(self, flat: int, entry: dict) -> None:
        self.set(flat, entry)
        if self.journal is not None:
            line = {"i": flat, "coords": self.sweep.coords(flat), **entry}
            self.journal.write(json.dumps(line) + "\n")
            self._sync()

    def _sync(self) -> None:
        self.journal.flush()
        os.fsync(self.journal.fileno())

    def snapshot(self, interval: float | None) -> None:
        """Rewrite the netCDF (atomically) if `interval` seconds passed since the last time (None: now)."""
        if self.out is None or (interval is not None and time.monotonic() - self.last_snapshot < interval):
            return
        ds = self.dataset()
        tmp = self.out.with_name(f".{self.out.name}.tmp-{os.getpid()}")
        try:
            ds.to_netcdf(tmp, engine="h5netcdf")
            os.replace(tmp, self.out)
        finally:
            if tmp.exists():
                tmp.unlink()
        self.last_snapshot = time.monotonic()

    def close(self, complete: bool) -> None:
        if self.journal is None:
            return
        if complete:
            _journal_path(self.out).unlink(missing_ok=True)
        self.journal.close()  # releases the lock
        self.journal = None

    # -- the Dataset
    def done(self) -> np.ndarray:
        return self.arrays["status"] != "pending"

    def dataset(self):
        import xarray as xr

        sweep = self.sweep
        dims = tuple(sweep.grid)
        coords = {k: (k, v, {"long_name": COORD_ATTRS[k]}) for k, v in sweep.grid.items()}
        if self.chains > 1:
            coords["chain"] = ("chain", np.arange(1, self.chains + 1), {"long_name": COORD_ATTRS["chain"]})
        data = {}
        for name, values in self.arrays.items():
            var_dims = dims + (("chain",) if values.ndim > len(dims) else ())
            data[name] = (var_dims, values.copy(), VARIABLE_ATTRS.get(name, {}))
        done = self.done()
        attrs = {
            "title": f"elastoactive sweep: {sweep.scene} over {', '.join(dims)}",
            "scene": sweep.scene,
            "engine": sweep.engine,
            "duration": sweep.duration,
            "transient": sweep.transient if sweep.transient is not None else 0.5 * sweep.duration,
            "grid": " ".join(dims),
            **{f"fixed_{k}": v for k, v in sweep.fixed.items()},
            **{f"numerics_{k}": v for k, v in sweep.fixed_numerics.items()},
            "package_version": _version(),
            "points_total": sweep.size,
            "points_done": int(done.sum()),
            "points_failed": int((self.arrays["status"] == "error").sum()),
            "complete": int(done.all()),
            "sweep_spec": _spec_text(self.spec),
            "units": "l = C1 = gamma = 1: times in tau = gamma l^2 / C1, frequencies f*tau",
        }
        if sweep.engine == "mujoco":
            import mujoco

            attrs["mujoco_version"] = mujoco.__version__
        return xr.Dataset(data, coords=coords, attrs=attrs)


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("elastoactive")
    except PackageNotFoundError:
        return "unknown"


# ----------------------------------------------------------------------------- the sweep


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
):
    """Run `scene` at every point of `grid` ({name: values}; names from GRID_KEYS) and return an
    xarray.Dataset (dims: the grid parameters in the given order, plus `chain` for the pair).

    fixed      physics values off the grid (others: Physics defaults)
    numerics   a Numerics or a preset name ('accurate', 'fast'); seed/dt/... may be on the grid
    out        netCDF file written as the sweep goes (see the module docstring); re-running with
               the same arguments resumes, different arguments for an existing file are refused
    workers    local processes (default: every core); ignored when `scheduler` is given
    scheduler  Dask scheduler address ('tcp://host:port') or a dask.distributed.Client
    on_point   called as on_point(coords, record) in this process after each point is stored
    timestep_check  refuse (record as an error) MuJoCo points whose dt is beyond the linear
               stability limit, as `elastoactive run` does
    """
    sweep = make_sweep(scene, grid, fixed=fixed, numerics=numerics, duration=duration, engine=engine,
                       transient=transient)
    for i in range(sweep.size):  # refuse an invalid point before starting
        sweep.case(i)
    out_path = Path(out) if out is not None else None
    if out_path is not None:
        out_path.parent.mkdir(parents=True, exist_ok=True)
    # import what a point needs here: forked pool workers then start with it (saves ~1 s each)
    from . import diagnose, results  # noqa: F401

    if engine == "mujoco":
        from . import simulate  # noqa: F401
    else:
        from .analysis import reduced  # noqa: F401
    store = _Store(sweep, out_path)
    store.open()
    complete = False
    try:
        status = store.arrays["status"].reshape(-1)
        todo = [i for i in range(sweep.size) if status[i] == "pending" or (retry_errors and status[i] == "error")]
        bar = None
        if progress:
            from tqdm.auto import tqdm

            bar = tqdm(total=sweep.size, initial=sweep.size - len(todo), desc=f"sweep {scene}", unit="point")
        if todo:
            runner = (_dask(todo, sweep, scheduler, timestep_check) if scheduler is not None
                      else _local(todo, sweep, default_workers() if workers is None else int(workers), timestep_check))
            try:
                for flat, record in runner:
                    store.record(flat, record)
                    store.snapshot(snapshot_interval)
                    if bar is not None:
                        bar.update()
                        if record["status"] != "ok":
                            bar.set_postfix(failed=int((store.arrays["status"] == "error").sum()))
                    if on_point is not None:
                        on_point(sweep.coords(flat), record)
            finally:
                runner.close()
                if bar is not None:
                    bar.close()
        elif bar is not None:
            bar.close()
        complete = bool(store.done().all())
        if todo or not (out_path and out_path.exists()):
            store.snapshot(None)
    except BaseException:
        try:
            store.snapshot(None)  # keep what is done readable; the journal has it anyway
        except Exception:
            pass
        raise
    finally:
        store.close(complete)
    return store.dataset()


# ----------------------------------------------------------------------------- command line


EXAMPLES = """examples:
  elastoactive sweep one-pinned --grid sigma=0.2:1.0:9 --grid n=5,7,9 --duration 300 --out onset.nc
  elastoactive sweep coupled-pair --grid kappa=0:2:11 --grid rho=1,1.333 --preset fast --out pair.nc
  elastoactive sweep one-pinned --grid seed=0:9:10 --noise 0.1 --engine reduced --out noise.nc
  elastoactive sweep ... --scheduler tcp://10.0.0.5:8786      (run on a Dask cluster)

Grid values: a comma list (kappa=0.5,1,2) or start:stop:num (sigma=0.2:1.0:9, ends included).
Re-running the same command continues an interrupted sweep (finished points are kept); the same
--out with a different grid or parameters is refused. Results: xarray.open_dataset(OUT)."""


def register(subparsers) -> None:
    import argparse

    p = subparsers.add_parser(
        "sweep", help="run a scene over a grid of parameters (every core or a Dask cluster) into a netCDF file",
        description="Run a scene at every point of a parameter grid and write the measurements (amplitude, "
        "frequency, ...) as an xarray Dataset to netCDF, point by point; resumable. Units: l = C1 = gamma = 1.",
        epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", choices=SCENES, metavar="SCENE", help="one of: " + ", ".join(SCENES))
    p.add_argument("--grid", action="append", required=True, metavar="NAME=VALUES",
                   help=f"a grid axis (repeat for more); NAME one of {', '.join(GRID_KEYS)}")
    d, dn = Physics(), Numerics()
    g = p.add_argument_group("fixed physics (off the grid; defaults as in `run`)")
    g.add_argument("--n", type=int, help=f"particles per chain N (default {d.n})")
    for name, text in (("sigma", "elasto-active number"), ("delta", "compression (two-pinned)"),
                       ("kappa", "coupling stiffness (pair)"), ("rho", "stiffness ratio C2/C1 (pair)"),
                       ("drag-ratio", "gamma_L / gamma_T"), ("noise", "noise amplitude a")):
        g.add_argument(f"--{name}", type=float, help=f"{text} (default {getattr(d, name.replace('-', '_')):.6g})")
    g = p.add_argument_group("numerics (default: the preset's; a given option overrides it)")
    g.add_argument("--preset", choices=tuple(PRESETS), default="accurate",
                   help="numerical settings (default %(default)s; fast: dt 0.01, ~4x quicker, results within 0.3%%)")
    g.add_argument("--dt", type=float, help="MuJoCo timestep in tau")
    g.add_argument("--mass-ratio", type=float, help="particle mass m / (gamma tau)")
    g.add_argument("--integrator", choices=("implicitfast", "implicit", "discrete", "Euler", "RK4"))
    g.add_argument("--seed", type=int, help=f"seed (default {dn.seed})")
    g.add_argument("--perturbation", type=float, help=f"initial kick, rad (default {dn.perturbation})")
    g.add_argument("--sample-dt", type=float, help=f"recording interval, tau (default {dn.sample_dt})")
    g = p.add_argument_group("run")
    g.add_argument("--engine", choices=("mujoco", "reduced"), default="mujoco", help="(default %(default)s)")
    g.add_argument("--duration", type=float, default=300.0, help="simulated time per point, tau (default %(default)s)")
    g.add_argument("--transient", type=float, help="time discarded before measuring, tau (default: half the run)")
    g.add_argument("--out", type=Path, required=True, help="netCDF file (resumed if it holds the same sweep)")
    g.add_argument("--workers", type=int, help="local worker processes (default: every core; unused with --scheduler)")
    g.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address, e.g. tcp://host:8786 (default: local processes)")
    g.add_argument("--retry-errors", action="store_true", help="when resuming, run failed points again")
    g.add_argument("--no-timestep-check", action="store_true", help="run MuJoCo points beyond the linear stability limit of dt")
    g.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_sweep)


def cmd_sweep(args) -> int:
    import sys

    grid = parse_grid(args.grid)
    fixed = {k: getattr(args, k) for k in PHYSICS_KEYS if getattr(args, k) is not None}
    overrides = {k: getattr(args, k) for k in ("dt", "mass_ratio", "integrator", "seed", "perturbation", "sample_dt")
                 if getattr(args, k) is not None}
    both = [k for k in grid if k in fixed or k in overrides]
    if both:
        raise ParameterError(f"{', '.join(both)} given both as an option and on the grid")
    numerics = Numerics.preset(args.preset, **overrides)
    ds = run_sweep(args.scene, grid, fixed=fixed, numerics=numerics, duration=args.duration, engine=args.engine,
                   transient=args.transient, out=args.out, workers=args.workers, scheduler=args.scheduler,
                   progress=not args.quiet, retry_errors=args.retry_errors,
                   timestep_check=not args.no_timestep_check)
    failed = ds["status"].values == "error"
    print(f"wrote {args.out}: {ds.attrs['points_done']} of {ds.attrs['points_total']} points over "
          f"{' x '.join(f'{k}[{v.size}]' for k, v in grid.items())}, {int(failed.sum())} failed")
    for err in list(dict.fromkeys(ds["error"].values[failed]))[:3]:
        print(f"  failed: {err}", file=sys.stderr)
    return 0

"""Parameter sweeps: any grid of physics parameters (and seed / numerics) of any scene.

    elastoactive sweep one-pinned --grid sigma=0.2:1.0:9 --grid n=5,7 --duration 300 --out s.nc

Each grid point is one `batch.Case`, measured by `results.measure`. The result is an xarray Dataset
whose dimensions are the grid parameters (plus `chain` for the pair), written to netCDF (h5netcdf
engine).

Running
-------
* MuJoCo points run in batches (`engines.mujoco_batch`): points that share one compiled model (same
  N, mass ratio, integrator, dt and sampling; sigma, seed, noise, kappa, rho, drag ratio, delta and
  perturbation are per-simulation fields or states of it) step together in one `mujoco.batch` on
  `workers` C threads of this process: no Python per step, bit for bit what `elastoactive run` gives.
  A batch holds at most `batch_size` points (default 8 per thread). Its points are journaled when it
  ends (together: one fsync); a point that fails at once (diverged early, or refused by the pre-flight
  check, diagnose.check_timestep, computed once per distinct model while the batch steps) as soon as
  it does. A diverged point is its own error; the others of its batch go on. A kill loses at most
  the running batches.
* Reduced-engine points run on a local process pool (its compiled kernels hold the GIL).
* On a Dask cluster (`scheduler="tcp://host:port"`) each task is one MuJoCo batch (on every thread of
  the worker that runs it, whose tasks take turns; at least one batch per worker), or one reduced point.
* Every point also records whether its motion is periodic (`periodic`: 1, 0, or NaN when the window
  holds too few cycles), its `period_spread` (per chain for the pair) and its `notes` (text).

Storage and resume
------------------
* `<out>.journal` is an append-only JSON-lines file: a header with the sweep's specification,
  then one line per finished point (its flat grid index, coordinates, status, error text,
  measurements, notes, wall time, finish time), flushed and fsync'ed as soon as the point is done.
  Appending one line is O(1) per point and a kill -9 can at worst leave a torn last line, which
  is skipped on reading; nothing already written can be damaged.
* Every journal line is validated when read: status "ok" or "error", index inside the grid,
  coordinates equal to the grid's at that index, the scene's measurements present (for "ok")
  with the right shape (one number per chain for the pair's per-chain values) and finite where
  they always are (NaN is allowed for snap_amplitude and frequency_mismatch, and for
  measurements this module does not know), periodic 1, 0 or NaN, notes a text, wall time a number. A line that fails is discarded
  with a SweepJournalWarning naming the count, and its point runs again. A point's record that
  would fail this check is stored as an error ("invalid result: ..."), so what is written reads back.
* `<out>` (netCDF) is the Dataset: rewritten atomically and durably (temporary file, fsync,
  os.replace, fsync of the directory) at most every `snapshot_interval` seconds while the sweep
  runs, so it can be opened at any time, and once more at the end (also on an error or Ctrl-C).
  When every point is done the journal is deleted, but only after the final netCDF is on disk:
  the netCDF alone is the result. A Ctrl-C during that final save waits until it is done (main
  thread), so the journal is never lost. Unfinished points have status "pending".
* Before each snapshot the free space is checked (twice the arrays' size plus 1 MB): if it is
  short, or a write fails (ENOSPC ...), a SweepStorageError names the file and the space needed,
  nothing more is written and the journal stays, so the sweep resumes once space is freed.
* Re-running the same sweep with the same `out` continues it: the finished points are read from
  the netCDF and the journal (the journal wins) and only the others run. Finished means status
  "ok" or "error" (a diverged point keeps its error text; `retry_errors=True` runs those again).
  The sweep's specification (scene, grid with its order, the scene's fixed physics, numerics,
  engine, duration, transient) is stored in both files; a different one is refused with the
  differences listed. A lock on the journal refuses a second sweep writing the same file. A
  journal whose header is corrupted is refused, naming it: restore it, or remove it to continue
  from the netCDF alone.
* Numerical settings only MuJoCo reads (dt, mass_ratio; integrator) are refused on the grid of a
  reduced-engine sweep, where they change nothing (dt is allowed when noise > 0: it is then the
  Euler-Maruyama step).

Dask: every worker of the cluster needs elastoactive (same version) installed; the batches (or
reduced points) are submitted with client.map and collected as they complete, as locally.

Why not rewrite the netCDF after every point: that costs O(size of the file) per point, i.e.
O(points^2) for the sweep; and zarr region writes would add a dependency and leave a directory
rather than the single self-describing file asked for.
"""

from __future__ import annotations

import contextlib
import dataclasses
import errno
import fcntl
import functools
import json
import math
import os
import shutil
import signal
import threading
import time
import warnings
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Callable, Iterator, Mapping, Sequence

import numpy as np

from . import registry
from .batch import Case, default_workers, run_case
from .engines import check_engine
from .errors import ParameterError
from .executor import imap
from .jsonio import to_jsonable
from .outputs import write_netcdf
from .params import LONG_CHAIN, PRESETS, Numerics, Physics, parameter_fields
from .results import HARMONICS, OBSERVABLES

PHYSICS_KEYS = tuple(f.name for f in parameter_fields(Physics))
NUMERICS_KEYS = ("seed", "dt", "mass_ratio", "perturbation", "sample_dt")
GRID_KEYS = PHYSICS_KEYS + NUMERICS_KEYS
INTEGER_KEYS = ("n", "seed")
MUJOCO_ONLY = ("dt", "integrator")
"""Numerical settings only the MuJoCo engine reads (the reduced engine uses dt only when noise > 0; it does use
mass_ratio, which decides whether a run is overdamped or inertial: docs/mujoco.md section 5)."""
FORMAT = 1
STATUSES = ("ok", "error")
TEXT_VARIABLES = ("status", "error", "notes")
"""Variables that hold text per point (the others are numbers, and finished_at a time)."""
"""Status of a finished point; an unfinished one is "pending"."""
MUST_BE_FINITE = ("amplitude", "rotation_rate", "constraint_violation")
"""Measurements that are always finite. The other known ones (OBSERVABLES: frequency, snap_amplitude,
frequency_mismatch, ...) are NaN when they cannot be measured, never infinite; measurements this
module does not know (plug-in scenes' observables, new fields) may be any number."""
VECTORS = {"harmonics": ("harmonic", HARMONICS)}
"""Measurements with several values per point (and chain): their extra dimension and its size. `harmonics`
(results.Results.harmonics): harmonics 1 .. HARMONICS of Theta, on a dimension `harmonic` (1: the fundamental)."""
SNAPSHOT_MARGIN = 1 << 20
"""Bytes of free space asked for beyond twice the arrays' size before writing a snapshot."""


def scene_variables(scene: str) -> tuple[str, ...]:
    """Measured variables of a scene (results.measure), present even before any point is done: amplitude,
    frequency, whether the motion is periodic and its period spread, the scene's observables and, for a
    pinned scene, the pin's largest violation. (Each point's notes are a text variable besides these.)"""
    s = registry.get(scene)
    names = ("amplitude", "frequency", "periodic", "period_spread", *s.observables)
    return tuple(dict.fromkeys(names)) + (("constraint_violation",) if s.pinned else ())


VARIABLE_ATTRS = {
    **{name: dict(units=o.units, long_name=o.long_name) for name, o in OBSERVABLES.items()},
    **{name: dict(units=o.units, long_name=o.long_name, flag_values=np.arange(len(o.categories), dtype=float),
                  flag_meanings=" ".join(o.categories)) for name, o in OBSERVABLES.items() if o.categories},
    "periodic": dict(
        units="1", long_name="whether the motion is periodic (results.Results.periodic)",
        flag_values=np.array([1.0, 0.0]), flag_meanings="periodic irregular",
        comment="1: a steady state or a regular beat (amplitude and frequency describe it); 0: irregular (cycle "
                "periods or amplitudes vary by more than 1% - noise, chaos, or a beat still growing: amplitude and "
                "frequency are averages); NaN: the measured window holds too few cycles to tell, or the point "
                "failed"),
    "notes": dict(long_name="what to know about the point's numbers (results.Results.notes, joined with '; '); "
                            "empty when there is nothing to say"),
    "constraint_violation": dict(units="l", long_name="largest distance of the last particle from its pin"),
    "wall_time_s": dict(units="s", long_name="wall time of the simulation (without measuring); for MuJoCo points run "
                                             "together in one mujoco.batch, its share: batch wall time x threads / points"),
    "finished_at": dict(long_name="when the point finished"),
    "status": dict(long_name="ok, error (see error) or pending (not run yet)"),
    "error": dict(long_name="error text of a failed point (empty if ok)"),
}
COORD_ATTRS = {
    **{f.name: f.metadata["help"] for cls in (Physics, Numerics) for f in parameter_fields(cls)},
    "n": "particles per chain N", "sigma": "elasto-active number F_a l / C1", "delta": "compression of the two-pinned chain",
    "kappa": "coupling stiffness K l^2 / C1", "rho": "stiffness ratio C2 / C1", "drag_ratio": "gamma_L / gamma_T",
    "noise": "noise amplitude a", "seed": "random seed", "dt": "timestep (tau)", "mass_ratio": "m / (gamma tau)",
    "perturbation": "initial kick (rad)", "sample_dt": "sampling interval (tau)", "chain": "chain (1: C1, 2: C2 = rho C1)",
    "harmonic": "harmonic number (1: the fundamental)",
}
"""long_name of each coordinate: every parameter's help text (params), shorter names for the paper's."""


class SweepMismatch(ParameterError):
    """The output file holds a different sweep (or is not a sweep file)."""


class SweepStorageError(ParameterError):
    """The netCDF (or the journal) cannot be written, e.g. the disk is full; the message names the
    file and the space needed. The journal keeps every point recorded before: free the space and
    re-run the same sweep to resume."""


class SweepJournalWarning(UserWarning):
    """Lines of the journal failed validation and were discarded: their points run again."""


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
            physics = self.physics.replace(**{k: v for k, v in point.items() if k in PHYSICS_KEYS})
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
    if scene not in registry.names():
        raise ParameterError(f"scene must be one of {', '.join(registry.names())}; got {scene!r}")
    check_engine(engine)
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
    noisy = bool(np.any(grid["noise"] > 0)) if "noise" in grid else physics.noise > 0
    check_engine_numerics(engine, [k for k in grid if k in MUJOCO_ONLY], noisy, lambda k: f"grid {k}")
    return Sweep(scene, grid, physics, numerics, duration, engine, None if transient is None else float(transient))


def check_engine_numerics(engine: str, names: Sequence[str], noisy: bool, label: Callable[[str], str] = str) -> None:
    """Refuse MuJoCo-only numerical settings (`names`, swept or given) with the reduced engine, where
    they change nothing: integrator always, dt unless some point has noise > 0 (dt is then the noise
    step). `label(name)` is how the message names the setting."""
    if engine != "reduced":
        return
    for name in names:
        if name not in MUJOCO_ONLY or (name == "dt" and noisy):
            continue
        why = " (the reduced engine integrates noise-free runs adaptively; it uses dt only when noise > 0)" \
            if name == "dt" else ""
        raise ParameterError(f"{label(name)}: {name} only affects the MuJoCo engine and changes nothing with "
                             f"engine reduced{why}; remove it or use engine mujoco")


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


# ----------------------------------------------------------------------------- running points

BATCH_POINTS_PER_THREAD = 8
"""Default size of a local MuJoCo batch: this many points per thread (a killed sweep loses at most the
batches that are running; a larger batch gains little once every thread has several simulations)."""
_TASK_LOCK = threading.Lock()
"""One batch task at a time per Dask worker process: each uses all the worker's threads, and the
follower callback is global to the process."""


def run_point(case: Case, timestep_check: bool = True) -> dict:
    """One grid point: never raises for a failed simulation, returns its error text instead."""
    start = time.perf_counter()
    try:
        if timestep_check and case.engine == "mujoco":
            from .diagnose import check_timestep  # start-up time: diagnose loads mujoco; the CLI imports this module

            check_timestep(case.physics, case.numerics)
        out = run_case(case)
        record = _ok_record(out.results, out.info, out.wall_time_s)
    except Exception as err:  # a diverged or refused point is recorded and the sweep goes on
        record = _error_record(err, time.perf_counter() - start)
    record["finished_at"] = time.time()
    return record


def _ok_record(results, info: dict, wall_time_s: float) -> dict:
    """A successful point's record: its numeric measurements, its notes as one text, its wall time."""
    values = results.as_dict()
    if "constraint_violation" in info:
        values["constraint_violation"] = info["constraint_violation"]
    notes = "; ".join(str(note) for note in (results.notes or ()))
    return {"status": "ok", "error": "", "results": _measurements(values), "notes": notes,
            "wall_time_s": float(wall_time_s)}


def _error_record(err: BaseException, wall_time_s: float) -> dict:
    return {"status": "error", "error": f"{type(err).__name__}: {err}", "results": {}, "notes": "",
            "wall_time_s": float(wall_time_s)}


class _TimestepChecks:
    """diagnose.check_timestep per point, computed once per distinct model: its outcome depends on the
    physics, dt, mass_ratio and integrator, on the seed only with noise (the linearisation sees the
    first step's noise draw) and on the initial state only for integrator discrete (its probe run).
    Thread-safe: a check another thread is computing is waited for, not computed again."""

    def __init__(self):
        self._cache: dict = {}
        self._running: dict = {}  # key -> Event set when that check is done
        self._models: dict = {}  # key -> the point's compiled model, offered by the batch (offer)
        self._lock = threading.Lock()

    def offer(self, physics: Physics, numerics: Numerics, model) -> None:
        """The compiled model of a point (as its run builds it), for its check to use instead of building it
        again (~1.5 ms at N = 7). Kept only until the check is done."""
        key = self.key(physics, numerics)
        with self._lock:
            if key not in self._cache:
                self._models.setdefault(key, model)

    @staticmethod
    def key(physics: Physics, numerics: Numerics) -> tuple:
        seed = numerics.seed if physics.noise > 0 or numerics.integrator == "discrete" else None
        perturbation = numerics.perturbation if numerics.integrator == "discrete" else None
        return (physics, numerics.dt, numerics.mass_ratio, numerics.integrator, seed, perturbation)

    def known_refusal(self, physics: Physics, numerics: Numerics) -> Exception | None:
        """The check's refusal if it is done and refused the point, else None (nothing is computed)."""
        key = self.key(physics, numerics)
        with self._lock:
            return self._cache.get(key)

    def refusal(self, physics: Physics, numerics: Numerics) -> Exception | None:
        """The check's refusal (a ParameterError, or whatever else it raised), or None if the point may run."""
        key = self.key(physics, numerics)
        while True:
            with self._lock:
                if key in self._cache:
                    return self._cache[key]
                running = self._running.get(key)
                if running is None:
                    running = self._running[key] = threading.Event()
                    break
            running.wait()  # another thread computes it
        from .diagnose import check_timestep  # start-up time: diagnose loads mujoco

        error = None
        with self._lock:
            model = self._models.get(key)
        try:
            # a point's model is the same for every point of its key when the check's outcome can depend on
            # it (key: the seed and perturbation only where they matter, which the model does not hold)
            check_timestep(physics, numerics, model=model)
        except Exception as err:  # refused (ParameterError) or failed: the point's error either way
            error = err
        except BaseException:  # interrupted: nothing is known
            with self._lock:
                del self._running[key]
            running.set()
            raise
        with self._lock:
            self._cache[key] = error
            self._models.pop(key, None)
            del self._running[key]
        running.set()
        return error

    def __call__(self, physics: Physics, numerics: Numerics) -> None:
        error = self.refusal(physics, numerics)
        if error is not None:
            raise error


def run_points(cases: Sequence[Case], timestep_check: bool = True, threads: int = 1, *,
               on_record: Callable[[int, dict], None] | None = None, cancel: threading.Event | None = None,
               checks: _TimestepChecks | None = None, on_start: Callable[[], None] | None = None) -> list[dict]:
    """MuJoCo grid points run together (engines.mujoco_batch, `threads` C threads); returns each point's
    record as run_point would (never raises for a failed point). on_record(j, record) is called as each
    is known: a point that fails at once, the others when their batch ends. The follower callback must
    be installed by the caller (mujoco_batch.run_chunks does).

    The pre-flight checks (diagnose.check_timestep, once per distinct model) run on a thread of their
    own while the batch steps: a refused point is dropped from its batch at its next chunk of samples
    and recorded with the refusal, as if it had never run; a point is recorded only once its check is
    done."""
    from .engines.mujoco_batch import Cancelled, as_runs, run_chunk  # start-up time: loads mujoco
    from .results import measure

    start = time.perf_counter()
    records: list[dict | None] = [None] * len(cases)
    checks = checks if checks is not None else _TimestepChecks()
    stepping, finished = threading.Event(), threading.Event()

    def put(j: int, record: dict) -> None:
        record["finished_at"] = time.time()
        records[j] = record
        if on_record is not None:
            on_record(j, record)

    def drop(j: int) -> BaseException | None:
        return checks.known_refusal(cases[j].physics, cases[j].numerics)

    def done(j: int, outcome) -> None:
        refused = checks.refusal(cases[j].physics, cases[j].numerics) if timestep_check else None
        if refused is not None:  # the check's verdict comes first, whatever the simulation did
            outcome = refused
        if isinstance(outcome, BaseException):
            put(j, _error_record(outcome, time.perf_counter() - start))
            return
        try:
            put(j, _ok_record(measure(outcome, cases[j].transient), outcome.info, outcome.wall_time_s))
        except Exception as err:  # measuring failed: the point's error, as in run_point
            put(j, _error_record(err, time.perf_counter() - start))

    def check_all() -> None:
        # after the stepping has started: the checks need the GIL, which preparing the models needs too
        while not (stepping.wait(0.05) or finished.is_set()):
            pass
        for case in cases:
            if finished.is_set() or (cancel is not None and cancel.is_set()):
                return
            with contextlib.suppress(Exception):
                checks.refusal(case.physics, case.numerics)

    def started() -> None:
        stepping.set()
        if on_start is not None:
            on_start()

    checker = threading.Thread(target=check_all, name="elastoactive-checks", daemon=True) if timestep_check else None
    if checker is not None:
        checker.start()
    try:
        offer = (lambda j, model: checks.offer(cases[j].physics, cases[j].numerics, model)) if timestep_check else None
        run_chunk(as_runs(cases), range(len(cases)), threads, done, cancel, started, drop if timestep_check else None,
                  offer)
    except Cancelled:
        raise
    except Exception as err:  # the batch itself failed: its unfinished points are errors, the sweep goes on
        for j, record in enumerate(records):
            if record is None:
                put(j, _error_record(err, time.perf_counter() - start))
    finally:
        finished.set()
        if checker is not None:
            checker.join()
    return records  # type: ignore[return-value]


def run_points_task(cases: Sequence[Case], timestep_check: bool = True) -> list[dict]:
    """A Dask task: one batch of MuJoCo points (run_points) on every thread of the worker that runs it;
    tasks of one worker process take turns."""
    threads = 1
    with contextlib.suppress(Exception):
        from dask.distributed import get_worker  # optional dependency, loaded on Dask workers only

        threads = max(1, int(get_worker().state.nthreads))
    from .controllers import follower_forces  # start-up time: loads mujoco

    with _TASK_LOCK, follower_forces():
        return run_points(cases, timestep_check, threads)


def _measurements(results: dict) -> dict:
    """The numeric measurements of Results.as_dict(), as JSON-ready numbers: a number, or one per chain
    (a list). None ("could not be measured") becomes NaN, a bool 0 or 1, a categorical observable's value
    (OBSERVABLES' categories, e.g. dish_state) its index; other text (the notes) is left out: it is stored as
    the record's `notes`."""
    coded = {name: float(OBSERVABLES[name].categories.index(value)) for name, value in results.items()
             if name in OBSERVABLES and value in OBSERVABLES[name].categories}
    return {name: _coded(to_jsonable(value, nonfinite="keep")) for name, value in {**results, **coded}.items()
            if _numeric(value)}


def _numeric(value, depth: int = 2) -> bool:
    """A number, or a non-empty list of them, or (VECTORS per chain) a list of such lists."""
    scalar = (int, float, np.integer, np.floating, np.bool_, type(None))
    if isinstance(value, (list, tuple, np.ndarray)):
        return depth > 0 and len(value) > 0 and all(_numeric(v, depth - 1) for v in value)
    return isinstance(value, scalar)


def _coded(value):
    """A measurement (JSON values: a number or lists of them) as numbers: None as NaN, a bool as 0.0 or 1.0."""
    if isinstance(value, list):
        return [_coded(v) for v in value]
    return math.nan if value is None else (float(value) if isinstance(value, bool) else value)


def _local(todo: list[int], sweep: Sweep, workers: int, check: bool) -> Iterator[tuple[int, dict]]:
    """Reduced-engine points on a process pool (its compiled kernels hold the GIL: threads would not help)."""
    if workers <= 1 or len(todo) <= 1:
        for i in todo:
            yield i, run_point(sweep.case(i), check)
        return

    task = functools.partial(run_point, timestep_check=check)
    for j, record in imap(task, [sweep.case(i) for i in todo], workers, completed=True):
        yield todo[j], record


def _chunks(todo: list[int], sweep: Sweep, max_points: int, min_chunks: int = 1) -> tuple[dict, list[list[int]]]:
    """The todo points' cases and their batches (flat indices), as engines.mujoco_batch.plan forms them."""
    from .engines.mujoco_batch import plan  # start-up time: loads mujoco

    cases = {i: sweep.case(i) for i in todo}
    chunks = plan([cases[i] for i in todo], max_points, min_chunks)
    return cases, [[todo[j] for j in chunk] for chunk in chunks]


def _local_mujoco(todo: list[int], sweep: Sweep, workers: int, check: bool,
                  batch_size: int | None, preload_xarray: bool = True) -> Iterator[tuple[int, dict]]:
    """MuJoCo points in mujoco.batch batches on `workers` threads of this process; each point's record is
    yielded (in this thread) as soon as it is known, so a killed sweep loses at most the running batches."""
    from .engines.mujoco_batch import run_chunks  # start-up time: loads mujoco

    cases, chunks = _chunks(todo, sweep, batch_size or BATCH_POINTS_PER_THREAD * workers)
    checks = _TimestepChecks()
    started, stop = threading.Event(), threading.Event()
    # what the netCDF snapshots and the returned Dataset need (h5netcdf; xarray only if a Dataset is returned:
    # preload_xarray) is loaded while the C threads step, instead of after them; the loading waits until the
    # stepping has started (it needs the GIL, which the pre-flight checks and the preparation of the models need
    # too). It shares the cores with the stepping threads, so only what will be used is loaded
    preload = threading.Thread(target=_preload_storage, args=(started, stop, preload_xarray),
                               name="elastoactive-preload", daemon=True)
    preload.start()

    def task(chunk, threads, emit, cancel):
        run_points([cases[i] for i in chunk], check, threads, cancel=cancel, checks=checks, on_start=started.set,
                   on_record=lambda j, record: emit((chunk[j], record)))

    try:
        yield from run_chunks(chunks, workers, task, idle=FLUSH)
    finally:
        stop.set()
        started.set()
        preload.join()


FLUSH = object()
"""Yielded by a runner when no record is waiting: the records before it are written out together."""


def _preload_storage(started: threading.Event, stop: threading.Event, dataset: bool = True) -> None:
    started.wait()
    if stop.is_set():
        return
    # (measuring a point, results.measure, needs nothing more: its harmonics no longer load scipy.optimize)
    with contextlib.suppress(Exception):
        # start-up time: loaded in the background, see _local_mujoco. Snapshots need h5netcdf (and h5py)
        import h5netcdf  # noqa: F401

        _version()  # reads the package's metadata
    if not dataset or stop.is_set():
        return
    with contextlib.suppress(Exception):
        # the Dataset run_sweep returns needs xarray (and pandas), and the index of a coordinate loads the
        # little of dask (dask.base) xarray asks whether it is a dask array; not dask.array (Store.dataset)
        import xarray

        xarray.Dataset(coords={"p": xarray.Variable(("p",), np.zeros(1), fastpath=True)})  # as Store.dataset


def _dask(todo: list[int], sweep: Sweep, scheduler, check: bool,
          batch_size: int | None = None) -> Iterator[tuple[int, dict]]:
    """Points on a Dask cluster: MuJoCo points one batch per task (run_points_task, on all the threads of
    the worker that runs it), at least one batch per worker; reduced-engine points one per task."""
    from dask.distributed import Client  # start-up time: dask (~1 s) loads only for --scheduler
    from dask.distributed import as_completed as dask_completed

    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    futures = {}
    try:
        if sweep.engine == "mujoco":
            # a task runs on every thread of its worker, and a worker's tasks take turns: at least one
            # batch per worker, and batches of at most BATCH_POINTS_PER_THREAD points per worker thread
            nthreads = list(client.nthreads().values()) or [1]
            cases, chunks = _chunks(todo, sweep, batch_size or BATCH_POINTS_PER_THREAD * max(nthreads),
                                    min_chunks=len(nthreads))
            futures = dict(zip(client.map(run_points_task, [[cases[i] for i in chunk] for chunk in chunks],
                                          [check] * len(chunks), pure=False), chunks))
        else:
            futures = dict(zip(client.map(run_point, [sweep.case(i) for i in todo], [check] * len(todo), pure=False),
                               [[i] for i in todo]))
        for future in dask_completed(futures):
            chunk = futures[future]
            try:
                records = future.result()
                if isinstance(records, dict):
                    records = [records]
            except Exception as err:  # e.g. KilledWorker: the task took its worker down
                records = [{**_error_record(err, float("nan")), "finished_at": time.time()} for _ in chunk]
            for i, record in zip(chunk, records):
                yield i, record
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
        self.chains = registry.get(sweep.scene).n_chains
        self.required = ("amplitude", "frequency") + (("constraint_violation",) if registry.get(sweep.scene).pinned else ())
        self.arrays: dict[str, np.ndarray] = {}
        for name in scene_variables(sweep.scene):
            self._allocate(name, per_chain=self.chains > 1 and name in OBSERVABLES and OBSERVABLES[name].per_chain)
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
        return _journal_path(self.out)

    # -- reading
    def open(self) -> None:
        """Lock the journal, then read what the netCDF and the journal hold."""
        if self.out is None:
            return
        if self.out.exists():
            self._read_netcdf()
        path = self.journal_path
        # errors="replace": a damaged byte makes its line fail validation instead of the whole read
        self.journal = open(path, "a+", encoding="utf-8", errors="replace")
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
            self.journal.write(json.dumps({"sweep_spec": self.spec}) + "\n")
            self._sync()
            return
        self.stale = True
        header = _header(lines[0])
        if header is None:
            raise SweepMismatch(
                f"the journal {path} is corrupted (its first line is not a sweep header), so the points recorded "
                f"in it cannot be trusted. To proceed, restore {path.name} from a backup and re-run, or remove it "
                f"to continue from {self.out.name if self.out.exists() else 'scratch'} (the points recorded only "
                "in the journal then run again).")
        if _spec_text(self.spec) != _spec_text(header):
            diff = "; ".join(_differences(self.spec, header)) or "format"
            raise SweepMismatch(
                f"the journal {path} holds a different sweep ({diff}). To resume it, repeat its exact grid and "
                f"parameters; to start a new sweep, choose another --out or remove {path.name} (and {self.out.name} "
                "if present).")
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
                f"(first: {discarded[0]}); the grid points they name run again", SweepJournalWarning, stacklevel=4)
        if not text.endswith("\n"):
            self.journal.write("\n")
            self._sync()

    def _read_netcdf(self) -> None:
        import xarray as xr  # start-up time: the CLI imports this module for its parser

        try:
            with xr.open_dataset(self.out, engine="h5netcdf") as ds:
                ds = ds.load()
        except Exception as err:
            raise SweepMismatch(f"{self.out} exists but cannot be read as netCDF ({err}); refusing to overwrite it. "
                                "Choose another --out or remove the file.") from None
        spec = ds.attrs.get("sweep_spec")
        try:
            spec = json.loads(spec) if isinstance(spec, str) else None
        except ValueError:
            spec = None
        _check_spec(self.out, self.spec, spec)
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
        if not (isinstance(coords, dict) and set(coords) == set(expected)
                and all(_is_number(coords[k]) and coords[k] == v for k, v in expected.items())):
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
        elif name in OBSERVABLES:
            per_chain = self.chains > 1 and OBSERVABLES[name].per_chain
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
            if (name in OBSERVABLES or name in MUST_BE_FINITE) and math.isinf(v):
                return f"= {value!r} is infinite"
            if name == "periodic" and not (math.isnan(v) or v in (0, 1)):
                return f"= {value!r} is not 1, 0 or NaN"
        return None

    def _vector_problem(self, name: str, value) -> str | None:
        """A VECTORS measurement: a list of its size (one per chain for the pair), numbers or NaN."""
        size = VECTORS[name][1]
        per_chain = self.chains > 1 and OBSERVABLES[name].per_chain
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
                per_chain = OBSERVABLES[name].per_chain if name in VECTORS else isinstance(value, list)
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
            entry = {"status": "error", "error": f"invalid result: {problem}", "results": {}, "notes": "",
                     "wall_time_s": _number_or_nan(entry.get("wall_time_s")),
                     "finished_at": _number_or_nan(entry.get("finished_at"), time.time())}
            line = {"i": flat, "coords": self.sweep.coords(flat), **entry}
        self.set(flat, entry)
        if self.journal is not None:
            try:
                self.journal.write(json.dumps(line) + "\n")
                self.unsynced = True
            except OSError as err:
                raise self._journal_error(err) from err
            if sync:
                self.sync()
        return entry

    def sync(self) -> None:
        """Flush and fsync the journal lines written since the last time."""
        if self.journal is None or not self.unsynced:
            return
        try:
            self._sync()
        except OSError as err:
            raise self._journal_error(err) from err
        self.unsynced = False

    def _journal_error(self, err: OSError) -> SweepStorageError:
        return SweepStorageError(
            f"cannot append to the journal {self.journal_path}: {_os_reason(err)}. The points recorded "
            "before are kept in it: fix this (e.g. free some space) and re-run the same sweep to resume.")

    def _sync(self) -> None:
        self.journal.flush()
        os.fsync(self.journal.fileno())

    def bytes_needed(self) -> int:
        """Free space asked for before writing a snapshot: twice the arrays' size, plus a margin."""
        size = sum(len(json.dumps(v.tolist())) for v in self.sweep.grid.values())
        for values in self.arrays.values():
            if values.dtype == object:  # status and error texts: most are short or empty
                size += 24 * values.size + 4 * sum(len(v) for v in values.flat if isinstance(v, str) and len(v) > 8)
            else:
                size += values.nbytes
        return 2 * size + SNAPSHOT_MARGIN

    def snapshot(self, interval: float | None) -> None:
        """Rewrite the netCDF (atomically and durably) if `interval` seconds passed since the last time (None: now).

        The new file is written beside the old one, fsync'ed, renamed over it (os.replace) and the
        directory fsync'ed: after a crash either the old or the new file is there, complete. No write
        starts without enough free space (SweepStorageError, before h5py is called: a full disk
        can crash it)."""
        if self.out is None or (interval is not None and time.monotonic() - self.last_snapshot < interval):
            return
        needed = self.bytes_needed()
        try:
            free = shutil.disk_usage(self.out.parent).free
        except OSError:
            free = None
        if free is not None and free < needed:
            raise SweepStorageError(
                f"not enough free space to write {self.out}: about {_megabytes(needed)} needed, {_megabytes(free)} "
                f"free in {self.out.parent}. Nothing was written; {self._kept()}")
        contents = self.contents()
        tmp = self.out.with_name(f".{self.out.name}.tmp-{os.getpid()}")
        try:
            write_netcdf(tmp, *contents)
            _fsync_path(tmp)
            os.replace(tmp, self.out)
            _fsync_path(self.out.parent)
        except OSError as err:
            if _is_disk_full(err):
                raise SweepStorageError(f"no space left on the device to write {self.out} (about {_megabytes(needed)} "
                                        f"needed); {self._kept()}") from err
            raise SweepStorageError(f"cannot write {self.out}: {_os_reason(err)}; {self._kept()}") from err
        finally:
            if tmp.exists():
                tmp.unlink()
        self.last_snapshot = time.monotonic()

    def _kept(self) -> str:
        return (f"the journal {self.journal_path} keeps every finished point: free some space (or fix the cause) "
                "and re-run the same sweep to resume")

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
                _fsync_path(self.out.parent)
        self.journal.close()  # releases the lock
        self.journal = None

    # -- the Dataset
    def done(self) -> np.ndarray:
        return np.isin(self.arrays["status"], STATUSES)

    def dataset(self):
        """The sweep as an xarray.Dataset (what the netCDF file holds)."""
        import xarray as xr  # start-up time: the CLI imports this module for its parser

        data, coords, attrs = self.contents()
        # fastpath: the arrays are numpy arrays of the final dtypes already; the checks it skips would load
        # dask.array (~0.3 s of CPU) to ask whether they are dask arrays
        return xr.Dataset({k: xr.Variable(d, v, a, fastpath=True) for k, (d, v, a) in data.items()},
                          coords={k: xr.Variable(d, v, a, fastpath=True) for k, (d, v, a) in coords.items()},
                          attrs=attrs)

    def contents(self) -> tuple[dict, dict, dict]:
        """(data variables, coordinates, attributes) of the Dataset: {name: (dims, array, attrs)}, {...}, {...}
        (outputs.write_netcdf writes them; `dataset` makes them an xarray.Dataset)."""
        sweep = self.sweep
        dims = tuple(sweep.grid)
        coords = {k: ((k,), v, {"long_name": COORD_ATTRS[k]}) for k, v in sweep.grid.items()}
        if self.chains > 1:
            coords["chain"] = (("chain",), np.arange(1, self.chains + 1), {"long_name": COORD_ATTRS["chain"]})
        data = {}
        for name, values in self.arrays.items():
            vector = (VECTORS[name][0],) if name in VECTORS else ()
            var_dims = dims + (("chain",) if values.ndim > len(dims) + len(vector) else ()) + vector
            data[name] = (var_dims, values.copy(), VARIABLE_ATTRS.get(name, {}))
            if vector:
                dim, size = VECTORS[name]
                coords[dim] = ((dim,), np.arange(1, size + 1), {"long_name": COORD_ATTRS[dim]})
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
            "measurements": "per point, after the transient: amplitude and frequency of Theta = theta_N - theta_1; "
                            "periodic (1: periodic, 0: irregular, NaN: too few cycles to tell or failed) with "
                            "period_spread (std / mean of the cycle periods; per chain for the pair); notes (text: "
                            "what to know about the numbers, '; '-separated); the scene's observables",
        }
        if sweep.engine == "mujoco":
            import mujoco  # start-up time: loaded by now only for MuJoCo sweeps

            attrs["mujoco_version"] = mujoco.__version__
            longest = int(np.max(sweep.grid["n"])) if "n" in sweep.grid else sweep.physics.n
            if longest >= LONG_CHAIN and sweep.numerics.automatic and not set(sweep.grid) & {"dt", "mass_ratio"}:
                attrs["numerics_automatic"] = (
                    f"points with n >= {LONG_CHAIN} run with the automatic long-chain numerics (Numerics.for_physics: "
                    "integrator Euler with a matched mass ratio and dt, where cheaper), not with the numerics_* "
                    "values, which are the defaults they replace")
        return data, coords, attrs


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


def _megabytes(size: int) -> str:
    return f"{size / 1e6:.1f} MB"


def _is_disk_full(err: OSError) -> bool:
    return err.errno in (errno.ENOSPC, errno.EDQUOT) or "no space left" in str(err).lower()


def _os_reason(err: OSError) -> str:
    return "no space left on the device" if _is_disk_full(err) else (err.strerror or str(err))


def _fsync_path(path: Path) -> None:
    """fsync a file or a directory (the latter makes a rename or removal in it durable)."""
    fd = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if path.is_dir() else 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


@contextlib.contextmanager
def _sigint_deferred():
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


@functools.cache
def _version() -> str:
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
    batch_size: int | None = None,
):
    """Run `scene` at every point of `grid` ({name: values}; names from GRID_KEYS) and return an
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
               stability limit, as `elastoactive run` does

    Raises ParameterError for invalid arguments (e.g. workers < 1, dt or mass_ratio on the grid of a
    reduced-engine sweep where they change nothing), SweepMismatch when `out` or its journal holds
    another sweep or is corrupted, SweepStorageError when `out` cannot be written (full disk: the
    journal is kept, re-run to resume). A failed point is not an exception: its status is "error".
    """
    return _run_sweep(scene, grid, fixed=fixed, numerics=numerics, duration=duration, engine=engine,
                      transient=transient, out=out, workers=workers, scheduler=scheduler, progress=progress,
                      retry_errors=retry_errors, timestep_check=timestep_check, snapshot_interval=snapshot_interval,
                      on_point=on_point, batch_size=batch_size).dataset()


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
) -> "_Store":
    """run_sweep's work; returns the closed store. `dataset`: the caller builds the xarray Dataset from it
    (then xarray is loaded in the background while MuJoCo points step)."""
    if workers is not None and (not isinstance(workers, (int, np.integer)) or isinstance(workers, bool) or workers < 1):
        raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
    if batch_size is not None and (not isinstance(batch_size, (int, np.integer)) or isinstance(batch_size, bool)
                                   or batch_size < 1):
        raise ParameterError(f"batch_size must be an integer >= 1, got {batch_size!r}")
    sweep = make_sweep(scene, grid, fixed=fixed, numerics=numerics, duration=duration, engine=engine,
                       transient=transient)
    for i in range(sweep.size):  # refuse an invalid point before starting
        sweep.case(i)
    out_path = Path(out) if out is not None else None
    if out_path is not None:
        out_path.parent.mkdir(parents=True, exist_ok=True)
    # import what a point needs here (not at the top: the CLI imports this module for its parser):
    # forked pool workers then start with it loaded (saves ~1 s each)
    from . import diagnose  # noqa: F401

    if engine == "mujoco":
        from .engines import mujoco, mujoco_batch  # noqa: F401
    else:
        from .engines import reduced  # noqa: F401
    store = _Store(sweep, out_path)
    store.open()
    saved = False  # the final netCDF is on disk
    try:
        status = store.arrays["status"].reshape(-1)
        todo = [i for i in range(sweep.size) if status[i] == "pending" or (retry_errors and status[i] == "error")]
        bar = None
        if progress:
            from tqdm.auto import tqdm  # start-up time: only when a bar is shown

            bar = tqdm(total=sweep.size, initial=sweep.size - len(todo), desc=f"sweep {scene}", unit="point")
        if todo:
            local = default_workers() if workers is None else int(workers)
            runner_flushes = scheduler is None and engine == "mujoco"  # yields FLUSH between groups of records
            if scheduler is not None:
                runner = _dask(todo, sweep, scheduler, timestep_check, batch_size)
            elif engine == "mujoco":
                runner = _local_mujoco(todo, sweep, local, timestep_check, batch_size, preload_xarray=dataset)
            else:
                runner = _local(todo, sweep, local, timestep_check)
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
        with _sigint_deferred():
            if todo or store.stale or not (out_path and out_path.exists()):
                store.snapshot(None)
            saved = True
            store.close(complete=bool(store.done().all()))
    except BaseException as err:
        if not saved and not isinstance(err, SweepStorageError):
            with _sigint_deferred():
                try:
                    store.snapshot(None)  # keep what is done readable; the journal has it anyway
                except Exception:
                    pass
        raise
    finally:
        store.close(complete=False)  # keeps the journal (a no-op if already closed above)
    return store


# ----------------------------------------------------------------------------- command line

"""Protocols: a ramp of one parameter up and then down in steps, each step starting from the previous step's end, for
several seeds, into one netCDF file with the direction as a coordinate (the hysteresis loop as data); resumable.

A ramp runs, for each seed, the steps value_1 .. value_K (direction "up") and then value_K .. value_1 ("down"), each
for `duration` from the last state of the step before (elastoactive.starts); the first step starts from the scene's
seeded state or from a given start (a saved run). The top value is run twice: going up, then again at the start of
the way down, continuing from where the way up ended.

Every finished step is appended to a journal beside the output (`<out>.journal`, JSON lines: a header holding the
ramp's specification, then one line per step with its measurements and the state it ended in), flushed and fsync'ed;
a re-run of the same ramp skips the finished steps and goes on from the last one's state (a torn last line, left by a
kill, is dropped and its step runs again). The same output with another ramp is refused, naming what differs. When
every step is done the netCDF is written atomically (with provenance) and only then the journal removed. Seeds run in
parallel (one process each, `workers`); the steps of one seed are sequential by nature.

The netCDF: dims seed, direction ("up", "down") and step (the ramped values, ascending, as the coordinate named after
the parameter); one variable per measured observable (a categorical one as its index, its names in flag_meanings),
`order` (when the step ran, 0-based along the ramp), where units have polarities, `unit_rate` (each unit's
|net turning rate| over the measured window, dim unit) and, where a step's measuring failed, `error` (that step's error
in one line, its measurements NaN; the step still ran, and the next starts from its end).

matplotlib is imported inside ramp_figure, the drawing's boundary: a ramp that is run without its figure never
loads it.
"""

from __future__ import annotations

import dataclasses
import fcntl
import json
import math
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .api import as_numerics, as_physics, load_sweep, measure, simulate
from .core import observables, parameters
from .core.errors import ParameterError
from .core.params import Numerics, Physics
from .io.executor import default_workers, imap
from .io.outputs import atomic_file, lock_file, provenance, utc_now, write_netcdf
from .records import error_line
from .starts import Start, as_start, last_state

DIRECTIONS = ("up", "down")
FORMAT = "elastoactive ramp journal"
"""The journal's header mark."""
MAX_STEPS = 400
"""Most steps one ramp may hold (values x 2 x seeds): hours of computing beyond."""


@dataclass(frozen=True)
class Ramp:
    """A ramp of `parameter` (a physics parameter) through `values` (ascending) up and back down, for each of
    `seeds` (Numerics.seed), each step `duration` long and measured after `transient`, in `engine`."""

    physics: Physics
    numerics: Numerics
    parameter: str
    values: tuple[float, ...]
    seeds: tuple[int, ...]
    duration: float
    transient: float
    engine: str = "reduced"
    start: Start | None = None

    def steps(self) -> list[tuple[str, int]]:
        """(direction, index into values) in the order a seed runs them."""
        up = [("up", k) for k in range(len(self.values))]
        return up + [("down", k) for k in reversed(range(len(self.values)))]

    def physics_at(self, value: float) -> Physics:
        return self.physics.replace(**{self.parameter: value})

    def numerics_of(self, seed: int) -> Numerics:
        return dataclasses.replace(self.numerics, seed=seed)

    def spec(self) -> dict:
        """What makes two ramps the same (the journal's header): everything but how many workers run it."""
        ramped = {self.parameter, parameters.get(self.parameter).instead_of}  # Pi stands for sigma
        physics = {k: _plain(v) for k, v in self.physics.given().items() if k not in ramped}
        return {
            "format": FORMAT,
            "scene": self.physics.scene,
            "physics": physics,
            "numerics": {k: _plain(v) for k, v in dataclasses.asdict(self.numerics).items() if k != "seed"},
            "parameter": self.parameter,
            "values": [float(v) for v in self.values],
            "seeds": [int(s) for s in self.seeds],
            "duration": float(self.duration),
            "transient": float(self.transient),
            "engine": self.engine,
            "start": None if self.start is None else self.start.source,
        }


def _plain(value):
    """A record's field as JSON holds it (text for anything that is not a number, a flag or text)."""
    return value if isinstance(value, (bool, int, float, str, type(None))) else str(value)


def make_ramp(
    physics,
    parameter: str,
    values: Sequence[float],
    *,
    numerics=None,
    seeds: Sequence[int] = (0,),
    duration: float,
    transient: float | None = None,
    engine: str = "reduced",
    start=None,
) -> Ramp:
    """A checked Ramp; a bad argument is refused in one line naming it."""
    physics, numerics = as_physics(physics), as_numerics(numerics)
    try:
        spec = parameters.get(parameter)
    except KeyError:
        raise ParameterError(f"ramp: {parameter!r} is not a physics parameter") from None
    if spec.kind is not float:
        raise ParameterError(f"ramp: {parameter} is not a real-valued parameter (a ramp steps a number)")
    values = tuple(float(f"{float(v):.12g}") for v in values)  # 0.3, not linspace's 0.30000000000000004
    if len(values) < 2 or any(not math.isfinite(v) for v in values) or any(b <= a for a, b in zip(values, values[1:])):
        raise ParameterError(f"ramp: {parameter}'s values must be two or more finite numbers, increasing; got {values}")
    seeds = tuple(int(s) for s in seeds)
    if not seeds or len(set(seeds)) != len(seeds) or min(seeds) < 0:
        raise ParameterError(f"seeds must be distinct integers >= 0, got {list(seeds)}")
    if 2 * len(values) * len(seeds) > MAX_STEPS:
        raise ParameterError(f"ramp: {2 * len(values) * len(seeds)} steps is more than {MAX_STEPS}; use fewer values")
    if not duration > 0:
        raise ParameterError(f"duration (in tau) must be a positive number, got {duration}")
    transient = duration / 2 if transient is None else float(transient)
    if not 0 <= transient < duration:
        raise ParameterError(f"transient must be in [0, duration = {duration:g}), got {transient:g}")
    for value in values:  # every step's physics is checked before any runs
        physics.replace(**{parameter: value})
    start = None if start is None else as_start(start).checked(physics)  # a state of this scene (elastoactive.starts)
    return Ramp(physics, numerics, parameter, values, seeds, float(duration), transient, engine, start)


# ------------------------------------------------------------------------------------------------ one step


def run_step(ramp: Ramp, seed: int, value: float, start: Start | None) -> tuple[dict, Start]:
    """One step: the run at `value` from `start` (None: the scene's seeded state), its record for the journal
    (measurements, each unit's |net turning rate|, wall time) and the state it ended in. A step whose measuring fails
    is still a step run: its record holds no measurements and `error` (one line), and the next step starts from its
    end."""
    began = time.perf_counter()
    traj = simulate(
        ramp.physics_at(value), ramp.numerics_of(seed), duration=ramp.duration, engine=ramp.engine, start=start
    )
    end = last_state(traj)
    try:
        record = {"results": _measurements(measure(traj, ramp.transient).as_dict())}
        if traj.polarity is not None and traj.polarity.size:
            keep = traj.t - traj.t[0] >= ramp.transient
            t, psi = traj.t[keep], np.unwrap(traj.polarity[keep], axis=0)
            record["unit_rate"] = (np.abs(psi[-1] - psi[0]) / (t[-1] - t[0])).tolist()
    except Exception as err:  # noqa: BLE001 (measuring failed: the step's error; the ramp goes on from its end)
        record = {"results": {}, "error": error_line(err)}
    record["wall_s"] = time.perf_counter() - began
    return record, end


def _measurements(results: dict) -> dict:
    """The numbers of Results.as_dict(): a categorical observable as its index (its spec's categories), None as NaN;
    text and lists (notes, harmonics) are left out."""
    out = {}
    for name, value in results.items():
        spec = observables.find(name)
        if spec is not None and spec.categories and value in spec.categories:
            out[name] = float(spec.categories.index(value))
        elif value is None or isinstance(value, bool):
            out[name] = math.nan if value is None else float(value)
        elif isinstance(value, (int, float)):
            out[name] = float(value)
    return out


def _state_json(start: Start) -> dict:
    if start.theta is not None:
        return {"theta": np.asarray(start.theta).tolist()}
    return {"positions": np.asarray(start.positions).tolist(), "polarity": np.asarray(start.polarity).tolist()}


def _state_of(record: dict, source: str) -> Start:
    if "theta" in record:
        return Start(theta=np.asarray(record["theta"], dtype=float), source=source)
    return Start(
        positions=np.asarray(record["positions"], dtype=float),
        polarity=np.asarray(record["polarity"], dtype=float),
        source=source,
    )


# ------------------------------------------------------------------------------------------------ the journal


def journal_path(out: Path) -> Path:
    return out.with_name(out.name + ".journal")


def read_journal(path: Path, spec: dict) -> dict[tuple[int, str, int], dict]:
    """The finished steps a journal holds, keyed (seed, direction, index); {} when there is none. A journal of
    another ramp is refused naming what differs; a torn or unreadable line (a killed run's last) is skipped."""
    if not path.is_file():
        return {}
    lines = path.read_text().splitlines()
    try:
        header = json.loads(lines[0]) if lines else None
    except json.JSONDecodeError:
        header = None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise ParameterError(f"--out: {path} is not a ramp's journal; remove it or choose another --out")
    differ = [k for k in spec if header.get(k) != json.loads(json.dumps(spec[k]))]
    if differ:
        raise ParameterError(
            f"--out: {path} holds another ramp ({', '.join(differ)} differ); rerun the same command, or choose "
            "another --out"
        )
    done = {}
    for line in lines[1:]:
        try:
            entry = json.loads(line)
            key = (int(entry["seed"]), str(entry["direction"]), int(entry["index"]))
            entry["results"], entry["state"]  # noqa: B018 (a complete line has both)
        except (json.JSONDecodeError, KeyError, TypeError, ValueError):
            continue
        done[key] = entry
    return done


def _append(path: Path, entry: dict) -> None:
    """Append one line to the journal under an exclusive lock (seeds' workers share it), flushed and fsync'ed."""
    text = json.dumps(entry, allow_nan=True) + "\n"
    with open(path, "a", encoding="utf-8") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def run_seed(job: tuple[Ramp, int, str, dict]) -> int:
    """Run one seed's steps not yet in the journal, each from the end of the one before; returns how many ran."""
    ramp, seed, journal, done = job
    start = ramp.start
    ran = 0
    for order, (direction, index) in enumerate(ramp.steps()):
        key = f"{direction}/{index}"
        if key in done:
            start = _state_of(done[key]["state"], f"journal step {order}")
            continue
        record, end = run_step(ramp, seed, ramp.values[index], start)
        entry = {"seed": seed, "direction": direction, "index": index, "order": order, **record}
        entry["state"] = _state_json(end)
        entry["finished"] = utc_now()
        _append(Path(journal), entry)
        start = end
        ran += 1
    return ran


# ------------------------------------------------------------------------------------------------ the ramp


@dataclass(frozen=True)
class RampOutcome:
    """What run_ramp did: the netCDF written, the steps it ran and those the journal already held."""

    path: Path
    ran: int
    kept: int
    wall_s: float
    errors: tuple[str, ...] = ()
    """The error of each step whose measuring failed (the netCDF's `error`), in the ramp's order."""


def run_ramp(ramp: Ramp, out, *, workers: int | None = None, progress: bool = False) -> RampOutcome:
    """Run `ramp` into the netCDF file `out` (resuming from its journal), seeds on `workers` processes (None: every
    core, at most one per seed)."""
    out = Path(out).expanduser()
    if out.suffix != ".nc":
        raise ParameterError(f"--out must name a netCDF file (.nc), got {out}")
    out.parent.mkdir(parents=True, exist_ok=True)
    began, started = time.perf_counter(), utc_now()
    journal = journal_path(out)
    spec = ramp.spec()
    with lock_file(out.with_name(out.name + ".lock"), "ramp"):
        done = read_journal(journal, spec)
        if not journal.is_file() or journal.stat().st_size == 0:
            journal.write_text(json.dumps(spec) + "\n")
        jobs = [
            (ramp, seed, str(journal), {f"{d}/{i}": e for (s, d, i), e in done.items() if s == seed})
            for seed in ramp.seeds
        ]
        workers = min(default_workers() if workers is None else int(workers), len(jobs))
        ran = 0
        if workers <= 1:
            for job in jobs:
                ran += run_seed(job)
                _say(progress, f"seed {job[1]} done")
        else:
            for k, count in imap(run_seed, jobs, workers, completed=True):
                ran += count
                _say(progress, f"seed {jobs[k][1]} done")
        done = read_journal(journal, spec)
        missing = [key for key in _keys(ramp) if key not in done]
        if missing:
            raise ParameterError(f"ramp: {len(missing)} step(s) did not finish; rerun the same command to resume")
        wall = time.perf_counter() - began
        write_ramp(out, ramp, done, provenance(started, wall))
        journal.unlink()
    errors = tuple(done[key]["error"] for key in _keys(ramp) if done[key].get("error"))
    return RampOutcome(out, ran, len(_keys(ramp)) - ran, wall, errors)


def _say(shown: bool, text: str) -> None:
    if shown:
        print(f"elastoactive ramp: {text}", flush=True)


def _keys(ramp: Ramp) -> list[tuple[int, str, int]]:
    return [(s, d, i) for s in ramp.seeds for d, i in ramp.steps()]


def write_ramp(out: Path, ramp: Ramp, done: dict, record: dict) -> None:
    """The netCDF of a finished ramp (the module's docstring), written atomically."""
    shape = (len(ramp.seeds), len(DIRECTIONS), len(ramp.values))
    names = list(dict.fromkeys(name for entry in done.values() for name in entry["results"]))
    arrays = {name: np.full(shape, np.nan) for name in names}
    order = np.full(shape, -1, dtype=int)
    units = max((len(e.get("unit_rate", ())) for e in done.values()), default=0)
    rates = np.full(shape + (units,), np.nan)
    for (seed, direction, index), entry in done.items():
        at = (ramp.seeds.index(seed), DIRECTIONS.index(direction), index)
        for name, value in entry["results"].items():
            arrays[name][at] = np.nan if value is None else value
        order[at] = entry["order"]
        if units and entry.get("unit_rate"):
            rates[at] = entry["unit_rate"]
    dims = ("seed", "direction", ramp.parameter)
    variables = {name: (dims, values, _attrs(name)) for name, values in arrays.items()}
    if any(entry.get("error") for entry in done.values()):  # steps whose measuring failed: their error, one line
        errors = np.full(shape, "", dtype=object)
        for (seed, direction, index), entry in done.items():
            errors[ramp.seeds.index(seed), DIRECTIONS.index(direction), index] = entry.get("error", "")
        variables["error"] = (dims, errors, {"long_name": "why the step was not measured (empty: measured)"})
    variables["order"] = (dims, order, {"long_name": "when the step ran along its seed's ramp (0: first)"})
    if units:
        variables["unit_rate"] = (
            dims + ("unit",),
            rates,
            {"units": "rad/tau", "long_name": "each active unit's |net turning rate| over the measured window"},
        )
    coords = {
        "seed": (("seed",), np.array(ramp.seeds), {"long_name": "seed of the first step's initial state"}),
        "direction": (("direction",), np.array(DIRECTIONS, dtype=object), {"long_name": "the ramp's leg"}),
        ramp.parameter: ((ramp.parameter,), np.array(ramp.values), _parameter_attrs(ramp.parameter)),
    }
    if units:
        coords["unit"] = (("unit",), np.arange(units), {"long_name": "active unit, in node order"})
    attrs = {
        "title": f"ramp of {ramp.parameter} up and down, {ramp.physics.scene}",
        "ramp": json.dumps(ramp.spec()),
        "provenance": json.dumps(record),
    }
    with atomic_file(out) as tmp:
        write_netcdf(tmp, variables, coords, attrs)


def _attrs(name: str) -> dict:
    spec = observables.find(name)
    if spec is None:
        return {}
    attrs = {"units": spec.units, "long_name": spec.long_name}
    if spec.categories:
        attrs.update(flag_values=np.arange(len(spec.categories), dtype=float), flag_meanings=" ".join(spec.categories))
    return attrs


def _parameter_attrs(name: str) -> dict:
    try:
        found = parameters.get(name)
    except KeyError:
        return {"long_name": name}
    return {"long_name": found.help, "units": found.units}


# ------------------------------------------------------------------------------------------------ the figure

DEFAULT_PLOTS = ("polarity_speed", "amplitude")
"""What a ramp's figure shows when not told: the first of these the ramp measured."""


def ramp_figure(path, figure, observable: str | None = None) -> Path:
    """The hysteresis loop of a ramp's netCDF `path` as a PNG `figure`: `observable` (default: DEFAULT_PLOTS' first
    measured) against the ramped parameter, each seed's way up (filled markers, solid) and down (open, dashed)."""
    import matplotlib  # start-up time: matplotlib only when a figure is drawn
    import matplotlib.pyplot as plt  # start-up time: as above

    matplotlib.use("Agg")
    data = load_sweep(path)
    spec = json.loads(data.attrs["ramp"])
    parameter = spec["parameter"]
    if observable is None:
        observable = next((name for name in DEFAULT_PLOTS if name in data), None)
    if observable not in data:
        measured = ", ".join(name for name in data.data_vars if data[name].dims[:3] == ("seed", "direction", parameter))
        raise ParameterError(f"--plot: {observable!r} was not measured by this ramp (measured: {measured})")
    values = data[parameter].values
    fig, ax = plt.subplots(figsize=(5.5, 4.0))
    for k, seed in enumerate(data.seed.values):
        colour = f"C{k % 10}"
        for direction, style, fill in (("up", "-", colour), ("down", "--", "none")):
            y = data[observable].sel(seed=seed, direction=direction).values
            ax.plot(values, y, style, marker="o", color=colour, mfc=fill, label=f"seed {seed}, {direction}")
    variable = data[observable]
    units = variable.attrs.get("units", "")
    ax.set_xlabel(
        f"{parameter}"
        + (
            f" [{data[parameter].attrs.get('units')}]"
            if data[parameter].attrs.get("units") not in (None, "", "1")
            else ""
        )
    )
    ax.set_ylabel(observable + (f" [{units}]" if units not in ("", "1") else ""))
    ax.set_title(f"{spec['scene']}: {parameter} up (filled) and down (open)", fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    figure = Path(figure)
    with atomic_file(figure) as tmp:
        fig.savefig(tmp, dpi=120, format="png")
    plt.close(fig)
    return figure

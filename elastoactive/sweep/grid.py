"""A sweep's grid and specification: what can be swept, parsing `--grid`, the `Sweep` (its cases, its
specification, what must match to resume), and the names and netCDF attributes of what a sweep records.

A grid axis is a comma list ('kappa=0.5,1,2') or 'start:stop:num' (num evenly spaced values, both ends
included). Numerical settings only MuJoCo reads (dt, integrator) are refused on the grid of a
reduced-engine sweep, where they change nothing (dt is allowed when noise > 0: it is then the
Euler-Maruyama step).
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ..batch import Case
from ..core import observables, registry
from ..core.errors import ParameterError
from ..core.observables import HARMONICS
from ..core.parameters import get as parameter_spec
from ..core.parameters import stochastic
from ..core.params import Numerics, Physics, parameter_fields, scene_parameters
from ..engines import MUJOCO_ONLY, check_engine, check_engine_numerics  # noqa: F401  (re-exported)

NUMERICS_KEYS = ("seed", "dt", "mass_ratio", "perturbation", "sample_dt")

MAX_GRID_POINTS = 10_000
"""Most points one grid may have: a point costs at least ~0.1 s (a short reduced-engine run and its measures), and a
MuJoCo point of the default 300 tau ~1 s, so 10 000 points already take hours on 2 cores. A larger grid is refused
when it is parsed (split it into several sweeps, each resumable)."""


def physics_keys() -> tuple[str, ...]:
    """Every declared physics parameter (elastoactive.core.parameters: the chain's, the terms', the scenes'), read when
    asked, so that a term or scene registered later is there too."""
    return tuple(f.name for f in parameter_fields(Physics))


def grid_keys() -> tuple[str, ...]:
    """What a grid can sweep: the numeric physics parameters and the numerical settings (a switch or a text value,
    like contact or loaded, is given as a fixed value instead)."""
    return tuple(f.name for f in parameter_fields(Physics) if f.kind in (int, float)) + NUMERICS_KEYS


def _integer(name: str) -> bool:
    return name == "seed" or (name in physics_keys() and parameter_spec(name).kind is int)


FORMAT = 1


VECTORS = {"harmonics": ("harmonic", HARMONICS)}
"""Measurements with several values per point (and chain): their extra dimension and its size. `harmonics`
(results.Results.harmonics): harmonics 1 .. HARMONICS of Theta, on a dimension `harmonic` (1: the fundamental)."""


def scene_variables(scene: str) -> tuple[str, ...]:
    """Measured variables of a scene (results.measure), present even before any point is done: amplitude,
    frequency, whether the motion is periodic and its period spread, the scene's observables and, for a
    pinned scene, the pin's largest violation. (Each point's notes are a text variable besides these.)"""
    s = registry.get(scene)
    names = ("amplitude", "frequency", "periodic", "period_spread", *s.observable_names())
    return tuple(dict.fromkeys(names)) + (("constraint_violation",) if s.pinned else ())


def variable_attrs(name: str) -> dict:
    """The netCDF attributes of a recorded variable: a declared observable's units and long name (and a categorical
    one's flag values and meanings) from its spec (elastoactive.core.observables), else VARIABLE_ATTRS' entry ({} for a
    value nothing declares)."""
    spec = observables.find(name)
    if spec is None:
        return VARIABLE_ATTRS.get(name, {})
    attrs = dict(units=spec.units, long_name=spec.long_name)
    if spec.categories:
        attrs.update(flag_values=np.arange(len(spec.categories), dtype=float), flag_meanings=" ".join(spec.categories))
    return attrs


VARIABLE_ATTRS = {
    "periodic": dict(
        units="1",
        long_name="whether the motion is periodic (results.Results.periodic)",
        flag_values=np.array([1.0, 0.0]),
        flag_meanings="periodic irregular",
        comment="1: a steady state or a regular beat (amplitude and frequency describe it); 0: irregular (cycle "
        "periods or amplitudes vary by more than 1% - noise, chaos, or a beat still growing: amplitude and "
        "frequency are averages); NaN: the measured window holds too few cycles to tell, or the point "
        "failed",
    ),
    "notes": dict(
        long_name="what to know about the point's numbers (results.Results.notes, joined with '; '); "
        "empty when there is nothing to say"
    ),
    "constraint_violation": dict(units="l", long_name="largest distance of the last particle from its pin"),
    "wall_time_s": dict(
        units="s",
        long_name="wall time of the simulation (without measuring); for MuJoCo points run "
        "together in one mujoco.batch, its share: batch wall time x threads / points",
    ),
    "finished_at": dict(long_name="when the point finished"),
    "status": dict(long_name="ok, error (see error) or pending (not run yet)"),
    "error": dict(long_name="error text of a failed point (empty if ok)"),
}


DIMENSION_ATTRS = {
    "chain": dict(long_name="chain (1: C1, 2: C2 = rho C1)"),
    "harmonic": dict(long_name="harmonic number (1: the fundamental)"),
}
"""Attributes of the dimensions that are not parameters."""


def coordinate_attrs(name: str) -> dict:
    """netCDF attributes of a grid coordinate: a physics parameter's help text and units from its spec
    (elastoactive.core.parameters), a numerical setting's help text (Numerics' fields), or a dimension's."""
    if name in DIMENSION_ATTRS:
        return dict(DIMENSION_ATTRS[name])
    if name in physics_keys():
        spec = parameter_spec(name)
        return {"long_name": spec.help, "units": spec.units}
    (field,) = [f for f in parameter_fields(Numerics) if f.name == name]
    return {"long_name": field.metadata["help"]}


class SweepMismatch(ParameterError):
    """The output file holds a different sweep (or is not a sweep file)."""


class SweepStorageError(ParameterError):
    """The netCDF (or the journal) cannot be written, e.g. the disk is full; the message names the
    file and the space needed. The journal keeps every point recorded before: free the space and
    re-run the same sweep to resume."""


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
            _check_size({name: int(num)})
            values = np.linspace(start, stop, int(num))
        else:
            items = [v.strip() for v in text.split(",")]
            if not all(items):
                raise ValueError
            values = np.array([float(v) for v in items])
    except ParameterError:  # a grid too large (_check_size)
        raise
    except ValueError:
        raise ParameterError(
            f"grid {name}={text!r}: expected a comma list (e.g. {name}=0.5,1,2) or start:stop:num "
            f"(e.g. {name}=0.2:1.0:9)"
        ) from None
    return _axis(name, values)


def _check_size(sizes: Mapping[str, int]) -> None:
    """Refuse a grid of more than MAX_GRID_POINTS points (one line naming the axes and their sizes)."""
    total = math.prod(sizes.values())
    if total > MAX_GRID_POINTS:
        axes = " x ".join(f"{name} {size}" for name, size in sizes.items())
        raise ParameterError(
            f"grid: {axes} = {total} points, more than {MAX_GRID_POINTS} (at 0.1-1 s a point, hours "
            "to days on 2 cores); use fewer values, or split the grid into several sweeps"
        )


EXACT_INTEGER = 2**53
"""The largest integer a grid's values (read as floating-point numbers) hold exactly."""


def _axis(name: str, values) -> np.ndarray:
    values = np.atleast_1d(np.asarray(values, dtype=float))
    if values.ndim != 1 or values.size == 0:
        raise ParameterError(f"grid {name}: needs at least one value")
    if not np.all(np.isfinite(values)):
        raise ParameterError(f"grid {name}: values must be finite, got {values.tolist()}")
    if _integer(name):
        if not np.all(values == np.round(values)):
            raise ParameterError(f"grid {name}: values must be integers, got {values.tolist()}")
        inexact = values[np.abs(values) > EXACT_INTEGER]
        if inexact.size:
            raise ParameterError(
                f"grid {name}: {inexact[0]:.17g} is past the integers a grid holds exactly (|value| <= 2^53 = "
                f"{EXACT_INTEGER})"
            )
        values = values.astype(np.int64)
    if len(set(values.tolist())) != values.size:  # (np.unique would load numpy.ma, ~10 ms of start-up)
        raise ParameterError(f"grid {name}: repeated values {values.tolist()}")
    return values


def _key(name: str) -> str:
    key = name.strip().replace("-", "_")
    if key not in grid_keys():
        if key in physics_keys():
            raise ParameterError(
                f"grid: {key} is not a number and cannot be swept; give it as a fixed value "
                f"({parameter_spec(key).option}) and run one sweep per value"
            )
        raise ParameterError(f"grid: unknown parameter {name!r}; choose from {', '.join(grid_keys())}")
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
    _check_size({k: v.size for k, v in grid.items()})
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
    _check_size({k: v.size for k, v in out.items()})
    return out


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
    _cases: dict[int, Case] = dataclasses.field(default_factory=dict, init=False, repr=False, compare=False)
    """The cases built so far, by flat index (a point's case is built once: its physics is validated then)."""

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(v.size for v in self.grid.values())

    @property
    def size(self) -> int:
        return math.prod(self.shape)

    @property
    def chains(self) -> int:
        """Chains of every point (Scene.chain_count: the star's arms; make_sweep keeps it the same over the grid)."""
        return self.physics.n_chains

    @property
    def fixed(self) -> dict:
        """The scene's physics parameters that are not on the grid, nor set by one on it (sigma by the coupling Pi:
        Parameter.instead_of)."""
        replaced = {parameter_spec(k).instead_of for k in self.grid if k in physics_keys()}
        return {
            k: v
            for k, v in self.physics.relevant().items()
            if k != "scene" and k not in self.grid and k not in replaced
        }

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
        """The point's Case (its physics and numerics with the grid's values); an invalid point is a ParameterError
        naming it. Built once per point (cases are immutable)."""
        if flat in self._cases:
            return self._cases[flat]
        point = self.coords(flat)
        try:
            physics = self.physics.replace(**{k: v for k, v in point.items() if k in physics_keys()})
            numerics = dataclasses.replace(self.numerics, **{k: v for k, v in point.items() if k in NUMERICS_KEYS})
        except ParameterError as err:
            raise ParameterError(f"grid point {point}: {err}") from None
        case = self._cases[flat] = Case(physics, numerics, self.duration, self.engine, self.transient)
        return case


def _chains(physics: Physics, key: str, value) -> int | None:
    """Chains of `physics` with `key` at `value` (None: the value alone is refused; the grid point says why)."""
    try:
        return physics.replace(**{key: value}).n_chains
    except ParameterError:
        return None


def _base_physics(scene: str, fixed: dict, grid: dict, first: dict) -> Physics:
    """The physics the grid's points replace values of: the fixed values with the first point's, or, where a fixed
    value's switch is swept and off at the first point (clamp_frequency with clamp_amplitude = 0, the undriven
    baseline), with the first value of that switch on the grid at which every fixed value acts (Sweep.case drops a
    fixed value at the points where its switch is off, as Physics.replace does). Refused as the first point is when
    no such value exists."""
    swept = {k: v for k, v in first.items() if k in physics_keys()}
    candidates = [swept] + [
        {**swept, key: value.item()} for key, values in grid.items() if key in physics_keys() for value in values[1:]
    ]
    refusal = None
    for point in candidates:
        try:
            return Physics(scene=scene, **fixed, **point)
        except ParameterError as err:
            refusal = refusal or err
    raise ParameterError(f"grid point {first}: {refusal}") from None


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
    bad = sorted(set(fixed) - set(physics_keys()))
    if bad:
        raise ParameterError(
            f"fixed: unknown physics parameter(s) {', '.join(bad)}; choose from {', '.join(physics_keys())} "
            "(numerical settings go in numerics)"
        )
    both = [k for k in grid if k in fixed]
    if both:
        raise ParameterError(f"{', '.join(both)} given both as a fixed value and on the grid")
    used = set(scene_parameters(registry.get(scene))) | {"scene"}
    unused = [k for k in grid if k in physics_keys() and k not in used]
    if unused:
        raise ParameterError(
            f"grid: {', '.join(unused)} has no effect on scene {scene} "
            f"(its parameters: {', '.join(sorted(used - {'scene'}))})"
        )
    first = {k: v[0].item() for k, v in grid.items()}
    try:
        numerics = dataclasses.replace(numerics, **{k: v for k, v in first.items() if k in NUMERICS_KEYS})
    except ParameterError as err:
        raise ParameterError(f"grid point {first}: {err}") from None
    physics = _base_physics(scene, fixed, grid, first)
    for key, values in grid.items():  # the per-chain results have one shape: the chains may not change on the grid
        if key in physics_keys() and any(
            _chains(physics, key, v.item()) not in (None, physics.n_chains) for v in values
        ):
            raise ParameterError(
                f"grid: {key} changes the number of chains of scene {scene}; sweep one value of "
                f"{key} at a time (--{key.replace('_', '-')} as a fixed value)"
            )
    noisy = stochastic(physics, grid)
    check_engine_numerics(engine, [k for k in grid if k in MUJOCO_ONLY], noisy, lambda k: f"grid {k}")
    return Sweep(scene, grid, physics, numerics, duration, engine, None if transient is None else float(transient))


def spec_text(spec: dict) -> str:
    return json.dumps(spec, sort_keys=True)


def spec_differences(mine: dict, theirs: dict) -> list[str]:
    out = []
    for key in sorted(set(mine) | set(theirs)):
        a, b = mine.get(key), theirs.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            out += [f"{key}.{d}" for d in spec_differences(a, b)]
        elif key == "grid" and isinstance(a, list) and isinstance(b, list):
            da, db = dict((k, v) for k, v in a), dict((k, v) for k, v in b)
            if [k for k, _ in a] != [k for k, _ in b]:
                out.append(f"grid parameters: {[k for k, _ in a]} here, {[k for k, _ in b]} in the file")
            for k in sorted(set(da) & set(db)):
                if da[k] != db[k]:
                    out.append(f"grid {k}: {da[k]} here, {db[k]} in the file")
        elif spec_text({"v": a}) != spec_text({"v": b}):
            out.append(f"{key}: {a!r} here, {b!r} in the file")
    return out


def check_spec(path: Path, mine: dict, theirs: dict | None) -> None:
    if theirs is None:
        raise SweepMismatch(
            f"{path} exists but is not an elastoactive sweep file; refusing to overwrite it. "
            "Choose another --out or remove the file."
        )
    if spec_text(mine) != spec_text(theirs):
        diff = "; ".join(spec_differences(mine, theirs)) or "format"
        raise SweepMismatch(
            f"{path} holds a different sweep ({diff}). To resume it, repeat its exact grid and "
            "parameters; to start a new sweep, choose another --out or remove the file "
            f"(and {journal_path(path).name} if present)."
        )


def journal_path(out: Path) -> Path:
    return out.with_name(out.name + ".journal")

"""What every study shares: the `Study` container, typed summaries and their JSON form, the sizes,
and running a batch of cases.

A study's `summary` is a frozen dataclass (a `Summary`); the numbers in it are plain floats, ints,
bools, strings, complex numbers, `analysis.fits.Fit`, lists, tuples, dicts keyed by strings and
nested summaries. `to_jsonable` writes that as JSON (non-finite floats as the strings "nan",
"inf", "-inf", so that a saved study reads back unchanged) and `from_jsonable` rebuilds it from
the dataclass's type hints.
"""

from __future__ import annotations

import dataclasses
import json
import math
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, TypeVar

import numpy as np

from ..outputs import write_files

from ..analysis.fits import Fit
from ..batch import Case, run_cases
from ..engines import ENGINES
from ..params import Numerics
from ..trajectory import Trajectory

__all__ = [
    "ENGINES", "SIZES", "Study", "Summary", "EngineParts", "check_size", "pick", "run", "fast", "safe", "try_fit",
    "downsample", "to_jsonable", "from_jsonable",
]

SIZES = ("tiny", "quick", "full")
"""tiny: tests (seconds); quick: the default reproduce run (minutes); full: publication resolution."""

S = TypeVar("S", bound="Summary")


# --------------------------------------------------------------------------------------------------
# typed summaries
# --------------------------------------------------------------------------------------------------
class Summary:
    """Base of the summary dataclasses: their JSON form and back."""

    def as_dict(self) -> dict:
        """The summary as JSON-ready nested dicts and lists."""
        return to_jsonable(self)

    @classmethod
    def from_dict(cls: type[S], data: dict) -> S:
        """The summary back from `as_dict`'s form."""
        return from_jsonable(cls, data)


class EngineParts(Summary):
    """A summary with one nested part per engine, in fields named after the engines."""

    def engine(self, name: str):
        """The part of engine `name` ("mujoco" or "reduced"); None where the study did not run it."""
        if name not in ENGINES:
            raise ValueError(f"engine must be one of {', '.join(ENGINES)}; got {name!r}")
        return getattr(self, name)


_NONFINITE = {"nan": math.nan, "inf": math.inf, "-inf": -math.inf}


def to_jsonable(v):
    """Nested dataclasses, containers and numpy scalars/arrays as JSON values."""
    if isinstance(v, Fit):
        return {"params": to_jsonable(v.params), "errors": to_jsonable(v.errors), "r2": to_jsonable(v.r2),
                "n": int(v.n), "extra": to_jsonable(v.extra)}
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return {f.name: to_jsonable(getattr(v, f.name)) for f in dataclasses.fields(v)}
    if isinstance(v, dict):
        return {str(k): to_jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [to_jsonable(x) for x in v]
    if isinstance(v, np.ndarray):
        return to_jsonable(v.tolist())
    if isinstance(v, (complex, np.complexfloating)):
        return {"re": to_jsonable(float(v.real)), "im": to_jsonable(float(v.imag))}
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isfinite(v):
            return v
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    return v


def _untyped(v):
    """A JSON value read without a type hint (e.g. a Fit's extra): only non-finite floats decoded."""
    if isinstance(v, str) and v in _NONFINITE:
        return _NONFINITE[v]
    if isinstance(v, dict):
        return {k: _untyped(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_untyped(x) for x in v]
    return v


def from_jsonable(tp, v):
    """Rebuild a value of type `tp` (a type hint) from its `to_jsonable` form."""
    origin = typing.get_origin(tp)
    if origin in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        if v is None:
            return None
        return from_jsonable(args[0], v) if len(args) == 1 else _untyped(v)
    if tp is Any or tp is None:
        return _untyped(v)
    if v is None:
        return math.nan if tp is float else None
    if tp is Fit:
        return Fit({k: from_jsonable(float, x) for k, x in v["params"].items()},
                   {k: from_jsonable(float, x) for k, x in v["errors"].items()},
                   from_jsonable(float, v["r2"]), int(v["n"]), _untyped(v.get("extra", {})))
    if isinstance(tp, type) and dataclasses.is_dataclass(tp):
        hints = typing.get_type_hints(tp)
        return tp(**{f.name: from_jsonable(hints[f.name], v[f.name]) for f in dataclasses.fields(tp)
                     if f.init and f.name in v})
    if tp is float:
        return _NONFINITE[v] if isinstance(v, str) else float(v)
    if tp is complex:
        return complex(from_jsonable(float, v["re"]), from_jsonable(float, v["im"]))
    if tp in (int, bool, str):
        return tp(v)
    if origin is list:
        (arg,) = typing.get_args(tp) or (Any,)
        return [from_jsonable(arg, x) for x in v]
    if origin is tuple:
        args = typing.get_args(tp)
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(from_jsonable(args[0], x) for x in v)
        return tuple(from_jsonable(a, x) for a, x in zip(args, v))
    if origin is dict:
        _, arg = typing.get_args(tp) or (str, Any)
        return {k: from_jsonable(arg, x) for k, x in v.items()}
    if tp in (list, tuple, dict):
        return tp(_untyped(v))
    return _untyped(v)


# --------------------------------------------------------------------------------------------------
# the container
# --------------------------------------------------------------------------------------------------
@dataclass
class Study:
    """What a study produced: arrays behind its figures (`data`, saved as NPZ) and the numbers the
    report quotes (`summary`, a Summary dataclass, saved as JSON)."""

    name: str
    size: str
    data: dict = field(default_factory=dict)
    summary: Summary | None = None
    wall_s: float = 0.0

    def save(self, folder: Path, provenance: dict | None = None) -> list[Path]:
        """<name>.npz and <name>.json in `folder`, written atomically together (the JSON, which may carry
        the provenance record of elastoactive.outputs, last)."""
        record = {"study": self.name, "size": self.size, "wall_s": to_jsonable(self.wall_s),
                  "summary": to_jsonable(self.summary)}
        if provenance is not None:
            record["provenance"] = provenance
        return write_files(Path(folder), {
            f"{self.name}.npz": lambda tmp: np.savez_compressed(tmp, **{k: np.asarray(v) for k, v in self.data.items()}),
            f"{self.name}.json": lambda tmp: tmp.write_text(json.dumps(record, indent=2) + "\n"),
        })

    @classmethod
    def load(cls, folder: Path, name: str, summary_type: type[Summary]) -> "Study":
        """Read back a study saved by `save`, its summary as `summary_type`."""
        folder = Path(folder)
        meta = json.loads((folder / f"{name}.json").read_text())
        with np.load(folder / f"{name}.npz") as f:
            data = {k: f[k] for k in f.files}
        summary = from_jsonable(summary_type, meta["summary"]) if meta.get("summary") is not None else None
        return cls(name, meta["size"], data, summary, from_jsonable(float, meta.get("wall_s", 0.0)))


# --------------------------------------------------------------------------------------------------
# plumbing shared by the study modules
# --------------------------------------------------------------------------------------------------
def check_size(size: str) -> str:
    if size not in SIZES:
        raise ValueError(f"size must be one of {', '.join(SIZES)}; got {size!r}")
    return size


def pick(size: str, tiny, quick, full):
    """The value for this size."""
    return {"tiny": tiny, "quick": quick, "full": full}[check_size(size)]


def run(cases: list[Case], workers, progress: bool, desc: str) -> list[Trajectory]:
    """Trajectories of the cases (input order), on `workers` processes (None: every core)."""
    if not cases:
        return []
    res = run_cases(cases, workers=workers, progress=progress, keep_trajectory=True, desc=desc)
    return [r.trajectory for r in res]


def fast(**kw) -> Numerics:
    """The 'fast' MuJoCo preset with overrides."""
    return Numerics.preset("fast", **kw)


def safe(fn: Callable, *args, default=float("nan"), **kw):
    """fn(*args, **kw), or `default` when it fails numerically."""
    try:
        return fn(*args, **kw)
    except (ValueError, RuntimeError, np.linalg.LinAlgError):
        return default


def try_fit(fit_fn: Callable[..., Fit], *args, **kw) -> Fit | None:
    """The fit, or None when there are too few points or it does not converge."""
    return safe(fit_fn, *args, default=None, **kw)


def downsample(a: np.ndarray, n: int = 2000) -> np.ndarray:
    step = max(1, a.shape[0] // n)
    return a[::step]

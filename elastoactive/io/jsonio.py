"""The package's one JSON converter: Python and numpy values as JSON values, and back from them.

`to_jsonable` turns nested dataclasses (e.g. a study's summary, analysis.fits.Fit), dicts (keys as
text), lists, tuples, numpy arrays, numpy scalars and complex numbers ({"re": .., "im": ..}) into
plain JSON values. JSON has no NaN or infinity; `nonfinite` says how such a float is written:

  "null"  None (summary.json: "could not be measured" reads as null in any JSON reader)
  "text"  the strings "nan", "inf", "-inf" (a study's JSON: read back unchanged by from_jsonable)
  "keep"  the float itself (json.dumps writes NaN / Infinity; the sweep's journal, read by Python)

`from_jsonable(tp, value)` rebuilds a value of the type hint `tp` from its "text" form (dataclasses
through their type hints).
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from typing import Any

import numpy as np

__all__ = ["NONFINITE", "to_jsonable", "from_jsonable"]

NONFINITE = ("null", "text", "keep")
"""How to_jsonable writes a float that is NaN or infinite (see the module docstring)."""

_TEXT = {"nan": math.nan, "inf": math.inf, "-inf": -math.inf}


def to_jsonable(value, nonfinite: str = "text"):
    """`value` as JSON values: nested dataclasses, containers and numpy scalars/arrays; non-finite floats as
    `nonfinite` says ("null", "text" or "keep")."""
    if nonfinite not in NONFINITE:
        raise ValueError(f"nonfinite must be one of {', '.join(NONFINITE)}, got {nonfinite!r}")
    return _convert(value, nonfinite)


def _convert(v, nonfinite: str):
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return {f.name: _convert(getattr(v, f.name), nonfinite) for f in dataclasses.fields(v)}
    if isinstance(v, dict):
        return {str(k): _convert(x, nonfinite) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_convert(x, nonfinite) for x in v]
    if isinstance(v, np.ndarray):
        return _convert(v.tolist(), nonfinite)
    if isinstance(v, (complex, np.complexfloating)):
        return {"re": _convert(float(v.real), nonfinite), "im": _convert(float(v.imag), nonfinite)}
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, np.integer):
        return int(v)
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isfinite(v) or nonfinite == "keep":
            return v
        if nonfinite == "null":
            return None
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    return v


def _untyped(v):
    """A JSON value read without a type hint (e.g. a fit's extra): only non-finite floats decoded."""
    if isinstance(v, str) and v in _TEXT:
        return _TEXT[v]
    if isinstance(v, dict):
        return {k: _untyped(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_untyped(x) for x in v]
    return v


def from_jsonable(tp, v):
    """Rebuild a value of type `tp` (a type hint) from its `to_jsonable` form (nonfinite="text")."""
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
    if isinstance(tp, type) and dataclasses.is_dataclass(tp):
        hints = typing.get_type_hints(tp)
        return tp(
            **{
                f.name: from_jsonable(hints[f.name], v[f.name])
                for f in dataclasses.fields(tp)
                if f.init and f.name in v
            }
        )
    if tp is float:
        return _TEXT[v] if isinstance(v, str) else float(v)
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

"""How a note, a summary line, a caption or a label writes a measured value: one path for every result shape.

A scene's result is a number, None (not measured), NaN (not defined), or one value per chain (a tuple or list: the
coupled pair's chains, the star's arms), any of whose entries may be None or NaN. Every text that quotes a result
formats it here, so that no producer assumes one chain: `text` writes any of these shapes, `text_with_error` a
value beside its standard error (per chain where either is per chain). A leaf module: it imports nothing of the
package.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

NOT_MEASURED = "not measured"
"""What a text says for a value that could not be measured (None) or is not defined (NaN)."""


def per_chain(value) -> bool:
    """Whether `value` holds one entry per chain (a tuple or list), rather than one number."""
    return isinstance(value, (tuple, list))


def _one(value, spec: str) -> str:
    if value is None or isinstance(value, bool):
        return NOT_MEASURED if value is None else str(value).lower()
    try:
        number = float(value)
    except (TypeError, ValueError):
        return str(value)
    return NOT_MEASURED if math.isnan(number) else format(number, spec)


def text(value, spec: str = ".4g", unit: str = "") -> str:
    """A result as text: '0.1234 rad'; 'not measured' for None or NaN; '0.1234, 0.1301 rad (chains 1, 2)' for one
    value per chain. A category (a string) is written as it is."""
    suffix = f" {unit}" if unit else ""
    if not per_chain(value):
        written = _one(value, spec)
        return written + (suffix if written != NOT_MEASURED else "")
    items = [_one(v, spec) for v in value]
    if not items:
        return NOT_MEASURED
    return ", ".join(items) + suffix + f" (chains {', '.join(str(k + 1) for k in range(len(items)))})"


def _pair(value, error, spec: str, error_spec: str) -> str:
    written = _one(value, spec)
    if written == NOT_MEASURED or error is None or (isinstance(error, float) and math.isnan(error)):
        return written
    return f"{written} +- {_one(error, error_spec)}"


def text_with_error(value, error, spec: str = ".4g", error_spec: str = ".2g", unit: str = "") -> str:
    """A result beside its standard error, '0.1234 +- 0.0012 rad', per chain where either is per chain ('0.1234 +-
    0.0012, 0.1301 +- 0.002 rad (chains 1, 2)'); a missing error leaves the value alone, a missing value says 'not
    measured'."""
    suffix = f" {unit}" if unit else ""
    if not (per_chain(value) or per_chain(error)):
        return _pair(value, error, spec, error_spec) + suffix
    count = max(len(value) if per_chain(value) else 1, len(error) if per_chain(error) else 1)
    pairs = [_pair(v, e, spec, error_spec) for v, e in zip(_spread(value, count), _spread(error, count))]
    return ", ".join(pairs) + suffix + f" (chains {', '.join(str(k + 1) for k in range(count))})"


def _spread(value, count: int) -> Sequence:
    """One entry per chain: a per-chain value as it is, a single one for the first chain (None: no entry)."""
    items = list(value) if per_chain(value) else [value]
    return items + [None] * (count - len(items))


def entries(value) -> tuple:
    """The value's entries: one per chain, or the value alone."""
    return tuple(value) if per_chain(value) else (value,)


__all__ = ["NOT_MEASURED", "entries", "per_chain", "text", "text_with_error"]

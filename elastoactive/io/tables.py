"""What a command prints of a run's results, by one rule: a short table with units for a person (the default), its rows
on one line with --quiet, the full record as JSON with --json. The notes are printed apart, as warnings (the command
does that, on stderr), and the details of the beat (DETAIL) are left to the JSON and summary.json.

Pure formatting: no simulation, no file; the command hands it summary.json's results and their units.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping

DETAIL = ("notes", "period_spread", "harmonics")
"""Results the table and the line leave out: the notes (printed as warnings) and the beat's details (in the JSON)."""
MISSING = "-"
"""How a value that was not measured (None, NaN) is shown."""


def _number(value) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return MISSING
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def shown(value) -> str:
    """A result as a person reads it: 4 significant digits, yes/no, '-' when not measured, per chain joined by ', '."""
    if isinstance(value, (list, tuple)):
        return ", ".join(_number(v) for v in value)
    return _number(value)


def rows(results: Mapping, units: Mapping[str, str]) -> list[tuple[str, str, str]]:
    """(name, value, units) of every result a person reads, in the results' order (DETAIL left out); a dimensionless
    result (no units, or '1') has units ''."""
    out = []
    for name, value in results.items():
        if name in DETAIL or isinstance(value, Mapping):
            continue
        unit = units.get(name) or ""
        out.append((name, shown(value), "" if unit == "1" else unit))
    return out


def table(results: Mapping, units: Mapping[str, str], title: str = "") -> str:
    """The results as an aligned table of name, value and units, under `title` when given."""
    lines = [title] if title else []
    found = rows(results, units)
    if found:
        width = [max(len(row[k]) for row in found) for k in range(2)]
        lines += [f"  {name:<{width[0]}}  {value:<{width[1]}}  {unit}".rstrip() for name, value, unit in found]
    return "\n".join(lines)


def line(results: Mapping, units: Mapping[str, str]) -> str:
    """The results on one line: 'amplitude 2.905 rad, frequency 0.04247 1/tau, periodic yes'."""
    return ", ".join(" ".join(part for part in row if part) for row in rows(results, units))


def results_text(
    record: Mapping, results: Mapping, units: Mapping[str, str], *, as_json: bool, quiet: bool, title: str = ""
) -> str:
    """What a command prints of a run's results: `record` as indented JSON (as_json), else the results' line (quiet),
    else their table under `title`."""
    if as_json:
        return json.dumps(record, indent=2)
    if quiet:
        return line(results, units)
    return table(results, units, title)

"""How a message names a setting: as the command line spells it (`--dt 0.025 --mass-ratio 0.0001`) or as Python does
(`numerics.dt`, `Numerics(dt=0.025, mass_ratio=0.0001)`).

A message that tells the user what to change names the setting through `option` or `settings`, never by a literal
`--name`: the same refusal then reads right from `ea.simulate` and from `elastoactive run`. The surface is Python
unless a caller says otherwise: the command line's entry (`elastoactive.cli.main`) runs each command inside
`command_line()`. The setting is the process's, not a thread's, so a command's worker threads and forked pool workers
word their messages as the command does.

A name is given as Python spells it: a Numerics field with its record, `numerics.dt`; a physics parameter or an
argument of the call bare, `sigma`, `duration`.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

PYTHON = "python"
COMMAND_LINE = "command line"

_surface = PYTHON


def current() -> str:
    """The surface messages are worded for now: PYTHON or COMMAND_LINE."""
    return _surface


@contextmanager
def command_line() -> Iterator[None]:
    """Word messages for the command line while the block runs (restored after, also on an exception)."""
    global _surface
    before, _surface = _surface, COMMAND_LINE
    try:
        yield
    finally:
        _surface = before


def _flag(name: str) -> str:
    return "--" + name.rpartition(".")[2].replace("_", "-")


def _value(value) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def option(name: str, value=None) -> str:
    """The setting `name` (Python's spelling: `numerics.dt`, `sigma`), with `value` when given, as the current surface
    spells it: `--dt`, `--dt 0.025` on the command line; `numerics.dt`, `numerics.dt = 0.025` in Python."""
    if _surface == COMMAND_LINE:
        return _flag(name) if value is None else f"{_flag(name)} {_value(value)}"
    return name if value is None else f"{name} = {_value(value) if not isinstance(value, str) else repr(value)}"


def settings(record: str, **values) -> str:
    """Settings of one record (`record`: "Numerics", "Physics") to give together, as the current surface spells them:
    `--dt 0.025 --mass-ratio 0.0001` on the command line, `Numerics(dt=0.025, mass_ratio=0.0001)` in Python."""
    if _surface == COMMAND_LINE:
        return " ".join(f"{_flag(name)} {_value(value)}" for name, value in values.items())
    given = ", ".join(
        f"{name}={repr(value) if isinstance(value, str) else _value(value)}" for name, value in values.items()
    )
    return f"{record}({given})"

"""`elastoactive --help` answers at once: the help path imports none of the heavy modules (by module list, not by a
timing), and the lazily built parser the command line uses prints what the whole parser prints."""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import subprocess
import sys

import pytest

from elastoactive.cli import build_parser, main

HEAVY = ("mujoco", "numba", "scipy.integrate", "xarray", "matplotlib", "dask", "h5py", "pandas")
"""Modules that each cost a large part of a second to import: no --help may load one."""

_PROBE = """
import contextlib, io, json, sys
from elastoactive.cli import main
heavy, loaded = json.loads(sys.argv[1]), {}
for argv in json.loads(sys.argv[2]):
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            main(argv)
        except SystemExit:
            pass
    loaded[" ".join(argv)] = [m for m in heavy if m in sys.modules]
print(json.dumps(loaded))
"""


def _commands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices


def _printed(argv: list[str]) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 0
    return out.getvalue()


def test_no_help_imports_a_heavy_module():
    """In a fresh process: `--help`, then every subcommand's --help, each followed by the list of heavy modules
    loaded so far (so a failure names the first help that loaded one)."""
    helps = [["--help"]] + [[name, "--help"] for name in _commands()]
    result = subprocess.run(
        [sys.executable, "-c", _PROBE, json.dumps(HEAVY), json.dumps(helps)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    loaded = json.loads(result.stdout)
    assert list(loaded) == [" ".join(h) for h in helps]
    assert all(modules == [] for modules in loaded.values()), loaded


def test_the_lazy_parser_prints_what_the_whole_parser_prints():
    """The top-level help and every subcommand's, as the command line prints them, equal the whole parser's."""
    assert _printed(["--help"]) == build_parser().format_help()
    commands = _commands()
    assert len(commands) >= 8
    for name, parser in commands.items():
        assert _printed([name, "--help"]) == parser.format_help(), name


def test_the_top_level_help_builds_no_subcommand():
    """build_parser(lazy=True) reads each command's one-line help only: no subcommand has its options yet."""
    lazy = next(a for a in build_parser(lazy=True)._actions if isinstance(a, argparse._SubParsersAction))
    assert [c.dest for c in lazy._choices_actions] == list(_commands())
    for name, parser in lazy.choices.items():
        assert [a.dest for a in parser._actions] == ["help"], name

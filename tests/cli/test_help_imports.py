"""`elastoactive --help` answers at once: the top-level help imports no command, no scene and not numpy, no help imports
a heavy module (by module list, not by a timing), and the lazily built parser the command line uses prints what the
whole parser prints."""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import subprocess
import sys

import pytest

from elastoactive.cli import COMMANDS, build_parser, command_module, main

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
    """build_parser(lazy=True) lists each command by its name and one line (COMMANDS), in that order, and imports no
    command's module: none has a parser of its own yet."""
    lazy = next(a for a in build_parser(lazy=True)._actions if isinstance(a, argparse._SubParsersAction))
    assert [c.dest for c in lazy._choices_actions] == list(_commands()) == list(COMMANDS)
    assert [c.help for c in lazy._choices_actions] == list(COMMANDS.values())
    for name, parser in lazy.choices.items():
        assert parser._actions == [] and parser._built is None, name


def test_every_command_is_a_module_with_register_and_main():
    """Each listed command is the module of its name, whose register adds that command's parser with its main."""
    for name in COMMANDS:
        module = command_module(name)
        assert callable(module.register) and callable(module.main), name
        assert _commands()[name].get_default("func") is module.main, name


_TOP_LEVEL = """
import contextlib, io, sys
from elastoactive.cli import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    try:
        main(["--help"])
    except SystemExit:
        pass
ours = ("numpy", "elastoactive.scenes", "elastoactive.terms", "elastoactive.core.params")
commands = [f"elastoactive.cli.{name}" for name in sys.argv[1:]]
print([m for m in sys.modules if m in ours or m in commands])
print(out.getvalue())
"""


def test_the_top_level_help_imports_no_command_no_scene_and_not_numpy():
    """In a fresh process, `elastoactive --help` lists every scene and command without importing numpy, a scene, a
    term, the records or any command's module (what makes it answer in a tenth of a second)."""
    result = subprocess.run(
        [sys.executable, "-c", _TOP_LEVEL, *COMMANDS], capture_output=True, text=True, timeout=120, check=True
    )
    loaded, printed = result.stdout.split("\n", 1)
    assert loaded == "[]", loaded
    assert printed.strip() == build_parser().format_help().strip()

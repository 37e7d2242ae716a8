"""`elastoactive`: the command line, in the paper's dimensionless parameters.

One module per subcommand, each with register(subparsers) and main(args). Building the parser
imports nothing heavy (the engines, matplotlib, xarray load only when a command runs), and the command line
builds it lazily: a subcommand's options are added only when that subcommand parses, so `elastoactive --help`
reads no more than each command's one-line help (tests/cli/test_help_imports.py holds both).
"""

from __future__ import annotations

import argparse
import sys

from ..core.errors import ParameterError, SimulationDiverged
from . import accuracy, filament, ramp, render, reproduce, run, stability, sweep, validate, whirl
from .options import UNITS, plugin_argument, preload_plugins, scene_help

COMMANDS = (run, validate, sweep, ramp, render, accuracy, reproduce, stability, filament, whirl)
"""The subcommands, in the order --help lists them."""


class _Parser(argparse.ArgumentParser):
    """argparse with the project's one-line errors (an invalid choice, a number that is not one, a missing argument):
    'elastoactive: error: ...' naming the command, the usage left to --help."""

    def error(self, message: str):
        command = self.prog.removeprefix("elastoactive").strip()
        self.exit(2, f"elastoactive: error: {command + ': ' if command else ''}{message} (see {self.prog} --help)\n")


class _Declared(Exception):
    """Raised by _Declaring.add_parser: a subcommand's name and add_parser keywords, read without the rest of its
    module's register (which builds every option)."""

    def __init__(self, name: str, kwargs: dict):
        super().__init__(name)
        self.name, self.kwargs = name, kwargs


class _Declaring:
    """The subparsers that `register` sees while its command's one-line help is read: add_parser, the first call of
    every register, stops it there."""

    def add_parser(self, name: str, **kwargs):
        raise _Declared(name, kwargs)


class _Filling:
    """The subparsers that `register` sees when a lazily built command parses: add_parser hands back that command's
    parser (made with the same keywords), which register then fills with its options."""

    def __init__(self, parser: argparse.ArgumentParser):
        self.parser = parser

    def add_parser(self, name: str, **kwargs):
        return self.parser


class _Command(_Parser):
    """A subcommand's parser whose options its module's register adds when it first parses (its --help, its
    arguments): what it prints and accepts is that of the parser register builds."""

    def __init__(self, *args, command=None, **kwargs):
        super().__init__(*args, **kwargs)
        self._command = command

    def parse_known_args(self, args=None, namespace=None):
        if self._command is not None:
            command, self._command = self._command, None
            command.register(_Filling(self))
        return super().parse_known_args(args, namespace)


def build_parser(*, lazy: bool = False) -> argparse.ArgumentParser:
    """The command line's parser. lazy=True (what `main` uses): each subcommand's options are added when it parses,
    so the top-level --help builds none of them; lazy=False: every subcommand's parser whole (for the reference
    pages and the tests that read a subcommand's options)."""
    parser = _Parser(
        prog="elastoactive",
        description="Elasto-active chains in MuJoCo (Zheng et al., 'Self-oscillation and synchronisation "
        "transitions in elasto-active structures'), checked against the reduced overdamped model. " + UNITS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=scene_help(),
    )
    plugin_argument(parser)
    sub = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", parser_class=_Command if lazy else _Parser
    )
    for command in COMMANDS:
        if not lazy:
            command.register(sub)
            continue
        try:
            command.register(_Declaring())
        except _Declared as declared:
            sub.add_parser(declared.name, command=command, **declared.kwargs)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    try:  # before the parser: a plug-in's scenes and terms are choices and options of the commands
        argv = preload_plugins(argv)
    except ParameterError as err:
        print(f"elastoactive: error: {err}", file=sys.stderr)
        return 2
    parser = build_parser(lazy=True)
    args = parser.parse_args(argv)
    try:
        render.check_mujoco_gl()
        return args.func(args)
    except ParameterError as err:
        print(f"elastoactive: error: {err}", file=sys.stderr)
        return 2
    except SimulationDiverged as err:
        print(f"elastoactive: {err}", file=sys.stderr)
        return 3
    except KeyboardInterrupt as err:  # Ctrl-C: one line saying where it stopped, no traceback
        print(f"elastoactive: interrupted{f': {err}' if str(err) else ''}", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (| head): stop quietly, as command-line tools do
        sys.stderr.close()
        return 141
    except OSError as err:  # a write that failed (full disk, file-size limit): the file and the cause, one line
        where = f"{err.filename}: " if err.filename else ""
        print(f"elastoactive: error: {where}{err.strerror or err}", file=sys.stderr)
        return 1

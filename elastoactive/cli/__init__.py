"""`elastoactive`: the command line, in the paper's dimensionless parameters.

One module per subcommand, each with register(subparsers) and main(args), listed with its one-line help in COMMANDS.
The command line builds its parser lazily: `elastoactive --help` reads COMMANDS and the scenes' lines from source
(elastoactive.cli.catalogue) and imports no command, no scene and not numpy; a subcommand's module is imported, and
its parser built, when that subcommand parses (`command_module`: the boundary past which a command loads what it
runs). tests/cli/test_help_imports.py holds both, and that the lazy parser prints what the whole one does.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from ..core.errors import ParameterError, SimulationDiverged
from ..core.surface import command_line
from .options import UNITS, check_mujoco_gl, plugin_argument, preload_plugins, scene_help

COMMANDS = {
    "run": "simulate one scene and write summary.json + trajectory.npz",
    "validate": "run MuJoCo and the reduced model on the paper's cases and tabulate the error",
    "sweep": "run a scene over a grid of parameters (every core or a Dask cluster) into a netCDF file",
    "ramp": "ramp one parameter up then down in steps, each from the last state (hysteresis) into a netCDF file",
    "render": "render a saved run (folder or trajectory.npz) to an MP4 video and/or a PNG still",
    "accuracy": "error against wall time for MuJoCo integrators/timesteps/mass ratios and reduced-model solvers",
    "reproduce": "regenerate the paper's figures, their data and report.md (claim by claim)",
    "stability": "onset sigma_c, omega_c and growth rates from the linear operator (no simulation)",
    "filament": "the clamped filament's beat and onset, extrapolated from a ladder of chains",
    "whirl": "the clamped filament's whirl in 3D (rate, tip radius), extrapolated from a ladder of chains",
}
"""The subcommands, in the order --help lists them, with the one line it gives each. The command `name` is the module
elastoactive.cli.<name>: its register(subparsers) builds the command's parser (subparsers.add_parser(name, ...): its
description, epilog and options; the one line is here) and sets its main(args) as the parser's func."""


class _Parser(argparse.ArgumentParser):
    """argparse with the project's one-line errors (an invalid choice, a number that is not one, a missing argument):
    'elastoactive: error: ...' naming the command, the usage left to --help."""

    def error(self, message: str):
        command = self.prog.removeprefix("elastoactive").strip()
        self.exit(2, f"elastoactive: error: {command + ': ' if command else ''}{message} (see {self.prog} --help)\n")


def command_module(name: str):
    """The module of the subcommand `name` (COMMANDS), imported: the command line's boundary, past which a command
    loads what it runs (the engines, numpy, the writers) and which --help does not cross."""
    return importlib.import_module(f".{name}", __name__)


class _Listed:
    """The subparsers a command's register sees in the whole parser: add_parser adds the command with its one line."""

    def __init__(self, subparsers):
        self.subparsers = subparsers

    def add_parser(self, name: str, **kwargs):
        return self.subparsers.add_parser(name, help=COMMANDS[name], **kwargs)


class _Own:
    """The subparsers a command's register sees when its lazily listed parser first parses: add_parser makes the
    command's parser on its own, under the listed parser's name (prog)."""

    def __init__(self, prog: str):
        self.prog = prog
        self.parser: argparse.ArgumentParser | None = None

    def add_parser(self, name: str, **kwargs):
        self.parser = _Parser(prog=self.prog, **kwargs)
        return self.parser


class _Command(_Parser):
    """A subcommand listed by name and one line, whose parser its module's register builds when it first parses (its
    --help, its arguments); parsing is then that parser's, so it prints and accepts what the whole parser does."""

    def __init__(self, *args, command: str, **kwargs):
        super().__init__(*args, add_help=False, **kwargs)
        self._command, self._built = command, None

    def parse_known_args(self, args=None, namespace=None):
        if self._built is None:
            own = _Own(self.prog)
            command_module(self._command).register(own)
            self._built = own.parser
        return self._built.parse_known_args(args, namespace)


def build_parser(*, lazy: bool = False) -> argparse.ArgumentParser:
    """The command line's parser. lazy=True (what `main` uses): each subcommand listed by its name and one line, its
    module imported and its parser built when it parses, so the top-level --help imports no command; lazy=False: every
    subcommand's parser whole (for the reference pages and the tests that read a subcommand's options)."""
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
    for name, line in COMMANDS.items():
        if lazy:
            sub.add_parser(name, help=line, command=name)
        else:
            command_module(name).register(_Listed(sub))
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
        check_mujoco_gl()
        with command_line():  # messages name settings as options (--dt), not as Python does (numerics.dt)
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

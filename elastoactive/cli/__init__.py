"""`elastoactive`: the command line, in the paper's dimensionless parameters.

One module per subcommand, each with register(subparsers) and main(args). Building the parser
imports nothing heavy (the engines, matplotlib, xarray load only when a command runs), so
`elastoactive --help` answers at once.
"""

from __future__ import annotations

import argparse
import sys

from ..errors import ParameterError, SimulationDiverged
from . import accuracy, filament, ramp, render, reproduce, run, stability, sweep, validate
from .options import UNITS, plugin_argument, preload_plugins, scene_help

COMMANDS = (run, validate, sweep, ramp, render, accuracy, reproduce, stability, filament)
"""The subcommands, in the order --help lists them."""


class _Parser(argparse.ArgumentParser):
    """argparse with the project's one-line errors (an invalid choice, a number that is not one, a missing argument):
    'elastoactive: error: ...' naming the command, the usage left to --help."""

    def error(self, message: str):
        command = self.prog.removeprefix("elastoactive").strip()
        self.exit(2, f"elastoactive: error: {command + ': ' if command else ''}{message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="elastoactive",
        description="Elasto-active chains in MuJoCo (Zheng et al., 'Self-oscillation and synchronisation "
        "transitions in elasto-active structures'), checked against the reduced overdamped model. " + UNITS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=scene_help(),
    )
    plugin_argument(parser)
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        command.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    try:  # before the parser: a plug-in's scenes and terms are choices and options of the commands
        argv = preload_plugins(argv)
    except ParameterError as err:
        print(f"elastoactive: error: {err}", file=sys.stderr)
        return 2
    parser = build_parser()
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

"""Options and texts the command line shares: the units line, --plugin and the plug-ins it preloads, --workers, --ns,
the scenes' epilog and the MUJOCO_GL check. Light: the top-level --help imports this and no scene (the scenes' lines:
elastoactive.cli.catalogue); the options generated from the parameter records are elastoactive.cli.fields.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ..core.errors import ParameterError
from ..core.units import CHAIN, NETWORK
from . import catalogue

UNITS = (
    f"Units: a chain scene's are {CHAIN.basis}, so times are in {CHAIN.time_text}, frequencies in "
    f"{CHAIN.rate_units} and sigma = {CHAIN.sigma}; a network scene's (lattice, network, trapped-unit) are "
    f"{NETWORK.basis}, so times are in {NETWORK.time_text} and sigma = {NETWORK.sigma}, with the coupling "
    "Pi = l_e / l_a as an option. `run SCENE --help` lists one scene's options in its own units."
)


def scene_help() -> str:
    """The registered scenes, one line each (the CLI's epilog)."""
    return "scenes:\n" + "\n".join(f"  {name:<13} {summary}" for name, summary in catalogue.scenes())


def workers_argument(p: argparse.ArgumentParser, help_text: str = "worker processes (default: every core)") -> None:
    """--workers K, K >= 1 (None: every core)."""

    def workers(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a whole number >= 1, got {text!r}") from None
        if value < 1:
            raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
        return value

    p.add_argument("--workers", type=workers, default=None, help=help_text)


PLUGIN_OPTION = "--plugin"
"""The option naming a plug-in (a module or a .py file); repeatable, given before or after the command."""


def ladder_argument(p: argparse.ArgumentParser, default: tuple[int, ...], *, count: int, smallest: int) -> None:
    """--ns: a ladder of chain sizes N for a continuum extrapolation (at least `count` distinct N >= `smallest`)."""

    def ladder(text: str) -> tuple[int, ...]:
        try:
            ns = tuple(sorted({int(v) for v in text.split(",") if v.strip()}))
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a comma list of whole numbers, got {text!r}") from None
        if len(ns) < count or ns[0] < smallest:
            raise argparse.ArgumentTypeError(f"expected at least {count} distinct N >= {smallest}, got {text!r}")
        return ns

    shown = ",".join(map(str, default))
    p.add_argument("--ns", type=ladder, default=default, help=f"the ladder of N, comma separated (default {shown})")


def plugin_argument(parser: argparse.ArgumentParser) -> None:
    """--plugin MODULE_OR_FILE on the top-level parser (for --help: preload_plugins has taken every one out of the
    arguments, wherever it stood, before the parser runs)."""
    parser.add_argument(
        PLUGIN_OPTION,
        action="append",
        metavar="MODULE_OR_FILE",
        help="load a plug-in first: a module name or a .py file whose scenes, terms and studies register when "
        "imported (repeatable; before or after the command). A run's summary.json records the plug-ins it "
        "needs, and `run --from` or `render` of that run load them again",
    )


def preload_plugins(argv: list[str]) -> list[str]:
    """Load the plug-ins that `argv` names (--plugin X or --plugin=X, anywhere) and those recorded by every run
    named on it (--from RUN, render's RUN: any argument that is a run's folder or file); returns argv without the
    --plugin options. A plug-in that cannot be loaded is a ParameterError naming it."""
    rest, specs = [], []
    items = iter(argv)
    for item in items:
        if item == PLUGIN_OPTION:
            spec = next(items, None)
            if spec is None:
                raise ParameterError(f"{PLUGIN_OPTION} needs a module name or a .py file")
            specs.append(spec)
        elif item.startswith(PLUGIN_OPTION + "="):
            specs.append(item.split("=", 1)[1])
        else:
            rest.append(item)
    values = (item.split("=", 1)[1] if item.startswith("--from=") else item for item in rest)
    runs = [v for v in values if v and not v.startswith("-") and Path(v).exists()]  # a run's record, maybe
    if not (specs or runs):
        return rest
    from .. import plugins  # the plug-in boundary: loading one reads the registries (every scene, term, numpy)

    for spec in dict.fromkeys(specs):
        plugins.load(spec)
    for value in runs:
        for spec in plugins.recorded(Path(value)):
            try:
                plugins.load(spec)
            except ParameterError as err:
                raise ParameterError(f"{value} was run with the plug-in {spec}, which did not load: {err}") from None
    return rest


MUJOCO_GL_ACCEPTED = (
    "",
    "disable",
    "disabled",
    "off",
    "false",
    "0",
    "enable",
    "enabled",
    "on",
    "true",
    "1",
    "glfw",
    "glx",
    "egl",
    "osmesa",
    "wgl",
    "cgl",
)
"""Values of MUJOCO_GL that MuJoCo's renderer takes on some system (mujoco.rendering.classic.gl_context): these need
no check, so a command that never simulates in MuJoCo (a reduced run) does not load it for one."""


def check_mujoco_gl() -> None:
    """Refuse a MUJOCO_GL that MuJoCo rejects (it reads the variable when it is imported, and raises on a value it
    does not know), in one line naming the variable, before any command loads MuJoCo. Unset, or a value MuJoCo takes
    (MUJOCO_GL_ACCEPTED), nothing is loaded; any other is put to MuJoCo itself, which has the last word."""
    value = os.environ.get("MUJOCO_GL")
    if not value or value.lower().strip() in MUJOCO_GL_ACCEPTED:
        return
    try:
        import mujoco  # noqa: F401 (loaded by every command that simulates or renders)
    except RuntimeError as err:
        if "MUJOCO_GL" not in str(err):
            raise
        raise ParameterError(
            f"environment variable MUJOCO_GL={value!r} is not a value MuJoCo accepts ({err}); "
            "unset it (rendering then tries egl, then osmesa) or set egl, osmesa or glfw"
        ) from None

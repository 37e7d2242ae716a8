"""Options shared by the subcommands, generated from the parameter records and the scene registry."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import plugins, registry
from ..errors import ParameterError
from ..params import Numerics, Physics, parameter_fields

UNITS = "Units: l = C1 = gamma = 1, so times are in tau = gamma l^2 / C1 and frequencies are f*tau."


def scene_help() -> str:
    """The registered scenes, one line each (the CLI's epilog)."""
    return "scenes:\n" + "\n".join(f"  {s.name:<13} {s.summary}" for s in registry.scenes())


def _used_by(name: str) -> str:
    """'; two-pinned only' for a scene's own parameter (the chain's and the terms' act in every scene)."""
    users = [s.name for s in registry.scenes() if name in s.own_parameter_names()]
    return f"; {', '.join(users)} only" if users else ""


def _text(text: str) -> str:
    """A text option's value as given (argparse also passes the default through it, which stays what it is)."""
    return text


def add_fields(group, cls, *, defaults: bool = True) -> None:
    """One option per user-set field of Physics or Numerics, named and explained by the field itself."""
    """defaults=False: options left out are None (the caller fills them, e.g. from a preset)."""
    default = cls()
    for f in parameter_fields(cls):
        value = getattr(default, f.name)
        option = f"--{f.name.replace('_', '-')}"
        if isinstance(value, bool):  # a switch: --contact / --no-contact
            group.add_argument(
                option,
                action=argparse.BooleanOptionalAction,
                default=value if defaults else None,
                help=f"{f.metadata['help']} (default {'on' if value else 'off'})",
            )
            continue
        kind = int if isinstance(value, int) else (str if isinstance(value, str) else float)
        shown = f"{value:.4g}" if kind is float else value
        # argparse passes a str default through `type`: str() would drop a Numerics default's mark (automatic)
        group.add_argument(
            option,
            type=_text if kind is str else kind,
            default=value if defaults else None,
            choices=f.metadata.get("choices"),
            help=f"{f.metadata['help']} (default {shown}{_used_by(f.name) if cls is Physics else ''})",
        )


def numerics_args(p: argparse.ArgumentParser) -> None:
    add_fields(p.add_argument_group("numerics"), Numerics)


def scene_argument(p: argparse.ArgumentParser, **kw) -> None:
    """The positional SCENE, one of the registered scenes."""
    p.add_argument(
        "scene", choices=registry.names(), metavar="SCENE", help="one of: " + ", ".join(registry.names()), **kw
    )


def numerics_from(args) -> Numerics:
    return Numerics(**{f.name: getattr(args, f.name) for f in parameter_fields(Numerics)})


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
    for spec in dict.fromkeys(specs):
        plugins.load(spec)
    for item in rest:
        value = item.split("=", 1)[1] if item.startswith("--from=") else item
        if value and not value.startswith("-") and (Path(value).is_dir() or Path(value).suffix in (".json", ".npz")):
            for spec in plugins.recorded(Path(value)):
                try:
                    plugins.load(spec)
                except ParameterError as err:
                    raise ParameterError(
                        f"{value} was run with the plug-in {spec}, which did not load: {err}"
                    ) from None
    return rest

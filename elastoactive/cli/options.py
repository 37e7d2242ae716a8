"""Options shared by the subcommands, generated from the parameter records and the scene registry.

Each scene speaks its own units (elastoactive.core.units): the commands' help names both systems, and `run SCENE
--help` or `sweep SCENE --help` lists that scene's options only, with their help and units in its words (`SceneHelp`).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from .. import plugins
from ..core import registry
from ..core.errors import ParameterError
from ..core.params import Numerics, Physics, has_coupling, parameter_fields, scene_parameters
from ..core.units import CHAIN, NETWORK, scene_units
from ..wording import field_help

UNITS = (
    f"Units: a chain scene's are {CHAIN.basis}, so times are in {CHAIN.time_text}, frequencies in "
    f"{CHAIN.rate_units} and sigma = {CHAIN.sigma}; a network scene's (lattice, network, trapped-unit) are "
    f"{NETWORK.basis}, so times are in {NETWORK.time_text} and sigma = {NETWORK.sigma}, with the coupling "
    "Pi = l_e / l_a as an option. `run SCENE --help` lists one scene's options in its own units."
)


def scene_help() -> str:
    """The registered scenes, one line each (the CLI's epilog)."""
    return "scenes:\n" + "\n".join(f"  {s.name:<13} {s.summary}" for s in registry.scenes())


def _used_by(name: str) -> str:
    """'; two-pinned only' for a scene's own parameter, or the coupling Pi, which only some scenes have (the chain's
    and the terms' act in every scene)."""
    users = [
        s.name
        for s in registry.scenes()
        if name in s.own_parameter_names() or (name == "Pi" and has_coupling(s))  # the coupling: Scene.coupling
    ]
    return f"; {', '.join(users)} only" if users else ""


def _text(text: str) -> str:
    """A text option's value as given (argparse also passes the default through it, which stays what it is)."""
    return text


def add_fields(group, cls, *, defaults: bool = True, scene: str | None = None) -> None:
    """One option per user-set field of Physics or Numerics, named and explained by the field itself.
    defaults=False: options left out are None (the caller fills them, e.g. from a preset).
    scene: only that scene's parameters, their help and units in its words (Parameter.help_in; a numerical setting's:
    wording.field_help), its defaults, and the values it holds fixed shown as such."""
    default = cls() if scene is None else (Physics(scene=scene) if cls is Physics else cls())
    units = scene_units(registry.get(scene)) if scene is not None else CHAIN
    fields = parameter_fields(cls)
    if scene is not None and cls is Physics:
        fields = tuple(f for f in fields if f.name in scene_parameters(registry.get(scene)))
    held = {name: why for name, _, why in registry.get(scene).fixed} if scene is not None else {}
    for f in fields:
        value = getattr(default, f.name)
        if cls is Physics:
            text = f.help_in(units) + (f" [{f.units_in(units)}]" if f.units_in(units) not in ("", "1") else "")
            if scene is None:  # every scene's help: what it is in the other systems' words too
                text += "".join(f"; on a {w.units} scene: {w.text}" for w in f.worded)
        else:
            text = field_help(f, units)
            if scene is None:
                text += "".join(f"; on a {w.units} scene: {w.text}" for w in f.metadata.get("worded", ()))
        if getattr(f, "instead_of", None):  # the coupling Pi: given in place of sigma, no default of its own
            scenes = _used_by(f.name) if scene is None else ""
            if scene is not None:
                formula = registry.get(scene).coupling_formula
                text = f"{f.title} Pi = l_e / l_a = {formula} on {scene}, given instead of {f.instead_of}"
            group.add_argument(
                f"--{f.name.replace('_', '-')}",
                type=float,
                default=None,
                help=f"{text} (default: from {f.instead_of}{scenes})",
            )
            continue
        if f.name in held:
            text = f"{text} (fixed at {value}: {held[f.name]})"
        option = f"--{f.name.replace('_', '-')}"
        if isinstance(value, bool):  # a switch: --contact / --no-contact
            group.add_argument(
                option,
                action=argparse.BooleanOptionalAction,
                default=value if defaults else None,
                help=f"{text} (default {'on' if value else 'off'})",
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
            help=f"{text} (default {shown}{_used_by(f.name) if cls is Physics and scene is None else ''})",
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


class SceneHelp(argparse.Action):
    """-h / --help of a command that takes a SCENE: after a scene (`run lattice --help`), that scene's own help
    (`fill(parser, scene)` builds it: its options only, in its units); else the command's, for every scene."""

    def __init__(self, option_strings, dest, fill: Callable[[argparse.ArgumentParser, str | None], None], **kwargs):
        super().__init__(option_strings, dest, nargs=0, default=argparse.SUPPRESS, **kwargs)
        self.fill = fill

    def __call__(self, parser, namespace, values, option_string=None):
        scene = getattr(namespace, "scene", None)
        if scene in registry.names():
            own = argparse.ArgumentParser(
                prog=f"{parser.prog} {scene}", formatter_class=argparse.RawDescriptionHelpFormatter, add_help=False
            )
            self.fill(own, scene)
            own.print_help()
        else:
            parser.print_help()
        parser.exit()


def help_argument(parser: argparse.ArgumentParser, fill) -> None:
    """-h / --help as SceneHelp, in place of argparse's (the parser is made with conflict_handler="resolve")."""
    parser.add_argument(
        "-h",
        "--help",
        action=SceneHelp,
        fill=fill,
        help="show this help and exit; after SCENE, that scene's options only, in its own units",
    )


def scene_description(scene: str) -> str:
    """A scene's summary and units, for the head of its own help."""
    definition = registry.get(scene)
    return f"{scene}: {definition.summary}.\n{scene_units(definition).text}"

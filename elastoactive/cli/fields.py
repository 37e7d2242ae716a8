"""The options generated from the parameter records and the scene registry: one per parameter of Physics or Numerics,
named, explained and checked by the parameter itself, and a scene's own help.

Each scene speaks its own units (elastoactive.core.units): the commands' help names both systems, and `run SCENE
--help` or `sweep SCENE --help` lists that scene's options only, with their help and units in its words (`SceneHelp`).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

from ..core import registry
from ..core.params import Numerics, Physics, has_coupling, parameter_fields, scene_parameters
from ..core.units import CHAIN, scene_units
from ..wording import field_help


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

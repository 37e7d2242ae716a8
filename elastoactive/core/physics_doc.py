"""Physics' generated docstring and signature: every registered parameter (the chain's, each scene's, each term's)
with its kind, default, units and help, grouped by who declares it, computed when read so that a plug-in's
parameters appear too (help(ea.Physics), inspect.signature)."""

from __future__ import annotations

import inspect
import textwrap

from . import parameters as _parameters
from . import registry, term_registry
from .params import DEFAULT_SCENE, LEADING, Physics
from .units import CHAIN, SYSTEMS, scene_units

DOC_WIDTH = 116
"""The width Physics' generated docstring is wrapped to."""


def _owners() -> list[tuple[str, list]]:
    """(who declares them, their specs) for the chain, every scene and every term, in registration order."""
    registry.names(), term_registry.names()  # the entry points' scenes and terms join the table first
    groups: dict[str, list] = {}
    for name in _names():
        groups.setdefault(_parameters.owner(name), []).append(_parameters.get(name))
    return list(groups.items())


def _names() -> tuple[str, ...]:
    """Every declared parameter: the leading ones (n, sigma, ...) first, then in declaration order."""
    return tuple(dict.fromkeys((*LEADING, *_parameters.names())))


def _entry(spec) -> str:
    kind = spec.kind.__name__
    choices = f" {{{', '.join(map(repr, spec.choices))}}}" if spec.choices else ""
    units = "" if spec.units in ("1", "") else f" [{spec.units}]"
    needs = f" (acts with {spec.need_text})" if spec.needs else ""
    text = textwrap.fill(f"{spec.help}{needs}", DOC_WIDTH, initial_indent="    ", subsequent_indent="    ")
    return f"{spec.name} : {kind}{choices}, default {spec.default!r}{units}\n{text}"


def physics_doc(head: str = "") -> str:
    """Physics' docstring: `head`, then every registered parameter (the chain's, each scene's, each term's) with its
    kind, default, units and help, grouped by who declares it; the registered scenes."""
    lines = [head.rstrip(), "", "Parameters", "----------", f"scene : str, default {DEFAULT_SCENE!r}"]
    scenes = "One of the registered scenes: " + ", ".join(registry.names()) + "."
    lines.append(  # a scene's name is one word: never broken at its hyphens
        textwrap.fill(scenes, DOC_WIDTH, initial_indent="    ", subsequent_indent="    ", break_on_hyphens=False)
    )
    for owner, specs in _owners():
        lines += ["", f"Declared by {owner}:", ""]
        lines += [_entry(spec) for spec in specs]
    lines += ["", "Units", "-----"]
    for system in SYSTEMS:  # each scene speaks its own (elastoactive.core.units); the entries above are in the chain's
        users = [s.name for s in registry.scenes() if scene_units(s) == system]
        text = f"{system.name} scenes ({', '.join(users)}). {system.text}"
        lines.append(textwrap.fill(text, DOC_WIDTH, break_on_hyphens=False))
        worded = [f"{spec.name}: {spec.help_in(system)}" for _, specs in _owners() for spec in specs if spec.worded]
        if system != CHAIN and worded:
            lines.append(textwrap.fill("There: " + "; ".join(worded) + ".", DOC_WIDTH, subsequent_indent="    "))
    note = (
        "The entries above are in the chain's units ([l] lengths, [tau] times); a number without units is "
        "dimensionless. Pi is given in place of sigma where a scene has the coupling."
    )
    lines.append(textwrap.fill(note, DOC_WIDTH))
    return "\n".join(lines)


def physics_signature() -> inspect.Signature:
    """Physics' signature: scene, then every registered parameter as a keyword with its default."""
    _owners()
    parameters = [inspect.Parameter("scene", inspect.Parameter.POSITIONAL_OR_KEYWORD, default=DEFAULT_SCENE)]
    parameters += [
        inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=_parameters.get(name).default)
        for name in _names()
    ]
    return inspect.Signature(parameters)


class _Generated:
    """A class attribute computed when read (``__doc__``, ``__signature__``), so that it lists what is registered
    at the time (a plug-in's parameters included)."""

    def __init__(self, make):
        self.make = make

    def __get__(self, obj, cls=None):
        return self.make()


def document_physics() -> None:
    """Give Physics its generated docstring and signature (import elastoactive does this once)."""
    if isinstance(Physics.__dict__.get("__doc__"), _Generated):
        return
    head = inspect.cleandoc(Physics.__dict__.get("__doc__") or "").split("\n\n    scene ")[0]
    head = head.split("\n\nscene ")[0]
    Physics.__doc__ = _Generated(lambda: physics_doc(head))
    Physics.__signature__ = _Generated(physics_signature)

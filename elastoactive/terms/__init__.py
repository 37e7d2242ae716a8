"""The term registry: every physical term is one module here, registered under its name.

    import elastoactive as ea
    ea.terms.names()                  # ('drag', 'noise', 'follower', ...): every registered term
    ea.terms.get("contact").parameters

A new term is a subclass of `Term` (elastoactive.terms.base) registered with `register`: its parameters join every
scene's (Physics, the CLI's options, sweeps), its `build` adds MJCF elements, its `reduced_system` or
`node_forces` its reduced-model contribution, its `measure` its observables. See docs/terms.md for the contract
and the diff a new term needs. Terms of the `elastoactive.terms` entry points join when the table is first listed
(elastoactive.plugins).
"""

from __future__ import annotations

from .. import observables as _observables
from .. import parameters as _parameters
from ..registry import UnknownName, load_entry_points
from .base import NodeForces, Term

_TERMS: dict[str, Term] = {}


def register(term: Term, *, replace: bool = False) -> Term:
    """Add a term (and its parameter and observable specs) under `term.name`; returns it."""
    name = getattr(term, "name", None)
    if not isinstance(name, str) or not name:
        raise ValueError(f"a term needs a non-empty string `name`, got {name!r}")
    if name in _TERMS and not replace and _TERMS[name] is not term:
        raise ValueError(f"a term named {name!r} is already registered (pass replace=True to replace it)")
    for spec in term.parameters:
        _parameters.register(spec, f"term {name}")
    _observables.declare(term.observables, f"term {name}")
    _TERMS[name] = term
    return term


def unregister(name: str) -> None:
    """Remove a term and its parameter and observable specs (a test's plug-in term cleans up with this)."""
    term = _TERMS.pop(name, None)
    for spec in getattr(term, "parameters", ()):
        _parameters.unregister(spec.name)
    _observables.withdraw(getattr(term, "observables", ()), f"term {name}")


class UnknownTerm(UnknownName):
    """Raised by `get` for a name that no term registered (its message lists the registered terms)."""

    kind, kinds = "term", "terms"


def _register_new(term: Term) -> None:
    """Register an entry point's term unless it registered itself on import; refuse what is not a term."""
    if not isinstance(term, Term):
        raise TypeError(f"{type(term).__name__} is not a term (elastoactive.terms.Term)")
    if getattr(term, "name", None) not in _TERMS:
        register(term)


def _plugins() -> None:
    """The terms of the `elastoactive.terms` entry points, loaded the first time the registry is listed."""
    load_entry_points("terms", _register_new)


def get(name: str) -> Term:
    """The registered term called `name` (the entry points' terms included)."""
    try:
        return _TERMS[name]
    except (KeyError, TypeError):
        pass
    _plugins()
    try:
        return _TERMS[name]
    except (KeyError, TypeError):
        raise UnknownTerm(name, names()) from None


def names() -> tuple[str, ...]:
    """Names of the registered terms (the entry points' included), in registration order."""
    _plugins()
    return tuple(_TERMS)


def terms() -> tuple[Term, ...]:
    """The registered terms (the entry points' included), in registration order."""
    _plugins()
    return tuple(_TERMS.values())


def parameter_names() -> tuple[str, ...]:
    """The parameters of every registered term (the entry points' included), in registration order."""
    _plugins()
    return tuple(p.name for t in _TERMS.values() for p in t.parameters)


from . import contact, drag, follower, moving_clamp, noise, self_aligning, tip_drive  # noqa: E402  (the built-in terms register into the table above)

for _module in (
    drag,
    noise,
    follower,
    contact,
    tip_drive,
    self_aligning,
    moving_clamp,
):  # this order: the summaries list noise before loaded
    register(_module.TERM)

__all__ = ["NodeForces", "Term", "get", "names", "parameter_names", "register", "terms", "unregister"]

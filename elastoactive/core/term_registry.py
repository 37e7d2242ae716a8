"""The term registry's table: term name -> Term object (a `Registry`, elastoactive.core.table).

A leaf module but for the parameter and observable tables, where a term's specs are registered with it, so that
`params` can list the terms while the term modules themselves import `params`. Terms enter the table through
`register`; the built-in ones when `elastoactive.terms` is imported, which `import elastoactive` does first; those of
the `elastoactive.terms` entry points when the table is first listed (elastoactive.core.table.load_entry_points).
`elastoactive.terms` is the public face of this table, with the full contract (elastoactive.terms.base.Term).
"""

from __future__ import annotations

from typing import Protocol

from . import observables as _observables
from . import parameters as _parameters
from .table import Registry, UnknownName


class Term(Protocol):
    """What the table needs of a term: its name, its parameter and observable specs, and whether a physics switches
    it on (the full contract: elastoactive.terms.base.Term)."""

    name: str
    parameters: tuple
    observables: tuple

    def active(self, physics) -> bool: ...


class UnknownTerm(UnknownName):
    """Raised by `get` for a name that no term registered (its message lists the registered terms)."""

    kind, kinds = "term", "terms"


def _adopt(term) -> None:
    """Register an entry point's term unless it registered itself on import; refuse what is not a term."""
    if not (callable(getattr(term, "active", None)) and hasattr(term, "parameters") and hasattr(term, "observables")):
        raise TypeError(f"{type(term).__name__} is not a term (elastoactive.terms.Term)")
    if getattr(term, "name", None) not in TERMS:
        register(term)


TERMS: Registry[Term] = Registry("term", error=UnknownTerm, group="terms", adopt=_adopt, built_ins=True)
"""The terms, in registration order."""


def register(term: Term, *, replace: bool = False) -> Term:
    """Add a term (and its parameter and observable specs) under `term.name`; returns it."""
    name = TERMS.admit(term, replace=replace)
    for spec in term.parameters:
        _parameters.register(spec, f"term {name}")
    _observables.declare(term.observables, f"term {name}")
    return TERMS.register(term, owner=f"term {name}", replace=True)


def unregister(name: str) -> None:
    """Remove a term and its parameter and observable specs (a test's plug-in term cleans up with this)."""
    term = TERMS.unregister(name)
    for spec in getattr(term, "parameters", ()):
        _parameters.unregister(spec.name)
    _observables.withdraw(getattr(term, "observables", ()), f"term {name}")


def get(name: str) -> Term:
    """The registered term called `name` (the entry points' included)."""
    return TERMS.get(name)


def names() -> tuple[str, ...]:
    """Names of the registered terms (the entry points' included), in registration order."""
    return TERMS.names()


def terms() -> tuple[Term, ...]:
    """The registered terms (the entry points' included), in registration order."""
    return TERMS.entries()


def parameter_names() -> tuple[str, ...]:
    """The parameters of every registered term (the entry points' included), in registration order."""
    return tuple(p.name for t in TERMS.entries() for p in t.parameters)

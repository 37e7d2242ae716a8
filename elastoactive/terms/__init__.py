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

import numpy as np

from .. import observables as _observables
from .. import parameters as _parameters
from ..table import Registry, UnknownName
from .base import NodeForces, Term


class UnknownTerm(UnknownName):
    """Raised by `get` for a name that no term registered (its message lists the registered terms)."""

    kind, kinds = "term", "terms"


def _adopt(term: Term) -> None:
    """Register an entry point's term unless it registered itself on import; refuse what is not a term."""
    if not isinstance(term, Term):
        raise TypeError(f"{type(term).__name__} is not a term (elastoactive.terms.Term)")
    if getattr(term, "name", None) not in TERMS:
        register(term)


TERMS: Registry[Term] = Registry("term", error=UnknownTerm, group="terms", adopt=_adopt)
"""The terms, in registration order (elastoactive.table.Registry)."""


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
    """The registered term called `name` (the entry points' terms included)."""
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


def polarity_terms() -> tuple[Term, ...]:
    """The registered terms that carry a polarity (Term.polarity_switch), in registration order."""
    return tuple(t for t in terms() if t.polarity_switch is not None)


def polarity_term(physics) -> Term | None:
    """The term whose units carry the polarity in this physics (the first active polarity-carrying term), or None."""
    return next((t for t in physics.active_terms() if t.polarity_switch is not None), None)


def turning_rate(physics) -> float:
    """The fastest rate at which the physics' units turn (Term.turning_rate of the polarity term; 0 without one)."""
    term = polarity_term(physics)
    return 0.0 if term is None else term.turning_rate(physics)


def check_reduced_span(physics, duration: float) -> None:
    """The polarity term's refusal of a reduced run too long for its units' stiffness (Term.check_reduced_span)."""
    term = polarity_term(physics)
    if term is not None:
        term.check_reduced_span(physics, duration)


def polarity_addresses(model) -> np.ndarray:
    """Where every unit keeps its polarity in mjData.act: each polarity-carrying term's units (Term.polarity_addresses),
    term by term."""
    found = [t.polarity_addresses(model) for t in polarity_terms()]
    return np.concatenate(found).astype(int) if found else np.empty(0, dtype=int)


def align_polarities(model, data) -> None:
    """Set every chain unit's polarity at t = 0 (Term.align_polarity of each polarity-carrying term)."""
    for term in polarity_terms():
        term.align_polarity(model, data)


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

__all__ = [
    "NodeForces",
    "Term",
    "align_polarities",
    "check_reduced_span",
    "get",
    "names",
    "parameter_names",
    "polarity_addresses",
    "polarity_term",
    "polarity_terms",
    "register",
    "terms",
    "turning_rate",
    "unregister",
]

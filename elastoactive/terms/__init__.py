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

from ..core.term_registry import TERMS, UnknownTerm, get, names, parameter_names, register, terms, unregister
from .base import NodeForces, Term


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


from . import contact, drag, follower, hydrodynamics, moving_clamp, noise, self_aligning, tip_drive  # noqa: E402  (the built-in terms register into the term table)

for _module in (
    drag,
    noise,
    follower,
    contact,
    tip_drive,
    self_aligning,
    moving_clamp,
    hydrodynamics,
):  # this order: the summaries list noise before loaded
    register(_module.TERM)

__all__ = [
    "TERMS",
    "NodeForces",
    "Term",
    "UnknownTerm",
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

"""The engines and builders reach the term that gives units a polarity through the term registry (Term's polarity
hooks), never by its name: the self-aligning term is found by its role, and a second polarity-carrying term is found
the same way."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive import terms
from elastoactive.core.parameters import Parameter
from elastoactive.terms import Term


def test_the_self_aligning_units_are_found_by_their_role():
    chain = ea.Physics(n=5, sigma=0.8)
    aligning = ea.Physics(n=5, sigma=0.8, active="self-aligning", alignment_length=0.5)
    assert terms.polarity_term(chain) is None and terms.turning_rate(chain) == 0.0
    assert terms.polarity_term(aligning) is ea.terms.get("self-aligning")
    assert terms.turning_rate(aligning) == pytest.approx(0.8 / 0.5)
    assert ea.terms.get("self-aligning") in terms.polarity_terms()
    assert ea.scenes.get("lattice").fixed[0][:2] == ea.terms.get("self-aligning").polarity_switch


def test_the_load_mask_comes_from_the_term_that_places_the_force():
    assert ea.Physics(n=4, loaded="tip").load_mask().tolist() == [False, False, False, True]
    assert [t.name for t in ea.terms.terms() if t.load_mask(ea.Physics(n=4)) is not None] == ["follower"]


class Spinning(Term):
    """A second polarity-carrying term (a test's): units that turn at a fixed rate."""

    name = "toy-spinning"
    parameters = (
        Parameter("spin_rate", 0.0, "turning rate of the toy's units (1 / tau)", low=0.0, quiet_default=True),
    )
    polarity_switch = ("spin_rate", "any value above 0")

    def turning_rate(self, physics) -> float:
        return float(physics.spin_rate)

    def initial_polarity(self, theta, mask):
        return np.zeros(int(np.count_nonzero(mask)))


def test_a_second_polarity_carrying_term_plugs_in_the_same_way():
    term = ea.terms.register(Spinning())
    try:
        physics = ea.Physics(n=3, spin_rate=2.5)
        assert terms.polarity_term(physics) is term and terms.turning_rate(physics) == 2.5
        assert term in terms.polarity_terms() and terms.polarity_term(ea.Physics(n=3)) is None
    finally:
        ea.terms.unregister(term.name)

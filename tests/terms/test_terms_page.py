"""docs/terms.md names every hook of the term contract (elastoactive.terms.base.Term), its example of a force that
depends on position runs in both engines and agrees, and a term that names no slower setting reads well in the
messages that would quote it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import elastoactive as ea
from elastoactive.core.parameters import Parameter
from elastoactive.results import _aliasing
from elastoactive.terms import Term
from elastoactive.terms.base import slower_advice

PAGE = (Path(__file__).resolve().parents[2] / "docs" / "terms.md").read_text()


def hooks() -> tuple[str, ...]:
    """Every hook of the contract: the public attributes and methods Term defines."""
    return tuple(name for name in vars(Term) if not name.startswith("_"))


def test_the_contract_has_the_hooks_the_page_was_written_for():
    assert {"rate", "slower", "start", "inertial_model", "node_forces", "build", "measure"} <= set(hooks())


@pytest.mark.parametrize("hook", hooks())
def test_the_page_names_every_hook(hook):
    table = PAGE[PAGE.index("## The term contract") :]
    assert re.search(rf"`{hook}(\(|`)", table), f"docs/terms.md's contract table does not name the hook {hook}"


def test_the_position_dependent_example_agrees_in_both_engines():
    (block,) = [b for b in re.findall(r"```python\n(.*?)```", PAGE, re.S) if "class Tether" in b]
    scope: dict = {}
    try:
        exec(compile(block, "docs/terms.md", "exec"), scope)  # noqa: S102
    finally:
        if "tether" in ea.terms.names():
            ea.terms.unregister("tether")
    mujoco, reduced = scope["tips"]["mujoco"], scope["tips"]["reduced"]
    assert reduced[1] > 0.5  # the tether lifts the tip (the chain lies along x without it)
    assert mujoco == pytest.approx(reduced, rel=0.01)


class Quiet(Term):
    """A term that imposes a rate and names no setting that would slow it (slower returns '')."""

    name = "toy-quiet-rate"
    parameters = (Parameter("quiet_rate", 0.0, "a rate the term imposes (1 / tau)", low=0.0, quiet_default=True),)

    def rate(self, physics):
        return physics.quiet_rate

    def slower(self, physics, rate):
        return ""


def test_an_empty_slower_leaves_the_or_out():
    term = ea.terms.register(Quiet())
    try:
        physics = ea.Physics(n=3, quiet_rate=100.0)
        assert slower_advice(term, physics, 1.0) == ""
        with pytest.raises(ea.ParameterError) as refusal:
            ea.simulate(physics, duration=1.0, engine="mujoco")
        assert "or (" not in str(refusal.value) and "  " not in str(refusal.value)
        (note,) = _aliasing(ea.simulate(physics, duration=1.0, engine="reduced"))
        assert "()" not in note and not note.rstrip().endswith("or") and "  " not in note
    finally:
        ea.terms.unregister(term.name)

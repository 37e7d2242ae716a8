"""The study registry's budgets: every registered study declares the wall time it may take at the quick size (the
wall times themselves are measured by reproduce and written into report.md)."""

from __future__ import annotations

import pytest

from elastoactive.studies import registry
from elastoactive.studies.base import Summary


@pytest.mark.parametrize("budget", [0, -1.0, float("nan"), float("inf"), "10", True, None])
def test_a_study_without_a_positive_budget_is_refused(budget):
    with pytest.raises(ValueError, match="budget"):
        registry.declare("toy_unbudgeted", summary=Summary, order=1e6, budget=budget)
    assert "toy_unbudgeted" not in registry.names()


def test_a_study_cannot_be_declared_without_a_budget():
    with pytest.raises(TypeError, match="budget"):
        registry.declare("toy_unbudgeted", summary=Summary, order=1e6)  # type: ignore[call-arg]

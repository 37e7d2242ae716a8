"""The study registry's budgets: every registered study declares the wall time it may take at the quick size, and the
built-in studies' budgets keep the default `elastoactive reproduce` within registry.QUICK_BUDGET_S on an idle 2-core
machine (a check of the declarations; the wall times themselves are measured by reproduce and written into report.md).
"""

from __future__ import annotations

import pytest

from elastoactive.studies import registry
from elastoactive.studies.base import Summary


def test_the_budgets_sum_within_the_quick_reproduction():
    total = sum(entry.budget for entry in registry.entries())
    assert total + registry.START_S <= registry.QUICK_BUDGET_S, (
        f"the studies' budgets sum to {total:.0f} s, plus {registry.START_S:.0f} s of start-up: more than the quick "
        f"reproduction's {registry.QUICK_BUDGET_S:.0f} s; slowest: "
        + ", ".join(f"{e.name} {e.budget:.0f} s" for e in sorted(registry.entries(), key=lambda e: -e.budget)[:3])
    )


@pytest.mark.parametrize("budget", [0, -1.0, float("nan"), float("inf"), "10", True, None])
def test_a_study_without_a_positive_budget_is_refused(budget):
    with pytest.raises(ValueError, match="budget"):
        registry.declare("toy_unbudgeted", summary=Summary, order=1e6, budget=budget)
    assert "toy_unbudgeted" not in registry.names()


def test_a_study_cannot_be_declared_without_a_budget():
    with pytest.raises(TypeError, match="budget"):
        registry.declare("toy_unbudgeted", summary=Summary, order=1e6)  # type: ignore[call-arg]

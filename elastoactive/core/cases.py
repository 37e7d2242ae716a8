"""A validation case: a physics `validate` runs through both engines, and for how long (a leaf record).

Scenes (elastoactive.scenes.base.Scene.validation_cases) and terms (elastoactive.terms.base.Term.validation_cases)
declare theirs; `validate` and `accuracy` run them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class ValidationCase:
    """A case `validate` runs through both engines (and `accuracy` measures error against cost).

    convergence: also part of `validate --convergence` (one case per scene is enough there).
    """

    physics: Any
    """An elastoactive.core.params.Physics."""
    duration: float
    convergence: bool = True

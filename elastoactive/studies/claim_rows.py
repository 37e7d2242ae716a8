"""What the studies' claim rows share: the row record and the formatting of its numbers.

A row sets one claim of the paper against both engines (paper, MuJoCo, reduced model), with a
verdict from a stated numeric rule and a note giving the numbers behind it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from fractions import Fraction

from .base import SIZES

NOT_JUDGED = "not judged at this size"
"""The verdict of a row whose study ran at a size too small for its rule (Claim.judged_from)."""
VERDICTS = ("yes", "no", "partly", NOT_JUDGED)


@dataclass
class Claim:
    claim: str
    paper: str
    mujoco: str
    reduced: str
    agree: str  # one of VERDICTS
    note: str = ""
    judged_from: str = "tiny"
    """The smallest reproduce size (studies.base.SIZES) whose grids and runs can meet the verdict's rule (a fit's
    error bars, a power law's range); at a smaller size the row's verdict is NOT_JUDGED (judge)."""

    def judge(self, size: str) -> Claim:
        """The row as a study of `size` reports it: its numbers, and its verdict only if that size can judge it."""
        if size not in SIZES or SIZES.index(size) >= SIZES.index(self.judged_from):
            return self
        why = (
            f"not judged at the {size} size: its grids and runs are too coarse for this rule (verdict from the "
            f"{self.judged_from} size on; the numbers are shown as measured)"
        )
        return dataclasses.replace(self, agree=NOT_JUDGED, note=f"{why}. {self.note}" if self.note else why)


def fmt(x, d: int = 4) -> str:
    """x to `d` significant digits; '-' for None or a non-finite value."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{x:.{d}g}"


def span(values, d: int = 3) -> str:
    """'lo-hi' of the finite values (each to `d` significant digits: a threshold over seeds); '-' where none is."""
    finite = [v for v in values if math.isfinite(v)]
    return f"{fmt(min(finite), d)}-{fmt(max(finite), d)}" if finite else "-"


def pm(v, e, d: int = 4) -> str:
    """'v ± e' (the error to one digit); v alone without a finite error, '-' without v."""
    if v is None:
        return "-"
    if e is None or not math.isfinite(e):
        return fmt(v, d)
    return f"{v:.{d}g} ± {e:.1g}"


def fit_value(fit, par: str):
    """(value, error) of parameter `par` of a Fit, or (None, None) without one."""
    if not fit:
        return None, None
    return fit.params[par], fit.errors[par]


def frac(x: float) -> str:
    """A paper's fraction as it prints it, e.g. 4/3 or 11/8."""
    return str(Fraction(x).limit_denominator(100))


def verdict(ok: bool, partly: bool = False) -> str:
    return "yes" if ok else ("partly" if partly else "no")

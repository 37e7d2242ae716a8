"""The study registry: study name -> what reproduce, the report and the README table need of it.

A study module declares itself once, after its summary type, and attaches its pieces with
decorators (as dm_control's `suite` tags its tasks)::

    HOPF = registry.declare("hopf", summary=HopfSummary, order=30, budget=19.5)

    @HOPF.run
    def hopf_study(size="quick", workers=None, progress=True) -> Study: ...

    @HOPF.figure
    def hopf_figures(study, out) -> list[Path]: ...

    @HOPF.claims
    def hopf_claims(study, read) -> list[Claim]: ...

`order` places the study in reproduce and its claim rows in the table; `reads` names the other
studies its claim rows read (they get them in `read`, a dict holding those that were run); `budget` is the wall time
the study may take at the quick size on an idle 2-core machine (seconds; its figures are drawn beside the next study):
the budgets of the built-in studies sum to at most QUICK_BUDGET_S less START_S (a test holds it), and reproduce sets
each study's time against its budget. A leaf
module (it imports nothing of the package but the registries' shared pieces), so that any module can register a
study; the built-in studies register when `elastoactive.studies` is imported, those of the `elastoactive.studies`
entry points when the registry is first listed (elastoactive.plugins).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..core.table import Registry, UnknownName

QUICK_BUDGET_S = 240.0
"""The wall time the default (quick) `elastoactive reproduce` may take on an idle 2-core machine (seconds): every
built-in study's budget, plus START_S. The budgets are the studies' wall times measured in whole quick runs on the
project's 2-core machine with a warm numba cache (their mean over two runs, 229 and 233 s in all at load <= 2.5;
docs/performance.md section 17), so a study that grows, or a new one, shows here first."""
START_S = 6.0
"""The part of QUICK_BUDGET_S that is no study's: the process's start (importing the package and the engines), the
code digest, the figures not drawn while a study ran (the last study's), report.md: 1.6 s inside the measured run,
4.1 s of start and exit around it."""

RunFn = Callable[..., Any]
"""run(size="quick", workers=None, progress=True) -> Study."""
FigureFn = Callable[[Any, Path], list]
"""figure(study, out) -> the paths written (PNG figures)."""
FileFn = Callable[[Any, Path], list]
"""file(study, out) -> the data files written besides the study's NPZ/JSON (e.g. a CSV table)."""
ClaimsFn = Callable[[Any, Mapping[str, Any]], list]
"""claims(study, read) -> claim rows (elastoactive.studies.claim_rows.Claim); `read`: the studies of `reads` that
ran."""
SectionFn = Callable[[Any], str]
"""section(study) -> a Markdown section of report.md, after the claims table."""


@dataclass
class StudyEntry:
    """One registered study. `run`, `summary` and `budget` are required; the other pieces are optional."""

    name: str
    summary: type
    order: float
    budget: float
    """Seconds of wall time at the quick size on an idle 2-core machine (the study's run, not its figures)."""
    reads: tuple[str, ...] = ()
    run_fn: RunFn | None = None
    figures: list[FigureFn] = field(default_factory=list)
    files: list[FileFn] = field(default_factory=list)
    claims_fn: ClaimsFn | None = None
    section_fn: SectionFn | None = None

    # decorators ----------------------------------------------------------------------------------
    def run(self, fn: RunFn) -> RunFn:
        """Register `fn` as the study's run function."""
        self.run_fn = fn
        return fn

    def figure(self, fn: FigureFn) -> FigureFn:
        """Register a figure function (several are drawn in registration order)."""
        self.figures.append(fn)
        return fn

    def file(self, fn: FileFn) -> FileFn:
        """Register a function that writes a data file from the study (reproduce writes it beside the figures)."""
        self.files.append(fn)
        return fn

    def claims(self, fn: ClaimsFn) -> ClaimsFn:
        """Register the function giving the study's claim rows."""
        self.claims_fn = fn
        return fn

    def section(self, fn: SectionFn) -> SectionFn:
        """Register a report section (Markdown) drawn from the study."""
        self.section_fn = fn
        return fn

    # use ------------------------------------------------------------------------------------------
    def claim_rows(self, study, studies: Mapping[str, Any]) -> list:
        """The study's claim rows, given every study at hand (its `reads` are picked from them)."""
        if self.claims_fn is None:
            return []
        return self.claims_fn(study, {name: studies[name] for name in self.reads if name in studies})

    def draw(self, study, out: Path) -> list[Path]:
        """Every figure of the study, drawn into `out`; the paths written."""
        return [p for fn in self.figures for p in fn(study, out)]

    def write_files(self, study, out: Path) -> list[Path]:
        """The study's extra data files, written into `out`; the paths written."""
        return [p for fn in self.files for p in fn(study, out)]


class UnknownStudy(UnknownName):
    """Raised by `get` for a name that no study registered (its message lists the registered studies)."""

    kind, kinds = "study", "studies"


STUDIES: Registry[StudyEntry] = Registry(
    "study",
    "studies",
    error=UnknownStudy,
    group="studies",
    order=lambda entry: entry.order,
    same=lambda known, entry: False,  # a study declared again is a new entry: refused unless replace=True
)
"""The studies, in reproduce's order (StudyEntry.order; ties: registration order) (elastoactive.core.table.Registry)."""


def declare(
    name: str,
    *,
    summary: type,
    order: float,
    budget: float,
    reads: tuple[str, ...] | list[str] = (),
    replace: bool = False,
) -> StudyEntry:
    """Register a study called `name` with its summary type, its place in reproduce (`order`, ascending), its budget
    (seconds of wall time of its run at the quick size on an idle 2-core machine) and the other studies its claim rows
    read; returns the entry whose decorators attach its pieces."""
    if not isinstance(name, str) or not name.isidentifier():
        raise ValueError(f"a study name must be an identifier (it names <name>.npz and <name>.json), got {name!r}")
    if isinstance(budget, bool) or not isinstance(budget, (int, float)) or not 0.0 < budget < float("inf"):
        raise ValueError(f"study {name}: budget must be a positive number of seconds, got {budget!r}")
    return STUDIES.register(
        StudyEntry(name, summary, float(order), float(budget), tuple(reads)), owner=f"study {name}", replace=replace
    )


def unregister(name: str) -> None:
    """Remove a study (tests that register a toy study clean up with this)."""
    STUDIES.unregister(name)


def get(name: str) -> StudyEntry:
    """The registered study called `name` (the entry points' included; it must have a run function)."""
    entry = STUDIES.get(name)
    if entry.run_fn is None:
        raise ValueError(f"study {name!r} was declared without a run function (decorate one with @<entry>.run)")
    return entry


def names() -> tuple[str, ...]:
    """Names of the registered studies, in reproduce's order."""
    return STUDIES.names()


def entries() -> tuple[StudyEntry, ...]:
    """The registered studies (the entry points' included), in reproduce's order (ties: registration order)."""
    return STUDIES.entries()

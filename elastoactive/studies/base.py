"""What every study shares: the `Study` container, typed summaries and their JSON form, the sizes,
and running a batch of cases.

A study's `summary` is a frozen dataclass (a `Summary`); the numbers in it are plain floats, ints,
bools, strings, complex numbers, `analysis.fits.Fit`, lists, tuples, dicts keyed by strings and
nested summaries. `to_jsonable` (jsonio) writes that as JSON (non-finite floats as the strings
"nan", "inf", "-inf", so that a saved study reads back unchanged) and `from_jsonable` rebuilds it
from the dataclass's type hints.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypeVar

import numpy as np

from ..analysis.fits import Fit
from ..batch import Case, CaseResult, run_cases
from ..core.params import Numerics
from ..core.trajectory import Trajectory
from ..engines import ENGINES
from ..io.jsonio import from_jsonable, to_jsonable
from ..io.outputs import write_files
from ..io.progress import progress_bar

__all__ = [
    "ENGINES",
    "SIZES",
    "Study",
    "Summary",
    "EngineParts",
    "check_size",
    "pick",
    "run",
    "fast",
    "safe",
    "try_fit",
    "downsample",
    "to_jsonable",
    "from_jsonable",
]

SIZES = ("tiny", "quick", "full")
"""tiny: tests (seconds); quick: the default reproduce run (minutes); full: publication resolution."""

S = TypeVar("S", bound="Summary")


# --------------------------------------------------------------------------------------------------
# typed summaries
# --------------------------------------------------------------------------------------------------
class Summary:
    """Base of the summary dataclasses: their JSON form and back."""

    def as_dict(self) -> dict:
        """The summary as JSON-ready nested dicts and lists."""
        return to_jsonable(self)

    @classmethod
    def from_dict(cls: type[S], data: dict) -> S:
        """The summary back from `as_dict`'s form."""
        return from_jsonable(cls, data)


class EngineParts(Summary):
    """A summary with one nested part per engine, in fields named after the engines."""

    def engine(self, name: str):
        """The part of engine `name` ("mujoco" or "reduced"); None where the study did not run it."""
        if name not in ENGINES:
            raise ValueError(f"engine must be one of {', '.join(ENGINES)}; got {name!r}")
        return getattr(self, name)


# --------------------------------------------------------------------------------------------------
# the container
# --------------------------------------------------------------------------------------------------
@dataclass
class Study:
    """What a study produced: arrays behind its figures (`data`, saved as NPZ) and the numbers the
    report quotes (`summary`, a Summary dataclass, saved as JSON)."""

    name: str
    size: str
    data: dict = field(default_factory=dict)
    summary: Summary | None = None
    wall_s: float = 0.0

    def save(self, folder: Path, provenance: dict | None = None) -> list[Path]:
        """<name>.npz and <name>.json in `folder`, written atomically together (the JSON, which may carry
        the provenance record of elastoactive.io.outputs, last)."""
        record = {
            "study": self.name,
            "size": self.size,
            "wall_s": to_jsonable(self.wall_s),
            "summary": to_jsonable(self.summary),
        }
        if provenance is not None:
            record["provenance"] = provenance
        return write_files(
            Path(folder),
            {
                f"{self.name}.npz": lambda tmp: np.savez_compressed(
                    tmp, **{k: np.asarray(v) for k, v in self.data.items()}
                ),
                f"{self.name}.json": lambda tmp: tmp.write_text(json.dumps(record, indent=2) + "\n"),
            },
        )

    @classmethod
    def load(cls, folder: Path, name: str, summary_type: type[Summary]) -> Study:
        """Read back a study saved by `save`, its summary as `summary_type`."""
        folder = Path(folder)
        meta = json.loads((folder / f"{name}.json").read_text())
        with np.load(folder / f"{name}.npz") as f:
            data = {k: f[k] for k in f.files}
        summary = from_jsonable(summary_type, meta["summary"]) if meta.get("summary") is not None else None
        return cls(name, meta["size"], data, summary, from_jsonable(float, meta.get("wall_s", 0.0)))


# --------------------------------------------------------------------------------------------------
# plumbing shared by the study modules
# --------------------------------------------------------------------------------------------------
def check_size(size: str) -> str:
    if size not in SIZES:
        raise ValueError(f"size must be one of {', '.join(SIZES)}; got {size!r}")
    return size


def pick(size: str, tiny, quick, full):
    """The value for this size."""
    return {"tiny": tiny, "quick": quick, "full": full}[check_size(size)]


def run(cases: list[Case], workers, progress: bool, desc: str) -> list[Trajectory]:
    """Trajectories of the cases (input order), on `workers` processes (None: every core). Not measured by
    results.measure: a study measures its trajectories itself."""
    if not cases:
        return []
    res = run_cases(cases, workers=workers, progress=progress, keep_trajectory=True, desc=desc, measured=False)
    return [r.trajectory for r in res]


def run_measured(
    cases: list[Case], workers, progress: bool, desc: str, keep_trajectory: bool = False
) -> list[CaseResult]:
    """The cases run and measured by results.measure (over each case's transient) in the workers, in input order;
    their trajectories too with keep_trajectory (a study that needs measure's numbers gets them computed in
    parallel, not one after the other in this process)."""
    if not cases:
        return []
    return run_cases(cases, workers=workers, progress=progress, keep_trajectory=keep_trajectory, desc=desc)


def run_ramps(ramps: list, folder: Path, workers, progress: bool) -> list:
    """Each ramp (elastoactive.protocols.Ramp) run and read back (api.load_sweep: an xarray Dataset, dims seed,
    direction and the parameter), as protocols.run_ramp gives it, but with every seed of every ramp one task of one
    pool of `workers` processes (None: every core): a seed's steps follow one another, the seeds and the ramps run
    side by side, so that a study of several ramps with fewer seeds than cores (or a seed count the cores do not
    divide) keeps every core busy. A seed's run does not depend on the others' (its start and its noise are its own),
    so the result is run_ramp's. Files go to `folder`."""
    import xarray as xr  # start-up time: xarray reads the ramps back

    from ..api import load_sweep  # the front door imports the studies' package: at call time
    from ..io.executor import default_workers, imap

    jobs = [(dataclasses.replace(ramp, seeds=(seed,)), Path(folder) / f"ramp{k}_seed{seed}.nc") for k, ramp in
            enumerate(ramps) for seed in ramp.seeds]  # fmt: skip
    workers = default_workers() if workers is None else workers
    bar = progress_bar(len(jobs), "ramps", "seed") if progress else None
    try:
        if workers <= 1 or len(jobs) <= 1:
            for job in jobs:
                _run_ramp_job(job)
                if bar:
                    bar.update()
        else:
            for _ in imap(_run_ramp_job, jobs, workers, completed=True):
                if bar:
                    bar.update()
    finally:
        if bar:
            bar.close()
    sweeps, k = [], 0
    for ramp in ramps:
        parts = [load_sweep(path) for _, path in jobs[k : k + len(ramp.seeds)]]
        k += len(ramp.seeds)
        sweeps.append(parts[0] if len(parts) == 1 else xr.concat(parts, dim="seed", data_vars="all"))
    return sweeps


def _run_ramp_job(job) -> None:
    """One seed's ramp into its file (run_ramps' task, on one core)."""
    from ..protocols import run_ramp  # start-up time: the protocols load the engines

    ramp, path = job
    run_ramp(ramp, path, workers=1)


def fast(**kw) -> Numerics:
    """The 'fast' MuJoCo preset with overrides."""
    return Numerics.preset("fast", **kw)


def safe(fn: Callable, *args, default=float("nan"), **kw):
    """fn(*args, **kw), or `default` when it fails numerically."""
    try:
        return fn(*args, **kw)
    except (ValueError, RuntimeError, np.linalg.LinAlgError):
        return default


def try_fit(fit_fn: Callable[..., Fit], *args, **kw) -> Fit | None:
    """The fit, or None when there are too few points or it does not converge."""
    return safe(fit_fn, *args, default=None, **kw)


def downsample(a: np.ndarray, n: int = 2000) -> np.ndarray:
    step = max(1, a.shape[0] // n)
    return a[::step]

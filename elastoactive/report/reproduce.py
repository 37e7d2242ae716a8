"""`elastoactive reproduce`: regenerate every figure, its data and report.md in one folder.

A thin layer over the study registry (`elastoactive.studies.registry`): each registered study runs,
saves its data (`<name>.npz`, `<name>.json`), draws its figures and writes its files; report.md is
rendered by `claims` from every study of the folder (the command line itself is
elastoactive.cli.reproduce). Also the helpers the scenario scripts in scripts/ share.

A folder is reproduced in place, study by study, so that work is never lost or silently replaced:

- resume: a study whose data in the folder are complete and were made at the same size by the same
  code (`source_digest`, recorded in each study's JSON) is kept, not rerun (`force` reruns it);
- merge: the studies of the folder that were not asked for (`only`) stay, and report.md and
  provenance.json are rebuilt from every study present, so a partial run never shrinks the report;
- a folder holding studies of another size is refused (one line) unless `force`: its report cannot mix
  sizes; with `force` those studies are rerun when asked for, otherwise left out of the report;
- on Ctrl-C the studies already finished stay saved (a rerun resumes after them); the one running is
  dropped, and `Interrupted` says which;
- each study's figures are drawn in a process of their own while the next study runs (with more than one worker,
  where pools fork), and each study's wall time, figures' time, CPU time (the process tree's) and declared budget
  (studies.registry.StudyEntry.budget) go into the log, provenance.json and report.md, the slowest named;
- one reproduce writes into a folder at a time: a second is refused in one line while the first holds the folder's
  lock file (LOCK), which a killed run leaves stale, never blocking.

The studies (and the claims table, which reads their registry) are imported inside the functions that run or save
them, the studies' boundary: they load both engines, which `elastoactive reproduce --help` and a script reading
`source_digest` do not need.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import hashlib
import importlib.util
import json
import os
import resource
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

from ..batch import default_workers
from ..core.errors import ParameterError
from ..io.executor import forks, process_pool
from ..io.outputs import lock_file, provenance, utc_now, write_text

CODE_KEY = "code"
"""Key of the source digest in the provenance record a study saves with its data."""

LOCK = ".reproduce.lock"
"""The lock file a reproduce holds in its folder while it writes there (outputs.lock_file): a second reproduce into
the same folder is refused; one left by a killed run is taken over."""


@dataclass(frozen=True)
class Timing:
    """Wall time of one study in this run: the study itself (simulations, pool start-up and compilation in its
    workers, analysis) and drawing its figures and files; `kept` when its saved data were reused. `cpu_s`: the CPU
    time of the process tree over both (this process's threads and its finished worker processes), which a loaded
    machine does not inflate as it does the wall time: on an idle machine of `cores` cores the study takes at least
    cpu_s / cores. `budget_s`: the study's declared budget for its run (registry.StudyEntry.budget)."""

    study_s: float
    figures_s: float
    kept: bool = False
    cpu_s: float = 0.0
    budget_s: float = float("nan")

    @property
    def total_s(self) -> float:
        """The study and its figures."""
        return self.study_s + self.figures_s

    @property
    def over(self) -> bool:
        """Ran now and took longer than its budget (on a loaded machine every study may)."""
        return not self.kept and self.study_s > self.budget_s


def cpu_seconds() -> float:
    """CPU time so far of this process (its threads) and of its children that have ended (the batch's pools)."""
    me, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + children.ru_utime + children.ru_stime


def _draw(name: str, study, out: Path) -> tuple[list[Path], float, float]:
    """The figures and files of study `name` drawn into `out` (in this process or the figure process): the figures'
    paths, the wall and CPU seconds it took."""
    from ..studies import registry  # start-up time: the studies load both engines

    wall, cpu = time.perf_counter(), time.process_time()
    entry = registry.get(name)
    paths = entry.draw(study, out)
    entry.write_files(study, out)
    return paths, time.perf_counter() - wall, time.process_time() - cpu


def _drawn(result: Reproduction, name: str, drawn: tuple[list[Path], float, float]) -> None:
    """Record `_draw`'s outcome for study `name`: its figures, and their time in its Timing."""
    paths, wall, cpu = drawn
    result.figures[name] = paths
    timing = result.timings[name]
    result.timings[name] = dataclasses.replace(timing, figures_s=wall, cpu_s=timing.cpu_s + cpu)


def slowest(timings: dict[str, Timing], count: int = 3) -> str:
    """The `count` studies that took longest now (study and figures), e.g. 'states3d 41 s, long_chain 30 s'."""
    ran = sorted(((t.total_s, name) for name, t in timings.items() if not t.kept), reverse=True)
    return ", ".join(f"{name} {wall:.0f} s" for wall, name in ran[:count])


@dataclass
class Reproduction:
    """What `reproduce` left in `out`: every study of the report (by name, in reproduce's order), the figures
    each has there, report.md, the wall time, and which studies ran now and which were kept."""

    out: Path
    studies: dict = field(default_factory=dict)
    figures: dict = field(default_factory=dict)
    report: Path | None = None
    wall_s: float = 0.0
    ran: list[str] = field(default_factory=list)
    kept: list[str] = field(default_factory=list)
    timings: dict[str, Timing] = field(default_factory=dict)


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during reproduce; the message says which study stopped and what stays saved."""


SOURCE_PACKAGES = ("elastoactive", "elastoactive.analysis", "elastoactive.controllers", "elastoactive.mjcf")
"""The packages whose files make the results: in a checkout the last three are top-level folders mapped into the
package (pyproject's package-dir), in an installed copy they sit inside it."""
SOURCE_SUFFIXES = (".py", ".xml", ".c")
"""The files that count: Python, the MJCF templates, the follower-force callback's C source."""


def source_files() -> dict[str, Path]:
    """The files of SOURCE_PACKAGES with SOURCE_SUFFIXES, by '<package>:<path inside it>' (an installed copy, whose
    sub-packages sit inside the package's folder, lists theirs twice: harmless)."""
    out = {}
    for name in SOURCE_PACKAGES:
        spec = importlib.util.find_spec(name)
        for root in (Path(p).resolve() for p in ((spec.submodule_search_locations or []) if spec else [])):
            out.update(
                {
                    f"{name}:{f.relative_to(root).as_posix()}": f
                    for f in root.rglob("*")
                    if f.suffix in SOURCE_SUFFIXES and f.is_file()
                }
            )
    return out


def source_digest() -> str:
    """SHA-256 (first 16 hex digits) of `source_files`: the code version a study's data were made with (a git commit
    says nothing about uncommitted edits or an installed copy)."""
    h = hashlib.sha256()
    for rel, path in sorted(source_files().items()):
        h.update(rel.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:16]


@dataclass(frozen=True)
class Saved:
    """A study's data found in the folder: its size and code digest (None when unreadable or missing)."""

    name: str
    size: str | None
    code: str | None
    complete: bool


def _saved(out: Path, name: str) -> Saved | None:
    """What `out` holds of study `name` (None: nothing)."""
    meta, data = out / f"{name}.json", out / f"{name}.npz"
    if not meta.exists() and not data.exists():
        return None
    try:
        record = json.loads(meta.read_text())
        size, code = record.get("size"), (record.get("provenance") or {}).get(CODE_KEY)
    except (OSError, ValueError, AttributeError):
        return Saved(name, None, None, False)
    return Saved(name, size, code, data.exists() and record.get("summary") is not None)


class Plan(NamedTuple):
    """What reproduce does with each study: run it, keep its saved data (asked for, same size and code), merge it
    into the report (not asked for, same size), or leave it out of the report (another size, with `force`)."""

    run: list[str]
    keep: list[str]
    merge: list[str]
    other_size: list[str]


def _plan(out: Path, names: list[str], every: tuple[str, ...], size: str, code: str, force: bool) -> Plan:
    """The plan for the requested `names` among the registered `every`, or a ParameterError when the folder holds
    another size's studies and `force` is not given."""
    saved = {n: s for n in every if (s := _saved(out, n)) is not None}
    other = [n for n in every if n in saved and saved[n].complete and saved[n].size != size]
    if other and not force:
        sizes = sorted({saved[n].size for n in other})
        raise ParameterError(
            f"--out {out} holds {'/'.join(sizes)}-size studies ({', '.join(other)}), not {size}: "
            "one report cannot mix sizes; choose another --out or pass --force to rerun or drop them"
        )
    current = {n for n, s in saved.items() if s.complete and s.size == size}
    keep = [n for n in names if n in current and saved[n].code == code and not force]
    return Plan(
        [n for n in names if n not in keep],
        keep,
        [n for n in every if n in current and n not in names],
        [n for n in other if n not in names],
    )


def reproduce(
    out: Path,
    size: str = "quick",
    workers: int | None = None,
    only: list[str] | None = None,
    progress: bool = True,
    log=print,
    force: bool = False,
) -> Reproduction:
    """Run the studies (all, or those in `only`) into `out`: data, figures and files of each, then report.md
    and provenance.json over every study of the folder (see the module's docstring for resume and merge)."""
    from ..studies import SIZES, registry  # start-up time: the studies load both engines

    if size not in SIZES:
        raise ParameterError(f"size must be one of {', '.join(SIZES)}; got {size!r}")
    every = registry.names()
    names = list(every) if not only else list(dict.fromkeys(only))
    unknown = [n for n in names if n not in every]
    if unknown:
        raise ParameterError(f"unknown studies {', '.join(map(repr, unknown))}; choose from {', '.join(every)}")
    names = [n for n in every if n in names]  # reproduce's order
    if isinstance(out, str) and not out.strip():  # Path('') would be the working folder
        raise ParameterError(f"out: an empty path ({out!r}); give a folder (. for this folder)")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    with lock_file(out / LOCK, "reproduce"):  # one reproduce per folder at a time
        return _reproduce(out, size, workers, names, progress, log, force)


def _reproduce(
    out: Path, size: str, workers: int | None, names: list[str], progress: bool, log, force: bool
) -> Reproduction:
    """reproduce's work on the folder `out`, which this process holds (`names`: the studies asked for, checked)."""
    # start-up time: the studies load both engines (and matplotlib when drawing)
    from ..studies import Study, load_study, registry
    from . import claims

    every = registry.names()
    code = source_digest()
    to_run, to_keep, merged, dropped = _plan(out, names, every, size, code, force)
    started = utc_now()
    workers = default_workers() if workers is None else workers
    start = time.perf_counter()
    result = Reproduction(out)
    unreadable = []
    for name in to_keep + merged:
        try:
            result.studies[name] = load_study(out, name)
        except (OSError, ValueError, KeyError, TypeError) as err:  # a torn file, or a summary this code cannot read
            if name in merged:
                unreadable.append(name)
                log(f"left out of the report: {name} ({out / name}.json/.npz cannot be read by this code: {err})")
    to_keep = [n for n in to_keep if n in result.studies]
    to_run = [n for n in names if n not in to_keep]
    merged = [n for n in merged if n in result.studies]
    report_names = [n for n in every if n in names or n in merged]
    if to_keep:
        log(f"kept from an earlier run at this size and code: {', '.join(to_keep)}")
    redo = [n for n in to_run if (s := _saved(out, n)) is not None and s.complete and s.size == size and not force]
    if redo:
        log(f"run again, their data in the folder made by other code: {', '.join(redo)}")
    if merged:
        log(f"in the report from this folder (not asked for): {', '.join(merged)}")
    if dropped:
        log(f"left out of the report (another size; --force): {', '.join(dropped)}")

    with contextlib.ExitStack() as stack:
        # the figures of each study are drawn in a process of their own while the next study runs (a study leaves a
        # core idle part of its time); in this process with one worker, or where pools do not fork
        painter = stack.enter_context(process_pool(1)) if workers > 1 and forks() and len(to_run) > 1 else None
        drawing = {}
        for i, name in enumerate(to_run, 1):
            entry = registry.get(name)
            log(f"[{i}/{len(to_run)}] {name} (budget {entry.budget:.0f} s) ...")
            t0 = t1 = time.perf_counter()
            cpu0 = cpu_seconds()
            saved = False
            try:
                study: Study = entry.run_fn(size, workers=workers, progress=progress)
                study.save(out, {**provenance(started, study.wall_s), CODE_KEY: code})
                saved, t1 = True, time.perf_counter()
                if painter is None:
                    drawn = _draw(name, study, out)
                else:
                    drawing[name] = painter.submit(_draw, name, study, out)
            except KeyboardInterrupt:
                kept = result.ran + ([name] if saved else []) + to_keep
                raise Interrupted(
                    f"interrupted during {name} ({i}/{len(to_run)}): "
                    + ("its data are saved, its figures not; " if saved else "its data were not saved; ")
                    + f"kept in {out}: {', '.join(kept) or 'no finished study'} (a figure not drawn yet is drawn "
                    "by the rerun); rerun the same command to resume"
                ) from None
            result.studies[name] = study
            result.ran.append(name)
            timing = Timing(t1 - t0, 0.0, cpu_s=cpu_seconds() - cpu0, budget_s=entry.budget)
            result.timings[name] = timing
            if painter is None:
                _drawn(result, name, drawn)
                timing = result.timings[name]
            log(
                f"[{i}/{len(to_run)}] {name} done in {timing.study_s:.1f} s (budget {timing.budget_s:.0f} s; CPU "
                f"{timing.cpu_s:.1f} s) -> "
                + (
                    ", ".join(p.name for p in result.figures[name]) + f" ({timing.figures_s:.1f} s)"
                    if painter is None
                    else "its figures drawn beside the next study"
                )
            )
        for name, future in drawing.items():
            _drawn(result, name, future.result())
        if drawing:
            log(
                "figures: "
                + ", ".join(f"{name} {result.timings[name].figures_s:.1f} s" for name in drawing)
                + (
                    f"; over budget: {', '.join(n for n in drawing if result.timings[n].over)}"
                    if any(result.timings[n].over for n in drawing)
                    else ""
                )
            )

    for name in report_names:  # the studies not run now: their figures and files, drawn again from their data
        if name not in result.figures:
            t1 = time.perf_counter()
            entry = registry.get(name)
            result.figures[name] = entry.draw(result.studies[name], out)
            entry.write_files(result.studies[name], out)
            result.kept.append(name)
            result.timings[name] = Timing(0.0, time.perf_counter() - t1, kept=True, budget_s=entry.budget)
    result.studies = {n: result.studies[n] for n in report_names}
    result.wall_s = time.perf_counter() - start
    command = "elastoactive reproduce" + (" --full" if size == "full" else "") + (" --tiny" if size == "tiny" else "")
    record = {
        **provenance(started, result.wall_s),
        CODE_KEY: code,
        "studies_run": result.ran,
        "studies_kept": result.kept,
        "load_average": list(os.getloadavg()),
        "timings": {name: dataclasses.asdict(t) for name, t in result.timings.items()},
    }
    write_text(out / "provenance.json", json.dumps(record, indent=2) + "\n")
    result.report = out / "report.md"
    write_text(
        result.report,
        claims.render_report(
            result.studies,
            result.figures,
            {
                "size": size,
                "workers": workers,
                "wall_s": result.wall_s,
                "command": command,
                "provenance": record,
                "timings": result.timings,
                "slowest": slowest(result.timings),
                "load_average": record["load_average"],
                "kept": result.kept,
                "unreadable": unreadable,
                "other_size": dropped,
            },
        ),
    )
    log(
        f"wrote {result.report} ({result.wall_s:.0f} s"
        + (f"; slowest: {slowest(result.timings)}" if result.ran else "")
        + (
            f"; over budget: {', '.join(n for n, t in result.timings.items() if t.over)}"
            if any(t.over for t in result.timings.values())
            else ""
        )
        + ")"
    )
    return result


# ------------------------------------------------------------------------------------------------
# shared by the scenario scripts in scripts/
# ------------------------------------------------------------------------------------------------
def scenario_parser(description: str, default_out: str) -> argparse.ArgumentParser:
    """--tiny / --full, --out, --workers: the arguments every scenario script takes."""
    p = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    g = p.add_mutually_exclusive_group()
    g.add_argument("--tiny", action="store_true", help="smallest size (seconds; for tests)")
    g.add_argument("--full", action="store_true", help="publication resolution (slow)")
    p.add_argument("--out", type=Path, default=Path(default_out), help="output folder (default %(default)s)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: every core)")
    return p


def scenario_size(args) -> str:
    return "tiny" if args.tiny else ("full" if args.full else "quick")


def save_all(studies, out: Path) -> list[Path]:
    """Save each study's data, figures and files into `out` (through the study registry); returns the figure paths."""
    from ..studies import registry  # start-up time: the studies load both engines

    paths = []
    for study in studies:
        entry = registry.get(study.name)
        study.save(out)
        paths += entry.draw(study, out)
        paths += entry.write_files(study, out)
    for p in paths:
        print(f"wrote {p}")
    return paths

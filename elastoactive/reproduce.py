"""`elastoactive reproduce`: regenerate every figure, its data and report.md in one folder.

A thin layer: the studies are `elastoactive.studies`, the figures `figures`, the claim table
`claims` (the command line itself is elastoactive.cli.reproduce). Also the helpers the scenario
scripts in scripts/ share.
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

from .outputs import atomic_file, provenance, utc_now, write_text


def reproduce(out: Path, size: str = "quick", workers: int | None = None, only: list[str] | None = None,
              progress: bool = True, log=print) -> dict:
    """Run the studies (all, or those in `only`), write figures, data and report.md into `out`.

    Returns {"studies": {name: Study}, "figures": {name: [paths]}, "report": path, "wall_s": seconds}.
    """
    from . import claims, figures  # start-up time: figures loads matplotlib
    from . import studies as st  # start-up time: the studies load both engines
    from .batch import default_workers  # start-up time: batch loads both engines

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    started = utc_now()
    workers = default_workers() if workers is None else workers
    names = list(st.STUDIES) if not only else only
    unknown = [n for n in names if n not in st.STUDIES]
    if unknown:
        raise ValueError(f"unknown studies {unknown}; choose from {', '.join(st.STUDIES)}")
    start = time.perf_counter()
    done, figs = {}, {}
    for i, name in enumerate(names, 1):
        log(f"[{i}/{len(names)}] {name} ...")
        study = st.STUDIES[name](size, workers=workers, progress=progress)
        study.save(out, provenance(started, study.wall_s))
        figs[name] = figures.make_figures(study, out)
        done[name] = study
        log(f"[{i}/{len(names)}] {name} done in {study.wall_s:.1f} s -> {', '.join(p.name for p in figs[name])}")
    if "stability" in done:
        with atomic_file(out / "stability_sigma_c.csv") as tmp, open(tmp, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["N", "sigma_c", "omega_c", "f_c", "N3_sigma_c"])
            for row in done["stability"].summary.table:
                w.writerow([row.n, repr(row.sigma_c), repr(row.omega_c), repr(row.f_c), repr(row.n ** 3 * row.sigma_c)])
    wall = time.perf_counter() - start
    command = "elastoactive reproduce" + (" --full" if size == "full" else "") + (" --tiny" if size == "tiny" else "")
    record = provenance(started, wall)
    write_text(out / "provenance.json", json.dumps(record, indent=2) + "\n")
    report = out / "report.md"
    write_text(report, claims.render_report(done, figs, {"size": size, "workers": workers, "wall_s": wall,
                                                          "command": command, "provenance": record}))
    log(f"wrote {report} ({wall:.0f} s)")
    return {"studies": done, "figures": figs, "report": report, "wall_s": wall}


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
    """Save each study's data and figures into `out`; returns the figure paths."""
    from . import figures  # start-up time: matplotlib

    paths = []
    for study in studies:
        study.save(out)
        paths += figures.make_figures(study, out)
    for p in paths:
        print(f"wrote {p}")
    return paths

"""Error against wall time: which MuJoCo and reduced-model settings reach 1%, 0.1%, 0.01%.

For each of the paper's cases (the validation cases of study_scenes(), run for a shorter time) every setting is
compared with a tight reference solution of the reduced model (numba-DOP853, rtol 1e-11, atol 1e-13; a scene whose
engine does not take that method is solved with one it takes: reference_method), using the error definitions of
validate.compare:

  amplitude, frequency  relative errors of Theta's steady amplitude and frequency (second half)
  rotation_rate         rotating pin: relative error of the mean rotation rate
  angle                 largest |theta - theta_ref| over the transient window
                        (validate.comparison_window), relative to the largest |theta_ref| there
  worst                 the largest of these (the 1% target of `elastoactive validate`)
  steady                the largest of amplitude, frequency and rotation rate only

MuJoCo settings are (integrator, dt, mass_ratio); Euler and RK4 treat the drag explicitly and need
dt < 2 m / gamma (RK4: 2.78 m / gamma), so they are paired with larger mass ratios. A setting beyond the
linear stability limit (diagnose.check_timestep with accuracy=False) is recorded as "refused", a run
that blows up as "diverged"; neither stops the study. Stable settings are run even when the
pre-flight accuracy guard (diagnose.check_accuracy) would refuse them; the column `guard` says
whether it would, so the guard's bounds can be checked against the measured errors. Reduced-model settings are
(method, rtol) with atol = rtol/100.

Wall time is the engine's own clock (Trajectory.wall_time_s: simulation only, no model build or
measurement), best of up to `repeats` runs while the runs are short. The machine is shared, so
timings carry noise of tens of percent.
"""

from __future__ import annotations

import csv
import json
import math
import os
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from ..batch import default_workers
from ..core.errors import ParameterError, SimulationDiverged
from ..core.params import PRESETS, Numerics, Physics
from ..core.registry import get as get_scene
from ..core.registry import names as scene_names
from ..engines.mujoco import simulate_mujoco
from ..engines.reduced import simulate_reduced
from ..engines.timestep import check_accuracy, check_timestep
from ..io.executor import imap
from ..io.outputs import atomic_file, provenance, provenance_line, utc_now, write_text
from ..io.progress import progress_bar
from ..results import default_transient, measure
from .validate import angle_errors, observable_errors

REFERENCE = dict(method="numba-DOP853", rtol=1e-11, atol=1e-13)
SAMPLE_DT = 0.04  # a whole number of steps for every dt in the grids below
LEVELS = (1e-2, 1e-3, 1e-4)
ERROR_KEYS = ("amplitude", "frequency", "rotation_rate", "angle")
STEADY_KEYS = ("amplitude", "frequency", "rotation_rate")

# Durations: this fraction of each validation case's (150 / 100 tau for a single chain, 300 / 200 for the
# pair), long enough for two or more periods (f ~ 0.04 / tau) in the measured second half.
DURATION_FRACTION = {"full": 0.5, "quick": 1.0 / 3.0, "tiny": 1.0 / 3.0}

SIZES = ("full", "quick", "tiny")
"""Sizes of the study: full (the numbers of docs/performance.md, ~16 min on 2 cores), quick (a coarser grid, 2-2.5
min) and tiny (one case, two settings per engine, a few seconds: a smoke test whose numbers say little)."""


def study_scenes() -> tuple[str, ...]:
    """The scenes whose own validation cases the study runs: the paper's chains (Scene.paper), which every engine
    setting of the grids (MuJoCo integrators, the reduced engine's chain methods) can run. The other scenes and the
    terms add no numerics of their own to these (a network scene's engine takes other methods; `validate` checks every
    scene at the defaults)."""
    return tuple(name for name in scene_names() if get_scene(name).paper)


DEFAULT_MUJOCO = dict(integrator="implicitfast", dt=Numerics().dt, mass_ratio=Numerics().mass_ratio)
FAST_MUJOCO = dict(integrator="implicitfast", dt=PRESETS["fast"]["dt"], mass_ratio=PRESETS["fast"]["mass_ratio"])
DEFAULT_REDUCED = dict(method="numba-DOP853", rtol=1e-9)


@dataclass(frozen=True)
class Setting:
    engine: str  # "mujoco" or "reduced"
    series: str  # integrator or method
    dt: float | None = None
    mass_ratio: float | None = None
    rtol: float | None = None

    @property
    def label(self) -> str:
        if self.engine == "mujoco":
            return f"{self.series} dt={self.dt:g} m={self.mass_ratio:g}"
        return f"{self.series} rtol={self.rtol:g}"

    def numerics(self) -> Numerics:
        if self.engine == "mujoco":
            return Numerics(dt=self.dt, mass_ratio=self.mass_ratio, integrator=self.series, sample_dt=SAMPLE_DT)
        return Numerics(sample_dt=SAMPLE_DT)


def _halvings(start: float, count: int) -> list[float]:
    return [start / 2**k for k in range(count)]


def _size(quick: bool | str) -> str:
    """A size of SIZES from the older quick flag (True: quick, False: full) or a size's name."""
    size = ("quick" if quick else "full") if isinstance(quick, bool) else quick
    if size not in SIZES:
        raise ParameterError(f"size must be one of {', '.join(SIZES)}, got {quick!r}")
    return size


def mujoco_grid(quick: bool | str = False) -> list[Setting]:
    """(integrator, dt, mass ratio) settings; Euler/RK4 only where dt is below their drag limit."""
    grid: list[tuple[str, float, float]] = []
    size = _size(quick)
    if size == "tiny":
        return [
            Setting("mujoco", "implicitfast", dt=dt, mass_ratio=m)
            for dt, m in (
                (DEFAULT_MUJOCO["dt"], DEFAULT_MUJOCO["mass_ratio"]),
                (FAST_MUJOCO["dt"], FAST_MUJOCO["mass_ratio"]),
            )
        ]
    if size == "quick":
        for m in (1e-3, 1e-4, 1e-5):
            grid += [("implicitfast", dt, m) for dt in (0.04, 0.01, 0.0025, 0.000625)]
        grid += [("implicit", dt, 1e-4) for dt in (0.01, 0.0025)]
        grid += [("discrete", dt, 1e-4) for dt in (0.04, 0.01, 0.0025, 0.000625)]
        grid += [("Euler", 0.01, 1e-2), ("Euler", 0.0025, 1e-2), ("Euler", 0.00125, 1e-3)]
        grid += [("RK4", 0.02, 1e-2), ("RK4", 0.0025, 1e-3)]
    else:
        dts = _halvings(0.04, 9)  # 0.04 ... 1.5625e-4
        for m in (1e-3, 1e-4, 1e-5, 1e-6):
            grid += [("implicitfast", dt, m) for dt in dts]
        for m in (1e-4, 1e-6):
            grid += [("implicit", dt, m) for dt in dts[:7]]
            grid += [("discrete", dt, m) for dt in dts]
        for m in (1e-2, 1e-3, 1e-4):
            grid += [("Euler", dt, m) for dt in _halvings(0.04, 10) if dt < 2.0 * m]
            grid += [("RK4", dt, m) for dt in _halvings(0.04, 9) if dt < 2.78 * m][:4]
    grid.append(("implicitfast", DEFAULT_MUJOCO["dt"], DEFAULT_MUJOCO["mass_ratio"]))
    grid.append(("implicitfast", FAST_MUJOCO["dt"], FAST_MUJOCO["mass_ratio"]))
    seen, out = set(), []
    for integrator, dt, m in grid:
        if (integrator, dt, m) not in seen:
            seen.add((integrator, dt, m))
            out.append(Setting("mujoco", integrator, dt=dt, mass_ratio=m))
    return out


REDUCED_METHODS = ("numba-DOP853", "DOP853", "RK45", "Radau", "LSODA")


def reduced_grid(quick: bool | str = False) -> list[Setting]:
    size = _size(quick)
    if size == "tiny":
        return [Setting("reduced", DEFAULT_REDUCED["method"], rtol=r) for r in (1e-4, DEFAULT_REDUCED["rtol"])]
    rtols = (1e-4, 1e-6, 1e-8) if size == "quick" else (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
    out = [Setting("reduced", method, rtol=r) for method in REDUCED_METHODS for r in rtols]
    if Setting("reduced", DEFAULT_REDUCED["method"], rtol=DEFAULT_REDUCED["rtol"]) not in out:
        out.append(Setting("reduced", DEFAULT_REDUCED["method"], rtol=DEFAULT_REDUCED["rtol"]))
    return out


def paper_cases(quick: bool | str = False) -> list[tuple[Physics, float]]:
    """The study's (physics, duration): the validation cases of study_scenes(), shortened (DURATION_FRACTION); the
    first one only at the tiny size."""
    size = _size(quick)
    cases = [
        (c.physics, round(DURATION_FRACTION[size] * c.duration, 9))
        for name in study_scenes()
        for c in get_scene(name).validation_cases()
    ]
    return cases[:1] if size == "tiny" else cases


def case_name(physics: Physics) -> str:
    return physics.scene_def.label(physics)


# ------------------------------------------------------------------------------------------------
# errors
# ------------------------------------------------------------------------------------------------
def reference_method(physics: Physics) -> str:
    """REFERENCE's method where the scene's reduced engine takes it, else the engine's DOP853 (a network's engine
    has its own methods: Scene.reduced_methods)."""
    methods = physics.scene_def.reduced_methods()  # the scene's kind's reduced engine
    return REFERENCE["method"] if REFERENCE["method"] in methods else "DOP853" if "DOP853" in methods else methods[0]


def reference_solution(physics: Physics, duration: float, sample_dt: float = SAMPLE_DT):
    """The tight reduced-model solution every setting is measured against (the paper's overdamped model)."""
    return simulate_reduced(
        physics,
        Numerics(sample_dt=sample_dt),
        duration,
        inertial=False,
        **{**REFERENCE, "method": reference_method(physics)},
    )


def errors_against(traj, reference, transient: float | None = None, reference_measure=None) -> dict:
    """validate.compare's errors of `traj` against `reference` (same sample times), plus the largest
    (`worst`) and the largest of the steady-state ones (`steady`)."""
    physics = reference.physics
    transient = default_transient(reference.t[-1]) if transient is None else transient
    a = measure(traj, transient)
    b = measure(reference, transient) if reference_measure is None else reference_measure
    compared = physics.scene_def.compared
    errors = {k: v for k, v in observable_errors(physics, a, b).items() if k in compared}
    errors.update(angle_errors(traj, reference))
    errors["worst"] = max(errors[k] for k in ERROR_KEYS if k in errors)
    errors["steady"] = max(errors[k] for k in STEADY_KEYS if k in errors)
    return errors


# ------------------------------------------------------------------------------------------------
# one setting on one case
# ------------------------------------------------------------------------------------------------
def _simulate(physics: Physics, duration: float, setting: Setting):
    if setting.engine == "mujoco":
        return simulate_mujoco(physics, setting.numerics(), duration)
    return simulate_reduced(
        physics, setting.numerics(), duration, method=setting.series, rtol=setting.rtol, atol=setting.rtol * 1e-2
    )


def run_setting(
    physics: Physics,
    duration: float,
    setting: Setting,
    reference,
    reference_measure=None,
    repeats: int = 3,
    min_time: float = 0.5,
) -> dict:
    """Errors and wall time of one setting on one case; never raises for an unstable setting."""
    row = {
        "case": case_name(physics),
        "scene": physics.scene,
        "duration": duration,
        **asdict(setting),
        "label": setting.label,
        "status": "ok",
        "wall_s": math.nan,
        "message": "",
        "guard": "",
    }
    try:
        if setting.engine == "mujoco":
            # stability only: the study measures the error of every stable setting, and records whether
            # the pre-flight accuracy guard (diagnose.check_accuracy) would have refused it
            limits = check_timestep(physics, setting.numerics(), accuracy=False)
            try:
                check_accuracy(physics, setting.numerics(), limits)
                row["guard"] = "pass"
            except ParameterError as err:
                row["guard"] = "refuse: " + str(err).split(";")[0].split(" for scene")[0]
        traj = _simulate(physics, duration, setting)
        walls = [traj.wall_time_s]
        while len(walls) < repeats and sum(walls) < min_time:
            walls.append(_simulate(physics, duration, setting).wall_time_s)
        row["wall_s"] = min(walls)
        row["runs"] = len(walls)
        row.update(errors_against(traj, reference, reference_measure=reference_measure))
        if "constraint_violation" in traj.info:
            row["pin_violation"] = traj.info["constraint_violation"]
    except ParameterError as err:
        row.update(status="refused", message=str(err))
    except SimulationDiverged as err:
        row.update(status="diverged", message=str(err))
    except RuntimeError as err:  # a reduced-model solver that gave up
        row.update(status="failed", message=str(err))
    return row


def _worker_init() -> None:
    # load the numba kernels once per process so that the first timed run does not pay for it
    for physics, _ in paper_cases("tiny"):
        simulate_reduced(physics, Numerics(), 1.0)


def _task(args):
    physics, duration, setting, reference, repeats = args
    return run_setting(physics, duration, setting, reference, repeats=repeats)


def run_study(
    quick: bool | str = False,
    workers: int | None = None,
    progress: bool = True,
    cases=None,
    mujoco=None,
    reduced=None,
    repeats: int = 3,
) -> tuple[list[dict], dict]:
    """All settings on all cases (`quick`: a size of SIZES, or True for quick); returns (rows, meta)."""
    size = _size(quick)
    cases = paper_cases(size) if cases is None else cases
    settings = (mujoco_grid(size) if mujoco is None else mujoco) + (reduced_grid(size) if reduced is None else reduced)
    workers = default_workers() if workers is None else workers
    start, started = time.perf_counter(), utc_now()
    references = [reference_solution(p, d) for p, d in cases]
    tasks = [(p, d, s, ref, repeats) for (p, d), ref in zip(cases, references) for s in settings]
    # longest first, so the pool does not end on one long run
    order = sorted(range(len(tasks)), key=lambda i: -_expected_cost(tasks[i][0], tasks[i][1], tasks[i][2]))
    rows: list[dict | None] = [None] * len(tasks)
    bar = None
    if progress:
        bar = progress_bar(len(tasks), "accuracy", "run")
    if workers <= 1:
        _worker_init()
        for i in order:
            rows[i] = _task(tasks[i])
            if bar:
                bar.update()
    else:
        for j, row in imap(_task, [tasks[i] for i in order], workers, initializer=_worker_init):
            rows[order[j]] = row
            if bar:
                bar.update()
    if bar:
        bar.close()
    meta = {
        "quick": size != "full",
        "size": size,
        "workers": workers,
        "elapsed_s": time.perf_counter() - start,
        "started_utc": started,
        "cases": [(case_name(p), d) for p, d in cases],
        "reference": REFERENCE,
        "sample_dt": SAMPLE_DT,
        "reference_wall_s": [r.wall_time_s for r in references],
        "cpu_count": os.cpu_count(),
    }
    return rows, meta  # type: ignore[return-value]


def _expected_cost(physics: Physics, duration: float, setting: Setting) -> float:
    if setting.engine == "reduced":
        return duration * (1e-3 if setting.series == "numba-DOP853" else 1e-2) / max(setting.rtol, 1e-12) ** 0.1
    per_step = {"implicitfast": 4.0, "implicit": 6.0, "discrete": 6.0, "Euler": 3.3, "RK4": 14.0}[setting.series]
    return physics.n_chains * per_step * duration / setting.dt


# ------------------------------------------------------------------------------------------------
# summaries
# ------------------------------------------------------------------------------------------------
def summarise(rows: list[dict]) -> list[dict]:
    """One line per setting over all cases: largest errors and total wall time per 100 tau."""
    by_label: dict[str, list[dict]] = {}
    for r in rows:
        by_label.setdefault(r["label"], []).append(r)
    out = []
    for rs in by_label.values():
        first = rs[0]
        ok = all(r["status"] == "ok" for r in rs)
        status = "ok" if ok else "/".join(sorted({r["status"] for r in rs if r["status"] != "ok"}))
        line = {k: first[k] for k in ("engine", "series", "dt", "mass_ratio", "rtol", "label")}
        line["status"] = status
        line["cases"] = len(rs)
        tau = sum(r["duration"] for r in rs)
        line["wall_s"] = sum(r["wall_s"] for r in rs) if ok else math.nan
        line["wall_per_100tau"] = 100.0 * line["wall_s"] / tau if ok else math.nan
        for key in ("worst", "steady", "amplitude", "frequency", "rotation_rate", "angle"):
            vals = [r[key] for r in rs if key in r]
            line[key] = max(vals) if (ok and vals) else math.nan
        line["pin_violation"] = max((r.get("pin_violation", 0.0) for r in rs), default=0.0) if ok else math.nan
        refused = [r["case"] for r in rs if r.get("guard", "").startswith("refuse")]
        line["guard"] = "-" if first["engine"] != "mujoco" else (f"refuses {', '.join(refused)}" if refused else "pass")
        out.append(line)
    return out


def recommend(summary: list[dict], levels=LEVELS, key: str = "worst") -> list[dict]:
    """Cheapest setting of each integrator / method whose largest error over the cases is <= level."""
    out = []
    for level in levels:
        for engine in ("mujoco", "reduced"):
            series = sorted({s["series"] for s in summary if s["engine"] == engine})
            for name in series:
                cands = [
                    s
                    for s in summary
                    if s["engine"] == engine and s["series"] == name and s["status"] == "ok" and s[key] <= level
                ]
                best = min(cands, key=lambda s: s["wall_s"]) if cands else None
                out.append({"level": level, "engine": engine, "series": name, "setting": best})
    return out


def _fmt(x, spec=".2e"):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return format(x, spec)


def _pct(x):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{100 * x:.3g}%"


def format_recommendations(recs: list[dict], key: str = "worst") -> str:
    lines = [
        f"| target ({key} error) | engine | integrator / method | cheapest setting | {key} error "
        "| wall s per 100 tau |",
        "|---|---|---|---|---|---|",
    ]
    for r in recs:
        s = r["setting"]
        if s is None:
            lines.append(f"| {_pct(r['level'])} | {r['engine']} | {r['series']} | not reached in the grid | - | - |")
            continue
        setting = f"dt={s['dt']:g}, m={s['mass_ratio']:g}" if r["engine"] == "mujoco" else f"rtol={s['rtol']:g}"
        lines.append(
            f"| {_pct(r['level'])} | {r['engine']} | {r['series']} | {setting} | {_pct(s[key])} "
            f"| {s['wall_per_100tau']:.3g} |"
        )
    return "\n".join(lines)


def format_summary(summary: list[dict]) -> str:
    lines = [
        "| engine | integrator / method | dt | mass ratio | rtol | status | worst err | amplitude | frequency "
        "| rotation rate | angle (transient) | pin violation | wall s / 100 tau | pre-flight accuracy guard |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for s in sorted(
        summary, key=lambda s: (s["engine"], s["series"], -(s["mass_ratio"] or 0), -(s["dt"] or 0), -(s["rtol"] or 0))
    ):
        lines.append(
            f"| {s['engine']} | {s['series']} | {_fmt(s['dt'], 'g')} | {_fmt(s['mass_ratio'], 'g')} "
            f"| {_fmt(s['rtol'], 'g')} "
            f"| {s['status']} | {_pct(s['worst'])} | {_pct(s['amplitude'])} | {_pct(s['frequency'])} "
            f"| {_pct(s['rotation_rate'])} | {_pct(s['angle'])} | {_fmt(s['pin_violation'], '.1e')} "
            f"| {_fmt(s['wall_per_100tau'], '.3g')} | {s.get('guard', '-')} |"
        )
    return "\n".join(lines)


def format_defaults(summary: list[dict]) -> str:
    wanted = [
        (
            "MuJoCo default ('accurate')",
            "mujoco",
            DEFAULT_MUJOCO["integrator"],
            DEFAULT_MUJOCO["dt"],
            DEFAULT_MUJOCO["mass_ratio"],
            None,
        ),
        (
            "MuJoCo 'fast' preset",
            "mujoco",
            FAST_MUJOCO["integrator"],
            FAST_MUJOCO["dt"],
            FAST_MUJOCO["mass_ratio"],
            None,
        ),
        ("reduced default", "reduced", DEFAULT_REDUCED["method"], None, None, DEFAULT_REDUCED["rtol"]),
    ]
    lines = [
        "| setting | worst err | amplitude | frequency | rotation rate | angle (transient) | wall s per 100 tau "
        "| simulated tau per wall s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for name, engine, series, dt, m, rtol in wanted:
        match = [
            s
            for s in summary
            if s["engine"] == engine
            and s["series"] == series
            and s["dt"] == dt
            and s["mass_ratio"] == m
            and s["rtol"] == rtol
        ]
        if not match:
            continue
        s = match[0]
        rate = 100.0 / s["wall_per_100tau"] if s["wall_per_100tau"] else math.nan
        lines.append(
            f"| {name} | {_pct(s['worst'])} | {_pct(s['amplitude'])} | {_pct(s['frequency'])} "
            f"| {_pct(s['rotation_rate'])} | {_pct(s['angle'])} | {_fmt(s['wall_per_100tau'], '.3g')} "
            f"| {_fmt(rate, '.0f')} |"
        )
    return "\n".join(lines)


MARKERS = {
    "implicitfast": "o",
    "implicit": "s",
    "discrete": "D",
    "Euler": "v",
    "RK4": "^",
    "numba-DOP853": "*",
    "DOP853": "P",
    "RK45": "X",
    "Radau": "h",
    "LSODA": "<",
}


def plot(rows: list[dict], summary: list[dict], path: Path, key: str = "worst") -> None:
    """Log-log error against wall time: one panel per case and one for all cases together."""
    import matplotlib  # start-up time: only when plotting

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # after matplotlib.use("Agg")

    cases = list(dict.fromkeys(r["case"] for r in rows))
    panels = cases + ["all cases (largest error, total time)"]
    ncol = 3
    nrow = math.ceil(len(panels) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 4.2 * nrow), squeeze=False)
    colours = {name: f"C{i}" for i, name in enumerate(MARKERS)}
    for ax, panel in zip(axes.flat, panels):
        data = summary if panel.startswith("all") else [r for r in rows if r["case"] == panel]
        for name, marker in MARKERS.items():
            pts = [
                d for d in data if d["series"] == name and d["status"] == "ok" and math.isfinite(d.get(key, math.nan))
            ]
            if not pts:
                continue
            groups: dict = {}
            for d in pts:
                groups.setdefault(d["mass_ratio"] if d["engine"] == "mujoco" else None, []).append(d)
            first = True
            for g in groups.values():
                g = sorted(g, key=lambda d: d["wall_s"])
                label = (f"{name} (MuJoCo)" if g[0]["engine"] == "mujoco" else f"{name} (reduced)") if first else None
                ax.plot(
                    [d["wall_s"] for d in g],
                    [max(d[key], 1e-12) for d in g],
                    marker=marker,
                    ls="-",
                    lw=0.6,
                    ms=5,
                    color=colours[name],
                    label=label,
                    alpha=0.85,
                )
                first = False
        for level in LEVELS:
            ax.axhline(level, color="0.7", lw=0.6, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(panel, fontsize=10)
        ax.set_xlabel("wall time, s")
        ax.set_ylabel(f"{key} relative error")
        ax.grid(True, which="major", alpha=0.3)
    for ax in list(axes.flat)[len(panels) :]:
        ax.axis("off")
    handles, labels = axes.flat[len(panels) - 1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", fontsize=9, ncol=5, frameon=False)
    fig.suptitle(
        "Error against the reduced model (rtol 1e-11) vs wall time; MuJoCo lines join dt at fixed mass ratio",
        fontsize=11,
    )
    fig.tight_layout(rect=(0, 0.07, 1, 0.97))
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_file(Path(path)) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


CSV_FIELDS = (
    "case",
    "scene",
    "duration",
    "engine",
    "series",
    "dt",
    "mass_ratio",
    "rtol",
    "status",
    "wall_s",
    "runs",
    "worst",
    "steady",
    "amplitude",
    "frequency",
    "rotation_rate",
    "angle",
    "angle_rad",
    "window",
    "pin_violation",
    "guard",
    "message",
)


OUTPUTS = ("accuracy.csv", "accuracy.md", "accuracy.png", "accuracy_steady.png", "accuracy_provenance.json")
"""The files write_outputs writes into its folder: a folder holding any of them holds a study's results."""


def write_outputs(out: Path, rows: list[dict], meta: dict) -> dict:
    """accuracy.csv (every run), accuracy.md (tables) and accuracy.png / accuracy_steady.png."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    with atomic_file(out / "accuracy.csv") as tmp, open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in CSV_FIELDS})
    summary = summarise(rows)
    plot(rows, summary, out / "accuracy.png", "worst")
    plot(rows, summary, out / "accuracy_steady.png", "steady")
    cases = ", ".join(f"{c} ({d:g} tau)" for c, d in meta["cases"])
    size = meta.get("size", "quick" if meta["quick"] else "full")
    size_note = "" if size == "full" else f" (--{size})"
    text = [
        f"# Accuracy against wall time{size_note}",
        "",
        f"Cases: {cases}. Reference: reduced model, {REFERENCE['method']} (or the scene engine's DOP853), "
        f"rtol {REFERENCE['rtol']:g}, "
        f"atol {REFERENCE['atol']:g}; samples every {SAMPLE_DT} tau. {meta['workers']} worker process(es); "
        f"study took {meta['elapsed_s']:.0f} s. Wall time: simulation only, best of up to 3 runs while short "
        "(shared machine: +-30% noise).",
        "",
        "Errors are the largest over the cases; `worst` = max(amplitude, frequency, rotation rate, angle over "
        "the transient), `steady` = max(amplitude, frequency, rotation rate).",
        "",
        "## Cost of the defaults",
        "",
        format_defaults(summary),
        "",
        "## Cheapest setting per target (all errors)",
        "",
        format_recommendations(recommend(summary, key="worst"), "worst"),
        "",
        "## Cheapest setting per target (steady observables only: amplitude, frequency, rotation rate)",
        "",
        format_recommendations(recommend(summary, key="steady"), "steady"),
        "",
        "## Every setting",
        "",
        format_summary(summary),
        "",
        "Plots: accuracy.png (worst error), accuracy_steady.png (steady observables). Per-run data: accuracy.csv.",
        "",
    ]
    record = provenance(meta.get("started_utc"), meta.get("elapsed_s"))
    write_text(out / "accuracy_provenance.json", json.dumps(record, indent=2) + "\n")
    text += ["## Provenance", "", provenance_line(record, "accuracy_provenance.json"), ""]
    write_text(out / "accuracy.md", "\n".join(text))
    return {"summary": summary}

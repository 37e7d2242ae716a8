"""The clamped chain in three dimensions above onset: which state it reaches (rest, planar beat, whirl, other) against
the load, the start (planar or not) and the drag anisotropy, in the reduced 3D engine (docs/model3d.md, section 6).

Beyond the paper (its chains move on a table). For each drag ratio gamma_L / gamma_T the onset of the whole 3D linear
operator (analysis.stability3d.onset3d, found, not assumed) is set beside the planar onset (analysis.stability.onset);
the loads are multiples of it. At each load the chain of N links is run from two starts of the same size: planar
(a push in the xy plane, which the reduced engine keeps planar bit for bit) and non-planar (a helix). The state of
each run is analysis.motion3d's, over its last MEASURED_PERIODS periods; a run classed 'whirl' is refined by Newton's
method (analysis.whirl.find_whirl: its exact rate and its stability in the rotating frame). The planar beat's
out-of-plane Floquet multipliers (analysis.whirl.beat_out_of_plane) are computed at some of the loads (_grid).

The engines' agreement (quick and full sizes, _engine_loads): the scene clamped-3d run as a user runs it, from its own
seeded non-planar start at the default numerics (MuJoCo's automatic dt, the reduced engine's default tolerance), in
both engines; the scene's frequency and amplitude (summary.json's) compared.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..analysis import stability
from ..analysis.motion3d import measure3d
from ..analysis.stability3d import onset3d
from ..analysis.whirl import beat_out_of_plane, find_whirl
from ..batch import Case, CaseResult, default_workers, run_case
from ..core.errors import ParameterError
from ..core.params import Numerics
from ..io.executor import imap
from ..reduced.chain3d import Chain3D, solve3d
from ..scenes import clamped3d
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick
from .claim_rows import Claim, fmt, verdict

STATES = ("rest", "beat", "whirl", "other")
"""The states of analysis.motion3d.classify, in the order of the data's state codes."""
STARTS = ("planar", "non-planar")
"""The two starts: a push in the xy plane, and a helix (the same push, plus as much out of the plane)."""
PUSH = 0.3
"""The start's push: link k of N turned by PUSH s_k (s_k = k / N) across the axis in y, and (non-planar) PUSH s_k^2
in z."""
SAMPLES_PER_PERIOD = 100
"""Samples per expected period of each run."""
RUN_PERIODS = 16
"""Length of each run in expected periods (the whirl settles from the helix within ~6 of its periods at N = 7)."""
MEASURED_PERIODS = 5
"""The last this many expected periods are measured (analysis.motion3d.measure3d's transient: the rest)."""
FREQUENCY_EXPONENT = 1.15
"""The expected frequency f_c (sigma / sigma_c)^FREQUENCY_EXPONENT of a load above onset (N = 7: the planar beat's
0.0082 at sigma = 0.2 and 0.0425 at 0.8 from f_c = 0.00683 at sigma_c = 0.1575) plans each run's length."""
TOLERANCE = 1e-9
"""rtol = atol of the runs (DOP853)."""
FLOQUET_SETTLE = 12
"""Expected periods the planar beat settles for before its Floquet multipliers are computed (at drag ratio 2 the beat
is ~0.6 times as fast as expected: the second half must still hold two of its periods)."""
ONSET_AGREEMENT = 1e-8
"""The 3D onset equals the planar one when they differ by less than this (relative)."""
ENGINE_PERIODS = RUN_PERIODS
"""Length of each run of the engines' agreement in expected periods (the second half measured)."""
ENGINE_AGREEMENT = 0.01
"""The engines agree when MuJoCo's frequency and amplitude are within this (relative) of the reduced engine's."""


@dataclass(frozen=True)
class Run3D:
    """One run: a drag ratio, a load, a start; the state it reached and its numbers."""

    gamma_l: float
    load: float
    """sigma / sigma_c."""
    sigma: float
    start: str
    state: str
    frequency: float
    """f tau of the tip's displacement along its major axis (analysis.motion3d)."""
    whirl_rate: float
    """Cycles per tau, signed (analysis.motion3d)."""
    tip_aspect: float
    tip_amplitude: float
    out_of_plane: float
    """The largest |z| of any link's tangent over the run (0: the run stayed in its plane)."""
    newton_rate: float
    """The whirl's rate by Newton's method (cycles per tau; NaN: not a whirl, or Newton found none)."""
    newton_growth: float
    """The whirl's largest growth rate in the rotating frame (1 / tau; < 0: stable; NaN as newton_rate)."""


@dataclass(frozen=True)
class Onset3D:
    """The onset of one drag ratio, from the whole 3D operator and from the planar one."""

    gamma_l: float
    sigma_c: float
    planar_sigma_c: float
    omega_c: float
    planar_omega_c: float


@dataclass(frozen=True)
class Floquet3D:
    """The planar beat's out-of-plane stability at one drag ratio and load."""

    gamma_l: float
    load: float
    period: float
    largest: float
    """The largest |multiplier| per period."""
    growth: float
    """log(largest) / period (1 / tau): > 0 when the beat grows out of its plane."""
    neutral: float
    """The distance of the multiplier nearest 1 from 1 (the beat's plane turned: 0 exactly)."""


@dataclass(frozen=True)
class Engines3D:
    """The scene clamped-3d at one load in both engines, each at its default numerics, from the scene's seeded
    non-planar start: the scene's own numbers (results.measure, summary.json's)."""

    load: float
    sigma: float
    duration: float
    states: tuple[str, str]
    """motion_state, reduced then MuJoCo."""
    frequency: tuple[float, float]
    amplitude: tuple[float, float]
    dt: float
    """The dt MuJoCo's automatic numerics chose."""
    wall_s: tuple[float, float]

    def difference(self, name: str) -> float:
        """MuJoCo's relative difference from the reduced engine in `name` (frequency or amplitude)."""
        reduced, mujoco = getattr(self, name)
        return mujoco / reduced - 1.0


@dataclass(frozen=True)
class States3DSummary(Summary):
    n: int
    drag_ratios: list[float]
    loads: list[float]
    onsets: list[Onset3D]
    runs: list[Run3D]
    floquet: list[Floquet3D]
    engines: list[Engines3D] = field(default_factory=list)


STATES3D = registry.declare("states3d", summary=States3DSummary, order=216, budget=12.5)


def start_tangents(n: int, start: str) -> np.ndarray:
    """The start's tangents (N, 3): planar (in the xy plane) or non-planar (a helix), unit length."""
    if start not in STARTS:
        raise ParameterError(f"start must be one of {', '.join(STARTS)}, got {start!r}")
    s = np.arange(1, n + 1) / n
    t = np.column_stack([np.ones(n), PUSH * s, PUSH * s * s if start == "non-planar" else np.zeros(n)])
    return t / np.linalg.norm(t, axis=1)[:, None]


def _point(task: tuple[int, float, float, float, float, bool]) -> tuple[list[Run3D], Floquet3D | None]:
    """Both starts at one drag ratio and load (and the beat's Floquet multipliers if asked): a worker's task."""
    n, gamma_l, load, sigma_c, f_c, floquet = task
    sigma = load * sigma_c
    chain = Chain3D(n=n, sigma=sigma, gamma_l=gamma_l)
    period = 1.0 / (f_c * load**FREQUENCY_EXPONENT)
    duration = RUN_PERIODS * period
    ts = np.linspace(0.0, duration, RUN_PERIODS * SAMPLES_PER_PERIOD + 1)
    runs = []
    for start in STARTS:
        path = solve3d(chain, ts, start_tangents(n, start), rtol=TOLERANCE, atol=TOLERANCE)
        m = measure3d(ts, path, transient=duration - MEASURED_PERIODS * period)
        rate = growth = float("nan")
        if m.state == "whirl":
            try:
                whirl = find_whirl(chain, path[-1], 2 * np.pi * m.whirl_rate)
                rate, growth = whirl.rate, whirl.growth
            except ParameterError:
                pass
        runs.append(
            Run3D(
                gamma_l, load, sigma, start, m.state, m.frequency, m.whirl_rate, m.tip_aspect, m.tip_amplitude,
                float(np.abs(path[..., 2]).max()), rate, growth,
            )
        )  # fmt: skip
    result = None
    if floquet:
        b = beat_out_of_plane(chain, settle=FLOQUET_SETTLE * period, periods=4)
        mu = b.multipliers
        result = Floquet3D(gamma_l, load, b.period, float(np.abs(mu[0])), b.growth, float(np.min(np.abs(mu - 1.0))))
    return runs, result


def _grid(size: str) -> tuple[int, tuple[float, ...], tuple[float, ...], tuple[float, ...]]:
    """(N, drag ratios, loads sigma / sigma_c, the loads with Floquet multipliers) of this size."""
    drags = pick(size, (1.0,), (0.5, 1.0, 2.0), (0.5, 1.0, 2.0))
    loads = pick(size, (2.0, 5.0), (1.5, 5.0, 8.0), (1.25, 1.5, 2.0, 3.0, 5.0, 8.0, 12.0))
    floquet = pick(size, (5.0,), (5.0,), loads)
    return 7, drags, loads, floquet


def _engine_loads(size: str) -> tuple[float, ...]:
    """The loads (sigma / sigma_c, drag ratio 1) of the engines' agreement: none at the tiny size; the quick size's
    the highest of its grid (the shortest run: a run lasts ENGINE_PERIODS periods, longer at a lower load)."""
    return pick(size, (), (8.0,), (2.0, 5.0, 8.0))


def _number(x) -> float:
    """A measured number, NaN where the run gave none (a window of fewer than two periods)."""
    return float("nan") if x is None else float(x)


def engine_cases(n: int, sigma_c: float, f_c: float, loads) -> list[Case]:
    """The scene clamped-3d at each load in both engines (default numerics, the scene's seeded start), ENGINE_PERIODS
    expected periods each (the second half measured): reduced, then MuJoCo, load by load."""
    cases = []
    for load in loads:
        physics = clamped3d.SCENE.physics(n=n, sigma=load * sigma_c)
        duration = ENGINE_PERIODS / (f_c * load**FREQUENCY_EXPONENT)
        cases += [Case(physics, Numerics(), duration, engine) for engine in ("reduced", "mujoco")]
    return cases


def engines3d(loads, cases: list[Case], results: list[CaseResult]) -> list[Engines3D]:
    """The engines' agreement at `loads` from engine_cases' cases and their measured runs (the same order)."""
    out = []
    for load, k in zip(loads, range(0, len(cases), 2)):
        reduced, mujoco = results[k], results[k + 1]
        pair = (reduced.results, mujoco.results)
        sigma = cases[k].physics.sigma
        out.append(
            Engines3D(
                load, sigma, cases[k].duration,
                tuple(str(r.extra["motion_state"]) for r in pair), tuple(_number(r.frequency) for r in pair),
                tuple(float(r.amplitude) for r in pair),
                float(mujoco.info.get("automatic_numerics", {}).get("dt", Numerics().dt)),
                (reduced.wall_time_s, mujoco.wall_time_s),
            )
        )  # fmt: skip
    return out


def _task(task):
    """A worker's task: a grid point (_point's tuple) or one run of the engines' agreement (a Case, measured)."""
    return run_case(task) if isinstance(task, Case) else _point(task)


@STATES3D.run
def states3d_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """The state reached from each start at each load and drag ratio, the onsets, the beat's Floquet multipliers."""
    clock = time.perf_counter()
    n, drags, loads, floquet_loads = _grid(size)
    planar_sigma_c, planar_omega_c = stability.onset(n)
    onsets = []
    tasks = []
    for g in drags:
        sigma_c, omega_c = onset3d(n, g)
        onsets.append(Onset3D(g, sigma_c, planar_sigma_c, omega_c, planar_omega_c))
        tasks += [(n, g, load, sigma_c, omega_c / (2 * np.pi), load in floquet_loads) for load in loads]
    isotropic = next(o for o in onsets if o.gamma_l == 1.0) if 1.0 in drags else None
    engine_loads = _engine_loads(size) if isotropic is not None else ()
    checks = engine_cases(n, isotropic.sigma_c, isotropic.omega_c / (2 * np.pi), engine_loads) if engine_loads else []
    w = default_workers() if workers is None else workers
    done = [result for _, result in imap(_task, checks + tasks, max(1, w))]  # the engines' runs first: the longest
    results = done[len(checks) :]
    runs = [r for point, _ in results for r in point]
    floquet = [f for _, f in results if f is not None]
    engines = engines3d(engine_loads, checks, done[: len(checks)])
    shape = (len(drags), len(loads), len(STARTS))

    def grid(field: str) -> np.ndarray:
        return np.array([getattr(r, field) for r in runs], dtype=float).reshape(shape)

    data = {
        "drag_ratios": np.array(drags),
        "loads": np.array(loads),
        "state": np.array([STATES.index(r.state) for r in runs]).reshape(shape),
        **{f: grid(f) for f in ("frequency", "whirl_rate", "tip_aspect", "tip_amplitude", "newton_rate")},
        "newton_growth": grid("newton_growth"),
        "floquet_gamma_l": np.array([f.gamma_l for f in floquet]),
        "floquet_load": np.array([f.load for f in floquet]),
        "floquet_growth": np.array([f.growth for f in floquet]),
    }
    summary = States3DSummary(n, list(drags), list(loads), onsets, runs, floquet, engines)
    return Study("states3d", size, data, summary, time.perf_counter() - clock)


@STATES3D.figure
@plots.styled
def states3d_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d = study.data
    drags, loads, state = d["drag_ratios"], d["loads"], d["state"]
    fig, axes = plt.subplots(1, 3, figsize=(14.0, 4.0))
    markers = {"rest": ("o", "0.6"), "beat": ("s", "C0"), "whirl": ("*", "C3"), "other": ("x", "k")}
    ax = axes[0]
    rows = [(g, start) for g in range(len(drags)) for start in range(len(STARTS))]
    for y, (g, start) in enumerate(rows):
        for j, load in enumerate(loads):
            name = STATES[int(state[g, j, start])]
            ax.scatter(load, y, marker=markers[name][0], color=markers[name][1], s=70)
    for name, (marker, colour) in markers.items():
        ax.scatter([], [], marker=marker, color=colour, label=name)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels([f"{STARTS[s]}, drag ratio {drags[g]:g}" for g, s in rows], fontsize=7)
    ax.set_xscale("log")
    ax.set_xticks(loads, [f"{x:g}" for x in loads], minor=False)
    ax.minorticks_off()
    ax.set_ylim(-0.5, len(rows) + 0.5)
    ax.set_xlabel(r"load $\sigma/\sigma_c$")
    ax.set_title(f"state reached (N = {study.summary.n}, reduced 3D engine)", fontsize=9)
    ax.legend(fontsize=7, loc="upper center", ncol=4)
    ax = axes[1]
    for g, ratio in enumerate(drags):
        sigma = loads * _sigma_c(study, ratio)
        ax.plot(sigma, np.abs(d["whirl_rate"][g, :, 1]), "-*", color=f"C{g}", label=f"whirl, drag ratio {ratio:g}")
        ax.plot(sigma, d["frequency"][g, :, 0], "--s", color=f"C{g}", mfc="none", label=f"planar beat, {ratio:g}")
    ax.set_xlabel(r"$\sigma$")
    ax.set_ylabel(r"$f\tau$ (whirl: $|$rate$|$)")
    ax.legend(fontsize=7)
    ax = axes[2]
    for g, ratio in enumerate(drags):
        pick_g = d["floquet_gamma_l"] == ratio
        ax.plot(d["floquet_load"][pick_g], d["floquet_growth"][pick_g], "-o", color=f"C{g}", label=f"beat, {ratio:g}")
        ax.plot(loads, d["newton_growth"][g, :, 1], "--*", color=f"C{g}", label=f"whirl, {ratio:g}")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xscale("log")
    ax.set_xticks(loads, [f"{x:g}" for x in loads], minor=False)
    ax.minorticks_off()
    ax.set_xlabel(r"load $\sigma/\sigma_c$")
    ax.set_ylabel(r"largest growth rate ($1/\tau$)")
    ax.set_title("beat out of its plane (Floquet), whirl (rotating frame)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figB_states3d.png")]


def _sigma_c(study: Study, gamma_l: float) -> float:
    return next(o.sigma_c for o in study.summary.onsets if o.gamma_l == gamma_l)


@STATES3D.claims
def states3d_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    source = "beyond the paper (its chains are planar): a clamped chain under follower forces in 3D"
    engine = f"reduced 3D engine, N = {s.n}, drag ratios {', '.join(f'{g:g}' for g in s.drag_ratios)}"
    rows = []
    gaps = [abs(o.sigma_c / o.planar_sigma_c - 1.0) for o in s.onsets]
    freq_gaps = [abs(o.omega_c / o.planar_omega_c - 1.0) for o in s.onsets]
    rows.append(
        Claim(
            "the onset in 3D equals the planar onset, at every drag ratio (in-plane and out-of-plane branches "
            "degenerate)",
            source,
            "-",
            f"sigma_c = {', '.join(fmt(o.sigma_c, 7) for o in s.onsets)} against the planar "
            f"{fmt(s.onsets[0].planar_sigma_c, 7)}; largest gap {fmt(max(gaps), 2)} (sigma_c), "
            f"{fmt(max(freq_gaps), 2)} (omega_c)",
            verdict(max(gaps) < ONSET_AGREEMENT and max(freq_gaps) < ONSET_AGREEMENT),
            f"the onset of the whole 3D operator found by root-finding, not assumed; agreement within "
            f"{ONSET_AGREEMENT:g}; {engine}",
        )
    )
    helix = [r for r in s.runs if r.start == "non-planar"]
    whirls = [r for r in helix if r.state == "whirl"]
    rows.append(
        Claim(
            "from a non-planar start the chain whirls at every load tested",
            source,
            "-",
            f"whirl in {len(whirls)} of {len(helix)} runs (loads {fmt(min(s.loads), 3)}-{fmt(max(s.loads), 3)} "
            f"sigma_c); states: {', '.join(sorted({r.state for r in helix}))}; |rate| "
            f"{fmt(min(abs(r.whirl_rate) for r in helix), 3)}-{fmt(max(abs(r.whirl_rate) for r in helix), 3)} "
            "cycles per tau",
            verdict(len(whirls) == len(helix), partly=bool(whirls)),
            f"state over the last {MEASURED_PERIODS} of {RUN_PERIODS} expected periods (analysis.motion3d); {engine}",
        )
    )
    refined = [r for r in whirls if np.isfinite(r.newton_growth)]
    if whirls:
        worst = max((abs(abs(r.newton_rate) / r.frequency - 1.0) for r in refined), default=float("nan"))
        rows.append(
            Claim(
                "the whirl is a stable relative equilibrium (Newton's shape turning rigidly; every perturbation "
                "decays in the rotating frame)",
                source,
                "-",
                f"Newton converged from {len(refined)} of {len(whirls)} whirls; largest growth "
                f"{fmt(max((r.newton_growth for r in refined), default=float('nan')), 3)} per tau; Newton's |rate| "
                f"against the measured frequency within {fmt(worst, 2)}",
                verdict(len(refined) == len(whirls) and all(r.newton_growth < 0 for r in refined)),
                f"analysis.whirl.find_whirl from each run's last shape; {engine}",
            )
        )
    planar = [r for r in s.runs if r.start == "planar"]
    beats = [r for r in planar if r.state == "beat" and r.out_of_plane == 0.0]
    rows.append(
        Claim(
            "from a planar start the chain beats in its plane at every load tested (the plane is invariant)",
            source,
            "-",
            f"planar beat in {len(beats)} of {len(planar)} runs; largest |z| of a tangent "
            f"{fmt(max(r.out_of_plane for r in planar), 2)}",
            verdict(len(beats) == len(planar), partly=bool(beats)),
            f"f tau {fmt(min(r.frequency for r in planar), 3)}-{fmt(max(r.frequency for r in planar), 3)}; {engine}",
        )
    )
    if s.floquet:
        unstable = [f for f in s.floquet if f.growth > 0 and f.neutral < 1e-6]
        rows.append(
            Claim(
                "the planar beat is unstable out of its plane",
                source,
                "-",
                f"largest out-of-plane Floquet multiplier {fmt(min(f.largest for f in s.floquet), 3)}-"
                f"{fmt(max(f.largest for f in s.floquet), 3)} per period, growth "
                f"{fmt(min(f.growth for f in s.floquet), 3)}-{fmt(max(f.growth for f in s.floquet), 3)} per tau, "
                f"in {len(unstable)} of {len(s.floquet)} cases",
                verdict(len(unstable) == len(s.floquet), partly=bool(unstable)),
                f"the neutral multiplier (the plane turned) within {fmt(max(f.neutral for f in s.floquet), 2)} of 1; "
                f"loads {', '.join(fmt(x, 3) for x in sorted({f.load for f in s.floquet}))} sigma_c; {engine}",
            )
        )
    pairs = [
        (b, w)
        for b in planar
        for w in helix
        if (b.gamma_l, b.load) == (w.gamma_l, w.load) and b.state == "beat" and w.state == "whirl"
    ]
    if pairs:
        ratios = [abs(w.whirl_rate) / b.frequency for b, w in pairs]
        rows.append(
            Claim(
                "the whirl turns faster than the planar beat oscillates at the same load",
                source,
                "-",
                f"|whirl rate| / beat f = {fmt(min(ratios), 3)}-{fmt(max(ratios), 3)} over {len(pairs)} loads and "
                "drag ratios",
                verdict(all(x > 1 for x in ratios), partly=any(x > 1 for x in ratios)),
                engine,
            )
        )
    if s.engines:
        worst = max(abs(e.difference(name)) for e in s.engines for name in ("frequency", "amplitude"))
        same = all(e.states[0] == e.states[1] for e in s.engines)
        rows.append(
            Claim(
                "MuJoCo and the reduced 3D engine agree on the whirl at their default numerics",
                source,
                "-",
                "; ".join(
                    f"{fmt(e.load, 3)} sigma_c: {e.states[1]}, f {e.difference('frequency'):+.2%}, amplitude "
                    f"{e.difference('amplitude'):+.2%} (MuJoCo dt {fmt(e.dt, 3)})"
                    for e in s.engines
                ),
                verdict(same and worst < ENGINE_AGREEMENT),
                f"scene clamped-3d from its seeded non-planar start, as `elastoactive run` gives it (default numerics, "
                f"MuJoCo's automatic dt); frequency and amplitude within {ENGINE_AGREEMENT:.0%}, the second half of "
                f"{ENGINE_PERIODS} expected periods; N = {s.n}, drag ratio 1",
            )
        )
    return rows

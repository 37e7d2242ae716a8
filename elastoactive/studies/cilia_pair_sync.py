"""A pair of cilia on the wall coupled only through the fluid: the final phase difference against the separation d and
sigma, from starts spread over the cycle, and where both in-phase and anti-phase locks are reached, their basins
(beyond the paper: its pair is coupled by a spring, its chains by no fluid).

Two cilia of N links (scene `cilia-pair` without the tips' spring: bases d apart along x at h = 0.5 l, bead radius
a / l = 0.1, the Rotne-Prager-Blake mobility) start on the isolated cilium's limit cycle (studies.cilia_runs.on_cycle),
the second START_LAGS ahead of the first, and run RUN_PERIODS periods; the lag Psi = Phi_2 - Phi_1 of their tips'
signals over the last MEASURED_PERIODS is classed by analysis.cilia.pair_locking (in-phase, anti-phase, lag, none).
Two cycles: the planar beat in the bases' plane (the lab's xz plane, which the mirror y -> -y keeps invariant: the pair
beats in it for ever, as Guo et al.'s filaments beat in theirs) and the co-rotating whirl (both cilia from the same
whirl). Exact 0 and pi are avoided: the anti-phase pair is mirror-symmetric about x = d / 2, a symmetry the dynamics
keeps, so a start exactly there stays there whether stable or not.

The scene's own start (`elastoactive run cilia-pair`, Cilium.initial_cilia: cilium c pushed as a clamped-3d chain of
seed numerics.seed + 2 c) is checked apart at N = 7, sigma = 0.8, a / l = 0.1, d = 3 from SCENE_SEEDS: its pushes
are independent, so the two cilia may whirl in opposite senses; the lag of two counter-rotating whirls projected on one
axis depends on that axis, and such a pair is locked when the sum of the tips' angles in the wall's plane is (their
mirror plane's angle), not their difference.

The literature: Guo, Fauci, Shelley & Kanso (J. Fluid Mech. 2018, arXiv 1708.02181) drive continuous filaments at
their base by a configuration-dependent torque, with full hydrodynamics above a wall: a pair locks in phase or in
anti-phase, the two bistable over a range of torque and separation (their movie: M_b = 1, d = 0.7 L). Man & Kanso
(Phys. Rev. Lett. 2020, arXiv 2008.08696) drive filaments by a follower force at the tip and find locks at lags
between 0 and pi as the activity and the coupling change. Here the force is on every bead of a discrete chain.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import cilia as ca
from ..analysis import measures
from ..analysis.locking import phase_spread
from ..analysis.motion3d import measure3d
from ..analysis.stability_fluid import onset_fluid
from ..batch import default_workers
from ..core.params import Numerics
from ..io.executor import imap
from ..reduced.blas import one_blas_thread
from ..scenes.cilia_pair import SCENE as PAIR_SCENE
from . import cilia_runs as cr
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick
from .claim_rows import Claim, fmt, verdict

RUN_PERIODS = 40
"""Length of each pair's run in periods of the isolated cycle (at d = 6 and 4 sigma_c a start near anti-phase is
within 0.5 rad of in phase after 30)."""
MEASURED_PERIODS = 8
"""The last this many periods are measured."""
SETTLED = 0.05
"""A run has settled when its mean lag over the last MEASURED_PERIODS differs by less than this (rad) from the mean
over the MEASURED_PERIODS before: a slow drift (weak coupling at large d) is not yet a lock, however small the lag's
spread over one window."""
TRACE_POINTS = 120
"""Samples of each run's lag Psi(t) kept for the figure."""
START_OFFSET = 0.2
"""The starts near in-phase and near anti-phase: lags START_OFFSET and pi - START_OFFSET (rad)."""
SCENE_SIGMA = 0.8
"""The scene check's sigma (N = 7, a / l = 0.1, d = 3: cilia-pair's defaults with the fluid on)."""
SCENE_DURATION = 400.0
"""The scene check's run (tau); the second half measured (the whirl's period ~14.6 tau)."""
SOURCE = "beyond the paper: two follower-force cilia on a no-slip wall coupled only through the fluid"
GUO = "Guo, Fauci, Shelley & Kanso JFM 2018: in-phase and anti-phase locks bistable over torque and separation"
MAN = "Man & Kanso PRL 2020: locks at lags between 0 and pi as activity and coupling change"


@dataclass(frozen=True)
class PairRun:
    """One pair's run: the cycle it started on, the load, the spacing, the start's lag; what it reached."""

    cycle: str
    """cilia_runs.CYCLES: the planar beat in the bases' plane, or the co-rotating whirl."""
    load: float
    sigma: float
    spacing: float
    start_lag: float
    """Phi_2 - Phi_1 at t = 0 (rad)."""
    lag: float
    """Circular mean of Psi over the measured window (rad, in (-pi, pi])."""
    spread: float
    state: str
    """analysis.cilia.LOCK_STATES."""
    frequency: float
    """The first cilium's f tau over the measured window."""
    closest: float
    """The smallest distance between a bead of one cilium and a bead of the other over the run (l): below 2 a the
    beads overlap (the mobility's overlap correction holds them; no contact force keeps them apart)."""
    drift: float
    """The mean lag over the last MEASURED_PERIODS less that over the MEASURED_PERIODS before (rad, wrapped); NaN
    without both."""
    wall_s: float

    @property
    def settled(self) -> bool:
        """Whether the lag has stopped moving (|drift| < SETTLED)."""
        return bool(abs(self.drift) < SETTLED)


@dataclass(frozen=True)
class SceneRun:
    """The scene cilia-pair from its own seeded start."""

    seed: int
    senses: tuple[float, float]
    """Each cilium's whirl rate (cycles per tau, signed: opposite signs are counter-rotating whirls)."""
    states: tuple[str, str]
    lag: float
    """pair_locking's lag on the first cilium's major axis (rad)."""
    lock_state: str
    angle_relation: float
    """Circular mean of the tips' angles' difference (co-rotating) or sum (counter-rotating) in the wall's plane
    (rad)."""
    angle_spread: float
    """Its circular spread (rad): small when the pair is locked."""


@dataclass(frozen=True)
class PairSyncSummary(Summary):
    n: int
    radius: float
    base_height: float
    sigma_c: float
    f_c: float
    loads: list[float]
    spacings: list[float]
    periods: dict[str, list[float]]
    """The isolated cycle's period at each load, by cycle."""
    runs: list[PairRun]
    scene: list[SceneRun]


CILIA_PAIR_SYNC = registry.declare("cilia_pair_sync", summary=PairSyncSummary, order=224, budget=5.5)


def start_lags(size: str, cycle: str) -> tuple[float, ...]:
    """The second cilium's lags at t = 0: near in-phase and near anti-phase, and (beat) a quarter period either way;
    the full size spreads eight over the cycle."""
    near = (START_OFFSET, math.pi - START_OFFSET)
    if size == "full":
        return tuple(START_OFFSET + k * math.pi / 4 for k in range(8))
    return (*near, math.pi / 2, 3 * math.pi / 2) if cycle == "beat" and size == "quick" else near


def _grid(size: str) -> tuple[int, tuple[float, ...], tuple[float, ...], tuple[int, ...]]:
    """(N, loads sigma / sigma_c, spacings d, the scene check's seeds) of this size."""
    return pick(
        size,
        (5, (3.0,), (1.5,), ()),
        (5, (2.0, 4.0), (3.0, 6.0), (0, 1)),
        (7, (2.0, 3.0, 5.0), (1.5, 3.0, 4.5, 6.0, 8.0), (0, 1, 2, 3)),
    )


def _cycle(task: tuple[int, float, float, float, str]) -> cr.Cycle:
    n, sigma, f_c, load, cycle = task
    return cr.limit_cycle(n, sigma, cycle, f_c, load)


def _pair(task) -> tuple[PairRun, np.ndarray, np.ndarray]:
    """One pair's run (a worker's task): its record and its lag Psi(t) (times, values) at TRACE_POINTS."""
    n, load, sigma, spacing, cycle_name, cycle, start_lag = task
    clock = time.perf_counter()
    beds = cr.wall_beds(n, sigma, cr.row_bases(2, spacing))
    duration = RUN_PERIODS * cycle.period
    ts = np.linspace(0.0, duration, RUN_PERIODS * cr.SAMPLES_PER_PERIOD + 1)
    path = cr.run(beds, ts, cr.on_cycle(cycle, (0.0, start_lag)))
    first, second = ca.tip_signals(cr.tips(path, beds))
    transient = duration - MEASURED_PERIODS * cycle.period
    lock = ca.pair_locking(ts, first, second, transient=transient)
    before = ts <= transient
    earlier = ca.pair_locking(ts[before], first[before], second[before], transient=transient - MEASURED_PERIODS
                              * cycle.period)  # fmt: skip
    drift = float(np.angle(np.exp(1j * (lock.lag - earlier.lag))))
    m = measure3d(ts, path[:, 0], transient=transient)
    positions = cr.tips(path, beds)
    closest = float(np.min(np.linalg.norm(positions[:, 0, :, None] - positions[:, 1, None, :], axis=-1)))
    try:
        tp, psi = measures.phase_difference(ts, first, second, transient=0.0)
        keep = np.linspace(0, tp.size - 1, TRACE_POINTS).astype(int)
        trace = (tp[keep], np.angle(np.exp(1j * psi[keep])))
    except ValueError:
        trace = (np.full(TRACE_POINTS, np.nan), np.full(TRACE_POINTS, np.nan))
    run = PairRun(cycle_name, load, sigma, spacing, start_lag, lock.lag, lock.spread, lock.state,
                  float(m.frequency or np.nan), closest, drift, time.perf_counter() - clock)  # fmt: skip
    return run, trace[0], trace[1]


def tip_angles(positions: np.ndarray) -> np.ndarray:
    """(C, T): each tip's angle (rad) about its mean position in the wall's plane (positions (T, C, N, 3))."""
    tips = positions[:, :, -1, :2]
    lateral = tips - tips.mean(axis=0)
    return np.arctan2(lateral[..., 1], lateral[..., 0]).T


def _scene(seed: int) -> SceneRun:
    """The scene cilia-pair from its seeded start (a worker's task)."""
    physics = PAIR_SCENE.physics(n=7, sigma=SCENE_SIGMA, bead_radius=cr.RADIUS)
    numerics = Numerics(seed=seed)
    start = PAIR_SCENE.initial_cilia(physics, numerics)
    beds = PAIR_SCENE.beds(physics)
    ts = np.arange(0.0, SCENE_DURATION + 1e-9, numerics.sample_dt)
    path = cr.run(beds, ts, start)
    half = SCENE_DURATION / 2
    motions = [measure3d(ts, path[:, c], transient=half) for c in range(2)]
    positions = cr.tips(path, beds)
    first, second = ca.tip_signals(positions)
    lock = ca.pair_locking(ts, first, second, transient=half)
    angles = tip_angles(positions[ts >= half])
    senses = tuple(float(m.whirl_rate) for m in motions)
    relation = angles[1] + angles[0] if senses[0] * senses[1] < 0 else angles[1] - angles[0]
    return SceneRun(seed, senses, tuple(m.state for m in motions), lock.lag, lock.state,
                    ca.circular_mean(relation), float(phase_spread(relation)))  # fmt: skip


@CILIA_PAIR_SYNC.run
def cilia_pair_sync_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Every cycle, load, spacing and start lag; the scene's seeded starts."""
    clock = time.perf_counter()
    n, loads, spacings, seeds = _grid(size)
    sigma_c, omega_c = onset_fluid(cr.wall_beds(n, 1.0, cr.row_bases(1, 1.0)))
    f_c = omega_c / (2 * np.pi)
    w = max(1, default_workers() if workers is None else workers)
    keys = [(load, cycle) for load in loads for cycle in cr.CYCLES]
    cycles = dict(zip(keys, (c for _, c in imap(_cycle, [(n, load * sigma_c, f_c, load, cy) for load, cy in keys],
                                                  w)), strict=True))  # fmt: skip
    tasks = [
        (n, load, load * sigma_c, d, cy, cycles[load, cy], lag)
        for load in loads
        for cy in cr.CYCLES
        for d in spacings
        for lag in start_lags(size, cy)
    ]
    tasks.sort(key=lambda t: -t[5].period)  # the longest runs first
    jobs = [("pair", t) for t in tasks] + [("scene", s) for s in seeds]
    results = [r for _, r in imap(_job, jobs, w)]
    pairs = [r for kind, r in zip(jobs, results, strict=True) if kind[0] == "pair"]
    scene = [r for kind, r in zip(jobs, results, strict=True) if kind[0] == "scene"]
    order = sorted(range(len(pairs)), key=lambda k: (pairs[k][0].cycle, pairs[k][0].load, pairs[k][0].spacing,
                                                      pairs[k][0].start_lag))  # fmt: skip
    runs = [pairs[k][0] for k in order]
    data = {
        "trace_t": np.array([pairs[k][1] for k in order]),
        "trace_psi": np.array([pairs[k][2] for k in order]),
        "start_lag": np.array([r.start_lag for r in runs]),
        "lag": np.array([r.lag for r in runs]),
        "spacing": np.array([r.spacing for r in runs]),
        "load": np.array([r.load for r in runs]),
        "cycle": np.array([cr.CYCLES.index(r.cycle) for r in runs]),
        "state": np.array([ca.LOCK_STATES.index(r.state) for r in runs]),
    }
    periods = {cy: [cycles[load, cy].period for load in loads] for cy in cr.CYCLES}
    summary = PairSyncSummary(n, cr.RADIUS, cr.BASE_HEIGHT, sigma_c, f_c, list(loads), list(spacings), periods, runs,
                              scene)  # fmt: skip
    return Study("cilia_pair_sync", size, data, summary, time.perf_counter() - clock)


def _job(job):
    """A pair's run or a scene check (a worker's task), on one BLAS thread (reduced.blas)."""
    kind, task = job
    with one_blas_thread():
        return _pair(task) if kind == "pair" else _scene(task)


@CILIA_PAIR_SYNC.figure
@plots.styled
def cilia_pair_sync_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, axes = plt.subplots(1, 3, figsize=(14.0, 4.2))
    colours = {"in-phase": "C0", "anti-phase": "C3", "lag": "C2", "none": "k"}
    for ax, cy in zip(axes[:2], cr.CYCLES, strict=True):
        for k, run in enumerate(s.runs):
            if run.cycle != cy:
                continue
            colour = colours[run.state]
            ax.plot(d["trace_t"][k] / s.periods[cy][s.loads.index(run.load)], d["trace_psi"][k], color=colour,
                    lw=0.8, alpha=0.8)  # fmt: skip
        for name, colour in colours.items():
            ax.plot([], [], color=colour, label=name)
        ax.set_yticks([-np.pi, -np.pi / 2, 0, np.pi / 2, np.pi], [r"$-\pi$", r"$-\pi/2$", "0", r"$\pi/2$", r"$\pi$"])
        ax.set_xlabel("t / T (periods of the isolated cycle)")
        ax.set_ylabel(r"$\Psi = \Phi_2 - \Phi_1$")
        title = "planar beats in the bases' plane" if cy == "beat" else "co-rotating whirls"
        ax.set_title(f"{title}: every load, d and start", fontsize=9)
        ax.legend(fontsize=7, loc="lower right")
    ax = axes[2]
    markers = {"beat": "s", "whirl": "*"}
    for run in s.runs:
        x = run.spacing * (1.0 + 0.03 * (s.loads.index(run.load) - 0.5 * (len(s.loads) - 1)))
        ax.scatter(x, abs(run.lag), marker=markers[run.cycle], color=colours[run.state], s=40,
                   facecolors="none" if run.cycle == "beat" else colours[run.state])  # fmt: skip
    for cy, marker in markers.items():
        ax.scatter([], [], marker=marker, color="0.3", label=cy)
    ax.set_yticks([0, np.pi / 4, np.pi / 2, 3 * np.pi / 4, np.pi], ["0", r"$\pi/4$", r"$\pi/2$", r"$3\pi/4$", r"$\pi$"])
    ax.set_xlabel(r"spacing $d/l$ (loads side by side)")
    ax.set_ylabel(r"final $|\Psi|$")
    ax.set_title(f"N = {s.n}, a/l = {s.radius:g}, loads {', '.join(f'{x:g}' for x in s.loads)} " r"$\sigma_c$",
                 fontsize=9)  # fmt: skip
    ax.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figH_cilia_pair_sync.png")]


def _points(s: PairSyncSummary, cycle: str) -> dict[tuple[float, float], list[PairRun]]:
    out: dict[tuple[float, float], list[PairRun]] = {}
    for r in s.runs:
        if r.cycle == cycle:
            out.setdefault((r.load, r.spacing), []).append(r)
    return out


def _lags(runs: list[PairRun]) -> str:
    return ", ".join(
        f"{r.start_lag:.2f} -> {r.lag:+.3f} ({r.state}{'' if r.settled else f', drifting {r.drift:+.2g}'}, "
        f"{r.closest:.2g} l)"
        for r in runs
    )


@CILIA_PAIR_SYNC.claims
def cilia_pair_sync_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    engine = (
        f"reduced engine, N = {s.n}, a/l = {s.radius:g}, h = {s.base_height:g}, loads "
        f"{', '.join(fmt(x, 3) for x in s.loads)} sigma_c (sigma_c = {fmt(s.sigma_c, 5)}), d = "
        f"{', '.join(fmt(x, 3) for x in s.spacings)} l; lag over the last {MEASURED_PERIODS} of {RUN_PERIODS} periods"
    )
    rows = []
    beats = _points(s, "beat")
    apart = {k: [r for r in runs if r.closest >= 2 * s.radius and r.settled] for k, runs in beats.items()}
    total = sum(len(v) for v in beats.values())
    overlapping = sum(1 for runs in beats.values() for r in runs if r.closest < 2 * s.radius)
    drifting = sum(1 for runs in beats.values() for r in runs if not r.settled)
    both = [k for k, runs in apart.items() if {"in-phase", "anti-phase"} <= {r.state for r in runs}]
    both_any = [k for k, runs in beats.items() if {"in-phase", "anti-phase"} <= {r.state for r in runs}]
    detail = "; ".join(f"{fmt(k[0], 3)} sigma_c, d {fmt(k[1], 3)}: {_lags(v)}" for k, v in beats.items())
    crossing = sorted({r.state for runs in beats.values() for r in runs if r.closest < 2 * s.radius})
    rows.append(
        Claim(
            "two planar beats coupled only through the fluid lock in phase or in anti-phase by their start: the two "
            "locks are bistable (as Guo et al. find for base-driven filaments)",
            f"{SOURCE}; {GUO}",
            "-",
            f"both locks reached at {len(both_any)} of {len(beats)} (load, d) points, at {len(both)} with the chains "
            f"apart and settled; {overlapping} of {total} runs bring beads of the two cilia closer than 2a (states "
            f"{', '.join(crossing) or '-'}), {drifting} still drift",
            verdict(len(both) == len(beats), partly=bool(both)),
            f"start lag -> final lag (closest approach): {detail}. Runs whose beads come closer than 2a pass through "
            "each other (the mobility's overlap correction holds them; no contact force keeps them apart) and do not "
            f"count, nor do runs whose lag still drifts by {SETTLED:g} rad or more between the last two windows. "
            "Their filaments are continuous and driven at the base by a torque; here every bead carries a "
            f"follower force; {engine}",
        )
    )
    lagged = [r for runs in beats.values() for r in runs if r.state == "lag"]
    lagged_apart = [r for r in lagged if r.closest >= 2 * s.radius and r.settled]
    rows.append(
        Claim(
            "planar beats also lock at lags between 0 and pi (multisynchrony, as Man & Kanso find)",
            f"{SOURCE}; {MAN}",
            "-",
            f"locked at a lag in {len(lagged)} of {total} runs ("
            + (", ".join(f"{fmt(r.load, 3)} sigma_c, d {fmt(r.spacing, 3)}: {r.lag:+.3f}" for r in lagged) or "none")
            + f"), {len(lagged_apart)} settled with the chains apart",
            verdict(bool(lagged_apart), partly=bool(lagged)),
            f"'lag': locked farther than pi/8 from 0 and pi (analysis.cilia); their filaments are driven by one "
            f"follower force at the tip; {engine}",
            judged_from="quick",
        )
    )
    whirls = _points(s, "whirl")
    if whirls:
        settled = [r for runs in whirls.values() for r in runs if r.settled]
        drifting = [r for runs in whirls.values() for r in runs if not r.settled]
        states = [r.state for r in settled]
        rows.append(
            Claim(
                "two co-rotating whirls lock in phase from near in-phase and near anti-phase starts (one lock, no "
                "bistability)",
                SOURCE,
                "-",
                "; ".join(f"{fmt(k[0], 3)} sigma_c, d {fmt(k[1], 3)}: {_lags(v)}" for k, v in whirls.items()),
                verdict(all(x == "in-phase" for x in states) and not drifting, partly="in-phase" in states),
                f"{len(drifting)} runs still drift (their lag moved by {SETTLED:g} rad or more between the last two "
                f"windows of {MEASURED_PERIODS} periods: weak coupling at large d); {engine}",
            )
        )
    if s.scene:
        counter = [r for r in s.scene if r.senses[0] * r.senses[1] < 0]
        lags = ", ".join(f"seed {r.seed}: {fmt(r.lag, 3)} ({r.lock_state})" for r in s.scene)
        relation = ", ".join(
            f"seed {r.seed}: {'sum' if r.senses[0] * r.senses[1] < 0 else 'difference'} {fmt(r.angle_relation, 3)} "
            f"(spread {fmt(r.angle_spread, 2)})"
            for r in s.scene
        )
        quarter = [r for r in s.scene if r.lock_state == "lag" and abs(abs(r.lag) - math.pi / 2) < math.pi / 8]
        rows.append(
            Claim(
                "the scene's default pair (N = 7, sigma = 0.8, a/l = 0.1, d = 3) locks at a quarter-period lag "
                "(-pi/2) from every seeded start",
                SOURCE,
                "-",
                f"lag on the first cilium's major axis: {lags}; counter-rotating whirls in {len(counter)} of "
                f"{len(s.scene)} starts; tips' angles: {relation}",
                verdict(len(quarter) == len(s.scene), partly=bool(quarter)),
                "the scene pushes each cilium from its own seed, so the whirls' senses are the seeds'; the lag of two "
                "counter-rotating whirls on one axis depends on that axis (their lock is in the sum of the tips' "
                "angles); "
                f"the second half of {fmt(SCENE_DURATION, 3)} tau measured",
            )
        )
    return rows

"""A row of cilia on the wall coupled only through the fluid: metachronal waves, their wave number against the spacing,
and the volume flux the row pumps along the wall (beyond the paper: its chains feel no fluid).

M cilia of N links (scene `cilia-row`: bases d apart along x at h = 0.5 l, bead radius a / l = 0.1, the
Rotne-Prager-Blake mobility) start on the isolated cilium's limit cycle at seeded random phases
(studies.cilia_runs.on_cycle; seed SEED), either the planar beat in the row's plane (the lab's xz plane, kept
invariant by the mirror y -> -y) or the co-rotating whirl, and run RUN_PERIODS periods. Over the last MEASURED_PERIODS
the neighbours' lags give the wave (analysis.cilia.metachronal_wave: k = -<Phi_m+1 - Phi_m> / d, its direction, or
none unless every neighbour pair locks), and the beads' forces on the fluid give Blake's flux along the row and across
it (analysis.cilia.blake_flux: Q_x = 6 a sum F_x h, Q_y likewise), its time mean against its root mean square (the size
of the back-and-forth flow each stroke drives).

Chakrabarti, Fuerthauer and Shelley (PNAS 2022) find metachronal waves in arrays of model cilia whose beat is
asymmetric (an effective and a recovery stroke), which pump a net flow; the follower-force beat and whirl here are
symmetric strokes.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import cilia as ca
from ..analysis.motion3d import measure3d
from ..analysis.stability_fluid import onset_fluid
from ..batch import default_workers
from ..io.executor import imap
from ..reduced.blas import one_blas_thread
from ..reduced.fluid import fluid_forces
from . import cilia_runs as cr
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick
from .claim_rows import Claim, fmt, verdict

RUN_PERIODS = 30
"""Length of each row's run in periods of the isolated cycle."""
MEASURED_PERIODS = 8
"""The last this many periods are measured."""
FLUX_SAMPLES = 240
"""Samples of the measured window whose forces the flux averages (evenly spaced: 30 a period)."""
SEED = 7
"""The seed of the starts' random phases."""
NET_FLUX = 0.05
"""A row pumps no net flux when |<Q>| is below this fraction of Q's root mean square."""
SOURCE = "beyond the paper: a row of follower-force cilia on a no-slip wall coupled only through the fluid"


@dataclass(frozen=True)
class RowRun:
    """One row's run: the cycle, the spacing; its wave and its flux."""

    cycle: str
    spacing: float
    start_phases: list[float]
    lags: list[float]
    """The neighbours' lags <Phi_m+1 - Phi_m> over the measured window (rad)."""
    wave_number: float
    """k (rad / l, signed along x); NaN unless every neighbour pair locks."""
    direction: str
    flux_x: float
    """Mean flux along the row (l^3 / tau)."""
    flux_y: float
    """Mean flux across it."""
    flux_rms: float
    """Root mean square of the flux along the row over the window."""
    frequency: float
    closest: float
    """The smallest distance between beads of different cilia over the run (l): below 2 a the chains pass through each
    other (the mobility's overlap correction holds them; no contact force keeps them apart)."""
    wall_s: float


@dataclass(frozen=True)
class RowWavesSummary(Summary):
    n: int
    cilia: int
    radius: float
    base_height: float
    load: float
    sigma: float
    spacings: list[float]
    runs: list[RowRun]


CILIA_ROW_WAVES = registry.declare("cilia_row_waves", summary=RowWavesSummary, order=226, budget=4)


def _grid(size: str) -> tuple[int, int, float, tuple[float, ...]]:
    """(N, M, load sigma / sigma_c, spacings d) of this size."""
    return pick(size, (5, 3, 3.0, (1.5,)), (5, 4, 3.0, (1.5, 3.0)), (5, 8, 3.0, (1.25, 1.5, 2.0, 3.0, 5.0)))


def start_phases(cilia: int, seed: int = SEED) -> list[float]:
    """The cilia's phases at t = 0 (rad): the first at 0, the others uniform random (seeded)."""
    rng = np.random.default_rng(seed)
    return [0.0, *(float(x) for x in rng.uniform(0.0, 2 * math.pi, cilia - 1))]


def _row(task) -> tuple[RowRun, np.ndarray]:
    """One row's run (a worker's task, on one BLAS thread: the forces' small dense solves spin threaded BLAS on a
    busy machine, 68 s of CPU for the quick size instead of 9): its record and its tips' signals' last periods."""
    with one_blas_thread():
        return _row_run(task)


def _row_run(task) -> tuple[RowRun, np.ndarray]:
    n, cilia, sigma, spacing, cycle_name, cycle = task
    clock = time.perf_counter()
    beds = cr.wall_beds(n, sigma, cr.row_bases(cilia, spacing))
    duration = RUN_PERIODS * cycle.period
    ts = np.linspace(0.0, duration, RUN_PERIODS * cr.SAMPLES_PER_PERIOD + 1)
    phases = start_phases(cilia)
    path = cr.run(beds, ts, cr.on_cycle(cycle, phases))
    positions = cr.tips(path, beds)
    signals = ca.tip_signals(positions)
    transient = duration - MEASURED_PERIODS * cycle.period
    wave = ca.metachronal_wave(ts, signals, spacing, transient=transient)
    window = np.flatnonzero(ts >= transient)
    pick_k = window[np.linspace(0, window.size - 1, FLUX_SAMPLES).astype(int)]
    forces = np.stack([fluid_forces(path[k], beds) for k in pick_k])
    heights = positions[pick_k][..., 2]
    qx = ca.blake_flux(forces[..., 0], heights, cr.RADIUS)
    qy = ca.blake_flux(forces[..., 1], heights, cr.RADIUS)
    frequency = float(measure3d(ts, path[:, 0], transient=transient).frequency or math.nan)
    closest = min(
        float(np.min(np.linalg.norm(positions[:, m, :, None] - positions[:, m + 1, None, :], axis=-1)))
        for m in range(cilia - 1)
    )
    shown = signals[:, ts >= duration - 3 * cycle.period]
    run = RowRun(cycle_name, spacing, phases, [float(x) for x in wave.lags], float(wave.wave_number), wave.direction,
                 float(qx.mean()), float(qy.mean()), float(np.sqrt(np.mean(qx * qx))), frequency, closest,
                 time.perf_counter() - clock)  # fmt: skip
    return run, shown


def _cycle(task) -> cr.Cycle:
    n, sigma, f_c, load, cycle = task
    return cr.limit_cycle(n, sigma, cycle, f_c, load)


@CILIA_ROW_WAVES.run
def cilia_row_waves_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Both cycles at every spacing from seeded random phases."""
    clock = time.perf_counter()
    n, cilia, load, spacings = _grid(size)
    sigma_c, omega_c = onset_fluid(cr.wall_beds(n, 1.0, cr.row_bases(1, 1.0)))
    sigma = load * sigma_c
    w = max(1, default_workers() if workers is None else workers)
    cycles = dict(zip(cr.CYCLES, (c for _, c in imap(_cycle, [(n, sigma, omega_c / (2 * np.pi), load, cy)
                                                             for cy in cr.CYCLES], w)), strict=True))  # fmt: skip
    tasks = [(n, cilia, sigma, d, cy, cycles[cy]) for cy in cr.CYCLES for d in spacings]
    results = [r for _, r in imap(_row, tasks, w)]
    runs = [r for r, _ in results]
    data = {
        "spacing": np.array([r.spacing for r in runs]),
        "cycle": np.array([cr.CYCLES.index(r.cycle) for r in runs]),
        "wave_number": np.array([r.wave_number for r in runs]),
        "lags": np.array([r.lags for r in runs]),
        "flux_x": np.array([r.flux_x for r in runs]),
        "flux_rms": np.array([r.flux_rms for r in runs]),
    }
    for k, (_, shown) in enumerate(results):
        data[f"signals_{k}"] = shown
    summary = RowWavesSummary(n, cilia, cr.RADIUS, cr.BASE_HEIGHT, load, sigma, list(spacings), runs)
    return Study("cilia_row_waves", size, data, summary, time.perf_counter() - clock)


@CILIA_ROW_WAVES.figure
@plots.styled
def cilia_row_waves_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, axes = plt.subplots(1, 3, figsize=(14.0, 4.2))
    ax = axes[0]
    for k, run in enumerate(s.runs):
        if run.cycle != "beat" or run.spacing != max(r.spacing for r in s.runs if r.cycle == "beat"):
            continue
        signals = d[f"signals_{k}"]
        for m, x in enumerate(signals):
            ax.plot(np.arange(x.size) / cr.SAMPLES_PER_PERIOD, x / np.abs(x).max() + 2.2 * m, color=f"C{m}")
        ax.set_title(f"planar beats, d = {run.spacing:g}: the tips' signals (cilium m shifted by 2.2 m)", fontsize=9)
    ax.set_xlabel("t / T (last periods)")
    ax.set_yticks([])
    ax = axes[1]
    for k, run in enumerate(s.runs):
        marker = "s--" if run.cycle == "beat" else "*-"
        wave = "no lock" if run.direction == "none" else f"{run.direction}, k = {run.wave_number:.2g}"
        ax.plot(np.arange(1, len(run.lags) + 1), run.lags, marker, color=f"C{k}",
                label=f"{run.cycle}, d = {run.spacing:g}: {wave}")  # fmt: skip
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_yticks([-np.pi, -np.pi / 2, 0, np.pi / 2, np.pi], [r"$-\pi$", r"$-\pi/2$", "0", r"$\pi/2$", r"$\pi$"])
    ax.set_xlabel("neighbour pair m (cilia m, m + 1)")
    ax.set_ylabel(r"lag $\langle\Phi_{m+1} - \Phi_m\rangle$")
    ax.set_title(f"M = {s.cilia}, N = {s.n}, a/l = {s.radius:g}, " rf"$\sigma$ = {s.load:g} $\sigma_c$", fontsize=9)
    ax.legend(fontsize=7)
    ax = axes[2]
    width = 0.35
    x = np.arange(len(s.runs))
    ax.bar(x - width / 2, [abs(r.flux_x) for r in s.runs], width, label=r"$|\langle Q_x\rangle|$")
    ax.bar(x + width / 2, [r.flux_rms for r in s.runs], width, label=r"rms $Q_x$")
    ax.set_yscale("log")
    ax.set_xticks(x, [f"{r.cycle}\nd = {r.spacing:g}" for r in s.runs], fontsize=7)
    ax.set_ylabel(r"flux along the row ($l^3/\tau$)")
    ax.set_title("Blake's flux: the mean against the stroke's back and forth", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figH_cilia_row_waves.png")]


@CILIA_ROW_WAVES.claims
def cilia_row_waves_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    engine = (
        f"reduced engine, M = {s.cilia} cilia of N = {s.n}, a/l = {s.radius:g}, h = {s.base_height:g}, sigma = "
        f"{fmt(s.sigma, 4)} ({fmt(s.load, 3)} sigma_c), from seeded random phases (seed {SEED}); the last "
        f"{MEASURED_PERIODS} of {RUN_PERIODS} periods"
    )
    rows = []
    for cy, name in (("beat", "planar beats in the row's plane"), ("whirl", "co-rotating whirls")):
        runs = [r for r in s.runs if r.cycle == cy]
        if not runs:
            continue
        locked = [r for r in runs if r.direction != "none"]
        waves = [r for r in locked if r.direction in ("+x", "-x")]
        text = "; ".join(
            f"d = {fmt(r.spacing, 3)}: {r.direction}, k = {fmt(r.wave_number, 3)} rad/l (lags "
            f"{', '.join(f'{x:+.3f}' for x in r.lags)}; closest beads {fmt(r.closest, 2)} l)"
            for r in runs
        )
        rows.append(
            Claim(
                f"a row of {name} coupled through the fluid locks into a metachronal wave (neighbours at a common "
                "non-zero lag)",
                SOURCE,
                "-",
                text,
                verdict(len(waves) == len(runs), partly=bool(waves)),
                f"'synchronous': every neighbour within pi/8 of in phase; 'none': some pair not locked "
                f"(analysis.cilia.metachronal_wave); closest beads below 2a = {fmt(2 * s.radius, 2)} l: neighbours "
                f"pass through each other (no contact force); {engine}",
            )
        )
    beats = sorted((r for r in s.runs if r.cycle == "beat" and np.isfinite(r.wave_number)), key=lambda r: r.spacing)
    if len(beats) >= 2:
        ks = [abs(r.wave_number * r.spacing) for r in beats]
        rows.append(
            Claim(
                "the planar beats' neighbour lag |k d| grows with the spacing (closer cilia lock nearer in phase)",
                SOURCE,
                "-",
                ", ".join(f"d = {fmt(r.spacing, 3)}: |k d| = {fmt(x, 3)} rad" for r, x in zip(beats, ks, strict=True)),
                verdict(all(b > a for a, b in zip(ks[:-1], ks[1:], strict=True))),
                engine,
                judged_from="quick",
            )
        )
    ratios = [abs(r.flux_x) / r.flux_rms for r in s.runs if r.flux_rms > 0]
    rows.append(
        Claim(
            "the row pumps no net flux along the wall: the follower-force beat and whirl are symmetric strokes "
            "(biological cilia pump through an asymmetric effective and recovery stroke)",
            f"{SOURCE}; Chakrabarti, Fuerthauer & Shelley PNAS 2022 (asymmetric strokes pump)",
            "-",
            "; ".join(
                f"{r.cycle}, d = {fmt(r.spacing, 3)}: <Q_x> = {fmt(r.flux_x, 2)}, <Q_y> = {fmt(r.flux_y, 2)}, rms "
                f"{fmt(r.flux_rms, 3)} l^3/tau"
                for r in s.runs
            ),
            verdict(bool(ratios) and max(ratios) < NET_FLUX),
            f"Blake's flux 6 a sum F h of the beads' forces (analysis.cilia.blake_flux), {FLUX_SAMPLES} samples of the "
            f"window; no net flux when |<Q_x>| < {NET_FLUX:g} of its rms (largest "
            f"{fmt(max(ratios, default=math.nan), 2)}); {engine}",
        )
    )
    return rows

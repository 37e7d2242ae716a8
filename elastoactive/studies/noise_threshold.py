"""Active solids: the collective-actuation threshold against the noise on the units' polarities.

Beyond the paper (its outlook's two-dimensional structures; experiments with active units are noisy): the pinned
triangular hexagon of the hysteresis study, its coupling Pi = l_e / l_a ramped up from seeded random polarities and
back down (elastoactive.protocols, each step from the last state), at several rotational diffusions D_r of the
polarities (terms.unit_noise: Ito, seeded, rad^2 per gamma / k), in the reduced engine. Per seed and noise level,
where the units start turning on the way up and where they still turn on the way down (analysis.network.states names
each step; turning: collective, mixed, heterogeneous or irregular; not turning: frozen, or oscillating, swinging
without a full turn, which noise alone makes of a frozen state). A polarity diffusing alone wanders by sqrt(2 D_r T)
over a window T, which the states' rule can read as a slow turn in either sense (mixed): a step counts as turning
only if its units' mean |net rate| (the edge's or the deepest ring's) also exceeds DIFFUSION_MARGIN times the
diffusive sqrt(2 D_r / T) (T the measured window, the run's second half).
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.network import stability
from ..analysis.network.states import STATES
from ..core.params import Numerics
from ..protocols import make_ramp
from ..scenes import lattice
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick, run_ramps
from .claim_rows import Claim, fmt, span, verdict

ALIGNMENT = 0.1
"""l_a / a of the ramps (the hysteresis study's)."""
TURNING = tuple(STATES.index(name) for name in ("collective", "mixed", "heterogeneous", "irregular"))
"""The named states in which the units turn (collective actuation in the wide sense)."""
DIFFUSION_MARGIN = 3.0
"""A turning step's mean |net rate| must exceed this many diffusive standard deviations sqrt(2 D_r / T)."""


@dataclass(frozen=True)
class NoiseLevel:
    rotational_diffusion: float
    up_start: list[float]
    """Per seed, the smallest coupling at which its units turn on the way up (NaN: at no step)."""
    down_stop: list[float]
    """Per seed, the smallest coupling at which its units still turn on the way down (NaN: at no step)."""


@dataclass(frozen=True)
class NoiseThresholdSummary(Summary):
    lattice: str
    couplings: list[float]
    levels: list[NoiseLevel]
    softest: float
    """lambda_1 of the patch: without noise every fixed point is stable below it (proved)."""
    duration: float


NOISE_THRESHOLD = registry.declare("noise_threshold", summary=NoiseThresholdSummary, order=213, budget=9)


def _first(couplings: np.ndarray, moving: np.ndarray) -> float:
    hit = np.flatnonzero(moving)
    return float(couplings[hit[0]]) if hit.size else float("nan")


@NOISE_THRESHOLD.run
def noise_threshold_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Ramps up and down at each noise level, several seeds."""
    start = time.perf_counter()
    rings = pick(size, 2, 3, 3)
    seeds = pick(size, (0,), (0,), tuple(range(6)))
    duration = pick(size, 60.0, 300.0, 800.0)  # quick: the noisy ramp (one core, Euler-Maruyama) is the critical path
    levels = pick(size, (0.0, 0.02), (0.0, 0.03), (0.0, 0.001, 0.003, 0.01, 0.03))
    couplings = pick(
        size,
        (1.0, 1.6),
        tuple(np.round(np.arange(0.6, 0.801, 0.05), 3)),  # quick: around the onset (0.75 up, 0.7 down without noise)
        tuple(np.round(np.arange(0.45, 0.901, 0.025), 3)),
    )
    name = f"triangular hexagon R = {rings}"
    data: dict = {"couplings": np.asarray(couplings), "levels": np.asarray(levels)}
    summaries = []
    speeds = []
    ramps = [
        make_ramp(
            lattice.SCENE.physics(
                rings=rings, boundary="pinned", alignment_length=ALIGNMENT, rotational_diffusion=level
            ),
            "Pi",
            couplings,
            numerics=Numerics(sample_dt=0.25),
            seeds=seeds,
            duration=duration,
        )
        for level in levels
    ]
    with tempfile.TemporaryDirectory() as folder:
        loops = run_ramps(ramps, Path(folder), workers, progress)
    for level, loop in zip(levels, loops):
        window = duration / 2  # the default transient: the run's first half
        rate = np.fmax(loop.edge_rate.values, loop.bulk_rate.values)
        turning = np.isin(loop.network_state.values, TURNING) & (  # (seed, direction, coupling)
            rate > DIFFUSION_MARGIN * np.sqrt(2 * level / window)
        )
        values = loop.Pi.values
        summaries.append(
            NoiseLevel(
                rotational_diffusion=float(level),
                up_start=[_first(values, turning[s, 0]) for s in range(turning.shape[0])],
                down_stop=[_first(values, turning[s, 1]) for s in range(turning.shape[0])],
            )
        )
        speeds.append(loop.polarity_speed.values)
    data["polarity_speed"] = np.asarray(speeds)  # (level, seed, direction, coupling)
    softest = stability.softest(lattice.SCENE.network(lattice.SCENE.physics(rings=rings, boundary="pinned")))
    summary = NoiseThresholdSummary(
        lattice=name,
        couplings=[float(c) for c in couplings],
        levels=summaries,
        softest=float(softest),
        duration=float(duration),
    )
    return Study("noise_threshold", size, data, summary, time.perf_counter() - start)


@NOISE_THRESHOLD.figure
@plots.styled
def noise_threshold_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    fig, ax = plt.subplots(figsize=(5.6, 4.2))
    couplings = study.data["couplings"]
    speed = study.data["polarity_speed"]
    for k, level in enumerate(study.summary.levels):
        colour = f"C{k % 10}"
        ax.plot(
            couplings,
            speed[k, :, 0].mean(axis=0),
            "-o",
            color=colour,
            ms=4,
            label=f"D_r = {level.rotational_diffusion:g}",
        )
        ax.plot(couplings, speed[k, :, 1].mean(axis=0), "--o", color=colour, mfc="none", ms=4)
    ax.axvline(study.summary.softest, color="0.5", ls=":", label=rf"$\lambda_1$ = {study.summary.softest:.3f}")
    ax.set_xlabel(r"elasto-active coupling $\Pi = \ell_e / \ell_a$")
    ax.set_ylabel(r"units' mean turning speed $\langle|\dot\psi|\rangle$ ($k/\gamma$), seed mean")
    ax.set_title(f"{study.summary.lattice}: up (filled), down (open)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figB_noise_threshold.png")]


@NOISE_THRESHOLD.claims
def noise_threshold_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    levels = study.summary.levels
    quiet, noisiest = levels[0], levels[-1]

    def median(values: list[float]) -> float:
        return float(np.nanmedian(values)) if np.any(np.isfinite(values)) else float("nan")

    step = study.summary.couplings[1] - study.summary.couplings[0]
    up = [median(level.up_start) for level in levels]
    down = [median(level.down_stop) for level in levels]
    lost = [int(np.count_nonzero(~np.isfinite(level.up_start))) for level in levels]
    changed = (
        lost[-1] > lost[0]
        or bool(np.isfinite(up[0]) and np.isfinite(up[-1]) and abs(up[-1] - up[0]) >= step - 1e-9)
        or bool(np.isfinite(down[0]) and np.isfinite(down[-1]) and abs(down[-1] - down[0]) >= step - 1e-9)
    )
    table = "; ".join(
        f"D_r = {level.rotational_diffusion:g}: turning up from Pi = {span(level.up_start)}, down still at "
        f"{span(level.down_stop)}"
        for level in levels
    )
    return [
        Claim(
            f"{study.summary.lattice}: noise on the polarities moves where the units start turning (or stops them)",
            "the active-solid literature: noise changes or destroys collective actuation above some level (not a "
            "quoted threshold)",
            "-",
            table,
            verdict(changed),
            f"seed medians without noise: turning from Pi = {fmt(up[0], 3)} up, still at {fmt(down[0], 3)} down; at "
            f"D_r = {noisiest.rotational_diffusion:g}: {fmt(up[-1], 3)} up, {fmt(down[-1], 3)} down, "
            f"{lost[-1]} seed(s) never turning up (a change: one step or more, or a seed lost); "
            f"lambda_1 = {study.summary.softest:.4f}; "
            f"steps of {fmt(step, 2)} in Pi, {study.summary.duration:g} "
            f"gamma / k each, l_a = {ALIGNMENT:g} a, {len(quiet.up_start)} seed(s); reduced engine (Euler-Maruyama)",
            judged_from="quick",
        )
    ]

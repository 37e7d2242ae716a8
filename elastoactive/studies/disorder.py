"""Active solids: collective actuation of disordered networks (a diluted triangular patch, Delaunay networks).

Beyond the paper (its outlook's "more intricate geometrical connections"): the active solid of Baconnier et al.,
Nature Physics 18, 1234 (2022), on networks without the lattice's order, from elastoactive.networks.lattices: the
pinned triangular hexagon with a fraction of its bonds removed at random (several dilutions), and Delaunay networks of
random points (several seeds), every free node carrying a unit. The coupling Pi = l_e / l_a is ramped up from seeded
random polarities and back down (elastoactive.protocols: each step from the last state of the one before) at a small
alignment length (l_a = 0.1 a), in the reduced engine. Per network and seed: where the units start turning on the way
up, where they still turn on the way down (analysis.network.states names each step; turning: collective, mixed,
heterogeneous or irregular) and the state they reach at the top; against the linear bracket of each network
(analysis.network.stability): every fixed point is stable below lambda_1 and none above the ceiling (both proved), the
median Pi_c of random polarities, and Pi_c of the seed's own starting polarities.
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
from ..io.executor import process_pool
from ..networks.state import initial_state
from ..scenes import network as network_scene
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick, run_ramps
from .claim_rows import Claim, fmt, span, verdict

ALIGNMENT = 0.1
"""l_a / a of the ramps (the hysteresis study's)."""
TURNING = tuple(STATES.index(name) for name in ("collective", "mixed", "heterogeneous", "irregular"))
"""The named states in which the units turn (collective actuation in the wide sense)."""
FROZEN = STATES.index("frozen")
SAMPLES = 200
"""Random polarities whose median Pi_c is each network's typical threshold."""


@dataclass(frozen=True)
class NetworkActuation:
    """One network's ramps."""

    name: str
    geometry: str
    dilution: float
    network_seed: int
    bonds: int
    coordination: float
    """Mean number of bonds of a free node."""
    floppy: int
    """Zero modes of the dynamical matrix (then lambda_1 = 0: some fixed point is unstable at any Pi > 0)."""
    softest: float
    """lambda_1: every fixed point is stable below it (proved)."""
    typical: float
    """Median Pi_c of SAMPLES random polarities."""
    best_found: float
    """The best Pi_c a search over the polarities found (some fixed point is stable up to it; full size only, else
    NaN: a search costs 10-30 s per network)."""
    ceiling: float
    """No fixed point is stable above it (proved)."""
    start_coupling: list[float]
    """Per seed, Pi_c of its starting polarities (where its start, were it a fixed point, would lose stability)."""
    up_motion: list[float]
    """Per seed, the smallest coupling at which it is not frozen on the way up (turning, or swinging: oscillating)."""
    up_start: list[float]
    """Per seed, the smallest coupling at which its units turn on the way up (NaN: at no step)."""
    down_stop: list[float]
    """Per seed, the smallest coupling at which its units still turn on the way down (NaN: at no step)."""
    top_states: list[str]
    """Per seed, the named state at the top of the ramp (the way up's last step)."""


@dataclass(frozen=True)
class DisorderSummary(Summary):
    couplings: list[float]
    seeds: list[int]
    duration: float
    networks: list[NetworkActuation]


DISORDER = registry.declare("disorder", summary=DisorderSummary, order=214, budget=7)


def _networks(size: str) -> list[tuple[str, dict]]:
    """(name, the network scene's parameters) of each network at this size."""
    patch = pick(size, 2, 3, 3)
    dilutions = pick(size, (0.0, 0.15), (0.0, 0.1, 0.2), (0.0, 0.05, 0.1, 0.15, 0.2, 0.25))
    seeds = pick(size, (), (0, 1), (0, 1, 2, 3))
    out = []
    for dilution in dilutions:
        own = dict(geometry="triangular", size=patch, dilution=dilution)
        if dilution > 0:
            own["network_seed"] = 0
        out.append((f"triangular {patch}, dilution {dilution:g}", own))
    for seed in seeds:
        out.append((f"delaunay {patch}, seed {seed}", dict(geometry="delaunay", size=patch, network_seed=seed)))
    return out


def _first(couplings: np.ndarray, moving: np.ndarray) -> float:
    hit = np.flatnonzero(moving)
    return float(couplings[hit[0]]) if hit.size else float("nan")


def _bracket(network, seeds, numerics: Numerics) -> tuple[float, float, float, list[float]]:
    """(lambda_1, median Pi_c of random polarities, the ceiling, Pi_c of each seed's starting polarities)."""
    floppy = stability.floppy_modes(network)
    if floppy:
        return 0.0, 0.0, stability.interlacing_ceiling(network), [0.0] * len(seeds)
    rng = np.random.default_rng(0)
    count = int(np.count_nonzero(network.active))
    typical = float(
        np.median([stability.critical_coupling(network, rng.uniform(0, 2 * np.pi, count)) for _ in range(SAMPLES)])
    )
    starts = [
        stability.critical_coupling(network, initial_state(network, numerics.perturbation, seed).polarity)
        for seed in seeds
    ]
    return float(stability.softest(network)), typical, float(stability.coupling_ceiling(network)), starts


@DISORDER.run
def disorder_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Ramps up and down on each network, several seeds, with each network's linear bracket."""
    from ..protocols import make_ramp  # start-up time: the protocols load the engines

    start = time.perf_counter()
    seeds = pick(size, (0,), (0,), (0, 1, 2, 3))  # quick: one seed per network (each seed is a job of its own)
    duration = pick(size, 60.0, 200.0, 400.0)
    couplings = pick(
        size,
        (0.5, 2.0),
        tuple(np.round(np.arange(0.3, 1.101, 0.1), 3)),
        tuple(np.round(np.arange(0.1, 1.301, 0.05), 3)),
    )
    data: dict = {"couplings": np.asarray(couplings)}
    networks, speeds, states = [], [], []
    nets = _networks(size)
    physics = [network_scene.SCENE.physics(alignment_length=ALIGNMENT, **own) for _, own in nets]
    ramps = [
        make_ramp(p, "Pi", couplings, numerics=Numerics(sample_dt=0.25), seeds=seeds, duration=duration)
        for p in physics
    ]
    with process_pool(1) as pool, tempfile.TemporaryDirectory() as folder:  # the brackets beside the ramps
        pending = [
            pool.submit(_bracket, network_scene.SCENE.network(p), seeds, ramp.numerics)
            for p, ramp in zip(physics, ramps)
        ]
        loops = run_ramps(ramps, Path(folder), workers, progress)
        brackets = [future.result() for future in pending]
    for (name, own), p, loop, bracket in zip(nets, physics, loops, brackets):
        network = network_scene.SCENE.network(p)
        state = loop.network_state.values.astype(int)  # (seed, direction, coupling): index into STATES
        turning = np.isin(state, TURNING)
        values = loop.Pi.values
        softest, typical, ceiling, start_coupling = bracket
        searched = size == "full" and not stability.floppy_modes(network)
        best = stability.threshold(network, starts=4, samples=2).coupling if searched else float("nan")
        free = ~network.pinned
        degree = np.bincount(network.bonds.ravel(), minlength=network.n_nodes)
        networks.append(
            NetworkActuation(
                name=name,
                geometry=own["geometry"],
                dilution=float(own.get("dilution", 0.0)),
                network_seed=int(own.get("network_seed", 0)),
                bonds=int(network.n_bonds),
                coordination=float(degree[free].mean()),
                floppy=int(stability.floppy_modes(network)),
                softest=softest,
                typical=typical,
                best_found=float(best),
                ceiling=ceiling,
                start_coupling=[float(c) for c in start_coupling],
                up_motion=[_first(values, state[s, 0] != FROZEN) for s in range(state.shape[0])],
                up_start=[_first(values, turning[s, 0]) for s in range(turning.shape[0])],
                down_stop=[_first(values, turning[s, 1]) for s in range(turning.shape[0])],
                top_states=[STATES[state[s, 0, -1]] for s in range(state.shape[0])],
            )
        )
        speeds.append(loop.polarity_speed.values)
        states.append(state)
    data["polarity_speed"] = np.asarray(speeds)  # (network, seed, direction, coupling)
    data["network_state"] = np.asarray(states)
    summary = DisorderSummary(
        couplings=[float(c) for c in couplings], seeds=list(seeds), duration=float(duration), networks=networks
    )
    return Study("disorder", size, data, summary, time.perf_counter() - start)


@DISORDER.figure
@plots.styled
def disorder_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    nets = study.summary.networks
    fig, axes = plt.subplots(1, len(nets), figsize=(3.4 * len(nets), 3.6), squeeze=False, sharey=True)
    couplings = study.data["couplings"]
    speed = study.data["polarity_speed"]
    for k, (ax, net) in enumerate(zip(axes[0], nets)):
        for s in range(speed.shape[1]):
            colour = f"C{s % 10}"
            ax.plot(couplings, speed[k, s, 0], "-o", color=colour, ms=3, label="up" if s == 0 else None)
            ax.plot(couplings, speed[k, s, 1], "--o", color=colour, mfc="none", ms=3, label="down" if s == 0 else None)
        ax.axvline(net.softest, color="0.5", ls=":", label=rf"$\lambda_1$ = {net.softest:.3f}")
        ax.axvline(net.typical, color="C3", ls="--", lw=1, label=rf"median $\Pi_c$ = {net.typical:.3f}")
        if net.ceiling <= couplings[-1]:
            ax.axvline(net.ceiling, color="k", ls="-.", lw=1, label=f"ceiling = {net.ceiling:.3f}")
        ax.set_xlabel(r"$\Pi = \ell_e / \ell_a$")
        ax.set_title(f"{net.name} (z = {net.coordination:.2f})", fontsize=8)
        ax.legend(fontsize=6)
    axes[0][0].set_ylabel(r"units' mean turning speed $\langle|\dot\psi|\rangle$ ($k/\gamma$)")
    fig.tight_layout()
    return [plots.save(fig, out, "figB_disorder.png")]


def _previous(couplings: list[float], value: float) -> float:
    """The coupling of the ramp's step before `value` (-inf before the first)."""
    index = couplings.index(value)
    return couplings[index - 1] if index else -np.inf


@DISORDER.claims
def disorder_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    nets = study.summary.networks
    couplings = study.summary.couplings
    step = couplings[1] - couplings[0]
    where = "; ".join(
        f"{n.name}: moving from Pi = {span(n.up_motion)}, turning from {span(n.up_start)}, lambda_1 = {n.softest:.3f}"
        for n in nets
    )
    bounded = [
        n.softest <= u and _previous(couplings, u) <= n.ceiling for n in nets for u in n.up_start if np.isfinite(u)
    ]
    triangular = [n for n in nets if n.geometry == "triangular"]
    onsets = [np.nanmean(n.up_start) if np.any(np.isfinite(n.up_start)) else np.nan for n in triangular]
    softened = triangular[-1].softest < 0.5 * triangular[0].softest
    steady = all(np.isfinite(onsets)) and abs(onsets[-1] - onsets[0]) <= step * (1 + 1e-9)
    disordered = [n for n in nets if n.dilution > 0 or n.geometry == "delaunay"]
    actuated = [n for n in disordered if any(STATES.index(s) in TURNING for s in n.top_states)]
    tops = "; ".join(f"{n.name}: {', '.join(n.top_states)}" for n in disordered)
    common = f"steps of {fmt(step, 2)} in Pi, {study.summary.duration:g} gamma / k each, l_a = {ALIGNMENT:g} a, " + (
        f"{len(study.summary.seeds)} seed(s); reduced engine"
    )
    return [
        Claim(
            "ordered, diluted and Delaunay networks: the units start turning inside each one's proved linear bracket",
            "the linear stability (analysis.network.stability): every fixed point stable below lambda_1, none above "
            "the ceiling",
            "-",
            where,
            verdict(bool(bounded) and all(bounded), partly=any(bounded)),
            f"{sum(bounded)} of {len(bounded)} onsets with lambda_1 <= onset and the step before <= the ceiling; "
            + common,
            judged_from="quick",
        ),
        Claim(
            "a ramp's onset is not set by the softest mode: diluting the triangular patch lowers lambda_1 and the "
            "median Pi_c several-fold, the onset by at most one step",
            "-",
            "-",
            "; ".join(
                f"dilution {n.dilution:g} (z = {n.coordination:.2f}): lambda_1 = {n.softest:.3f}, median Pi_c "
                f"{n.typical:.3f}, ceiling {n.ceiling:.3f}, onset {fmt(o, 3)} (seed mean)"
                for n, o in zip(triangular, onsets)
            ),
            verdict(softened and steady, partly=steady),
            "raising Pi step by step, the frozen polarities settle into fixed points stable well above the median "
            "Pi_c of random ones (up to the ceiling: no fixed point is stable above it); " + common,
            judged_from="quick",
        ),
        Claim(
            "collective actuation without a lattice's order: disordered networks actuate",
            "Baconnier et al. 2025 (arXiv 2504.08572, introduction): collective actuation was first reported in a "
            "numerical dense packing of soft active particles (a disordered solid), then in a pinned spring network "
            "and a biofilm; no threshold for a disordered network quoted",
            "-",
            f"at Pi = {fmt(couplings[-1], 3)}: {tops}",
            verdict(len(actuated) == len(disordered) and bool(disordered), partly=bool(actuated)),
            f"{len(actuated)} of {len(disordered)} disordered networks turning at the top of the ramp; " + common,
            judged_from="quick",
        ),
    ]

"""Active solids: the hysteresis loop of collective actuation, on the pinned triangular hexagon and a kagome patch.

Beyond the paper (its outlook's two-dimensional structures): the active solid of Baconnier et al., Nature Physics 18,
1234 (2022). The coupling Pi = l_e / l_a is ramped up from seeded random polarities and back down
(elastoactive.protocols: each step starts from the last state of the one before), at a small alignment length
(l_a = 0.1 a), for several seeds, in the reduced engine. On the way up a seed starts moving at the first coupling
where its state is not frozen; on the way down it freezes below the last coupling where it still moves
(analysis.network.states names each step's state). The linear stability (analysis.network.stability) brackets both:
every fixed point is stable below lambda_1 (nothing can start moving there), and some fixed point found stays stable
up to the best Pi_c of a search (a frozen state can persist up to there at least).
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
from ..protocols import make_ramp
from ..scenes import lattice, network
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick, run_ramps
from .claim_rows import Claim, fmt, span, verdict

ALIGNMENT = 0.1
"""l_a / a of the ramps (as the active-solid study's): displacements of order l_a stay in the linear regime."""
FROZEN = STATES.index("frozen")


@dataclass(frozen=True)
class LoopSummary:
    """One lattice's loop."""

    lattice: str
    couplings: list[float]
    up_start: list[float]
    """Per seed, the smallest coupling at which it is not frozen on the way up (NaN: frozen at every step)."""
    down_stop: list[float]
    """Per seed, the smallest coupling at which it still moves on the way down (NaN: frozen at every step)."""
    down_freeze: list[float]
    """Per seed, the largest coupling at which it is frozen on the way down (NaN: moving at every step)."""
    softest: float
    """lambda_1: every fixed point is stable below it (proved)."""
    linear_threshold: float
    """The best Pi_c found over the polarities: some fixed point is stable up to it."""
    moving_states: list[str]
    """The named states of the moving steps (each state once, in STATES' order)."""
    edge_rate: float
    """Mean |net turning rate| of the edge ring at the top of the ramp (seed mean, way down's first step)."""
    bulk_rate: float
    """Of the deepest ring, same steps."""


@dataclass(frozen=True)
class HysteresisSummary(Summary):
    loops: list[LoopSummary]


HYSTERESIS = registry.declare("hysteresis", summary=HysteresisSummary, order=212, budget=6.5)


def _cases(size: str) -> list[tuple[str, object, dict, tuple[float, ...]]]:
    """(name, scene, its own parameters, the couplings) of each loop at this size."""
    triangular = pick(
        size,
        (1.0, 1.6),
        tuple(np.round(np.arange(0.55, 0.851, 0.05), 3)),
        (0.5, *np.round(np.arange(0.55, 0.901, 0.025), 3)),
    )
    kagome = pick(
        size, (0.3, 1.2), tuple(np.round(np.arange(0.2, 1.01, 0.1), 3)), tuple(np.round(np.arange(0.15, 1.01, 0.05), 3))
    )
    rings = pick(size, 2, 3, 3)
    return [
        (f"triangular hexagon R = {rings}", lattice.SCENE, dict(rings=rings, boundary="pinned"), triangular),
        (f"kagome hexagon size {rings}", network.SCENE, dict(geometry="kagome", size=rings), kagome),
    ]


@HYSTERESIS.run
def hysteresis_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """The ramp up and down of each lattice, several seeds, with the linear bracket."""
    start = time.perf_counter()
    seeds = pick(size, (0,), (0, 1), tuple(range(6)))  # each seed is a job of its own (run_ramps)
    duration = pick(size, 60.0, 400.0, 800.0)
    data: dict = {}
    cases = _cases(size)
    physics = [scene.physics(alignment_length=ALIGNMENT, **own) for _, scene, own, _ in cases]
    ramps = [
        make_ramp(p, "Pi", couplings, numerics=Numerics(sample_dt=0.25), seeds=seeds, duration=duration)
        for p, (_, _, _, couplings) in zip(physics, cases)
    ]
    starts, samples = pick(size, 1, 2, 6), pick(size, 10, 50, 200)
    with process_pool(1) as pool, tempfile.TemporaryDirectory() as folder:  # the brackets beside the ramps
        pending = [
            pool.submit(stability.threshold, scene.network(p), starts=starts, samples=samples)
            for (_, scene, _, _), p in zip(cases, physics)
        ]
        sweeps = run_ramps(ramps, Path(folder), workers, progress)
        brackets = [future.result() for future in pending]
    loops = [
        _summarise(name, sweep, bracket, data, k)
        for k, ((name, _, _, _), sweep, bracket) in enumerate(zip(cases, sweeps, brackets))
    ]
    return Study("hysteresis", size, data, HysteresisSummary(loops=loops), time.perf_counter() - start)


def _summarise(name: str, loop, bracket, data: dict, k: int) -> LoopSummary:
    """A loop's thresholds per seed, its moving states and ring rates, and its arrays into `data` (prefix loop<k>_)."""
    couplings = loop.Pi.values
    state = loop.network_state.values  # (seed, direction, coupling): index into STATES
    up_start, down_stop, down_freeze = [], [], []
    for s in range(state.shape[0]):
        moving_up = np.flatnonzero(state[s, 0] != FROZEN)
        moving_down = np.flatnonzero(state[s, 1] != FROZEN)
        frozen_down = np.flatnonzero(state[s, 1] == FROZEN)
        up_start.append(float(couplings[moving_up[0]]) if moving_up.size else float("nan"))
        down_stop.append(float(couplings[moving_down[0]]) if moving_down.size else float("nan"))
        down_freeze.append(float(couplings[frozen_down[-1]]) if frozen_down.size else float("nan"))
    moving = sorted({int(v) for v in state.ravel() if v != FROZEN})
    top = loop.sel(direction="down").isel(Pi=-1)
    for key in ("network_state", "polarity_speed", "edge_rate", "bulk_rate", "mode_space", "mode_space_share"):
        data[f"loop{k}_{key}"] = loop[key].values
    data[f"loop{k}_couplings"] = couplings
    return LoopSummary(
        lattice=name,
        couplings=[float(c) for c in couplings],
        up_start=up_start,
        down_stop=down_stop,
        down_freeze=down_freeze,
        softest=float(bracket.softest),
        linear_threshold=float(bracket.coupling),
        moving_states=[STATES[i] for i in moving],
        edge_rate=float(top.edge_rate.mean()),
        bulk_rate=float(top.bulk_rate.mean()),
    )


@HYSTERESIS.figure
@plots.styled
def hysteresis_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    loops = study.summary.loops
    fig, axes = plt.subplots(1, len(loops), figsize=(4.8 * len(loops), 4.0), squeeze=False)
    for k, (ax, loop) in enumerate(zip(axes[0], loops)):
        speed = study.data[f"loop{k}_polarity_speed"]
        couplings = study.data[f"loop{k}_couplings"]
        for s in range(speed.shape[0]):
            colour = f"C{s % 10}"
            ax.plot(couplings, speed[s, 0], "-o", color=colour, ms=4, label="up" if s == 0 else None)
            ax.plot(couplings, speed[s, 1], "--o", color=colour, mfc="none", ms=4, label="down" if s == 0 else None)
        ax.axvline(loop.softest, color="0.5", ls=":", label=rf"$\lambda_1$ = {loop.softest:.3f}")
        ax.axvline(
            loop.linear_threshold, color="C3", ls="--", lw=1, label=rf"best $\Pi_c$ = {loop.linear_threshold:.3f}"
        )
        ax.set_xlabel(r"elasto-active coupling $\Pi = \ell_e / \ell_a$")
        ax.set_ylabel(r"units' mean turning speed $\langle|\dot\psi|\rangle$ ($k/\gamma$)")
        ax.set_title(f"{loop.lattice}: up (filled), down (open)", fontsize=9)
        ax.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figB_hysteresis.png")]


@HYSTERESIS.claims
def hysteresis_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    rows = []
    source = (
        "Baconnier et al. 2022 (Nat. Phys.): collective actuation above a critical coupling (abstract; its threshold "
        "not at hand); hysteresis when tension goes back and forth ('Discontinuous tension-controlled transition "
        "between collective actuations in active solids', abstract)"
    )
    for loop in study.summary.loops:
        opened = [d < u for d, u in zip(loop.down_stop, loop.up_start) if np.isfinite(d) and np.isfinite(u)]
        upper = [u for u in loop.up_start if np.isfinite(u)]
        inside = bool(upper) and loop.softest <= min(upper) <= loop.linear_threshold
        step = loop.couplings[1] - loop.couplings[0]
        rows.append(
            Claim(
                f"{loop.lattice}: lowering Pi keeps the motion below where raising it started (hysteresis)",
                source,
                "-",
                f"up: moving from Pi = {span(loop.up_start)} (seeds); down: still moving at "
                f"{span(loop.down_stop)}, frozen at Pi <= {span(loop.down_freeze)}; a loop in "
                f"{sum(opened)} of {len(loop.up_start)} seeds; moving states: {', '.join(loop.moving_states) or '-'}",
                verdict(bool(opened) and all(opened) and inside, partly=any(opened)),
                f"steps of {fmt(step, 2)} in Pi, each from the last state; every fixed point stable below "
                f"lambda_1 = {loop.softest:.4f}, some up to at least Pi = {loop.linear_threshold:.4f} (best found); "
                f"at the top, edge ring |rate| {fmt(loop.edge_rate, 3)} against the deepest ring's "
                f"{fmt(loop.bulk_rate, 3)} k/gamma; l_a = {ALIGNMENT:g} a; reduced engine",
                judged_from="quick",
            )
        )
    return rows

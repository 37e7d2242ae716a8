"""Active solids: the transition to collective actuation of the pinned hexagonal lattice, and the trapped unit.

Beyond the paper (its outlook's two-dimensional structures and non-follower forces): the active solid of Baconnier et
al., Nature Physics 18, 1234 (2022). The pinned hexagon of 2 rings (7 free nodes, each with a self-aligning unit) is
run against the elasto-active coupling Pi = l_e / l_a = sigma / alignment_length at a small alignment length
(l_a = 0.1 a, so displacements stay small against the lattice spacing and the elasticity is nearly linear, as in the
sources' model), from several seeded random polarities each: whether the units end still or turn together
(actuation), and which normal modes hold the elastic energy. The linear stability (analysis.network.stability)
brackets the transition: every fixed point is stable below the softest mode's eigenvalue lambda_1, none above Pi*.
The trapped unit is run across its threshold Pi = 1 against its derivation (docs/network.md). Reduced engine; MuJoCo
reruns seed 0 at MUJOCO_COUPLINGS (the same cases, its automatic numerics) as the cross-check of the transition's
bracket and of the selected modes.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.network import hexagonal_patch, stability
from ..batch import Case
from ..core.params import Numerics
from ..io.executor import process_pool
from ..scenes import lattice, trap
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick, run_measured
from .claim_rows import Claim, fmt, verdict

ALIGNMENT = 0.1
"""l_a / a of the lattice runs: small, so that the lattice's displacements (of order l_a) stay in the linear regime."""
MUJOCO_COUPLINGS = {"tiny": (1.0, 1.5), "quick": (1.4, 1.5), "full": (1.0, 1.2, 1.4, 1.5, 1.6, 2.0, 2.5)}
"""Couplings at which MuJoCo reruns the lattice's seed 0 (each in the reduced engine's set of that size): quick, the
two that bracket the reduced engine's transition."""
ACTUATED = 0.1
"""Actuation (coherence of the units' turning) above which a run counts as actuated (still units: 0;
units turning together at one rate: 1)."""


@dataclass(frozen=True)
class ActiveSolidSummary(Summary):
    couplings: list[float]
    actuated_fraction: list[float]
    """Share of the seeds that end in collective actuation, at each coupling."""
    still_below: float
    """Largest coupling at which every seed came to rest."""
    actuated_above: float
    """Smallest coupling from which every seed actuates collectively."""
    softest: float
    """lambda_1 of the pinned hexagon's dynamical matrix (every fixed point is stable below it)."""
    linear_threshold: float
    """The best Pi_c found over the polarities: some fixed point is stable up to it (a lower bound on Pi*, where the
    last loses stability)."""
    typical_threshold: float
    """Median Pi_c of uniformly random polarities."""
    modes: list[list[int]]
    """The two most energetic modes (ranks by stiffness) of each actuated run."""
    trap_couplings: list[float]
    trap_radius_error: float
    """Largest relative error of the trapped unit's orbit radius against sqrt(l_e l_a) (l_e below threshold)."""
    trap_rate_error: float
    """Largest error of its angular frequency against trap sqrt(Pi - 1) (relative; absolute below threshold)."""
    mujoco_couplings: list[float]
    mujoco_actuation: list[float]
    """MuJoCo's actuation of seed 0 at each of mujoco_couplings."""
    reduced_actuation: list[float]
    """The reduced engine's, same cases."""
    mujoco_modes: list[list[int]]
    """MuJoCo's two most energetic modes at each of mujoco_couplings (ranks by stiffness)."""
    reduced_modes: list[list[int]]


ACTIVE_SOLID = registry.declare("active_solid", summary=ActiveSolidSummary, order=210, budget=5.5)


@ACTIVE_SOLID.run
def active_solid_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Collective actuation of the pinned hexagon against Pi, its linear bracket, the trapped unit's transition."""
    start = time.perf_counter()
    couplings = pick(
        size, (1.0, 1.5, 2.0), (1.0, 1.2, 1.4, 1.5, 1.6, 2.0, 2.5), tuple(np.round(np.arange(1.0, 2.61, 0.1), 2))
    )
    seeds = pick(size, (0,), (0, 1), tuple(range(8)))
    duration = pick(size, 200.0, 300.0, 1000.0)
    cases = [
        lattice.SCENE.physics(rings=2, boundary="pinned", sigma=c * ALIGNMENT, alignment_length=ALIGNMENT)
        for c in couplings
        for _ in seeds
    ]
    numerics = [Numerics(sample_dt=0.25, seed=s) for _ in couplings for s in seeds]
    trap_couplings = pick(
        size, (0.5, 2.0), (0.5, 0.9, 1.1, 2.0, 4.0), (0.25, 0.5, 0.8, 0.9, 0.95, 1.05, 1.1, 1.5, 2.0, 4.0, 8.0)
    )
    trap_cases = [trap.SCENE.physics(sigma=c * 0.5, trap=1.0, alignment_length=0.5) for c in trap_couplings]
    checked = pick(size, *(MUJOCO_COUPLINGS[k] for k in ("tiny", "quick", "full")))
    batch = [Case(p, n, duration, "reduced", duration / 2) for p, n in zip(cases, numerics)]
    batch += [Case(p, Numerics(sample_dt=0.1), 300.0, "reduced", 150.0) for p in trap_cases]
    batch += [
        Case(cases[couplings.index(c) * len(seeds)], Numerics(sample_dt=0.25, seed=0), duration, "mujoco", duration / 2)
        for c in checked
    ]
    with process_pool(1) as pool:  # the linear bracket beside the runs
        pending = pool.submit(
            stability.threshold, hexagonal_patch(2), starts=pick(size, 1, 1, 8), samples=pick(size, 50, 100, 2000)
        )
        results = [r.results for r in run_measured(batch, workers, progress, "active solid")]
        bracket = pending.result()
    lattice_results = results[: len(cases)]
    trap_results = results[len(cases) : len(cases) + len(trap_cases)]
    mujoco_results = results[len(cases) + len(trap_cases) :]
    twins = [lattice_results[couplings.index(c) * len(seeds)] for c in checked]
    actuation = np.array([r.extra["actuation"] for r in lattice_results]).reshape(len(couplings), len(seeds))
    modes = np.array([[r.extra["dominant_mode"], r.extra["second_mode"]] for r in lattice_results])
    fraction = (actuation > ACTUATED).mean(axis=1)
    still = [c for c, a in zip(couplings, actuation) if np.all(a == 0.0)]
    moving = [c for k, c in enumerate(couplings) if np.all(fraction[k:] == 1.0)]
    radius = np.array([r.orbit_radius for r in trap_results])
    rate = np.abs([r.orbit_rate for r in trap_results])
    expected = np.array([trap.orbit(p.sigma, p.trap, p.alignment_length) for p in trap_cases])
    moving_trap = expected[:, 1] > 0
    rate_error = np.where(
        moving_trap,
        np.abs(rate - expected[:, 1]) / np.where(moving_trap, expected[:, 1], 1.0),
        np.abs(rate - expected[:, 1]),
    )
    data = {
        "couplings": np.array(couplings),
        "actuation": actuation,
        "fraction": fraction,
        "modes": modes.reshape(len(couplings), len(seeds), 2),
        "polarization": np.array([r.extra["polarization"] for r in lattice_results]).reshape(actuation.shape),
        "frequency": np.array([np.nan if r.frequency is None else r.frequency for r in lattice_results]).reshape(
            actuation.shape
        ),
        "trap_couplings": np.array(trap_couplings),
        "trap_radius": radius,
        "trap_rate": rate,
        "trap_expected": expected,
    }
    summary = ActiveSolidSummary(
        couplings=[float(c) for c in couplings],
        actuated_fraction=[float(f) for f in fraction],
        still_below=float(max(still)) if still else float("nan"),
        actuated_above=float(min(moving)) if moving else float("nan"),
        softest=bracket.softest,
        linear_threshold=bracket.coupling,
        typical_threshold=bracket.typical,
        modes=[[int(a), int(b)] for (a, b), act in zip(modes, actuation.reshape(-1)) if act > ACTUATED],
        trap_couplings=[float(c) for c in trap_couplings],
        trap_radius_error=float(np.max(np.abs(radius - expected[:, 0]) / expected[:, 0])),
        trap_rate_error=float(np.max(rate_error)),
        mujoco_couplings=[float(c) for c in checked],
        mujoco_actuation=[float(r.extra["actuation"]) for r in mujoco_results],
        reduced_actuation=[float(r.extra["actuation"]) for r in twins],
        mujoco_modes=[[int(r.extra["dominant_mode"]), int(r.extra["second_mode"])] for r in mujoco_results],
        reduced_modes=[[int(r.extra["dominant_mode"]), int(r.extra["second_mode"])] for r in twins],
    )
    return Study("active_solid", size, data, summary, time.perf_counter() - start)


@ACTIVE_SOLID.figure
@plots.styled
def active_solid_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4.0))
    for k in range(d["actuation"].shape[1]):
        a1.plot(d["couplings"], d["actuation"][:, k], "o", ms=4, alpha=0.7, label="runs (seeds)" if k == 0 else None)
    a1.plot(d["couplings"], d["fraction"], "k-", lw=1, label="share actuated")
    a1.axvspan(s.softest, s.linear_threshold, color="0.85", label=r"linear: some fixed points stable")
    a1.axvline(s.softest, color="C2", ls=":", label=rf"$\lambda_1$ = {s.softest:.3f}")
    a1.axvline(s.linear_threshold, color="C3", ls="--", label=rf"best $\Pi_c$ found = {s.linear_threshold:.3f}")
    a1.set_xlabel(r"elasto-active coupling $\Pi = \ell_e / \ell_a$")
    a1.set_ylabel("actuation (coherence of the units' turning)")
    a1.set_title("Pinned hexagon (R = 2): collective actuation")
    a1.legend(fontsize=7)
    c = d["trap_couplings"]
    fine = np.linspace(min(c.min(), 0.2), c.max(), 200)
    a2.plot(fine, np.sqrt(np.clip(fine - 1.0, 0, None)), "k-", lw=1, label=r"derivation: $k_t\sqrt{\Pi - 1}$")
    a2.plot(c, d["trap_rate"], "o", color="C0", label="reduced model")
    a2.set_xlabel(r"$\Pi = \ell_e / \ell_a$ ($k_t$ = 1)")
    a2.set_ylabel(r"orbit's angular frequency $\omega$ ($k/\gamma$)")
    a2.set_title("Trapped unit: rest below Pi = 1, orbit above")
    a2.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figB_active_solid.png")]


@ACTIVE_SOLID.claims
def active_solid_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    source = "Baconnier et al. 2022 (Nat. Phys.): collective actuation above a critical coupling"
    inside = s.still_below < s.actuated_above and s.softest < s.actuated_above  # none actuates below lambda_1
    softest_pair = all(sorted(m) == [1, 2] for m in s.modes)
    mj_on = [a > ACTUATED for a in s.mujoco_actuation]
    same_side = mj_on == [a > ACTUATED for a in s.reduced_actuation]
    runs = [f"Pi = {fmt(c, 3)}: {fmt(a, 2)}" for c, a in zip(s.mujoco_couplings, s.mujoco_actuation)]
    mj_still = [c for c, on in zip(s.mujoco_couplings, mj_on) if not on]
    mj_moving = [c for c, on in zip(s.mujoco_couplings, mj_on) if on]
    mujoco_row = (
        f"seed 0, actuation {'; '.join(runs)} (still at Pi <= {fmt(max(mj_still), 3) if mj_still else '-'}, "
        f"actuated from {fmt(min(mj_moving), 3) if mj_moving else '-'}; the reduced engine: "
        f"{'; '.join(fmt(a, 2) for a in s.reduced_actuation)})"
    )
    modes_mj = [m for m, on in zip(s.mujoco_modes, mj_on) if on]
    modes_same = all(sorted(a) == sorted(b) for a, b, on in zip(s.mujoco_modes, s.reduced_modes, mj_on) if on)
    return [
        Claim(
            "Pinned hexagon (R = 2): rest below a critical Pi = l_e / l_a, collective actuation above",
            source,
            mujoco_row,
            f"all seeds still at Pi <= {fmt(s.still_below, 3)}, all actuated from Pi = {fmt(s.actuated_above, 3)}",
            verdict(inside and same_side, partly=np.isfinite(s.actuated_above)),
            f"linear: every fixed point stable below lambda_1 = {s.softest:.4f}; some stable up to at least "
            f"Pi = {s.linear_threshold:.4f} (the best found over the polarities); median Pi_c over random "
            f"polarities {s.typical_threshold:.3f}; l_a = "
            f"{ALIGNMENT:g} a; MuJoCo reruns the reduced engine's seed 0 (its automatic numerics); the source's "
            "numerical threshold for its own lattice is not quoted here (docs/network.md)",
        ),
        Claim(
            "The actuated dynamics condenses on few modes",
            "selected modes not necessarily the lowest-energy ones",
            "modes of each actuated run: "
            + (", ".join("+".join(str(x) for x in sorted(m)) for m in modes_mj) or "-")
            + (" (the reduced engine's, same cases)" if modes_same else " (differ from the reduced engine's)"),
            "modes (by stiffness) of each actuated run: "
            + ", ".join("+".join(str(x) for x in m) for m in sorted(set(tuple(sorted(m)) for m in s.modes))),
            verdict(bool(s.modes) and modes_same),
            "the two softest (degenerate) modes of this small patch"
            + ("" if softest_pair else "; other pairs in some runs"),
        ),
        Claim(
            "Trapped unit: rest at l_e below Pi = 1, circle of radius sqrt(l_e l_a) at k_t sqrt(Pi - 1) above",
            "derived here (docs/network.md)",
            "-",
            f"radius within {100 * s.trap_radius_error:.2g}%, rate within {s.trap_rate_error:.2g}",
            verdict(s.trap_radius_error < 1e-2 and s.trap_rate_error < 1e-2),
            f"Pi = {', '.join(fmt(c, 3) for c in s.trap_couplings)}",
        ),
    ]

"""The dish: a free chain in a paraboloid (the supplement's satellite-dish experiment, sigma = 0.30).

dish_study:
- the phase diagram over (sigma, trap) for N = 7 in the reduced model (analysis.dish.dish_state: rest, spin,
  orbit, crawl, beat, irregular), with the body rotation rate, the orbit rate and radius, and the curvature;
  a point still settling (irregular) next to a threshold is run longer (SETTLE_FACTOR, SETTLE_RETRIES);
- both engines side by side at the supplement's sigma = 0.30 over the trap stiffness and at a beating point;
- the supplement's observation ("tends to rotate around the center of the paraboloid, but ... also crawls in
  circles at the same time") located on the diagram: a fine scan of the trap stiffness at sigma = 0.30, and the
  band where the chain goes round the centre.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import dish
from ..batch import Case
from ..core.params import Numerics
from ..results import Results
from ..scenes import paraboloid
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick, run_measured
from .claim_rows import Claim, verdict
from .inertia import HEXBUG_MASS_KG
from .paper import PAPER

__all__ = ["DishPoint", "DishSummary", "dish_study", "focal_length_m"]

N = 7
SUPPLEMENT_SIGMA = PAPER.dish_sigma
"""The supplement's dish experiment (0.30)."""
GRAVITY = 9.81
"""m/s^2."""
SAMPLE_DT = 0.2
"""tau between samples (the dish's motions are slow: 0.2 rad/tau at most below sigma = 1)."""


SETTLE_FACTOR = 4.0
"""A point classified 'irregular' is run again this many times longer (its rates may still be settling) ..."""
SETTLE_RETRIES = 2
"""... at most this many times; what stays irregular is reported as such."""
CHECK_DURATION = {"tiny": 600.0, "quick": 600.0, "full": math.inf}
"""The engines' checks run at most this long (tau): at sigma = 0.3, trap 0.03-0.3, and sigma = 1.2, trap 0.3, the
reduced engine's state, rates and orbit radius at 600 tau are those at 1200 to 4 digits."""


def _duration(trap: float) -> float:
    """Run length: long enough to settle, the slowest relaxation being the trap's (rate ~ trap / gamma)."""
    return float(min(8000.0, max(1200.0, 10.0 * math.ceil(4.0 / trap))))


def focal_length_m(trap: float, sigma: float, mass_kg: float = HEXBUG_MASS_KG) -> float:
    """The focal length f (m) of a satellite dish z = r^2 / (4 f) whose small-slope trap on a bug of mass `mass_kg`
    is `trap`: gravity pushes it with -m g r / (2 f), so k = m g / (2 f), and trap = k l^2 / C1 with
    C1 = F_a l / sigma (the paper's F_a and link pitch; the mass is ASSUMED, studies.inertia.HEXBUG_MASS_KG)."""
    k = trap * PAPER.active_force_n / (sigma * PAPER.link_pitch_m)  # N/m
    return mass_kg * GRAVITY / (2.0 * k)


@dataclass(frozen=True)
class DishPoint(Summary):
    sigma: float
    trap: float
    engine: str
    duration: float
    state: str
    rotation_rate: float
    orbit_rate: float
    orbit_radius: float
    curvature: float
    amplitude: float
    """Amplitude of Theta (the beat, when it beats)."""


@dataclass(frozen=True)
class DishSummary(Summary):
    n: int
    sigmas: tuple[float, ...]
    traps: tuple[float, ...]
    states: dict[str, int]
    """How many grid points fall in each state (reduced model)."""
    crawl_found: bool
    """Whether any grid point crawls (orbit rate != body rotation rate)."""
    supplement_sigma: float
    supplement_orbit_traps: tuple[float, float]
    """The smallest and largest trap of the fine scan at sigma = 0.30 where the chain goes round the centre (NaN:
    none)."""
    supplement_focal_length_m: tuple[float, float]
    """The focal lengths of a real satellite dish whose small-slope trap spans that band (focal_length_m; an ASSUMED
    bug mass), shortest first."""
    supplement_states: dict[str, str]
    """State at sigma = 0.30 by trap of the fine scan (reduced model)."""
    checks: list[DishPoint]
    """MuJoCo and the reduced model side by side."""
    engines_max_rel_diff: float
    """Largest |MuJoCo / reduced - 1| of the rotation and orbit rates over the checks (where they turn)."""
    engines_same_state: bool


def _point(case: Case, r: Results) -> DishPoint:
    """The point of a case measured (by results.measure) in the workers."""
    p = case.physics
    end = float(case.numerics.sample_times(case.duration)[-1])
    return DishPoint(
        p.sigma,
        p.trap,
        case.engine,
        end,
        r.dish_state,
        r.rotation_rate,
        r.orbit_rate,
        r.orbit_radius,
        r.curvature,
        float(r.amplitude),
    )


DISH = registry.declare("dish", summary=DishSummary, order=150, budget=14)


@DISH.run
def dish_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """The (sigma, trap) phase diagram of N = 7 (reduced model) and both engines at the supplement's sigma = 0.30."""
    start = time.perf_counter()
    sigmas = pick(
        size,
        (0.3, 1.2),
        (0.1, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0),
        tuple(np.round(np.geomspace(0.1, 3.0, 25), 4)),
    )
    traps = pick(
        size,
        (0.1, 0.3),
        # quick: 0.0095-3, a decade in 3 steps (0.003, all rest like 0.0095, took 44% of the grid's time at 8000 tau);
        # the fine scan resolves sigma = 0.30
        tuple(np.round(np.geomspace(0.003, 3.0, 7), 5)[1:]),
        tuple(np.round(np.geomspace(0.003, 3.0, 31), 5)),
    )
    if SUPPLEMENT_SIGMA not in sigmas:
        sigmas = tuple(sorted(sigmas + (SUPPLEMENT_SIGMA,)))
    checks = pick(
        size,
        ((SUPPLEMENT_SIGMA, 0.1),),
        tuple((SUPPLEMENT_SIGMA, k) for k in (0.03, 0.1, 0.3)) + ((1.2, 0.3),),
        tuple((SUPPLEMENT_SIGMA, k) for k in (0.003, 0.01, 0.03, 0.1, 0.2, 0.3, 1.0, 3.0)) + ((1.2, 0.3), (0.5, 0.1)),
    )
    scan = tuple(float(k) for k in np.round(np.geomspace(0.03, 0.6, pick(size, 4, 19, 41)), 5))
    scene = paraboloid.SCENE
    numerics = Numerics(sample_dt=SAMPLE_DT)
    cases = [
        Case(scene.physics(n=N, sigma=s, trap=k), numerics, _duration(k), "reduced") for s in sigmas for k in traps
    ]
    cases += [Case(scene.physics(n=N, sigma=SUPPLEMENT_SIGMA, trap=k), numerics, _duration(k), "reduced") for k in scan]
    cases += [
        Case(scene.physics(n=N, sigma=s, trap=k), numerics, min(_duration(k), CHECK_DURATION[size]), e)
        for s, k in checks
        for e in ("mujoco", "reduced")
    ]
    points = [_point(c, r.results) for c, r in zip(cases, run_measured(cases, workers, progress, "dish N=7"))]
    unsettled = [i for i, p in enumerate(points) if p.state == "irregular"]
    for _ in range(SETTLE_RETRIES):  # next to a threshold the motion settles slowly: run those points longer
        longer = [dataclasses.replace(cases[i], duration=SETTLE_FACTOR * cases[i].duration) for i in unsettled]
        for i, c, r in zip(unsettled, longer, run_measured(longer, workers, progress, "dish N=7, settling")):
            cases[i], points[i] = c, _point(c, r.results)
        unsettled = [i for i in unsettled if points[i].state == "irregular"]
    cut = len(sigmas) * len(traps)
    grid, line, check = points[:cut], points[cut : cut + len(scan)], points[cut + len(scan) :]
    data: dict = {"sigma": np.array(sigmas), "trap": np.array(traps)}
    shape = (len(sigmas), len(traps))
    data["state"] = np.array([dish.STATES.index(p.state) for p in grid]).reshape(shape)
    data["state_names"] = np.array(dish.STATES)
    for key in ("rotation_rate", "orbit_rate", "orbit_radius", "curvature", "amplitude"):
        data[key] = np.array([getattr(p, key) for p in grid]).reshape(shape)
    counts = {s: int(np.count_nonzero(data["state"] == i)) for i, s in enumerate(dish.STATES)}
    for key in ("rotation_rate", "orbit_rate", "orbit_radius"):
        data[f"scan_{key}"] = np.array([getattr(p, key) for p in line])
    data["scan_trap"] = np.array(scan)
    data["scan_state"] = np.array([dish.STATES.index(p.state) for p in line])
    at = {p.trap: p for p in line}
    orbiting = [k for k, p in at.items() if p.state in ("orbit", "crawl")]
    diffs, same = [], True
    for mj, red in zip(check[0::2], check[1::2]):
        same &= mj.state == red.state
        for key in ("rotation_rate", "orbit_rate"):
            a, b = getattr(mj, key), getattr(red, key)
            if math.isfinite(a) and math.isfinite(b) and abs(b) > dish.REST_RATE:
                diffs.append(abs(a / b - 1))
    summary = DishSummary(
        N,
        tuple(float(s) for s in sigmas),
        tuple(float(k) for k in traps),
        counts,
        counts["crawl"] > 0,
        SUPPLEMENT_SIGMA,
        (min(orbiting), max(orbiting)) if orbiting else (math.nan, math.nan),
        (focal_length_m(max(orbiting), SUPPLEMENT_SIGMA), focal_length_m(min(orbiting), SUPPLEMENT_SIGMA))
        if orbiting
        else (math.nan, math.nan),
        {f"{k:g}": p.state for k, p in sorted(at.items())},
        check,
        float(max(diffs)) if diffs else math.nan,
        bool(same),
    )
    return Study("dish", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# figures
# --------------------------------------------------------------------------------------------------
DISH_COLOURS = {"rest": "0.85", "spin": "C1", "orbit": "C0", "crawl": "C2", "beat": "C3", "irregular": "k"}
"""Colour of each state of analysis.dish.dish_state in the phase diagram."""


@DISH.figure
@plots.styled
def dish_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    mpl = plots.matplotlib()
    d, s = study.data, study.summary
    names = [str(n) for n in d["state_names"]]
    sig, trap = np.asarray(d["sigma"]), np.asarray(d["trap"])
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11.0, 4.4))
    cmap = mpl.colors.ListedColormap([DISH_COLOURS[n] for n in names])
    a1.pcolormesh(
        plots.edges(trap, log=True),
        plots.edges(sig, log=True),
        d["state"],
        cmap=cmap,
        vmin=-0.5,
        vmax=len(names) - 0.5,
        shading="flat",
    )
    for p in s.checks:
        if p.engine == "mujoco":
            a1.plot(p.trap, p.sigma, "o", mfc="none", mec="w", ms=9, mew=1.5)
    a1.axhline(s.supplement_sigma, color="w", ls=":", lw=1)
    a1.set_xscale("log")
    a1.set_yscale("log")
    a1.set_xlabel(r"trap $k l^2 / C_1$")
    a1.set_ylabel(r"$\sigma$")
    a1.set_title(f"N = {s.n} in the dish (reduced model; rings: MuJoCo checks)")
    present = [n for i, n in enumerate(names) if np.any(d["state"] == i)]
    a1.legend(handles=[plots.patch(color=DISH_COLOURS[n], label=n) for n in present], loc="upper left", fontsize=8)
    scan = d["scan_trap"]
    a2.plot(scan, np.abs(d["scan_rotation_rate"]), "o-", color="C0", ms=4, label=r"|body rotation| $|\dot\theta_1|$")
    a2.plot(scan, np.abs(d["scan_orbit_rate"]), "x--", color="C3", label="|orbit rate| of the centre of mass")
    lo, hi = s.supplement_orbit_traps
    if np.isfinite(lo):
        a2.axvspan(lo, hi, color=DISH_COLOURS["orbit"], alpha=0.15, label="goes round the centre (orbit)")
    for p in s.checks:
        if p.engine == "mujoco" and p.sigma == s.supplement_sigma:
            a2.plot(p.trap, abs(p.rotation_rate), "s", mfc="none", color="k", ms=8)
    a2.plot([], [], "s", mfc="none", color="k", label="MuJoCo")
    a2.set_xscale("log")
    a2.set_xlabel(r"trap $k l^2 / C_1$")
    a2.set_ylabel(r"rad / $\tau$")
    ax = a2.twinx()
    ax.plot(scan, d["scan_orbit_radius"], ":", color="C2")
    ax.set_yscale("log")
    ax.set_ylabel("orbit radius / l (dotted)", color="C2")
    a2.set_title(rf"the supplement's $\sigma$ = {s.supplement_sigma:g}")
    a2.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    return [plots.save(fig, out, "figA_dish.png")]


# --------------------------------------------------------------------------------------------------
# claim rows
# --------------------------------------------------------------------------------------------------
@DISH.claims
def dish_claims(st: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = st.summary
    lo, hi = s.supplement_orbit_traps
    states = ", ".join(f"{k}: {v}" for k, v in s.supplement_states.items())
    mj = [p for p in s.checks if p.engine == "mujoco" and p.sigma == s.supplement_sigma]
    mj_txt = "; ".join(
        f"trap {p.trap:g}: {p.state}, body {p.rotation_rate:+.4f}, orbit {p.orbit_rate:+.4f} rad/tau, "
        f"R {p.orbit_radius:.3g}"
        for p in mj
    )
    counts = ", ".join(f"{k} {v}" for k, v in s.states.items() if v)
    return [
        Claim(
            f"Chain in a paraboloid dish (sigma = {s.supplement_sigma:g}): goes round the centre and crawls in circles",
            f'"{PAPER.dish_words}"',
            mj_txt,
            f"by trap: {states}",
            verdict(math.isfinite(lo)),
            f"The dish as a harmonic trap -k r (its small-slope limit), N = {s.n}. At sigma = {s.supplement_sigma:g} "
            "the chain goes round the centre, its bent body crawling head first along the circle, for trap "
            f"{lo:g}-{hi:g} (of a fine scan); weaker traps hold it still far out, "
            f"pointing outward; stiffer ones curl it into a spin near the centre. "
            "A real dish z = r^2 / (4 f) gives trap = m g l sigma / (2 f F_a): with an ASSUMED 7 g bug and the paper's "
            f"F_a and pitch, the orbit band is a focal length of {s.supplement_focal_length_m[0]:.2f}-"
            f"{s.supplement_focal_length_m[1]:.2f} m, comparable to a household satellite dish (f / D ~ 0.6 at "
            "0.6-1 m across). "
            f"Phase diagram over {len(s.sigmas)} x {len(s.traps)} (sigma, trap) points: {counts}. "
            + (
                "A crawl with a body rotation different from the orbit occurs. "
                if s.crawl_found
                else "Nowhere does the body turn at a rate other than the orbit's: the steady crawl of the dish is a "
                "rigid orbit, so the supplement's two motions are one. "
            )
            + f"Engines: rates within {100 * s.engines_max_rel_diff:.2g}%, "
            + ("the same state at every check" if s.engines_same_state else "states differ at some checks"),
        )
    ]

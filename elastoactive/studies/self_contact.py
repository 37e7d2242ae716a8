"""Self-contact: the supplement's N = 17 chain and its "higher harmonics ... due to self-contact".

long_chain_study:
- N = 17 pinned at one end, a sigma sweep (the supplement's 0.8 among them), with and without self-contact
  (MuJoCo): does the chain pass through itself without contact (non-adjacent links crossing), and what does
  contact do to the spectrum of Theta and of a mid-chain angle (harmonics 1-5 relative to the fundamental)?
- the engines side by side where contact happens: the reduced model's steep penalty against MuJoCo's
  near-hard contact (N = 17, the sweep's sigmas);
- the contact's convergence: overlap and results as dt and the mass ratio shrink (MuJoCo);
- winding: N = 7 at sigma = 50 winds many turns through itself without contact; what contact makes of it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..analysis import observables as obs
from ..analysis import spectrum
from ..analysis.reduced.contact import capsule_clearance, contact_pairs, link_distance
from ..batch import Case
from ..paper import PAPER
from ..params import Numerics
from ..results import HARMONICS, measure
from ..scenes import one_pinned
from .base import Study, Summary, pick, run

__all__ = ["ContactRun", "ConvergenceRow", "LongChainSummary", "link_crossings", "long_chain_study"]

LONG_N = PAPER.long_chain_n
"""The supplement's long chain (17)."""
LONG_SIGMA = PAPER.long_chain_sigma
"""The supplement's sigma for it (0.8)."""
MID = LONG_N // 2
"""Index of the mid-chain angle whose spectrum is reported (theta_9 of 17)."""
WIND_N, WIND_SIGMA = 7, 50.0
"""The chain that winds through itself without contact."""
CROSSING = 1e-9
"""l: non-adjacent links closer than this intersect (the chain passes through itself)."""


def link_crossings(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per sample of a chain theta (T, N) pinned at the origin: the smallest distance between non-adjacent links
    (whole links, particle to particle) and the smallest distance between non-adjacent particles (|i - j| >= 2)."""
    theta = np.atleast_2d(np.asarray(theta, dtype=float))
    links = link_distance(theta)
    ends = np.cumsum(np.stack([np.cos(theta), np.sin(theta)], axis=-1), axis=1)
    particles = np.full(theta.shape[0], np.inf)
    for i, j in contact_pairs(theta.shape[1]):
        gap = ends[:, i] - ends[:, j]
        particles = np.minimum(particles, np.hypot(gap[:, 0], gap[:, 1]))
    return links, particles


@dataclass(frozen=True)
class ContactRun(Summary):
    """One run of the long chain (or the winding chain)."""

    n: int
    sigma: float
    contact: bool
    engine: str
    duration: float
    amplitude: float
    frequency: float
    """f tau of Theta (NaN when not measured)."""
    periodic: bool
    harmonics: tuple[float, ...]
    """Harmonics 1-5 of Theta relative to the fundamental (NaN without a periodic beat)."""
    harmonics_mid: tuple[float, ...]
    """The same for the mid-chain angle theta_{MID+1}."""
    crossing_fraction: float
    """Share of the measured samples in which non-adjacent links intersect (passing through itself)."""
    min_link_distance: float
    min_particle_distance: float
    """Smallest distance between non-adjacent particles over the measured window, in l."""
    contact_fraction: float
    """Share of the measured samples with overlapping capsules (NaN without contact)."""
    min_clearance: float
    """Smallest capsule clearance (negative: overlap depth), in l."""
    theta_span: float
    """max - min of Theta over the whole run (winding: 2 pi per turn)."""
    wall_s: float


@dataclass(frozen=True)
class ConvergenceRow(Summary):
    """The contact's convergence (MuJoCo): N = 17, sigma = 0.8, one dt and mass ratio."""

    dt: float
    mass_ratio: float
    overlap: float
    """Deepest capsule overlap over the measured window, in l."""
    amplitude: float
    frequency: float
    harmonic_3: float
    contact_fraction: float
    wall_s: float


@dataclass(frozen=True)
class LongChainSummary(Summary):
    n: int
    sigma: float
    runs: list[ContactRun]
    convergence: list[ConvergenceRow]
    winding: list[ContactRun]
    passes_through: bool
    """Whether the N = 17, sigma = 0.8 chain without contact passes through itself (links cross)."""
    odd_harmonics_raised: bool
    """Whether contact raises Theta's 3rd and 5th harmonics at N = 17, sigma = 0.8 (MuJoCo)."""
    contact_onset_sigma: float
    """Smallest sigma of the sweep at which the chain without contact passes through itself (NaN: none)."""
    engines_max_rel_diff: float
    """Largest |MuJoCo / reduced - 1| of amplitude and frequency with contact, over the compared sigmas."""


def _run(tr, transient: float) -> ContactRun:
    r = measure(tr, transient)
    p = tr.physics
    steady = tr.t - tr.t[0] >= transient
    links, particles = link_crossings(tr.theta[steady])
    if p.contact:  # results.measure has them, over the same window
        fraction, clearance = r.contact_fraction, r.min_clearance
    else:  # how deep the capsules would overlap without contact (-2R: the chain passes through itself)
        fraction, clearance = math.nan, float(capsule_clearance(tr.theta[steady], p.contact_radius).min())
    big = obs.curvature(tr.theta)
    mid = spectrum.harmonics(tr.t, tr.theta[:, min(MID, p.n - 1)], transient, HARMONICS)
    return ContactRun(
        p.n, p.sigma, p.contact, tr.engine, float(tr.t[-1]), float(r.amplitude),
        math.nan if r.frequency is None else float(r.frequency), bool(r.periodic), tuple(float(h) for h in r.harmonics),
        tuple(float(h) for h in mid), float(np.mean(links < CROSSING)), float(links.min()), float(particles.min()),
        fraction, clearance,
        float(big.max() - big.min()), float(tr.wall_time_s))


def long_chain_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """N = 17 with and without contact over sigma (MuJoCo; the reduced model with contact alongside), the contact's
    convergence in dt and mass ratio, and the N = 7 chain at sigma = 50 that winds through itself."""
    start = time.perf_counter()
    sigmas = pick(size, (LONG_SIGMA,), (0.2, 0.4, 0.6, 0.8, 1.2, 2.0), (0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0, 1.2, 1.6, 2.0, 3.0))
    duration = pick(size, 150.0, 600.0, 1200.0)
    compared = pick(size, (), (0.4, 0.8), (0.4, 0.6, 0.8, 1.2))
    steps = pick(size, ((0.0025, 1e-4), (0.00125, 1e-4)),
                 tuple((dt, m) for dt in (0.0025, 0.00125, 0.000625) for m in (1e-4, 1e-5)),
                 tuple((dt, m) for dt in (0.0025, 0.00125, 0.000625, 0.0003125) for m in (1e-4, 1e-5, 1e-6)))
    conv_duration = pick(size, 100.0, 300.0, 600.0)
    wind_duration = pick(size, 40.0, 100.0, 200.0)
    scene = one_pinned.SCENE
    cases, meta = [], []
    for s in sigmas:
        for contact in (False, True):
            cases.append(Case(scene.physics(n=LONG_N, sigma=s, contact=contact), Numerics(), duration, "mujoco"))
            meta.append(("sweep", contact, duration))
    for s in compared:
        cases.append(Case(scene.physics(n=LONG_N, sigma=s, contact=True), Numerics(), duration, "reduced"))
        meta.append(("sweep", True, duration))
    for dt, m in steps:
        cases.append(Case(scene.physics(n=LONG_N, sigma=LONG_SIGMA, contact=True), Numerics(dt=dt, mass_ratio=m),
                          conv_duration, "mujoco"))
        meta.append(("convergence", True, conv_duration))
    for contact in (False, True):
        for engine in ("mujoco",) + (("reduced",) if contact else ()):
            cases.append(Case(scene.physics(n=WIND_N, sigma=WIND_SIGMA, contact=contact), Numerics(), wind_duration,
                              engine))
            meta.append(("winding", contact, wind_duration))
    trajs = run(cases, workers, progress, "long chain, self-contact")
    runs, winding, conv = [], [], []
    data: dict = {}
    for (kind, contact, dur), case, tr in zip(meta, cases, trajs):
        item = _run(tr, dur / 2)
        if kind == "sweep":
            runs.append(item)
        elif kind == "winding":
            winding.append(item)
        else:
            conv.append(ConvergenceRow(case.numerics.dt, case.numerics.mass_ratio, -item.min_clearance, item.amplitude,
                                       item.frequency, item.harmonics[2], item.contact_fraction, item.wall_s))
        if kind == "sweep" and case.physics.sigma == LONG_SIGMA and case.engine == "mujoco":
            key = "contact" if contact else "free"
            keep = tr.t >= tr.t[-1] - 4.0 / max(item.frequency, 1e-3) if math.isfinite(item.frequency) else tr.t >= 0
            data[f"t_{key}"] = tr.t[keep]
            data[f"Theta_{key}"] = obs.curvature(tr.theta)[keep]
            data[f"mid_{key}"] = tr.theta[keep, MID]
            data[f"shape_{key}"] = tr.theta[-1]
    mj = {(r.sigma, r.contact): r for r in runs if r.engine == "mujoco"}
    for key in ("amplitude", "frequency", "crossing_fraction", "contact_fraction"):
        for contact in (False, True):
            data[f"{key}_{'contact' if contact else 'free'}"] = np.array([getattr(mj[s, contact], key) for s in sigmas])
    for contact in (False, True):
        data[f"harmonics_{'contact' if contact else 'free'}"] = np.array([mj[s, contact].harmonics for s in sigmas])
        data[f"harmonics_mid_{'contact' if contact else 'free'}"] = np.array([mj[s, contact].harmonics_mid for s in sigmas])
    data["sigma"] = np.array(sigmas)
    free, touch = mj[LONG_SIGMA, False], mj[LONG_SIGMA, True]
    diffs = []
    for r in runs:
        if r.engine == "reduced":
            m = mj[r.sigma, True]
            diffs += [abs(m.amplitude / r.amplitude - 1), abs(m.frequency / r.frequency - 1)]
    onset = [s for s in sigmas if mj[s, False].crossing_fraction > 0]
    summary = LongChainSummary(
        LONG_N, LONG_SIGMA, runs, conv, winding, passes_through=free.crossing_fraction > 0,
        odd_harmonics_raised=bool(touch.harmonics[2] > free.harmonics[2] and touch.harmonics[4] > free.harmonics[4]),
        contact_onset_sigma=float(min(onset)) if onset else math.nan,
        engines_max_rel_diff=float(np.nanmax(diffs)) if diffs else math.nan)
    return Study("long_chain", size, data, summary, time.perf_counter() - start)

"""Self-snapping, both ends pinned (Fig. 4c-d; the supplement's map for N = 9).

Snap amplitude (std of theta_3) and frequency against the compression delta for N = 7 at the
paper's two sigma (0.6, 0.8), both engines; the (delta, sigma) map for N = 9 (MuJoCo; full: both);
the sigma below which a compressed N = 9 chain stays buckled, by bisection.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..analysis import fits
from ..analysis import observables as obs
from ..batch import Case
from ..paper import PAPER
from ..scenes import two_pinned
from .base import ENGINES, EngineParts, Study, Summary, fast, pick, run, safe

SNAP_THRESHOLD = 0.02
"""rad: a std of theta_3 above this is self-snapping (the static arch has ~0)."""


@dataclass(frozen=True)
class SnapSeries(Summary):
    """The N = 7 chain at one sigma against delta."""

    sigma: float
    snap_at_delta0: float | None
    snap_monotonic_in_delta: bool
    snap_min_positive_delta: float
    snap_max_delta: float
    freq_min_positive_delta: float
    freq_max_delta: float
    delta_min: float
    """Smallest positive delta of the grid."""
    delta_max: float
    snap_exponent: float
    """std theta_3 ~ delta^exponent over delta > 0 (nan if the fit fails)."""


@dataclass(frozen=True)
class SnapMap(Summary):
    """The N = 9 map over (delta, sigma)."""

    sigmas_snapping_at_all_delta_gt0: list[float]
    sigmas_never_snapping: list[float]
    delta0_max_snap: float | None


@dataclass(frozen=True)
class SnappingEngine(Summary):
    sigma_snap_n9: float
    """Smallest sigma that snaps (N = 9, delta = threshold_delta): middle of the bisection bracket."""
    sigma_snap_n9_halfwidth: float
    n7: tuple[SnapSeries, ...]
    """One series per sigma of SnappingSummary.n7_sigmas."""
    map: SnapMap | None = None
    """None where this engine did not run the map."""


@dataclass(frozen=True)
class SnappingSummary(EngineParts):
    snap_threshold_rad: float
    threshold_delta: float
    n7_sigmas: tuple[float, ...]
    mujoco: SnappingEngine
    reduced: SnappingEngine


def _snap_measures(tr, transient):
    x = tr.theta[:, 2]
    snap = obs.snap_amplitude(tr.theta, tr.t, transient)
    freq = obs.frequency(tr.t, x, transient) if snap > SNAP_THRESHOLD else np.nan
    return snap, freq


def snapping_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Snapping against delta (N = 7), the N = 9 map and the N = 9 snapping threshold in sigma."""
    start = time.perf_counter()
    sigmas7 = PAPER.snapping_sigmas
    deltas = pick(size, (0.0, 0.1, 0.3), (0.0, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3),
                  tuple(np.round(np.r_[0.0, 0.005, 0.01, 0.02, np.arange(0.03, 0.401, 0.025)], 4)))
    dur7 = pick(size, 300.0, 800.0, 2000.0)
    cases, meta = [], []
    for s in sigmas7:
        for d in deltas:
            for eng in ENGINES:
                cases.append(Case(two_pinned.SCENE.physics(n=7, sigma=s, delta=d), fast(perturbation=0.05, sample_dt=0.1),
                                  dur7, eng, dur7 / 2))
                meta.append(("n7", s, d, eng))
    n9 = PAPER.snapping_map_n
    map_sig = pick(size, (0.1, 0.3, 0.8), (0.1, 0.15, 0.2, 0.3, 0.5, 0.8),
                   tuple(np.round(np.r_[0.05, 0.1, 0.125, 0.15, 0.16, 0.17, 0.18, 0.19, 0.2, 0.25, 0.3, 0.4, 0.5, 0.65, 0.8, 1.0], 4)))
    map_del = pick(size, (0.0, 0.1, 0.3), (0.0, 0.05, 0.1, 0.2, 0.3), tuple(np.round(np.arange(0.0, 0.401, 0.04), 4)))
    map_engines = pick(size, ("mujoco",), ("mujoco",), ENGINES)
    dur9 = pick(size, 300.0, 1000.0, 3000.0)
    for s in map_sig:
        for d in map_del:
            for eng in map_engines:
                cases.append(Case(two_pinned.SCENE.physics(n=n9, sigma=s, delta=d), fast(perturbation=0.05, sample_dt=0.1),
                                  dur9, eng, dur9 / 2))
                meta.append(("n9", s, d, eng))
    trajs = run(cases, workers, progress, "self-snapping")
    data = {"delta": np.array(deltas), "map_sigma": np.array(map_sig), "map_delta": np.array(map_del)}
    n7 = {}
    maps = {eng: np.full((len(map_sig), len(map_del)), np.nan) for eng in map_engines}
    mapf = {eng: np.full((len(map_sig), len(map_del)), np.nan) for eng in map_engines}
    example = None
    example_sigma, example_delta = PAPER.snapping_sigma, 0.1
    for (kind, s, d, eng), tr in zip(meta, trajs):
        snap, freq = _snap_measures(tr, tr.t[-1] / 2)
        if kind == "n7":
            n7[(s, d, eng)] = (snap, freq)
            if eng == "mujoco" and s == example_sigma and abs(d - example_delta) < 1e-9:
                example = tr
        else:
            i, j = map_sig.index(s), map_del.index(d)
            maps[eng][i, j], mapf[eng][i, j] = snap, freq
    for s in sigmas7:
        for eng in ENGINES:
            data[f"snap_{s:g}_{eng}"] = np.array([n7[(s, d, eng)][0] for d in deltas])
            data[f"freq_{s:g}_{eng}"] = np.array([n7[(s, d, eng)][1] for d in deltas])
    for eng in map_engines:
        data[f"map_snap_{eng}"], data[f"map_freq_{eng}"] = maps[eng], mapf[eng]
    if example is not None:  # one snapping period of the N = 7 chain at sigma = 0.8, delta = 0.1
        f = n7[(example_sigma, example_delta, "mujoco")][1]
        m = example.t >= example.t[-1] - (1.0 / f if np.isfinite(f) and f > 0 else 50.0)
        data["example_t"], data["example_theta"] = example.t[m], example.theta[m]

    # the smallest sigma that snaps, N = 9, delta = 0.1 (bisection, both engines side by side)
    steps = pick(size, 2, 5, 9)
    d_thr = 0.1
    lo = {eng: 0.1 for eng in ENGINES}
    hi = {eng: 0.3 for eng in ENGINES}
    dur_thr = pick(size, 400.0, 2000.0, 6000.0)
    for _ in range(steps):
        cs = [Case(two_pinned.SCENE.physics(n=n9, sigma=0.5 * (lo[e] + hi[e]), delta=d_thr),
                   fast(perturbation=0.05, sample_dt=0.1), dur_thr, e, dur_thr / 2) for e in ENGINES]
        for e, tr in zip(ENGINES, run(cs, workers, False, "snap threshold")):
            mid = 0.5 * (lo[e] + hi[e])
            if _snap_measures(tr, dur_thr / 2)[0] > SNAP_THRESHOLD:
                hi[e] = mid
            else:
                lo[e] = mid

    parts = {}
    d = np.array(deltas)
    pos = d > 0
    for eng in ENGINES:
        series = []
        for s in sigmas7:
            snap = data[f"snap_{s:g}_{eng}"]
            freq = data[f"freq_{s:g}_{eng}"]
            series.append(SnapSeries(
                sigma=s,
                snap_at_delta0=float(snap[d == 0][0]) if np.any(d == 0) else None,
                snap_monotonic_in_delta=bool(np.all(np.diff(snap[pos]) > 0)),
                snap_min_positive_delta=float(snap[pos][0]), snap_max_delta=float(snap[pos][-1]),
                freq_min_positive_delta=float(freq[pos][0]), freq_max_delta=float(freq[pos][-1]),
                delta_min=float(d[pos][0]), delta_max=float(d[pos][-1]),
                snap_exponent=safe(lambda: fits.power_law_fit(d[pos], snap[pos])["exponent"]),  # noqa: B023
            ))
        snap_map = None
        if eng in map_engines:
            m = maps[eng]
            snaps = m > SNAP_THRESHOLD
            snap_map = SnapMap(
                sigmas_snapping_at_all_delta_gt0=[float(s) for s, row in zip(map_sig, snaps) if row[np.array(map_del) > 0].all()],
                sigmas_never_snapping=[float(s) for s, row in zip(map_sig, snaps) if not row.any()],
                delta0_max_snap=float(np.nanmax(m[:, np.array(map_del) == 0])) if 0.0 in map_del else None)
        parts[eng] = SnappingEngine(sigma_snap_n9=0.5 * (lo[eng] + hi[eng]), sigma_snap_n9_halfwidth=0.5 * (hi[eng] - lo[eng]),
                                    n7=tuple(series), map=snap_map)
    summary = SnappingSummary(snap_threshold_rad=SNAP_THRESHOLD, threshold_delta=d_thr, n7_sigmas=tuple(sigmas7), **parts)
    return Study("snapping", size, data, summary, time.perf_counter() - start)

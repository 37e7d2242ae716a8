"""Noise and anisotropic drag, N = 2 at sigma = 3.5 (supplement).

noise_study: limit cycles (Omega, Theta) with multiplicative white noise of amplitude a on the
active force (the same seeded noise in both engines); period and amplitude variability as measures
of irregularity.
anisotropy_study: limit cycles, amplitude and frequency against tau_L / tau_T (both engines), and
the onset: growth rates of a small kick at sigma = 3 -/+ 0.2 for each ratio (linear theory: -/+ 0.2
whatever the ratio), interpolated to the onset sigma.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..analysis import fits
from ..analysis import measures as ms
from ..analysis import observables as obs
from ..analysis import stability as stab
from ..batch import Case
from ..paper import PAPER
from ..params import Numerics
from ..scenes import one_pinned
from .base import ENGINES, EngineParts, Study, Summary, fast, pick, run, safe
from .inertia import experiment_scales

PROBE_SIGMAS = (2.8, 3.2)
"""The growth-rate probes of the anisotropy study: the N = 2 onset sigma = 3 -/+ 0.2."""
PROBE_SPAN = 0.4
"""PROBE_SIGMAS[1] - PROBE_SIGMAS[0], written exactly."""


@dataclass(frozen=True)
class NoiseEngine(Summary):
    period_cv: dict[str, float]
    """std/mean of the cycle periods by noise amplitude a (formatted :g); nan where not sustained."""
    amplitude: dict[str, float]
    not_sustained: list[str]
    """The a (formatted :g) without a sustained oscillation."""
    amplitude_cv: dict[str, float]
    irregularity_increases: bool | None
    """Whether the period CV grows with a (None with fewer than two sustained a)."""


@dataclass(frozen=True)
class NoiseSummary(EngineParts):
    sigma: float
    seed: int
    mujoco: NoiseEngine
    reduced: NoiseEngine


@dataclass(frozen=True)
class AnisotropyEngine(Summary):
    amplitude: dict[str, float]
    """Amplitude of Theta by tau_L / tau_T (formatted :g)."""
    amplitude_decreasing: bool
    onset: dict[str, float]
    """Onset sigma (probe growth rates interpolated to 0) by tau_L / tau_T."""
    onset_max_dev: float
    """Largest |onset - 3|."""


@dataclass(frozen=True)
class AnisotropySummary(EngineParts):
    sigma: float
    probe_sigmas: tuple[float, float]
    linear_rate_at_upper_probe: float
    """Re lambda at probe_sigmas[1] (linear theory, any ratio)."""
    mujoco: AnisotropyEngine
    reduced: AnisotropyEngine


def noise_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Limit cycles and their irregularity with multiplicative noise, N = 2, sigma = 3.5."""
    start = time.perf_counter()
    amps = pick(size, (0.0, 0.1), (0.0, 0.05, 0.1, 0.2, 0.3), (0.0, 0.02, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4))
    dur = pick(size, 150.0, 600.0, 2000.0)
    transient = 50.0
    seed = 1
    cases, meta = [], []
    for a in amps:
        for eng in ENGINES:
            cases.append(Case(one_pinned.SCENE.physics(n=2, sigma=PAPER.noise_sigma, noise=a),
                              fast(perturbation=0.5, sample_dt=0.05, seed=seed), dur, eng, transient))
            meta.append((a, eng))
    trajs = run(cases, workers, progress, "noise N=2")
    data = {"noise": np.array(amps)}
    out = {}
    for (a, eng), tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)
        amp = obs.amplitude(tr.t, x, transient)
        osc = obs.is_oscillating(tr.t, x, threshold=1e-2, transient=transient)
        out[(a, eng)] = (amp, safe(ms.period_variability, tr.t, x, transient) if osc else np.nan,
                         safe(ms.amplitude_variability, tr.t, x, transient) if osc else np.nan, osc)
        if eng == "mujoco":
            m = tr.t >= transient
            m &= tr.t <= transient + min(150.0, dur - transient)
            om, th = obs.limit_cycle(tr.theta[m])
            data[f"cycle_{a:g}_omega"], data[f"cycle_{a:g}_theta"] = om, th
    parts = {}
    for eng in ENGINES:
        for i, key in enumerate(("amplitude", "period_cv", "amplitude_cv", "sustained")):
            data[f"{key}_{eng}"] = np.array([out[(a, eng)][i] for a in amps])
        cv = data[f"period_cv_{eng}"]
        ok = np.isfinite(cv)
        parts[eng] = NoiseEngine(
            period_cv={f"{a:g}": float(v) for a, v in zip(amps, cv)},
            amplitude={f"{a:g}": float(v) for a, v in zip(amps, data[f"amplitude_{eng}"])},
            not_sustained=[f"{a:g}" for a, v in zip(amps, data[f"sustained_{eng}"]) if not v],
            amplitude_cv={f"{a:g}": float(v) for a, v in zip(amps, data[f"amplitude_cv_{eng}"])},
            irregularity_increases=bool(np.all(np.diff(cv[ok]) > 0)) if ok.sum() >= 2 else None)
    summary = NoiseSummary(sigma=PAPER.noise_sigma, seed=seed, **parts)
    return Study("noise", size, data, summary, time.perf_counter() - start)


def anisotropy_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """N = 2, sigma = 3.5: limit cycles, amplitude and frequency against tau_L / tau_T (both engines),
    and the onset from growth rates at sigma = 3 -/+ 0.2 for each ratio."""
    start = time.perf_counter()
    ratios = pick(size, (1.0, 4.0), (0.5, 1.0, 2.0, 4.0, 8.0), (0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0))
    dur = pick(size, 150.0, 400.0, 1000.0)
    transient = dur / 2
    s_lo, s_hi = PROBE_SIGMAS
    cases, meta = [], []
    for r in ratios:
        for eng in ENGINES:
            cases.append(Case(one_pinned.SCENE.physics(n=2, sigma=PAPER.anisotropy_sigma, drag_ratio=r),
                              fast(perturbation=0.5, sample_dt=0.05), dur, eng, transient))
            meta.append(("cycle", r, 0.0, eng))
            for s in PROBE_SIGMAS:
                cases.append(Case(one_pinned.SCENE.physics(n=2, sigma=s, drag_ratio=r),
                                  Numerics.preset("accurate", perturbation=1e-5, sample_dt=0.05), 25.0, eng, 0.0))
                meta.append(("growth", r, s, eng))
    trajs = run(cases, workers, progress, "anisotropic drag N=2")
    data = {"ratio": np.array(ratios)}
    out = {}
    for (kind, r, s, eng), tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)
        if kind == "cycle":
            out[("amp", r, eng)] = obs.amplitude(tr.t, x, transient)
            out[("freq", r, eng)] = obs.frequency(tr.t, x, transient)
            if eng == "mujoco":
                m = tr.t >= transient
                om, th = obs.limit_cycle(tr.theta[m])
                data[f"cycle_{r:g}_omega"], data[f"cycle_{r:g}_theta"] = om, th
        else:
            out[("rate", r, s, eng)] = fits.exp_oscillation_fit(tr.t, x)["rate"]
    parts = {}
    for eng in ENGINES:
        amp = np.array([out[("amp", r, eng)] for r in ratios])
        data[f"amplitude_{eng}"] = amp
        data[f"frequency_{eng}"] = np.array([out[("freq", r, eng)] for r in ratios])
        g_lo = np.array([out[("rate", r, s_lo, eng)] for r in ratios])
        g_hi = np.array([out[("rate", r, s_hi, eng)] for r in ratios])
        onset = s_lo + PROBE_SPAN * g_lo / (g_lo - g_hi)
        data[f"rate_{s_lo:g}_{eng}"], data[f"rate_{s_hi:g}_{eng}"], data[f"onset_{eng}"] = g_lo, g_hi, onset
        parts[eng] = AnisotropyEngine(
            amplitude={f"{r:g}": float(a) for r, a in zip(ratios, amp)},
            amplitude_decreasing=bool(np.all(np.diff(amp) < 0)),
            onset={f"{r:g}": float(o) for r, o in zip(ratios, onset)},
            onset_max_dev=float(np.max(np.abs(onset - PAPER.sigma_c_2))))
    summary = AnisotropySummary(sigma=PAPER.anisotropy_sigma, probe_sigmas=PROBE_SIGMAS,
                                linear_rate_at_upper_probe=float(stab.eigenvalues(2, s_hi)[0].real), **parts)
    return Study("anisotropy", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# claim 21 under each reading of the noise
# --------------------------------------------------------------------------------------------------
HEXBUG_NOISE_CORRELATION_S = (0.02, 0.05)
"""ASSUMPTION (not in the paper): the correlation time of a Hexbug's force, tens of ms (its vibration-driven
gait: the paper says only that the force 'fluctuated rapidly')."""


@dataclass(frozen=True)
class NoiseReading(Summary):
    reading: str
    """"ito", "stratonovich" (white) or "tau_c=<x>" (Ornstein-Uhlenbeck of that correlation time)."""
    noise_correlation: float
    calculus: str
    mujoco: NoiseEngine | None
    """None for white Stratonovich noise (MuJoCo reaches it only as tau_c -> 0)."""
    reduced: NoiseEngine
    survives: bool
    """Whether every engine run sustains the beat at every a."""


@dataclass(frozen=True)
class ExperimentNoise(Summary):
    relative_spread: float
    """std / mean of the measured force (paper: 3.1 / 15.7)."""
    correlation_s: tuple[float, ...]
    """Assumed correlation times (s)."""
    tau_s: tuple[float, float]
    """The experiment's tau range (s), from inertia.experiment_scales."""
    tau_c: tuple[float, float]
    """Smallest and largest correlation time in units of tau."""
    amplitude: tuple[float, float]
    """Equivalent white-noise amplitude a = spread sqrt(2 tau_c) (OU variance a^2 / (2 tau_c) = spread^2)."""


@dataclass(frozen=True)
class NoiseReadingsSummary(Summary):
    sigma: float
    n: int
    seed: int
    amplitudes: tuple[float, ...]
    readings: list[NoiseReading]
    experiment: ExperimentNoise


def experiment_noise() -> ExperimentNoise:
    """The experiment's noise regime: relative spread (paper) and an assumed correlation time in units of tau."""
    taus = experiment_scales().tau_s
    t_lo, t_hi = min(taus), max(taus)
    tc = (min(HEXBUG_NOISE_CORRELATION_S) / t_hi, max(HEXBUG_NOISE_CORRELATION_S) / t_lo)
    s = PAPER.force_relative_spread
    return ExperimentNoise(s, HEXBUG_NOISE_CORRELATION_S, (t_lo, t_hi), tc,
                           (s * float(np.sqrt(2 * tc[0])), s * float(np.sqrt(2 * tc[1]))))


def _reading_engine(amps, rows) -> NoiseEngine:
    cv = np.array([r[1] for r in rows])
    ok = np.isfinite(cv)
    return NoiseEngine(
        period_cv={f"{a:g}": float(v) for a, v in zip(amps, cv)},
        amplitude={f"{a:g}": float(r[0]) for a, r in zip(amps, rows)},
        not_sustained=[f"{a:g}" for a, r in zip(amps, rows) if not r[3]],
        amplitude_cv={f"{a:g}": float(r[2]) for a, r in zip(amps, rows)},
        irregularity_increases=bool(np.all(np.diff(cv[ok]) > 0)) if ok.sum() >= 2 else None)


def noise_readings_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """The noise study's case (N = 2, sigma = 3.5) under Ito and Stratonovich white noise and coloured noise."""
    start = time.perf_counter()
    amps = pick(size, (0.0, 0.3), (0.0, 0.1, 0.2, 0.3), (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3))
    tcs = pick(size, (0.2,), (0.05, 0.2, 1.0), (0.02, 0.05, 0.1, 0.2, 0.5, 1.0))
    dur = pick(size, 150.0, 600.0, 2000.0)
    transient = 50.0
    seed = 1
    readings = [("ito", 0.0, "ito", ENGINES), ("stratonovich", 0.0, "stratonovich", ("reduced",))]
    readings += [(f"tau_c={tc:g}", tc, "ito", ENGINES) for tc in tcs]
    cases, meta = [], []
    for name, tc, calc, engines in readings:
        for a in amps:
            for eng in engines:
                phys = one_pinned.SCENE.physics(n=2, sigma=PAPER.noise_sigma, noise=a,
                                                noise_correlation=tc if a > 0 else 0.0, noise_calculus=calc)
                cases.append(Case(phys, fast(perturbation=0.5, sample_dt=0.05, seed=seed), dur, eng, transient))
                meta.append((name, a, eng))
    trajs = run(cases, workers, progress, "noise readings N=2")
    out = {}
    for key, tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)
        osc = obs.is_oscillating(tr.t, x, threshold=1e-2, transient=transient)
        out[key] = (obs.amplitude(tr.t, x, transient),
                    safe(ms.period_variability, tr.t, x, transient) if osc else np.nan,
                    safe(ms.amplitude_variability, tr.t, x, transient) if osc else np.nan, bool(osc))
    data = {"noise": np.array(amps)}
    parts = []
    for name, tc, calc, engines in readings:
        eng_parts = {}
        for eng in engines:
            rows = [out[(name, a, eng)] for a in amps]
            eng_parts[eng] = _reading_engine(amps, rows)
            data[f"period_cv_{name}_{eng}"] = np.array([r[1] for r in rows])
            data[f"sustained_{name}_{eng}"] = np.array([r[3] for r in rows])
        parts.append(NoiseReading(name, tc, calc, eng_parts.get("mujoco"), eng_parts["reduced"],
                                  all(not p.not_sustained for p in eng_parts.values())))
    data["readings"] = np.array([r[0] for r in readings])
    summary = NoiseReadingsSummary(PAPER.noise_sigma, 2, seed, tuple(amps), parts, experiment_noise())
    return Study("noise_readings", size, data, summary, time.perf_counter() - start)

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
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import fits
from ..analysis import measures as ms
from ..analysis import observables as obs
from ..analysis import stability as stab
from ..batch import Case
from ..core.params import Numerics
from ..scenes import one_pinned
from . import plotting as plots
from . import registry
from .base import ENGINES, EngineParts, Study, Summary, fast, pick, run, safe
from .claim_rows import Claim, fmt, verdict
from .inertia import experiment_scales
from .paper import PAPER

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


NOISE = registry.declare("noise", summary=NoiseSummary, order=100, reads=("anisotropy",), budget=1.5)


@NOISE.run
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
            cases.append(
                Case(
                    one_pinned.SCENE.physics(n=2, sigma=PAPER.noise_sigma, noise=a),
                    fast(perturbation=0.5, sample_dt=0.05, seed=seed),
                    dur,
                    eng,
                    transient,
                )
            )
            meta.append((a, eng))
    trajs = run(cases, workers, progress, "noise N=2")
    data = {"noise": np.array(amps)}
    out = {}
    for (a, eng), tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)
        amp = obs.amplitude(tr.t, x, transient)
        osc = obs.is_oscillating(tr.t, x, threshold=1e-2, transient=transient)
        out[(a, eng)] = (
            amp,
            safe(ms.period_variability, tr.t, x, transient) if osc else np.nan,
            safe(ms.amplitude_variability, tr.t, x, transient) if osc else np.nan,
            osc,
        )
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
            irregularity_increases=bool(np.all(np.diff(cv[ok]) > 0)) if ok.sum() >= 2 else None,
        )
    summary = NoiseSummary(sigma=PAPER.noise_sigma, seed=seed, **parts)
    return Study("noise", size, data, summary, time.perf_counter() - start)


ANISOTROPY = registry.declare("anisotropy", summary=AnisotropySummary, order=110, budget=1.5)


@ANISOTROPY.run
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
            cases.append(
                Case(
                    one_pinned.SCENE.physics(n=2, sigma=PAPER.anisotropy_sigma, drag_ratio=r),
                    fast(perturbation=0.5, sample_dt=0.05),
                    dur,
                    eng,
                    transient,
                )
            )
            meta.append(("cycle", r, 0.0, eng))
            for s in PROBE_SIGMAS:
                cases.append(
                    Case(
                        one_pinned.SCENE.physics(n=2, sigma=s, drag_ratio=r),
                        Numerics.preset("accurate", perturbation=1e-5, sample_dt=0.05),
                        25.0,
                        eng,
                        0.0,
                    )
                )
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
            onset_max_dev=float(np.max(np.abs(onset - PAPER.sigma_c_2))),
        )
    summary = AnisotropySummary(
        sigma=PAPER.anisotropy_sigma,
        probe_sigmas=PROBE_SIGMAS,
        linear_rate_at_upper_probe=float(stab.eigenvalues(2, s_hi)[0].real),
        **parts,
    )
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
    return ExperimentNoise(
        s, HEXBUG_NOISE_CORRELATION_S, (t_lo, t_hi), tc, (s * float(np.sqrt(2 * tc[0])), s * float(np.sqrt(2 * tc[1])))
    )


def _reading_engine(amps, rows) -> NoiseEngine:
    cv = np.array([r[1] for r in rows])
    ok = np.isfinite(cv)
    return NoiseEngine(
        period_cv={f"{a:g}": float(v) for a, v in zip(amps, cv)},
        amplitude={f"{a:g}": float(r[0]) for a, r in zip(amps, rows)},
        not_sustained=[f"{a:g}" for a, r in zip(amps, rows) if not r[3]],
        amplitude_cv={f"{a:g}": float(r[2]) for a, r in zip(amps, rows)},
        irregularity_increases=bool(np.all(np.diff(cv[ok]) > 0)) if ok.sum() >= 2 else None,
    )


NOISE_READINGS = registry.declare("noise_readings", summary=NoiseReadingsSummary, order=120, budget=4.5)


@NOISE_READINGS.run
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
                if a == 0 and (None, 0.0, eng) in meta:  # a = 0: no noise to read; one run per engine serves all
                    continue
                reading = {"noise_correlation": tc, "noise_calculus": calc} if a > 0 else {}
                phys = one_pinned.SCENE.physics(n=2, sigma=PAPER.noise_sigma, noise=a, **reading)
                cases.append(Case(phys, fast(perturbation=0.5, sample_dt=0.05, seed=seed), dur, eng, transient))
                meta.append((name if a > 0 else None, a, eng))
    trajs = run(cases, workers, progress, "noise readings N=2")
    out = {}
    for key, tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)
        osc = obs.is_oscillating(tr.t, x, threshold=1e-2, transient=transient)
        out[key] = (
            obs.amplitude(tr.t, x, transient),
            safe(ms.period_variability, tr.t, x, transient) if osc else np.nan,
            safe(ms.amplitude_variability, tr.t, x, transient) if osc else np.nan,
            bool(osc),
        )
    data = {"noise": np.array(amps)}
    parts = []
    for name, tc, calc, engines in readings:
        eng_parts = {}
        for eng in engines:
            rows = [out[(name if a > 0 else None, a, eng)] for a in amps]
            eng_parts[eng] = _reading_engine(amps, rows)
            data[f"period_cv_{name}_{eng}"] = np.array([r[1] for r in rows])
            data[f"sustained_{name}_{eng}"] = np.array([r[3] for r in rows])
        parts.append(
            NoiseReading(
                name,
                tc,
                calc,
                eng_parts.get("mujoco"),
                eng_parts["reduced"],
                all(not p.not_sustained for p in eng_parts.values()),
            )
        )
    data["readings"] = np.array([r[0] for r in readings])
    summary = NoiseReadingsSummary(PAPER.noise_sigma, 2, seed, tuple(amps), parts, experiment_noise())
    return Study("noise_readings", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# figures
# --------------------------------------------------------------------------------------------------
@NOISE.figure
@plots.styled
def noise_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d = study.data
    amps = list(d["noise"])
    ncol = 3 if len(amps) + 1 <= 6 else 4
    nrow = int(np.ceil((len(amps) + 1) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.2 * ncol, 3.0 * nrow + 0.4), squeeze=False)
    flat = axes.ravel()
    portraits = flat[: len(amps)]
    for ax in portraits[1:]:
        ax.sharex(portraits[0])
        ax.sharey(portraits[0])
    sus = d.get("sustained_mujoco")
    for i, (ax, a) in enumerate(zip(portraits, amps)):
        ax.plot(d[f"cycle_{a:g}_omega"], d[f"cycle_{a:g}_theta"], lw=0.6)
        cv = d["period_cv_mujoco"][i]
        if sus is not None and not bool(sus[i]):
            note = "beat not sustained"
        elif np.isfinite(cv):
            note = f"period CV {cv:.3f}"
        else:
            note = "no beat"
        ax.set_title(f"a = {a:g}: {note}")
        if i + ncol >= len(amps):  # no limit cycle below this one: label the x axis here
            ax.set_xlabel(plots.OMEGA_DEF + " (rad)")
        else:
            ax.tick_params(labelbottom=False)
        if i % ncol == 0:
            ax.set_ylabel(r"$\Theta=\theta_2-\theta_1$ (rad)")
        else:
            ax.tick_params(labelleft=False)
    extra = flat[len(amps)]
    for eng in plots.engines(d, "period_cv"):
        cv = d[f"period_cv_{eng}"]
        ok = np.isfinite(cv)
        extra.plot(np.asarray(amps)[ok], cv[ok], **plots.ENGINE_STYLE[eng])
    bad = ~np.isfinite(d["period_cv_mujoco"])
    if bad.any():
        for a in np.asarray(amps)[bad]:
            extra.axvline(a, color="0.6", ls=":", lw=1)
        extra.plot([], [], ":", color="0.6", label="no sustained beat")
    extra.set_xlabel("noise amplitude a")
    extra.set_ylabel("period CV (std / mean)")
    extra.set_title("irregularity of the period")
    extra.set_xlim(-0.05 * max(amps), 1.08 * max(amps))
    top = np.nanmax([np.nanmax(np.r_[d[f"period_cv_{e}"], 0.0]) for e in plots.engines(d, "period_cv")] + [1e-3])
    extra.set_ylim(-0.05 * top, 1.6 * top)  # room for the legend above the points
    extra.legend(loc="upper left")
    for ax in flat[len(amps) + 1 :]:
        ax.set_visible(False)
    fig.suptitle(
        rf"Fig. A-noise: N = 2, $\sigma$ = {study.summary.sigma:g}, active force $F_a(1+\eta)$ with "
        r"$\langle\eta(t)\eta(t')\rangle=a^2\delta(t-t')$"
        "\n"
        r"limit cycles over 150 $\tau$ after the transient (MuJoCo); $\Omega$: mean polarisation"
    )
    fig.tight_layout()
    return [plots.save(fig, out, "figA_noise.png")]


@ANISOTROPY.figure
@plots.styled
def anisotropy_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, axes = plt.subplots(2, 2, figsize=(9.5, 7.4))
    (a1, a2), (a3, a4) = axes
    for r in d["ratio"]:
        om, th = d[f"cycle_{r:g}_omega"], d[f"cycle_{r:g}_theta"]
        (line,) = a1.plot(om, th, lw=1.2)
        j = int(np.argmax(th))
        a1.annotate(
            f"{r:g}",
            (om[j], th[j]),
            xytext=(0, 1),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=8.5,
            color=line.get_color(),
            fontweight="bold",
        )
    a1.set_xlabel(plots.OMEGA_DEF + " (rad)")
    a1.set_ylabel(r"$\Theta=\theta_2-\theta_1$ (rad)")
    a1.set_ylim(a1.get_ylim()[0], a1.get_ylim()[1] + 0.08)
    a1.set_title(rf"limit cycles, N = 2, $\sigma$ = {s.sigma:g} (MuJoCo)" "\n" r"labels: drag ratio $\tau_L/\tau_T$")
    for eng in ("mujoco", "reduced"):
        a2.plot(d["ratio"], d[f"amplitude_{eng}"], **plots.ENGINE_STYLE[eng])
        if f"frequency_{eng}" in d:
            a3.plot(d["ratio"], d[f"frequency_{eng}"], **plots.ENGINE_STYLE[eng])
        a4.plot(d["ratio"], d[f"onset_{eng}"], **plots.ENGINE_STYLE[eng])
    for ax in (a2, a3, a4):
        ax.set_xscale("log")
        plots.log_ticks(ax, d["ratio"])
        ax.set_xlabel(r"drag ratio $\tau_L/\tau_T$ (log scale)")
    a2.set_ylabel(r"amplitude of $\Theta$ (rad)")
    a2.legend()
    a2.set_title(rf"amplitude, $\sigma$ = {s.sigma:g}")
    a3.set_ylabel(r"$f\tau$ (cycles per $\tau$)")
    a3.legend()
    a3.set_title(rf"frequency, $\sigma$ = {s.sigma:g}")
    a4.axhline(PAPER.sigma_c_2, color="k", lw=0.8, ls="--", label=f"linear stability: {PAPER.sigma_c_2:g}")
    a4.set_ylim(PAPER.sigma_c_2 - 0.1, PAPER.sigma_c_2 + 0.1)
    a4.set_ylabel(r"onset $\sigma_c$")
    a4.legend()
    a4.set_title(
        rf"onset: growth rates at $\sigma$ = {s.probe_sigmas[0]:g}, {s.probe_sigmas[1]:g}" "\n" "interpolated to 0"
    )
    fig.suptitle("Fig. A-anisotropy: N = 2 with drag anisotropy (longitudinal / transverse drag)")
    fig.tight_layout()
    return [plots.save(fig, out, "figA_anisotropy.png")]


@NOISE_READINGS.figure
@plots.styled
def noise_readings_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    amps = np.asarray(d["noise"])
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for i, r in enumerate(s.readings):
        for eng in ("mujoco", "reduced"):
            key = f"period_cv_{r.reading}_{eng}"
            if key not in d:
                continue
            cv = np.asarray(d[key], dtype=float)
            ok = np.isfinite(cv)
            st = dict(
                marker="o" if eng == "mujoco" else "x",
                mfc="none" if eng == "mujoco" else None,
                ls="-" if eng == "mujoco" else "--",
                color=f"C{i}",
            )
            ax.plot(amps[ok], cv[ok], label=f"{r.reading} ({'MuJoCo' if eng == 'mujoco' else 'reduced'})", **st)
            for a in amps[~ok]:
                ax.plot([a], [0], marker="v", color=f"C{i}", ms=9, ls="none")
    ax.plot([], [], "v", color="0.4", label="beat dies (plotted at 0)")
    ax.set_xlabel("noise amplitude a")
    ax.set_ylabel("period CV (std / mean)")
    ax.set_title(rf"Claim 21 under each reading: N = {s.n}, $\sigma$ = {s.sigma:g}")
    ax.legend(fontsize=7.5, ncol=2)
    fig.tight_layout()
    return [plots.save(fig, out, "figA_noise_readings.png")]


# --------------------------------------------------------------------------------------------------
# claim rows
# --------------------------------------------------------------------------------------------------
@NOISE.claims
def noise_claims(no: Study, read: Mapping[str, Study]) -> list[Claim]:
    an = read.get("anisotropy")
    rows = []
    s = no.summary
    m, r = s.mujoco, s.reduced
    cv = lambda e: ", ".join(f"{k}: {fmt(v, 3)}" for k, v in e.period_cv.items())  # noqa: E731
    dead = m.not_sustained
    rows.append(
        Claim(
            "Multiplicative noise makes the limit cycle increasingly irregular",
            "increasingly irregular",
            f"period CV by a: {cv(m)}",
            cv(r),
            verdict(bool(m.irregularity_increases)),
            f"N = 2, sigma = {s.sigma:g}, a = noise amplitude (<eta eta'> = a^2 delta(t - t'), Ito), same seeded "
            "noise in both engines; CV = std/mean of the cycle periods ('-': no sustained oscillation)"
            + (
                f". At a = {', '.join(dead)} the chain mostly sits straight with noise-driven bursts: in the "
                "Ito reading multiplicative noise lowers the growth rate of small bends by ~(a sigma)^2 / 2 (scalar "
                "estimate, 0.55 at a = 0.3 against mu = 0.5), so the straight state turns stable (the Stratonovich "
                "reading has no such shift in that estimate). The paper does not say which calculus it uses"
                if dead
                else ""
            ),
        )
    )
    if an:
        a = an.summary
        am, ar = a.mujoco, a.reduced
        amp = lambda e: ", ".join(f"{k}: {v:.3f}" for k, v in e.amplitude.items())  # noqa: E731
        rows.append(
            Claim(
                "Anisotropic drag: onset unchanged",
                f"unchanged (sigma_c = {PAPER.sigma_c_2:g})",
                f"onset {min(am.onset.values()):.4f}-{max(am.onset.values()):.4f}",
                f"{min(ar.onset.values()):.4f}-{max(ar.onset.values()):.4f}",
                verdict(am.onset_max_dev < 0.01 and ar.onset_max_dev < 0.01),
                f"growth rates of a small kick at sigma = {a.probe_sigmas[0]:g} and {a.probe_sigmas[1]:g} for "
                f"each tau_L/tau_T, interpolated to 0 (linear theory: ±{a.linear_rate_at_upper_probe:.2f} "
                "whatever the ratio)",
            )
        )
        rows.append(
            Claim(
                f"Anisotropic drag: amplitude shrinks as tau_L/tau_T grows (sigma = {a.sigma:g})",
                "shrinks",
                f"amplitude of Theta by ratio: {amp(am)}",
                amp(ar),
                verdict(am.amplitude_decreasing and ar.amplitude_decreasing),
                "uses the correct drag matrix; the supplement's printed N = 2 anisotropic equations are not "
                "rotation invariant (docs/errata.md, item 4) but agree at linear order",
            )
        )
    return rows


@NOISE_READINGS.claims
def noise_readings_claims(st: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = st.summary
    amax = f"{max(s.amplitudes):g}"

    def txt(eng):
        parts = []
        for r in s.readings:
            e = getattr(r, eng)
            if e is None:
                continue
            cv = ", ".join(f"{k}: {fmt(v, 2)}" for k, v in e.period_cv.items() if k != "0")
            parts.append(f"{r.reading}: {cv}" + (" (dies)" if e.not_sustained else ""))
        return "; ".join(parts)

    dead = [r.reading for r in s.readings if not r.survives]
    grows = [
        r.reading
        for r in s.readings
        if r.survives and all(e is None or e.irregularity_increases for e in (r.mujoco, r.reduced))
    ]
    x = s.experiment
    return [
        Claim(
            "Claim 21 under Ito / Stratonovich / coloured noise: the cycle grows increasingly irregular",
            "increasingly chaotic (white noise, calculus unstated)",
            f"period CV by a: {txt('mujoco')}",
            txt("reduced"),
            verdict(not dead and len(grows) == len(s.readings), partly=bool(grows)),
            f"N = {s.n}, sigma = {s.sigma:g}, seed {s.seed}, one realisation per a. Irregularity grows with a and the "
            f"beat survives up to a = {amax} under: {', '.join(grows) or 'none'}; the beat dies under: "
            f"{', '.join(dead) or 'none'} (Ito's drift lowers the growth rate of small bends; Stratonovich and "
            "coloured noise, its physical white limit by Wong-Zakai, keep the cycle). So the claim holds in the "
            "Stratonovich / coloured readings; under Ito it holds only up to the a where the beat dies. Experiment: "
            f"force spread {x.relative_spread:.3f} (paper, 3.1/15.7); ASSUMED correlation "
            f"{1e3 * min(x.correlation_s):g}-{1e3 * max(x.correlation_s):g} ms (vibration gait) over tau = "
            f"{x.tau_s[0]:.2f}-{x.tau_s[1]:.2f} s -> tau_c = {x.tau_c[0]:.3f}-{x.tau_c[1]:.2f} tau << 1: the white "
            "(Stratonovich) regime, of equivalent amplitude a = spread sqrt(2 tau_c) = "
            f"{x.amplitude[0]:.2f}-{x.amplitude[1]:.2f}, well below the a where Ito and Stratonovich part",
        )
    ]

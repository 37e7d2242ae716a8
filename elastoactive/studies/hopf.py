"""The Hopf bifurcation of the N = 7 chain (Fig. 3a-b, Fig. 2): amplitude (half peak-to-peak of
Theta) and f tau against sigma, both engines; fits of sigma_c and the exponent near onset; limit
cycles (Omega, Theta)."""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import fits
from ..analysis import observables as obs
from ..analysis import stability as stab
from ..analysis.fits import Fit
from ..batch import Case
from ..scenes import one_pinned
from . import plotting as plots
from . import registry
from .base import ENGINES, EngineParts, Study, Summary, downsample, fast, pick, run, try_fit
from .claim_rows import Claim, fit_value, pm, verdict
from .paper import PAPER

HOPF_CYCLES = (PAPER.fig2_sigmas[0], 0.3, PAPER.fig2_sigma_simulation)
"""sigma of the limit cycles and time series kept for Fig. 2 (MuJoCo)."""


@dataclass(frozen=True)
class BetaWindow(Summary):
    """The pure power-law fit over sigma <= sigma_max."""

    sigma_max: float
    n: int
    onset: float
    beta: float
    beta_err: float


@dataclass(frozen=True)
class HopfEngine(Summary):
    power_law: Fit | None
    """A = a (sigma - sigma_c)^beta over the sustained beats with sigma <= fit_sigma_max."""
    power_law_corrected: Fit | None
    """A = a (sigma - sigma_c)^beta (1 + c (sigma - sigma_c)), sigma <= fit_sigma_max_corrected."""
    sqrt_fit: Fit | None
    beta_by_window: list[BetaWindow]
    freq_linear_all: Fit | None
    """f tau = intercept + slope sigma over every sustained beat."""
    freq_linear_far: Fit | None
    """The same for sigma >= 0.4."""
    freq_linear_near: Fit | None
    """The same for sigma <= fit_sigma_max."""
    last_stable_sigma: float
    first_oscillating_sigma: float
    amplitude_at_fig2_sigma: float
    """Amplitude at the grid sigma nearest the paper's Fig. 2 simulation (0.8)."""
    frequency_at_fig2_sigma: float
    f_at_onset_from_near_fit: float | None = None


@dataclass(frozen=True)
class HopfSummary(EngineParts):
    sigma_c_linear: float
    f_c_linear: float
    fit_sigma_max: float
    fit_sigma_max_corrected: float
    mujoco: HopfEngine
    reduced: HopfEngine


def _hopf_duration(
    n: int, sigma: float, cap: float, min_window: float, max_window: float = 3000.0
) -> tuple[float, float]:
    """(duration, transient) of the N = 7 run at sigma: a transient of 6 relaxation times of the amplitude (at least
    300, at most cap), then 8 periods of the linearisation's beat (min_window to max_window). Where the straight chain's
    leading eigenvalue is real (sigma above ~0.55: no linear period) the beat is far above onset and fast (f tau > 0.03,
    8 periods < 270 tau): min_window."""
    lam = stab.eigenvalues(n, sigma)[0]
    rate = max(abs(lam.real), 1e-5)
    transient = min(cap, max(300.0, 6.0 / (2 * rate)))
    if abs(lam.imag) < 1e-9 * max(abs(lam.real), 1.0):
        window = min_window
    else:
        window = max(min_window, min(8 * 2 * np.pi / abs(lam.imag), max_window))
    return float(np.ceil(transient + window)), float(transient)


HOPF = registry.declare("hopf", summary=HopfSummary, order=30, budget=19.5)


@HOPF.run
def hopf_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Amplitude and f*tau against sigma for N = 7, both engines; fits of sigma_c and the exponent
    near onset; limit cycles (Omega, Theta)."""
    start = time.perf_counter()
    n = 7
    sigmas = pick(
        size,
        (0.15, 0.166, 0.2, 0.3, 0.8),
        (
            0.155,
            0.1585,
            0.1595,
            0.161,
            0.1625,
            0.164,
            0.166,
            0.17,
            0.175,
            0.18,
            0.19,
            0.2,
            0.25,
            0.3,
            0.4,
            0.5,
            0.6,
            0.695,
            0.8,
            1.0,
        ),
        tuple(
            np.round(
                np.r_[
                    0.13,
                    0.14,
                    0.15,
                    0.155,
                    0.1578,
                    0.158,
                    0.1585,
                    0.159,
                    0.1595,
                    0.1605,
                    0.161,
                    0.1625,
                    np.arange(0.164, 0.2, 0.002),
                    np.arange(0.2, 0.5, 0.025),
                    np.arange(0.5, 1.21, 0.05),
                    PAPER.fig2_sigmas,
                ],
                4,
            )
        ),
    )
    sigmas = tuple(sorted(set(float(s) for s in sigmas)))
    cap = pick(size, 500.0, 8000.0, 20000.0)
    min_window = pick(size, 300.0, 600.0, 1200.0)
    max_window = pick(size, 400.0, 3000.0, 4000.0)
    fit_max = pick(size, 0.2, 0.166, 0.166)  # pure power law: close to onset only
    fit_max_corr = pick(size, 0.3, 0.175, 0.175)  # with the leading correction (1 + c (sigma - sigma_c))
    windows = (0.1625, 0.166, 0.17, 0.175, 0.18, 0.19, 0.2)
    cases, meta = [], []
    s_lin = stab.critical_sigma(n)[0]
    for s in sigmas:
        dur, tr_ = _hopf_duration(n, s, cap, min_window, max_window)
        # start near the expected limit cycle (max angle ~ 0.73 x amplitude of Theta ~ 0.73 x 5 sqrt(sigma - sigma_c),
        # from a first pass) so that the slow approach near onset only has a small gap to close
        kick = float(np.clip(0.73 * 5.0 * math.sqrt(max(s - s_lin, 0.0)), 0.05, 0.5))
        for eng in ENGINES:
            cases.append(
                Case(one_pinned.SCENE.physics(n=n, sigma=s), fast(perturbation=kick, sample_dt=0.1), dur, eng, tr_)
            )
            meta.append((s, eng, tr_))
    trajs = run(cases, workers, progress, "Hopf N=7")
    data = {"sigma": np.array(sigmas)}
    res = {eng: {"amplitude": [], "frequency": [], "sustained": [], "duration": []} for eng in ENGINES}
    for (s, eng, tr_), tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)
        amp = obs.amplitude(tr.t, x, tr_)
        sustained = obs.is_oscillating(tr.t, x, threshold=1e-3, transient=tr_, max_decay=0.02)
        res[eng]["amplitude"].append(amp if sustained else 0.0)
        res[eng]["frequency"].append(obs.frequency(tr.t, x, tr_) if sustained else np.nan)
        res[eng]["sustained"].append(sustained)
        res[eng]["duration"].append(tr.t[-1])
        if eng == "mujoco" and any(abs(s - c) < 1e-9 for c in HOPF_CYCLES):
            m = tr.t >= tr_
            om, th = obs.limit_cycle(tr.theta[m])
            key = f"{s:g}"
            data[f"cycle_{key}_t"] = downsample(tr.t[m])
            data[f"cycle_{key}_omega"] = downsample(om)
            data[f"cycle_{key}_theta"] = downsample(th)
            last = tr.t >= tr.t[-1] - 120.0  # full resolution for the time series
            data[f"series_{key}_t"] = tr.t[last]
            data[f"series_{key}_omega"], data[f"series_{key}_theta"] = obs.limit_cycle(tr.theta[last])
    s7, w7 = stab.critical_sigma(n)
    parts = {}
    for eng in ENGINES:
        for k, v in res[eng].items():
            data[f"{k}_{eng}"] = np.array(v)
        amp, freq, ok = data[f"amplitude_{eng}"], data[f"frequency_{eng}"], data[f"sustained_{eng}"].astype(bool)
        sig = data["sigma"]
        near = ok & (sig <= fit_max)
        pl = try_fit(fits.onset_power_law_fit, sig[near], amp[near])
        wide = ok & (sig <= fit_max_corr)
        plc = try_fit(fits.onset_power_law_fit, sig[wide], amp[wide], correction=True)
        by_window = []
        for wmax in windows:
            f = try_fit(fits.onset_power_law_fit, sig[ok & (sig <= wmax)], amp[ok & (sig <= wmax)])
            if f:
                by_window.append(
                    BetaWindow(
                        sigma_max=wmax, n=f.n, onset=f.params["onset"], beta=f.params["beta"], beta_err=f.errors["beta"]
                    )
                )
        sq = try_fit(fits.square_root_onset_fit, sig[near & (sig <= 0.175)], amp[near & (sig <= 0.175)])
        lin = try_fit(fits.linear_fit, sig[ok], freq[ok])
        lin_far = try_fit(fits.linear_fit, sig[ok & (sig >= 0.4)], freq[ok & (sig >= 0.4)])
        lin_near = try_fit(fits.linear_fit, sig[near], freq[near])
        first_on = float(sig[ok].min()) if ok.any() else float("nan")
        last_off = float(sig[~ok & (sig < first_on)].max()) if np.any(~ok & (sig < first_on)) else float("nan")
        at_fig2 = int(np.argmin(np.abs(sig - PAPER.fig2_sigma_simulation)))
        f_onset = None
        if pl is not None and lin_near:
            f_onset = lin_near.params["intercept"] + lin_near.params["slope"] * pl.params["onset"]
        parts[eng] = HopfEngine(
            power_law=pl,
            power_law_corrected=plc,
            sqrt_fit=sq,
            beta_by_window=by_window,
            freq_linear_all=lin,
            freq_linear_far=lin_far,
            freq_linear_near=lin_near,
            last_stable_sigma=last_off,
            first_oscillating_sigma=first_on,
            amplitude_at_fig2_sigma=float(amp[at_fig2]),
            frequency_at_fig2_sigma=float(freq[at_fig2]),
            f_at_onset_from_near_fit=f_onset,
        )
    summary = HopfSummary(
        sigma_c_linear=s7,
        f_c_linear=w7 / (2 * np.pi),
        fit_sigma_max=fit_max,
        fit_sigma_max_corrected=fit_max_corr,
        **parts,
    )
    return Study("hopf", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# figures
# --------------------------------------------------------------------------------------------------
def _last_period(t, *ys, f):
    """The samples of the last period 1/f of a record (all of it if f is not a frequency or the
    record is shorter than one period), with one sample more so that the loop closes."""
    t = np.asarray(t)
    if not (np.isfinite(f) and f > 0) or t[-1] - t[0] < 1.0 / f:
        return (t, *ys)
    dt = np.median(np.diff(t))
    m = t >= t[-1] - 1.0 / f - 1.01 * dt
    return (t[m], *(np.asarray(y)[m] for y in ys))


@HOPF.figure
@plots.styled
def hopf_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    mpl = plots.matplotlib()
    d, s = study.data, study.summary
    sig = d["sigma"]
    sc = s.sigma_c_linear
    paths = []
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4.2))
    for ax in (a1, a2):
        ax.axvspan(0, sc, **plots.STABLE)
        ax.set_xlim(sig.min() - 0.02, sig.max() + 0.02)
        ax.set_xlabel(r"$\sigma$")
    for eng in plots.engines(d, "amplitude"):
        a1.plot(sig, d[f"amplitude_{eng}"], **plots.ENGINE_STYLE[eng])
        a2.plot(sig, d[f"frequency_{eng}"], **plots.ENGINE_STYLE[eng])
    pl = s.mujoco.power_law
    plc = s.mujoco.power_law_corrected
    if plc:
        p = plc.params
        xx = np.linspace(p["onset"] + 1e-7, s.fit_sigma_max_corrected, 200)
        a1.plot(
            xx,
            p["prefactor"] * (xx - p["onset"]) ** p["beta"] * (1 + p["c"] * (xx - p["onset"])),
            "C0-",
            lw=1,
            label="fit "
            r"$a\Delta^\beta(1+c\Delta)$, $\Delta=\sigma-\sigma_c$:"
            "\n"
            rf"$\sigma_c$ = {p['onset']:.5f}, $\beta$ = {p['beta']:.3f}",
        )
    a1.axvline(sc, color="C3", ls="--", lw=0.8, label=rf"$\sigma_c$, linear stability: {sc:.4f}")
    a1.set_ylabel(r"amplitude of $\Theta=\theta_N-\theta_1$ (rad)")
    plots.add_handle(a1, plots.stable_patch(), loc="upper left", bbox_to_anchor=(0.06, 1.0))
    a1.set_ylim(-0.1, 1.7 * np.nanmax([d[f"amplitude_{e}"].max() for e in plots.engines(d, "amplitude")]))
    a1.set_title("Fig. 3a: N = 7, amplitude of the beat")
    if pl:
        ins = a1.inset_axes([0.6, 0.14, 0.37, 0.3])
        for eng in plots.engines(d, "amplitude"):
            ok = d[f"sustained_{eng}"].astype(bool)
            ins.loglog(sig[ok] - pl.params["onset"], d[f"amplitude_{eng}"][ok], **{**plots.ENGINE_STYLE[eng], "ms": 3})
        xx = np.geomspace(1e-3, 1, 50)
        ins.loglog(xx, pl.params["prefactor"] * xx**PAPER.hopf_exponent, "k--", lw=0.7)
        ins.set_xlabel(r"$\sigma-\sigma_c$", fontsize=8, labelpad=1)
        ins.tick_params(labelsize=7, pad=1)
        ins.set_title(f"log-log; dashes: slope {PAPER.hopf_exponent:g} (paper)", fontsize=7.5, pad=2)
        amax = max(d[f"amplitude_{e}"].max() for e in plots.engines(d, "amplitude"))
        plots.log_ticks(ins, [v for v in (0.1, 0.3, 1, 3, 10) if v <= 1.5 * amax], axis="y")
        ins.xaxis.set_major_locator(mpl.ticker.LogLocator(numticks=4))
    lin = s.mujoco.freq_linear_all
    if lin:
        xx = np.linspace(sc, sig.max(), 50)
        a2.plot(
            xx,
            lin.params["intercept"] + lin.params["slope"] * xx,
            "k-",
            lw=0.7,
            label=f"straight-line fit (MuJoCo), R² = {lin.r2:.4f}",
        )
    a2.plot(
        [sc],
        [s.f_c_linear],
        "*",
        color="gold",
        mec="k",
        mew=0.6,
        ms=13,
        zorder=5,
        label=rf"onset, linear stability: $f\tau$ = {s.f_c_linear:.5f}",
    )
    a2.set_ylabel(r"beat frequency $f\tau$ (cycles per $\tau$)")
    plots.add_handle(a2, plots.stable_patch(), loc="upper left")
    a2.set_title("Fig. 3b: N = 7, frequency of the beat")
    fig.tight_layout()
    paths.append(plots.save(fig, out, "fig3ab_hopf.png"))

    keys = sorted({k.split("_")[1] for k in d if k.startswith("cycle_") and k.endswith("_omega")}, key=float)
    if keys:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4))
        big = keys[-1]
        t = d[f"series_{big}_t"]
        a1.plot(t - t[0], d[f"series_{big}_theta"], label=r"$\Theta=\theta_N-\theta_1$")
        a1.plot(t - t[0], d[f"series_{big}_omega"], label=plots.OMEGA_DEF)
        a1.set_xlabel(r"$t/\tau$ (last 120 $\tau$ of the run)")
        a1.set_ylabel("angle (rad)")
        lo = min(d[f"series_{big}_theta"].min(), d[f"series_{big}_omega"].min())
        hi = max(d[f"series_{big}_theta"].max(), d[f"series_{big}_omega"].max())
        a1.set_ylim(lo - 0.1 * (hi - lo), hi + 0.38 * (hi - lo))  # room for the legend above the crests
        a1.legend(loc="upper center", ncol=2)
        a1.set_title(rf"Fig. 2e: time series, N = 7, $\sigma$ = {big} (MuJoCo)")
        for k in keys:
            f = np.nan
            i = np.flatnonzero(np.isclose(sig, float(k)))
            if i.size and "frequency_mujoco" in d:
                f = d["frequency_mujoco"][i[0]]
            # one period of the steady cycle, from the full-resolution series when it holds one
            src = "series" if (np.isfinite(f) and f > 0 and np.ptp(d[f"series_{k}_t"]) >= 1.0 / f) else "cycle"
            _, om, th = _last_period(d[f"{src}_{k}_t"], d[f"{src}_{k}_omega"], d[f"{src}_{k}_theta"], f=f)
            a2.plot(om, th, lw=1.3, label=rf"$\sigma$ = {k}")
        a2.set_xlabel(plots.OMEGA_DEF + " (rad)")
        a2.set_ylabel(r"$\Theta=\theta_N-\theta_1$ (rad)")
        a2.legend(loc="upper left")
        a2.set_title("Fig. 2f: limit cycles, one period each (MuJoCo)")
        fig.tight_layout()
        paths.append(plots.save(fig, out, "fig2_limit_cycles.png"))
    return paths


# --------------------------------------------------------------------------------------------------
# claim rows
# --------------------------------------------------------------------------------------------------
@HOPF.claims
def hopf_claims(h: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = h.summary
    rows = []
    m, r = s.mujoco, s.reduced
    corrected = bool(m.power_law_corrected)
    wmax = s.fit_sigma_max_corrected if corrected else s.fit_sigma_max
    mfit, rfit = (m.power_law_corrected, r.power_law_corrected) if corrected else (m.power_law, r.power_law)
    mo, mo_e = fit_value(mfit, "onset")
    ro, ro_e = fit_value(rfit, "onset")
    mb, mb_e = fit_value(mfit, "beta")
    rb, rb_e = fit_value(rfit, "beta")
    po, po_e = fit_value(m.power_law, "onset")
    pb, pb_e = fit_value(m.power_law, "beta")
    model = "A = a (sigma - sigma_c)^beta (1 + c (sigma - sigma_c))" if corrected else "A = a (sigma - sigma_c)^beta"
    rows.append(
        Claim(
            "N = 7 simulations: onset sigma_c",
            f"{PAPER.sigma_c_7_sim:g} ± {PAPER.sigma_c_7_sim_err:g}",
            pm(mo, mo_e, 6),
            pm(ro, ro_e, 6),
            verdict(mo is not None and abs(mo - PAPER.sigma_c_7_sim) <= PAPER.sigma_c_7_sim_err + 2 * (mo_e or 0)),
            f"fit of {model} to the sustained beats with sigma <= {wmax} (MuJoCo fast preset); linear stability "
            f"{s.sigma_c_linear:.6f}; last stable / first oscillating grid point: {m.last_stable_sigma} / "
            f"{m.first_oscillating_sigma}",
            judged_from="quick",
        )
    )  # the tiny size: short runs, a coarse grid far from onset
    trend = ", ".join(f"{w.beta:.3f} (sigma <= {w.sigma_max:g})" for w in m.beta_by_window)
    rows.append(
        Claim(
            f"Amplitude grows as (sigma - sigma_c)^{PAPER.hopf_exponent:g} (supercritical Hopf)",
            f"{PAPER.hopf_exponent:g}",
            pm(mb, mb_e, 3),
            pm(rb, rb_e, 3),
            verdict(mb is not None and abs(mb - PAPER.hopf_exponent) <= max(3 * (mb_e or 0), 0.01)),
            "exponent of the same fit. Without the correction term the fitted exponent depends on the window, because "
            f"the amplitude (~6 sqrt(sigma - sigma_c) rad) saturates early: {trend} (MuJoCo; sigma_c "
            f"{pm(po, po_e, 5)} for sigma <= {s.fit_sigma_max})",
            judged_from="quick",
        )
    )
    lin_m, lin_r = m.freq_linear_all, r.freq_linear_all
    near, far = m.freq_linear_near, m.freq_linear_far
    if lin_m:
        r2 = lin_m.r2
        txt = f"R^2 = {r2:.4f} over the oscillating range"
        note = (
            f"slope of f tau vs sigma: {near.params['slope']:.4f} near onset (sigma <= {s.fit_sigma_max}), "
            f"{far.params['slope']:.4f} for sigma >= 0.4; onset f tau = {s.f_c_linear:.5f} (linear stability); "
            f"f tau at sigma = {PAPER.fig2_sigma_simulation:g}: {m.frequency_at_fig2_sigma:.5f}"
            if near and far
            else ""
        )
        ok = r2 > 0.999
        rows.append(
            Claim(
                "Rescaled frequency f tau grows linearly with sigma",
                "linear",
                txt,
                f"R^2 = {lin_r.r2:.4f}" if lin_r else "-",
                verdict(ok, partly=r2 > 0.99),
                note + ("" if ok else ": linear above sigma ~ 0.3, but the slope near onset is less than half"),
            )
        )
    return rows

"""The Hopf bifurcation of the N = 7 chain (Fig. 3a-b, Fig. 2): amplitude (half peak-to-peak of
Theta) and f tau against sigma, both engines; fits of sigma_c and the exponent near onset; limit
cycles (Omega, Theta)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..analysis import fits
from ..analysis import observables as obs
from ..analysis import stability as stab
from ..analysis.fits import Fit
from ..batch import Case
from ..paper import PAPER
from ..scenes import one_pinned
from .base import ENGINES, EngineParts, Study, Summary, downsample, fast, pick, run, try_fit

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


def _hopf_duration(n: int, sigma: float, cap: float, min_window: float, max_window: float = 3000.0) -> tuple[float, float]:
    lam = stab.eigenvalues(n, sigma)[0]
    rate = max(abs(lam.real), 1e-5)
    period = 2 * np.pi / max(abs(lam.imag), 1e-6)
    transient = min(cap, max(300.0, 6.0 / (2 * rate)))
    window = max(min_window, min(8 * period, max_window))
    return float(np.ceil(transient + window)), float(transient)


def hopf_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Amplitude and f*tau against sigma for N = 7, both engines; fits of sigma_c and the exponent
    near onset; limit cycles (Omega, Theta)."""
    start = time.perf_counter()
    n = 7
    sigmas = pick(
        size,
        (0.15, 0.166, 0.2, 0.3, 0.8),
        (0.14, 0.15, 0.155, 0.1585, 0.1595, 0.161, 0.1625, 0.164, 0.166, 0.17, 0.175, 0.18, 0.19, 0.2, 0.25, 0.3,
         0.4, 0.5, 0.6, 0.695, 0.8, 1.0),
        tuple(np.round(np.r_[0.13, 0.14, 0.15, 0.155, 0.1578, 0.158, 0.1585, 0.159, 0.1595, 0.1605, 0.161, 0.1625,
                            np.arange(0.164, 0.2, 0.002), np.arange(0.2, 0.5, 0.025),
                            np.arange(0.5, 1.21, 0.05), PAPER.fig2_sigmas], 4)),
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
            cases.append(Case(one_pinned.SCENE.physics(n=n, sigma=s), fast(perturbation=kick, sample_dt=0.1), dur, eng, tr_))
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
                by_window.append(BetaWindow(sigma_max=wmax, n=f.n, onset=f.params["onset"], beta=f.params["beta"],
                                            beta_err=f.errors["beta"]))
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
            power_law=pl, power_law_corrected=plc, sqrt_fit=sq, beta_by_window=by_window, freq_linear_all=lin,
            freq_linear_far=lin_far, freq_linear_near=lin_near, last_stable_sigma=last_off, first_oscillating_sigma=first_on,
            amplitude_at_fig2_sigma=float(amp[at_fig2]), frequency_at_fig2_sigma=float(freq[at_fig2]),
            f_at_onset_from_near_fit=f_onset)
    summary = HopfSummary(sigma_c_linear=s7, f_c_linear=w7 / (2 * np.pi), fit_sigma_max=fit_max,
                          fit_sigma_max_corrected=fit_max_corr, **parts)
    return Study("hopf", size, data, summary, time.perf_counter() - start)

"""Linear stability (Fig. 3c-d, Fig. A-size) and the linear growth the simulations see.

stability_study: sigma_c(N) and the onset frequency for N = 2..50 (full: ..100), the N^-3 law, the
extrapolation of N^3 sigma_c to N -> infinity against the continuum problem, and the eigenvalues
against sigma for N = 2 and 7 (no simulation).
growth_study: growth/decay rate and angular frequency of a small kick at sigma_c (1 -/+ eps) for
several N, both engines, against the eigenvalues; each engine's sigma_c(N).

Run lengths follow the linear growth rates: the transient discarded is a few 1 / (rate gap) and
every measurement window holds several periods.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..analysis import fits
from ..analysis import observables as obs
from ..analysis import stability as stab
from ..analysis.continuum import continuum_critical
from ..analysis.fits import Fit
from ..batch import Case
from ..params import Numerics
from ..scenes import one_pinned
from .base import ENGINES, EngineParts, Study, Summary, fast, pick, run


# --------------------------------------------------------------------------------------------------
# summaries
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SigmaCRow(Summary):
    """One N of the sigma_c(N) table."""

    n: int
    sigma_c: float
    omega_c: float
    f_c: float


@dataclass(frozen=True)
class StabilitySummary(Summary):
    sigma_c_7: float
    omega_c_7: float
    f_c_7: float
    sigma_c_2: float
    omega_c_2: float
    n_fit_min: int
    """Smallest N of the large-N fits."""
    n_max: int
    exponent_large_n: float
    exponent_large_n_err: float
    exponent_all_n: float
    local_exponent_at_nmax: float
    n3_sigma_c_limit: float
    """N -> infinity limit of N^3 sigma_c (fit a + b/N + c/N^2)."""
    n3_sigma_c_limit_err: float
    n3_sigma_c_at_nmax: float
    n4_omega_c_limit: float
    n4_omega_c_limit_err: float
    continuum_onset: float
    """S_c of the continuum eigenproblem."""
    continuum_omega: float
    fit_n3: Fit
    fit_power: Fit
    table: list[SigmaCRow]


@dataclass(frozen=True)
class GrowthOnset(Summary):
    """sigma_c of one N: linear stability, the interpolation of the exact rates, and each engine's."""

    n: int
    sigma_c_linear: float
    sigma_c_interp_theory: float
    sigma_c_mujoco: float
    sigma_c_reduced: float

    def engine_sigma_c(self, engine: str) -> float:
        """sigma_c of engine "mujoco" or "reduced"."""
        return {"mujoco": self.sigma_c_mujoco, "reduced": self.sigma_c_reduced}[engine]


@dataclass(frozen=True)
class GrowthEngine(Summary):
    max_rel_err_rate: float
    """Largest relative error of the measured growth rate against Re lambda."""
    max_rel_err_omega: float
    exponent: float
    """Power-law exponent of this engine's sigma_c(N) over N >= 3 (nan with fewer than three N)."""


@dataclass(frozen=True)
class GrowthSummary(EngineParts):
    eps: float
    per_n: list[GrowthOnset]
    mujoco: GrowthEngine
    reduced: GrowthEngine


# --------------------------------------------------------------------------------------------------
# 1. linear stability
# --------------------------------------------------------------------------------------------------
def stability_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """sigma_c(N), the N^-3 law, N^3 sigma_c against the continuum, eigenvalues vs sigma (N = 2, 7)."""
    start = time.perf_counter()
    n_max = pick(size, 20, 50, 100)
    n_fit = pick(size, 10, 20, 20)
    ns = np.arange(2, n_max + 1)
    sc, wc = stab.critical_sigmas(ns, tol=1e-12)
    big = ns >= n_fit
    law = fits.power_law_fit(ns[big], sc[big])
    law_all = fits.power_law_fit(ns, sc)
    limit = fits.finite_size_fit(ns[big], ns[big] ** 3 * sc[big], order=2)
    limit_w = fits.finite_size_fit(ns[big], ns[big] ** 4.0 * wc[big], order=2)
    S_c, W_c = continuum_critical()
    local = np.gradient(np.log(sc), np.log(ns))
    data = {"n": ns, "sigma_c": sc, "omega_c": wc, "f_c": wc / (2 * np.pi), "n3_sigma_c": ns**3 * sc,
            "n4_omega_c": ns**4.0 * wc, "local_exponent": local}
    npts = pick(size, 41, 301, 801)
    for n, top in ((2, 5.0), (7, 0.5)):
        sig = np.linspace(0.0, top, npts)
        lam = np.array([stab.eigenvalues(n, s) for s in sig])
        data[f"eig_sigma_{n}"] = sig
        data[f"eig_re_{n}"] = lam.real
        data[f"eig_im_{n}"] = lam.imag
    s7, w7 = stab.critical_sigma(7, tol=1e-12)
    s2, w2 = stab.critical_sigma(2, tol=1e-12)
    summary = StabilitySummary(
        sigma_c_7=s7, omega_c_7=w7, f_c_7=w7 / (2 * np.pi),
        sigma_c_2=s2, omega_c_2=w2,
        n_fit_min=int(n_fit), n_max=int(n_max),
        exponent_large_n=law["exponent"], exponent_large_n_err=law.err("exponent"),
        exponent_all_n=law_all["exponent"], local_exponent_at_nmax=float(local[-1]),
        n3_sigma_c_limit=limit["limit"], n3_sigma_c_limit_err=limit.err("limit"),
        n3_sigma_c_at_nmax=float(ns[-1] ** 3 * sc[-1]),
        n4_omega_c_limit=limit_w["limit"], n4_omega_c_limit_err=limit_w.err("limit"),
        continuum_onset=S_c, continuum_omega=W_c,
        fit_n3=limit, fit_power=law,
        table=[SigmaCRow(int(n), float(s), float(w), float(w / (2 * np.pi))) for n, s, w in zip(ns, sc, wc)],
    )
    return Study("stability", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# 2. the linear growth seen by the simulations
# --------------------------------------------------------------------------------------------------
def growth_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Growth/decay rate and angular frequency of a small kick at sigma = sigma_c (1 -/+ eps) for
    several N, both engines, against the eigenvalues; each engine's sigma_c(N) by interpolating its
    two rates to zero."""
    start = time.perf_counter()
    ns = pick(size, (2, 7), (2, 3, 5, 7, 10), (2, 3, 4, 5, 7, 10, 14))
    eps = pick(size, 0.1, 0.05, 0.05)
    cases, meta = [], []
    for n in ns:
        s_c, _ = stab.critical_sigma(n)
        for sgn in (-1, 1):
            sigma = s_c * (1 + sgn * eps)
            lam = stab.eigenvalues(n, sigma)[0]
            settle = 5.0 / max(lam.real - stab.subdominant_rate(n, sigma), 1e-6)
            period = 2 * np.pi / abs(lam.imag)
            window = max(2.5 * period, 3.0 / abs(lam.real))
            # small enough to stay linear: the kick ends near 1e-3 rad when it grows
            kick = max(1e-8, 1e-3 * math.exp(-max(lam.real, 0.0) * (settle + window)))
            num = (Numerics.preset("accurate", perturbation=kick, sample_dt=0.025)
                   if n <= 3 else fast(perturbation=kick, sample_dt=0.1 if period > 40 else 0.05))
            for eng in ENGINES:
                cases.append(Case(one_pinned.SCENE.physics(n=n, sigma=sigma), num, float(np.ceil(settle + window)), eng,
                                  settle))
                meta.append((n, sigma, lam, settle, eng))
    trajs = run(cases, workers, progress, "linear growth")
    rows = {}
    for (n, sigma, lam, settle, eng), tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)
        m = tr.t >= settle
        f = fits.exp_oscillation_fit(tr.t[m], x[m])
        rows.setdefault((n, sigma), {"lam": lam})[eng] = (f["rate"], f["omega"])
    keys = sorted(rows)
    data = {"n": np.array([k[0] for k in keys]), "sigma": np.array([k[1] for k in keys]),
            "rate_theory": np.array([rows[k]["lam"].real for k in keys]),
            "omega_theory": np.array([abs(rows[k]["lam"].imag) for k in keys])}
    for eng in ENGINES:
        data[f"rate_{eng}"] = np.array([rows[k][eng][0] for k in keys])
        data[f"omega_{eng}"] = np.array([rows[k][eng][1] for k in keys])
    per_n = []
    for n in ns:
        i = np.flatnonzero(data["n"] == n)
        s1, s2 = data["sigma"][i]
        interp = lambda g: s1 + (s2 - s1) * g[i][0] / (g[i][0] - g[i][1])  # noqa: E731
        per_n.append(GrowthOnset(n=int(n), sigma_c_linear=stab.critical_sigma(n)[0],
                                 sigma_c_interp_theory=interp(data["rate_theory"]),
                                 sigma_c_mujoco=interp(data["rate_mujoco"]), sigma_c_reduced=interp(data["rate_reduced"])))
    nn = np.array([p.n for p in per_n], float)
    parts = {}
    for eng in ENGINES:
        rel_rate = np.abs(data[f"rate_{eng}"] - data["rate_theory"]) / np.abs(data["rate_theory"])
        rel_om = np.abs(data[f"omega_{eng}"] - data["omega_theory"]) / data["omega_theory"]
        sc = np.array([p.engine_sigma_c(eng) for p in per_n])
        parts[eng] = GrowthEngine(
            max_rel_err_rate=float(rel_rate.max()), max_rel_err_omega=float(rel_om.max()),
            exponent=fits.power_law_fit(nn[nn >= 3], sc[nn >= 3])["exponent"] if np.sum(nn >= 3) >= 3 else float("nan"))
    data["per_n_n"] = np.array([p.n for p in per_n])
    data["per_n_sigma_c_linear"] = np.array([p.sigma_c_linear for p in per_n])
    data["per_n_sigma_c_interp_theory"] = np.array([p.sigma_c_interp_theory for p in per_n])
    for eng in ENGINES:
        data[f"per_n_sigma_c_{eng}"] = np.array([p.engine_sigma_c(eng) for p in per_n])
    summary = GrowthSummary(eps=eps, per_n=per_n, **parts)
    return Study("growth", size, data, summary, time.perf_counter() - start)

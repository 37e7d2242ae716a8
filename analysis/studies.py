"""The studies behind the paper's figures and claims (issue 3), shared by `elastoactive reproduce`
and the scenario scripts in scripts/.

Each study is one function ``name_study(size="quick", workers=None, progress=True) -> Study``: it
chooses its parameter grid and run lengths from ``size`` ("tiny" for tests, "quick" for the default
reproduce run, "full" for publication resolution), runs every simulation through
`elastoactive.batch.run_cases` (a process pool: all cores) and returns the arrays behind the figure
(`Study.data`, saved as NPZ) and the numbers the report quotes (`Study.summary`, saved as JSON).
MuJoCo ("mujoco") and the reduced overdamped model ("reduced") run the same cases from the same
initial state.

Run lengths follow the linear growth rates (analysis.stability): near an onset the approach to the
limit cycle goes like exp(-2 Re(lambda) t), so the transient discarded is a few 1 / (2 Re lambda),
and every measurement window holds several periods.
"""

from __future__ import annotations

import json
import math
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..batch import Case, default_workers, run_cases
from ..params import Numerics, Physics
from . import fits
from . import measures as ms
from . import observables as obs
from . import stability as stab
from .continuum import continuum_critical

SIZES = ("tiny", "quick", "full")
ENGINES = ("mujoco", "reduced")

# The paper's numbers (main text and supplement) that the studies are set against.
PAPER = {
    "sigma_c_7_linear": 0.15,
    "sigma_c_7_sim": 0.16,
    "sigma_c_7_sim_err": 0.005,
    "hopf_exponent": 0.5,
    "sigma_c_2": 3.0,
    "omega_c_2": 1.0,
    "scaling_exponent": -3.0,
    "continuum_onset": 76.0,
    "landau_supplement": complex(-1.0, -1.0 / 8.0),
    "landau_main": complex(-0.5, 1.25),
    "kappa_c_7": 1.1,
    "rotation_sigma_experiment": 0.33,
    "noise_sigma": 3.5,
    "anisotropy_sigma": 3.5,
}


# --------------------------------------------------------------------------------------------------
# plumbing
# --------------------------------------------------------------------------------------------------
@dataclass
class Study:
    """What a study produced: arrays (NPZ) and the numbers the report quotes (JSON)."""

    name: str
    size: str
    data: dict = field(default_factory=dict)
    summary: dict = field(default_factory=dict)
    wall_s: float = 0.0

    def save(self, folder: Path) -> list[Path]:
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        npz = folder / f"{self.name}.npz"
        np.savez_compressed(npz, **{k: np.asarray(v) for k, v in self.data.items()})
        js = folder / f"{self.name}.json"
        js.write_text(json.dumps(_jsonable({"study": self.name, "size": self.size, "wall_s": self.wall_s,
                                            "summary": self.summary}), indent=2) + "\n")
        return [npz, js]


def _jsonable(v):
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, np.ndarray):
        return _jsonable(v.tolist())
    if isinstance(v, (complex, np.complexfloating)):
        return {"re": _jsonable(v.real), "im": _jsonable(v.imag)}
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (np.integer,)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return float(v) if np.isfinite(v) else None
    return v


def _check_size(size: str) -> str:
    if size not in SIZES:
        raise ValueError(f"size must be one of {', '.join(SIZES)}; got {size!r}")
    return size


def _pick(size: str, tiny, quick, full):
    return {"tiny": tiny, "quick": quick, "full": full}[_check_size(size)]


def _run(cases: list[Case], workers, progress: bool, desc: str):
    """Trajectories of the cases (input order), on every core."""
    if not cases:
        return []
    res = run_cases(cases, workers=workers, progress=progress, keep_trajectory=True, desc=desc)
    return [r["trajectory"] for r in res]


def _fast(**kw) -> Numerics:
    return Numerics.preset("fast", **kw)


def _safe(fn, *args, default=float("nan"), **kw):
    try:
        return fn(*args, **kw)
    except (ValueError, RuntimeError, np.linalg.LinAlgError):
        return default


def _fit_dict(fit_fn, *args, **kw) -> dict | None:
    try:
        return fit_fn(*args, **kw).as_dict()
    except (ValueError, RuntimeError, np.linalg.LinAlgError):
        return None


def _downsample(a: np.ndarray, n: int = 2000) -> np.ndarray:
    step = max(1, a.shape[0] // n)
    return a[::step]


# --------------------------------------------------------------------------------------------------
# 1. linear stability: sigma_c(N), N^-3, continuum, eigenvalues vs sigma (Fig 3c-d, Fig A-size)
# --------------------------------------------------------------------------------------------------
def stability_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """sigma_c(N) and the onset frequency for N = 2..50 (full: ..100), the N^-3 law, the
    extrapolation of N^3 sigma_c to N -> infinity against the continuum problem, and the
    eigenvalues against sigma for N = 2 and 7."""
    start = time.perf_counter()
    n_max = _pick(size, 20, 50, 100)
    n_fit = _pick(size, 10, 20, 20)
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
    npts = _pick(size, 41, 301, 801)
    for n, top in ((2, 5.0), (7, 0.5)):
        sig = np.linspace(0.0, top, npts)
        lam = np.array([stab.eigenvalues(n, s) for s in sig])
        data[f"eig_sigma_{n}"] = sig
        data[f"eig_re_{n}"] = lam.real
        data[f"eig_im_{n}"] = lam.imag
    s7, w7 = stab.critical_sigma(7, tol=1e-12)
    s2, w2 = stab.critical_sigma(2, tol=1e-12)
    summary = {
        "sigma_c_7": s7, "omega_c_7": w7, "f_c_7": w7 / (2 * np.pi),
        "sigma_c_2": s2, "omega_c_2": w2,
        "n_fit_min": int(n_fit), "n_max": int(n_max),
        "exponent_large_n": law["exponent"], "exponent_large_n_err": law.err("exponent"),
        "exponent_all_n": law_all["exponent"], "local_exponent_at_nmax": float(local[-1]),
        "n3_sigma_c_limit": limit["limit"], "n3_sigma_c_limit_err": limit.err("limit"),
        "n3_sigma_c_at_nmax": float(ns[-1] ** 3 * sc[-1]),
        "n4_omega_c_limit": limit_w["limit"], "n4_omega_c_limit_err": limit_w.err("limit"),
        "continuum_onset": S_c, "continuum_omega": W_c,
        "fit_n3": limit.as_dict(), "fit_power": law.as_dict(),
        "table": [{"n": int(n), "sigma_c": float(s), "omega_c": float(w), "f_c": float(w / (2 * np.pi))}
                  for n, s, w in zip(ns, sc, wc)],
    }
    return Study("stability", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# 2. the linear growth seen by the simulations (MuJoCo's sigma_c(N) across N)
# --------------------------------------------------------------------------------------------------
def _next_rate(n: int, sigma: float) -> float:
    """Real part of the first eigenvalue below the dominant (conjugate) pair."""
    lam = stab.eigenvalues(n, sigma)
    top = lam[0]
    rest = [l for l in lam[1:] if abs(l - np.conj(top)) > 1e-9 * max(1.0, abs(top))]
    return float(rest[0].real) if rest else -np.inf


def growth_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Growth/decay rate and angular frequency of a small kick at sigma = sigma_c (1 -/+ eps) for
    several N, both engines, against the eigenvalues; each engine's sigma_c(N) by interpolating its
    two rates to zero."""
    start = time.perf_counter()
    ns = _pick(size, (2, 7), (2, 3, 5, 7, 10), (2, 3, 4, 5, 7, 10, 14))
    eps = _pick(size, 0.1, 0.05, 0.05)
    cases, meta = [], []
    for n in ns:
        s_c, _ = stab.critical_sigma(n)
        for sgn in (-1, 1):
            sigma = s_c * (1 + sgn * eps)
            lam = stab.eigenvalues(n, sigma)[0]
            settle = 5.0 / max(lam.real - _next_rate(n, sigma), 1e-6)
            period = 2 * np.pi / abs(lam.imag)
            window = max(2.5 * period, 3.0 / abs(lam.real))
            # small enough to stay linear: the kick ends near 1e-3 rad when it grows
            kick = max(1e-8, 1e-3 * math.exp(-max(lam.real, 0.0) * (settle + window)))
            num = (Numerics.preset("accurate", perturbation=kick, sample_dt=0.025)
                   if n <= 3 else _fast(perturbation=kick, sample_dt=0.1 if period > 40 else 0.05))
            for eng in ENGINES:
                cases.append(Case(Physics(n=n, sigma=sigma), num, float(np.ceil(settle + window)), eng, settle))
                meta.append((n, sigma, lam, settle, eng))
    trajs = _run(cases, workers, progress, "linear growth")
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
        entry = {"n": int(n), "sigma_c_linear": stab.critical_sigma(n)[0],
                 "sigma_c_interp_theory": interp(data["rate_theory"])}
        for eng in ENGINES:
            entry[f"sigma_c_{eng}"] = interp(data[f"rate_{eng}"])
        per_n.append(entry)
    summary = {"eps": eps, "per_n": per_n}
    for eng in ENGINES:
        rel_rate = np.abs(data[f"rate_{eng}"] - data["rate_theory"]) / np.abs(data["rate_theory"])
        rel_om = np.abs(data[f"omega_{eng}"] - data["omega_theory"]) / data["omega_theory"]
        summary[f"max_rel_err_rate_{eng}"] = float(rel_rate.max())
        summary[f"max_rel_err_omega_{eng}"] = float(rel_om.max())
        nn = np.array([p["n"] for p in per_n], float)
        sc = np.array([p[f"sigma_c_{eng}"] for p in per_n])
        summary[f"exponent_{eng}"] = fits.power_law_fit(nn[nn >= 3], sc[nn >= 3])["exponent"] if np.sum(nn >= 3) >= 3 else float("nan")
    data["per_n_n"] = np.array([p["n"] for p in per_n])
    for key in ("sigma_c_linear", "sigma_c_interp_theory") + tuple(f"sigma_c_{e}" for e in ENGINES):
        data[f"per_n_{key}"] = np.array([p[key] for p in per_n])
    return Study("growth", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# 3. the Hopf bifurcation of the N = 7 chain (Fig 3a-b, Fig 2)
# --------------------------------------------------------------------------------------------------
HOPF_CYCLES = (0.166, 0.3, 0.8)


def _hopf_duration(n: int, sigma: float, cap: float, min_window: float, max_window: float = 3000.0) -> tuple[float, float]:
    lam = stab.eigenvalues(n, sigma)[0]
    rate = max(abs(lam.real), 1e-5)
    period = 2 * np.pi / max(abs(lam.imag), 1e-6)
    transient = min(cap, max(300.0, 6.0 / (2 * rate)))
    window = max(min_window, min(8 * period, max_window))
    return float(np.ceil(transient + window)), float(transient)


def hopf_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Amplitude (half peak-to-peak of Theta) and f*tau against sigma for N = 7, both engines;
    fits of sigma_c and the exponent near onset; limit cycles (Omega, Theta)."""
    start = time.perf_counter()
    n = 7
    sigmas = _pick(
        size,
        (0.15, 0.166, 0.2, 0.3, 0.8),
        (0.14, 0.15, 0.155, 0.1585, 0.1595, 0.161, 0.1625, 0.164, 0.166, 0.17, 0.175, 0.18, 0.19, 0.2, 0.25, 0.3,
         0.4, 0.5, 0.6, 0.695, 0.8, 1.0),
        tuple(np.round(np.r_[0.13, 0.14, 0.15, 0.155, 0.1578, 0.158, 0.1585, 0.159, 0.1595, 0.1605, 0.161, 0.1625,
                            np.arange(0.164, 0.2, 0.002), np.arange(0.2, 0.5, 0.025),
                            np.arange(0.5, 1.21, 0.05), 0.166, 0.695], 4)),
    )
    sigmas = tuple(sorted(set(float(s) for s in sigmas)))
    cap = _pick(size, 500.0, 8000.0, 20000.0)
    min_window = _pick(size, 300.0, 600.0, 1200.0)
    max_window = _pick(size, 400.0, 3000.0, 4000.0)
    fit_max = _pick(size, 0.2, 0.166, 0.166)  # pure power law: close to onset only
    fit_max_corr = _pick(size, 0.3, 0.175, 0.175)  # with the leading correction (1 + c (sigma - sigma_c))
    windows = (0.1625, 0.166, 0.17, 0.175, 0.18, 0.19, 0.2)
    cases, meta = [], []
    s_lin = stab.critical_sigma(n)[0]
    for s in sigmas:
        dur, tr_ = _hopf_duration(n, s, cap, min_window, max_window)
        # start near the expected limit cycle (max angle ~ 0.73 x amplitude of Theta ~ 0.73 x 5 sqrt(sigma - sigma_c),
        # from a first pass) so that the slow approach near onset only has a small gap to close
        kick = float(np.clip(0.73 * 5.0 * math.sqrt(max(s - s_lin, 0.0)), 0.05, 0.5))
        for eng in ENGINES:
            cases.append(Case(Physics(n=n, sigma=s), _fast(perturbation=kick, sample_dt=0.1), dur, eng, tr_))
            meta.append((s, eng, tr_))
    trajs = _run(cases, workers, progress, "Hopf N=7")
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
            data[f"cycle_{key}_t"] = _downsample(tr.t[m])
            data[f"cycle_{key}_omega"] = _downsample(om)
            data[f"cycle_{key}_theta"] = _downsample(th)
            last = tr.t >= tr.t[-1] - 120.0  # full resolution for the time series
            data[f"series_{key}_t"] = tr.t[last]
            data[f"series_{key}_omega"], data[f"series_{key}_theta"] = obs.limit_cycle(tr.theta[last])
    s7, w7 = stab.critical_sigma(n)
    summary = {"sigma_c_linear": s7, "f_c_linear": w7 / (2 * np.pi), "fit_sigma_max": fit_max,
               "fit_sigma_max_corrected": fit_max_corr}
    for eng in ENGINES:
        for k, v in res[eng].items():
            data[f"{k}_{eng}"] = np.array(v)
        amp, freq, ok = data[f"amplitude_{eng}"], data[f"frequency_{eng}"], data[f"sustained_{eng}"].astype(bool)
        sig = data["sigma"]
        near = ok & (sig <= fit_max)
        pl = _fit_dict(fits.onset_power_law_fit, sig[near], amp[near])
        wide = ok & (sig <= fit_max_corr)
        plc = _fit_dict(fits.onset_power_law_fit, sig[wide], amp[wide], correction=True)
        by_window = []
        for wmax in windows:
            f = _fit_dict(fits.onset_power_law_fit, sig[ok & (sig <= wmax)], amp[ok & (sig <= wmax)])
            if f:
                by_window.append({"sigma_max": wmax, "n": f["n"], "onset": f["params"]["onset"], "beta": f["params"]["beta"],
                                  "beta_err": f["errors"]["beta"]})
        sq = _fit_dict(fits.square_root_onset_fit, sig[near & (sig <= 0.175)], amp[near & (sig <= 0.175)])
        lin = _fit_dict(fits.linear_fit, sig[ok], freq[ok])
        lin_far = _fit_dict(fits.linear_fit, sig[ok & (sig >= 0.4)], freq[ok & (sig >= 0.4)])
        lin_near = _fit_dict(fits.linear_fit, sig[near], freq[near])
        first_on = float(sig[ok].min()) if ok.any() else float("nan")
        last_off = float(sig[~ok & (sig < first_on)].max()) if np.any(~ok & (sig < first_on)) else float("nan")
        summary[eng] = {"power_law": pl, "power_law_corrected": plc, "sqrt_fit": sq, "beta_by_window": by_window, "freq_linear_all": lin, "freq_linear_far": lin_far,
                        "freq_linear_near": lin_near, "last_stable_sigma": last_off, "first_oscillating_sigma": first_on,
                        "amplitude_at_0.8": float(amp[np.argmin(np.abs(sig - 0.8))]),
                        "frequency_at_0.8": float(freq[np.argmin(np.abs(sig - 0.8))])}
        if pl is not None:
            summary[eng]["f_at_onset_from_near_fit"] = (
                lin_near["params"]["intercept"] + lin_near["params"]["slope"] * pl["params"]["onset"] if lin_near else None)
    return Study("hopf", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# 4. N = 2 normal form: which printed Landau-Stuart coefficient holds
# --------------------------------------------------------------------------------------------------
def landau_prediction(mu, which: str):
    """(<|z|^2>, omega) on the limit cycle of the printed normal form: 'supplement' (c = -1 - mu/2 +
    i(-1/8 + 5 mu / 4)) or 'main' (c = -(sigma - 5/2) + i (17/4 - sigma), sigma = 3 + mu)."""
    mu = np.asarray(mu, dtype=float)
    if which == "supplement":
        re, im = -1.0 - mu / 2, -1.0 / 8 + 1.25 * mu
    elif which == "main":
        re, im = -(0.5 + mu), 1.25 - mu
    else:
        raise ValueError("which must be 'supplement' or 'main'")
    z2 = mu / -re
    return z2, 1.0 + im * z2


def _z_stats(traj, mu: float, transient: float) -> tuple[float, float]:
    m = traj.t >= transient
    z = ms.landau_variable(traj.theta[m], mu)
    omega = abs(np.polyfit(traj.t[m], np.unwrap(np.angle(z)), 1)[0])
    return float(np.mean(np.abs(z) ** 2)), float(omega)


def normal_form_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """<|z|^2> and the angular frequency on the N = 2 limit cycle just above sigma = 3, reduced
    model and MuJoCo (two timesteps, Richardson-extrapolated to dt -> 0: implicitfast shifts the
    onset by about +dt/2 in mu), against both printed cubic coefficients."""
    start = time.perf_counter()
    mus = _pick(size, (0.05, 0.1), (0.01, 0.02, 0.04, 0.08), (0.005, 0.01, 0.02, 0.04, 0.08, 0.16))
    dts = _pick(size, (0.0025, 0.00125), (0.00125, 0.000625), (0.00125, 0.000625))
    window = _pick(size, 100.0, 250.0, 500.0)
    cases, meta = [], []
    for mu in mus:
        transient = 3.0 / mu + 50.0
        dur = float(np.ceil(transient + window))
        phys = Physics(n=2, sigma=3.0 + mu)
        cases.append(Case(phys, Numerics(perturbation=math.sqrt(mu), sample_dt=0.05), dur, "reduced", transient))
        meta.append((mu, "reduced", transient))
        for dt in dts:
            cases.append(Case(phys, Numerics(dt=dt, mass_ratio=1e-5, perturbation=math.sqrt(mu), sample_dt=0.05),
                              dur, "mujoco", transient))
            meta.append((mu, f"mujoco_dt{dt:g}", transient))
    trajs = _run(cases, workers, progress, "normal form N=2")
    out: dict = {}
    for (mu, key, tr_), tr in zip(meta, trajs):
        out.setdefault(key, []).append(_z_stats(tr, mu, tr_))
    mu_arr = np.array(mus)
    data = {"mu": mu_arr}
    for key, vals in out.items():
        data[f"z2_{key}"] = np.array([v[0] for v in vals])
        data[f"omega_{key}"] = np.array([v[1] for v in vals])
    c, f = (f"mujoco_dt{d:g}" for d in dts)
    data["z2_mujoco"] = fits.richardson(data[f"z2_{c}"], data[f"z2_{f}"])
    data["omega_mujoco"] = fits.richardson(data[f"omega_{c}"], data[f"omega_{f}"])
    for which in ("supplement", "main"):
        z2p, omp = landau_prediction(mu_arr, which)
        data[f"z2_{which}"], data[f"omega_{which}"] = z2p, omp
    summary = {"dts": list(dts), "mu": list(mus)}
    for eng in ("reduced", "mujoco", c, f):
        z2, om = data[f"z2_{eng}"], data[f"omega_{eng}"]
        re_fit = fits.linear_fit(mu_arr, mu_arr / z2) if len(mus) >= 3 else None
        im_fit = fits.linear_fit(mu_arr, (om - 1.0) / z2) if len(mus) >= 3 else None
        onset = fits.linear_fit(3.0 + mu_arr, z2) if len(mus) >= 3 else None
        om_fit = fits.linear_fit(mu_arr, om) if len(mus) >= 3 else None
        i0 = int(np.argmin(mu_arr))
        entry = {
            "minus_re_c_smallest_mu": float(mu_arr[i0] / z2[i0]),
            "im_c_smallest_mu": float((om[i0] - 1.0) / z2[i0]),
        }
        if re_fit is not None:
            entry.update({
                "re_c": -re_fit["intercept"], "re_c_err": re_fit.err("intercept"),
                "im_c": im_fit["intercept"], "im_c_err": im_fit.err("intercept"),
                "sigma_c": -onset["intercept"] / onset["slope"], "omega_at_onset": om_fit["intercept"],
                "omega_at_onset_err": om_fit.err("intercept"),
            })
        else:
            entry.update({"re_c": -entry["minus_re_c_smallest_mu"], "im_c": entry["im_c_smallest_mu"]})
        summary[eng] = entry
    return Study("normal_form", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# 5. self-snapping (Fig 4c-d; supplement map for N = 9)
# --------------------------------------------------------------------------------------------------
SNAP_THRESHOLD = 0.02  # rad: a std of theta_3 above this is self-snapping (the static arch has ~0)


def _snap_measures(tr, transient):
    x = tr.theta[:, 2]
    snap = obs.snap_amplitude(tr.theta, tr.t, transient)
    freq = obs.frequency(tr.t, x, transient) if snap > SNAP_THRESHOLD else np.nan
    return snap, freq


def snapping_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Snap amplitude (std of theta_3) and frequency against the compression delta for N = 7 at
    sigma = 0.6 and 0.8, both engines; the (delta, sigma) map for N = 9 (MuJoCo; full: both);
    the sigma below which a compressed N = 9 chain stays buckled, by bisection."""
    start = time.perf_counter()
    deltas = _pick(size, (0.0, 0.1, 0.3), (0.0, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3),
                   tuple(np.round(np.r_[0.0, 0.005, 0.01, 0.02, np.arange(0.03, 0.401, 0.025)], 4)))
    dur7 = _pick(size, 300.0, 800.0, 2000.0)
    cases, meta = [], []
    for s in (0.6, 0.8):
        for d in deltas:
            for eng in ENGINES:
                cases.append(Case(Physics(scene="two-pinned", n=7, sigma=s, delta=d), _fast(perturbation=0.05, sample_dt=0.1),
                                  dur7, eng, dur7 / 2))
                meta.append(("n7", s, d, eng))
    map_sig = _pick(size, (0.1, 0.3, 0.8), (0.1, 0.15, 0.2, 0.3, 0.5, 0.8),
                    tuple(np.round(np.r_[0.05, 0.1, 0.125, 0.15, 0.16, 0.17, 0.18, 0.19, 0.2, 0.25, 0.3, 0.4, 0.5, 0.65, 0.8, 1.0], 4)))
    map_del = _pick(size, (0.0, 0.1, 0.3), (0.0, 0.05, 0.1, 0.2, 0.3), tuple(np.round(np.arange(0.0, 0.401, 0.04), 4)))
    map_engines = _pick(size, ("mujoco",), ("mujoco",), ENGINES)
    dur9 = _pick(size, 300.0, 1000.0, 3000.0)
    for s in map_sig:
        for d in map_del:
            for eng in map_engines:
                cases.append(Case(Physics(scene="two-pinned", n=9, sigma=s, delta=d), _fast(perturbation=0.05, sample_dt=0.1),
                                  dur9, eng, dur9 / 2))
                meta.append(("n9", s, d, eng))
    trajs = _run(cases, workers, progress, "self-snapping")
    data = {"delta": np.array(deltas), "map_sigma": np.array(map_sig), "map_delta": np.array(map_del)}
    n7 = {}
    maps = {eng: np.full((len(map_sig), len(map_del)), np.nan) for eng in map_engines}
    mapf = {eng: np.full((len(map_sig), len(map_del)), np.nan) for eng in map_engines}
    example = None
    for (kind, s, d, eng), tr in zip(meta, trajs):
        snap, freq = _snap_measures(tr, tr.t[-1] / 2)
        if kind == "n7":
            n7[(s, d, eng)] = (snap, freq)
            if eng == "mujoco" and s == 0.8 and abs(d - 0.1) < 1e-9:
                example = tr
        else:
            i, j = map_sig.index(s), map_del.index(d)
            maps[eng][i, j], mapf[eng][i, j] = snap, freq
    for s in (0.6, 0.8):
        for eng in ENGINES:
            data[f"snap_{s:g}_{eng}"] = np.array([n7[(s, d, eng)][0] for d in deltas])
            data[f"freq_{s:g}_{eng}"] = np.array([n7[(s, d, eng)][1] for d in deltas])
    for eng in map_engines:
        data[f"map_snap_{eng}"], data[f"map_freq_{eng}"] = maps[eng], mapf[eng]
    if example is not None:  # one snapping period of the N = 7 chain at sigma = 0.8, delta = 0.1
        f = n7[(0.8, 0.1, "mujoco")][1]
        m = example.t >= example.t[-1] - (1.0 / f if np.isfinite(f) and f > 0 else 50.0)
        data["example_t"], data["example_theta"] = example.t[m], example.theta[m]

    # the smallest sigma that snaps, N = 9, delta = 0.1 (bisection, both engines side by side)
    steps = _pick(size, 2, 5, 9)
    d_thr = 0.1
    lo = {eng: 0.1 for eng in ENGINES}
    hi = {eng: 0.3 for eng in ENGINES}
    dur_thr = _pick(size, 400.0, 2000.0, 6000.0)
    for _ in range(steps):
        cs = [Case(Physics(scene="two-pinned", n=9, sigma=0.5 * (lo[e] + hi[e]), delta=d_thr),
                   _fast(perturbation=0.05, sample_dt=0.1), dur_thr, e, dur_thr / 2) for e in ENGINES]
        for e, tr in zip(ENGINES, _run(cs, workers, False, "snap threshold")):
            mid = 0.5 * (lo[e] + hi[e])
            if _snap_measures(tr, dur_thr / 2)[0] > SNAP_THRESHOLD:
                hi[e] = mid
            else:
                lo[e] = mid

    summary = {"snap_threshold_rad": SNAP_THRESHOLD, "threshold_delta": d_thr}
    for eng in ENGINES:
        summary[f"sigma_snap_n9_{eng}"] = 0.5 * (lo[eng] + hi[eng])
        summary[f"sigma_snap_n9_{eng}_halfwidth"] = 0.5 * (hi[eng] - lo[eng])
        for s in (0.6, 0.8):
            snap = data[f"snap_{s:g}_{eng}"]
            freq = data[f"freq_{s:g}_{eng}"]
            d = np.array(deltas)
            pos = d > 0
            summary[f"n7_sigma{s:g}_{eng}"] = {
                "snap_at_delta0": float(snap[d == 0][0]) if np.any(d == 0) else None,
                "snap_monotonic_in_delta": bool(np.all(np.diff(snap[pos]) > 0)),
                "snap_min_positive_delta": float(snap[pos][0]), "snap_max_delta": float(snap[pos][-1]),
                "freq_min_positive_delta": float(freq[pos][0]), "freq_max_delta": float(freq[pos][-1]),
                "delta_min": float(d[pos][0]), "delta_max": float(d[pos][-1]),
                "snap_exponent": _safe(lambda: fits.power_law_fit(d[pos], snap[pos])["exponent"]),
            }
    for eng in map_engines:
        m = maps[eng]
        snaps = m > SNAP_THRESHOLD
        rows_snapping = [float(s) for s, row in zip(map_sig, snaps) if row[np.array(map_del) > 0].all()]
        rows_static = [float(s) for s, row in zip(map_sig, snaps) if not row.any()]
        summary[f"map_{eng}"] = {"sigmas_snapping_at_all_delta_gt0": rows_snapping, "sigmas_never_snapping": rows_static,
                                 "delta0_max_snap": float(np.nanmax(m[:, np.array(map_del) == 0])) if 0.0 in map_del else None}
    return Study("snapping", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# 6. freely rotating pin
# --------------------------------------------------------------------------------------------------
def rotating_operator(n: int, sigma: float) -> np.ndarray:
    """Linearisation of the rotating-pin chain about the straight state, on the rotation-invariant
    bend angles psi_i = theta_{i+1} - theta_i (the rigid rotation, eigenvalue 0, factored out)."""
    idx = np.arange(1, n + 1)
    D0 = (n - np.maximum(idx[:, None], idx[None, :]) + 1).astype(float)  # drag at rest
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[0, 0] = K[-1, -1] = 1.0  # no clamp spring; free end
    S = np.diag((n - idx).astype(float)) - np.triu(np.ones((n, n)), k=1)  # linearised follower forces
    A = -np.linalg.solve(D0, K - sigma * S)
    R = np.diff(np.eye(n), axis=0)  # (n-1) x n
    return R @ A @ np.linalg.pinv(R)


def rotation_threshold(n: int = 7) -> float:
    """sigma above which the straight chain on a free pin is unstable (a real eigenvalue: steady rotation)."""
    from scipy.optimize import brentq

    g = lambda s: float(np.max(np.linalg.eigvals(rotating_operator(n, s)).real))  # noqa: E731
    hi = 1e-3
    while g(hi) < 0:
        hi *= 1.5
    return float(brentq(g, hi / 1.5, hi, xtol=1e-12))


def rotation_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Rotation rate and the steady shape (frame turning with pendulum 1) against sigma for N = 7,
    both engines; the sign of the rotation for several seeds at sigma = 0.33."""
    start = time.perf_counter()
    n = 7
    sigmas = _pick(size, (0.05, 0.2, 0.8), (0.03, 0.06, 0.075, 0.0825, 0.09, 0.1, 0.125, 0.15, 0.2, 0.33, 0.5, 0.8, 1.2),
                   tuple(np.round(np.r_[0.02, 0.04, 0.06, np.arange(0.07, 0.13, 0.005), np.arange(0.15, 0.41, 0.05), 0.33,
                                       0.5, 0.65, 0.8, 1.0, 1.2, 1.5], 4)))
    sigmas = tuple(sorted(set(float(s) for s in sigmas)))
    seeds = _pick(size, (0, 1, 2, 3), tuple(range(8)), tuple(range(16)))
    s_r = rotation_threshold(n)
    cases, meta = [], []
    for s in sigmas:
        rate = float(np.max(np.linalg.eigvals(rotating_operator(n, s)).real))
        grow = 12.0 / rate if rate > 0 else 0.0
        dur = float(np.ceil(min(8000.0, 300.0 + grow)))
        for eng in ENGINES:
            cases.append(Case(Physics(scene="rotating-pin", n=n, sigma=s), _fast(perturbation=0.01, sample_dt=0.1), dur, eng,
                              dur - 150.0))
            meta.append(("sigma", s, 0, eng))
    s_exp = PAPER["rotation_sigma_experiment"]
    for seed in seeds:
        for eng in ENGINES:
            cases.append(Case(Physics(scene="rotating-pin", n=n, sigma=s_exp), _fast(perturbation=0.01, sample_dt=0.1, seed=seed),
                              400.0, eng, 250.0))
            meta.append(("seed", s_exp, seed, eng))
    trajs = _run(cases, workers, progress, "rotating pin")
    res = {}
    signs = {eng: [] for eng in ENGINES}
    for (kind, s, seed, eng), tr in zip(meta, trajs):
        transient = tr.t[-1] - 150.0
        rate = obs.rotation_rate(tr.t, tr.theta, transient)
        if kind == "sigma":
            shape, spread = ms.steady_shape(tr.theta, tr.t, transient)
            unif = ms.rotation_uniformity(tr.t, tr.theta, transient) if abs(rate) > 1e-6 else np.nan
            res[(s, eng)] = (rate, shape, spread, unif)
        else:
            signs[eng].append(rate)
    data = {"sigma": np.array(sigmas), "seeds": np.array(seeds)}
    summary = {"sigma_r_linear": s_r, "sigma_seeds": s_exp}
    for eng in ENGINES:
        rate = np.array([res[(s, eng)][0] for s in sigmas])
        data[f"rate_{eng}"] = rate
        data[f"shape_{eng}"] = np.array([res[(s, eng)][1] for s in sigmas])
        data[f"shape_spread_{eng}"] = np.array([res[(s, eng)][2] for s in sigmas])
        data[f"uniformity_{eng}"] = np.array([res[(s, eng)][3] for s in sigmas])
        data[f"seed_rate_{eng}"] = np.array(signs[eng])
        sig = np.array(sigmas)
        turning = np.abs(rate) > 1e-4
        near = turning & (sig <= 0.15)
        on = sig[turning].min() if turning.any() else np.nan
        off = sig[~turning & (sig < on)].max() if np.any(~turning & (sig < on)) else np.nan
        summary[eng] = {
            "first_rotating_sigma": float(on), "last_still_sigma": float(off),
            "onset_fit": _fit_dict(fits.onset_power_law_fit, sig[near], np.abs(rate[near])),
            "n_positive": int(np.sum(np.array(signs[eng]) > 0)), "n_negative": int(np.sum(np.array(signs[eng]) < 0)),
            "rate_at_0.33_abs": float(np.mean(np.abs(signs[eng]))),
            "max_uniformity": float(np.nanmax(data[f"uniformity_{eng}"][turning])) if turning.any() else None,
            "max_shape_spread": float(np.max(data[f"shape_spread_{eng}"][turning])) if turning.any() else None,
        }
    return Study("rotation", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# 7. synchronisation of a pair (Fig 5), Arnold tongue, N = 2 theory of kappa_c
# --------------------------------------------------------------------------------------------------
def _pair_measures(tr, transient):
    x1, x2 = obs.curvature(tr.chain(0)), obs.curvature(tr.chain(1))
    f1, f2 = obs.frequency(tr.t, x1, transient), obs.frequency(tr.t, x2, transient)
    a1, a2 = obs.amplitude(tr.t, x1, transient), obs.amplitude(tr.t, x2, transient)
    if min(a1, a2) < 1e-3 or f1 == 0 or f2 == 0:
        return {"mismatch": np.nan, "slips": np.nan, "locked": False, "f1": f1, "f2": f2, "a1": a1, "a2": a2}
    mism = obs.frequency_mismatch(tr.t, x1, x2, transient)
    slips = ms.phase_slips(tr.t, x1, x2, transient)
    return {"mismatch": mism, "slips": slips, "locked": slips < 0.5, "f1": f1, "f2": f2, "a1": a1, "a2": a2}


def locking_threshold(kappa, locked) -> tuple[float, float]:
    """(kappa_lo, kappa_hi): the largest unlocked kappa below the smallest kappa from which every
    larger kappa of the (sorted) grid is locked."""
    kappa = np.asarray(kappa, float)
    locked = np.asarray(locked, bool)
    order = np.argsort(kappa)
    kappa, locked = kappa[order], locked[order]
    if not locked[-1]:
        return float(kappa[-1]), float("inf")
    i = kappa.size - 1
    while i > 0 and locked[i - 1]:
        i -= 1
    return (float(kappa[i - 1]) if i > 0 else float("nan")), float(kappa[i])


def _alt_pair_run(args):
    """What-if pair (reduced model): chain 2 as stiff as chain 1 but with a weaker active force
    (sigma_2 = factor * sigma), i.e. sigma_2 = 0.6 at the same tau. Not the paper's stated model."""
    from scipy.integrate import solve_ivp

    from ..initial import initial_angles
    from .reduced import rhs

    n, sigma, factor, kappa, duration, transient = args
    phys = Physics(scene="coupled-pair", n=n, sigma=sigma, rho=1.0, kappa=kappa)
    f = rhs(phys, factor=np.r_[np.ones(n), factor * np.ones(n)])
    th0 = initial_angles(phys, Numerics(perturbation=0.3))
    t = np.arange(0.0, duration + 1e-9, 0.1)
    sol = solve_ivp(f, (0.0, t[-1]), th0, method="DOP853", t_eval=t, rtol=1e-7, atol=1e-9)
    th = sol.y.T
    x1, x2 = th[:, n - 1] - th[:, 0], th[:, 2 * n - 1] - th[:, n]
    return {"mismatch": obs.frequency_mismatch(t, x1, x2, transient), "slips": ms.phase_slips(t, x1, x2, transient),
            "f1": obs.frequency(t, x1, transient), "f2": obs.frequency(t, x2, transient)}


def sync_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Frequency mismatch against kappa for the paper's pair (N = 7, sigma_1 = 0.8, rho = 4/3, so
    sigma_2 = 0.6), both engines; the critical kappa; phase differences Psi(t); and a what-if with
    chain 2 as stiff as chain 1 but a weaker active force (sigma_2 = 0.6 at the same tau)."""
    start = time.perf_counter()
    n, sigma, rho = 7, 0.8, 4.0 / 3.0
    kappas = _pick(size, (0.0, 0.04, 0.1, 1.1),
                   (0.0, 0.03, 0.05, 0.065, 0.07, 0.075, 0.08, 0.09, 0.15, 0.4, 0.8, 1.1, 2.0),
                   tuple(np.round(np.r_[np.arange(0.0, 0.05, 0.01), np.arange(0.05, 0.09, 0.0025), np.arange(0.09, 0.2, 0.02),
                                       np.arange(0.2, 2.51, 0.1), 0.8, 1.1, 1.2], 4)))
    kappas = tuple(sorted(set(float(k) for k in kappas)))
    dur = _pick(size, 800.0, 3000.0, 6000.0)
    tr_ = dur / 2
    cases, meta = [], []
    for k in kappas:
        for eng in ENGINES:
            cases.append(Case(Physics(scene="coupled-pair", n=n, sigma=sigma, rho=rho, kappa=k), _fast(perturbation=0.3, sample_dt=0.1),
                              dur, eng, tr_))
            meta.append((k, eng))
    trajs = _run(cases, workers, progress, "sync N=7")
    data = {"kappa": np.array(kappas)}
    res = {}
    psi_keep = {}
    for (k, eng), tr in zip(meta, trajs):
        res[(k, eng)] = _pair_measures(tr, tr_)
        if eng == "mujoco":
            try:
                tp, psi = ms.phase_difference(tr.t, obs.curvature(tr.chain(0)), obs.curvature(tr.chain(1)), 0.0)
                psi_keep[k] = (_downsample(tp, 1500), _downsample(psi - psi[0], 1500))
            except ValueError:
                pass
    summary = {"n": n, "sigma_1": sigma, "rho": rho, "sigma_2": sigma / rho, "duration": dur}
    for eng in ENGINES:
        for key in ("mismatch", "slips", "locked", "f1", "f2", "a1", "a2"):
            data[f"{key}_{eng}"] = np.array([res[(k, eng)][key] for k in kappas])
        lo, hi = locking_threshold(kappas, data[f"locked_{eng}"])
        kap = np.array(kappas)
        unl = (~data[f"locked_{eng}"]) & (kap > 0) & (kap <= lo)
        adler = None
        if np.count_nonzero(unl) >= 3:
            adler = _fit_dict(fits.square_root_onset_fit, -kap[unl][-4:], np.abs(data[f"mismatch_{eng}"][unl][-4:]))
        i0 = int(np.argmin(kap))
        i11 = int(np.argmin(np.abs(kap - 1.1)))
        summary[eng] = {
            "kappa_c_bracket": [lo, hi], "kappa_c": 0.5 * (lo + hi) if np.isfinite(hi) else float("nan"),
            "kappa_c_adler": -adler["params"]["onset"] if adler else None,
            "mismatch_uncoupled": float(data[f"mismatch_{eng}"][i0]),
            "f1_uncoupled": float(data[f"f1_{eng}"][i0]), "f2_uncoupled": float(data[f"f2_{eng}"][i0]),
            "f_locked_at_1.1": float(data[f"f1_{eng}"][i11]) if data[f"locked_{eng}"][i11] else None,
            "locked_at_0.8": bool(data[f"locked_{eng}"][int(np.argmin(np.abs(kap - 0.8)))]) if size != "tiny" else None,
        }
    # phase differences of one unlocked and two locked cases (the paper's K = 0.8 and 1.2 analogues)
    lo_m = summary["mujoco"]["kappa_c_bracket"][0]
    picks = [k for k in kappas if k in psi_keep]
    chosen = sorted({min(picks, key=lambda k: abs(k - target)) for target in (0.5 * lo_m if np.isfinite(lo_m) else 0.0, 0.8, 1.2)})
    for k in chosen:
        data[f"psi_{k:g}_t"], data[f"psi_{k:g}"] = psi_keep[k]
    data["psi_kappas"] = np.array(chosen)

    # what-if: sigma_2 = 0.6 with chain 2 as stiff as chain 1 (the main text's wording "rho is the ratio
    # of the elasto-active numbers" read literally)
    alt_k = _pick(size, (), (0.0, 0.4, 0.6, 0.7, 0.8, 1.0, 1.2), tuple(np.round(np.arange(0.0, 1.61, 0.1), 4)))
    alt_dur = _pick(size, 0.0, 2000.0, 4000.0)
    if alt_k:
        args = [(n, sigma, 0.75, k, alt_dur, alt_dur / 2) for k in alt_k]
        w = default_workers() if workers is None else workers
        with ProcessPoolExecutor(max_workers=max(1, min(w, len(args)))) as pool:
            alt = list(pool.map(_alt_pair_run, args))
        data["alt_kappa"] = np.array(alt_k)
        data["alt_mismatch"] = np.array([a["mismatch"] for a in alt])
        data["alt_locked"] = np.array([a["slips"] < 0.5 for a in alt])
        data["alt_f1"] = np.array([a["f1"] for a in alt])
        lo_a, hi_a = locking_threshold(alt_k, data["alt_locked"])
        summary["alt_same_stiffness"] = {"kappa_c_bracket": [lo_a, hi_a], "kappa_c": 0.5 * (lo_a + hi_a),
                                        "mismatch_lowest_kappa": float(data["alt_mismatch"][0]), "kappa_lowest": float(alt_k[0]),
                                        "kappa_max": float(alt_k[-1]), "f_locked_kappa_max": float(data["alt_f1"][-1])}
    return Study("sync", size, data, summary, time.perf_counter() - start)


def tongue_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """|frequency mismatch| and locking over (rho, kappa) for N = 7, sigma_1 = 0.8 (quick: reduced
    model; full: both engines)."""
    start = time.perf_counter()
    rhos = _pick(size, (0.5, 1.0, 3.0), (0.5, 0.75, 1.0, 4 / 3, 2.0, 3.0),
                 tuple(np.r_[np.geomspace(0.4, 4.0, 15), 4 / 3]))
    rhos = tuple(sorted(set(round(float(r), 6) for r in rhos)))
    kappas = _pick(size, (0.0, 0.1, 0.5), (0.0, 0.03, 0.07, 0.15, 0.3, 0.6),
                   (0.0, 0.01, 0.02, 0.035, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 0.8, 1.1, 1.5))
    engines = _pick(size, ("reduced",), ("reduced",), ENGINES)
    dur = _pick(size, 600.0, 2400.0, 6000.0)
    cases, meta = [], []
    for r in rhos:
        for k in kappas:
            for eng in engines:
                cases.append(Case(Physics(scene="coupled-pair", n=7, sigma=0.8, rho=r, kappa=k), _fast(perturbation=0.3, sample_dt=0.2),
                                  dur, eng, dur / 2))
                meta.append((r, k, eng))
    trajs = _run(cases, workers, progress, "Arnold tongue")
    data = {"rho": np.array(rhos), "kappa": np.array(kappas)}
    grids = {eng: (np.full((len(rhos), len(kappas)), np.nan), np.zeros((len(rhos), len(kappas)), bool)) for eng in engines}
    for (r, k, eng), tr in zip(meta, trajs):
        m = _pair_measures(tr, dur / 2)
        i, j = rhos.index(r), kappas.index(k)
        grids[eng][0][i, j] = m["mismatch"]
        grids[eng][1][i, j] = m["locked"]
    summary = {"engines": list(engines), "duration": dur}
    for eng in engines:
        data[f"mismatch_{eng}"], data[f"locked_{eng}"] = grids[eng]
        kc = np.array([locking_threshold(kappas, row)[1] for row in grids[eng][1]])
        data[f"kappa_c_{eng}"] = kc
        r = np.array(rhos)
        below, above = kc[r < 1], kc[r > 1]
        summary[eng] = {"kappa_c_by_rho": {f"{x:.4g}": float(y) for x, y in zip(rhos, kc)},
                        "tongue_widens": bool(np.all(np.diff(kc[r >= 1]) >= 0) and np.all(np.diff(kc[r <= 1]) <= 0)),
                        "kappa_c_min_rho": float(r[int(np.argmin(kc))])}
    return Study("tongue", size, data, summary, time.perf_counter() - start)


def kappa_c_formula(mu, rho):
    """The paper's near-onset N = 2 threshold kappa_c = 11 / (4 sqrt 6) sqrt(mu |1 - rho|)."""
    return 11.0 / (4.0 * math.sqrt(6.0)) * np.sqrt(np.asarray(mu) * np.abs(1.0 - np.asarray(rho)))


def kappa_c_phase_equation(mu, rho):
    """kappa_c from the supplement's own phase equation d Psi/dt = d nu + eps / cos Psi_0 sin(Psi - Psi_0):
    |d nu| = |eps / cos Psi_0| with d nu = 11/8 (rho - 1), eps = kappa (2 mu - 3 (rho - 1)) / (2 sqrt(mu (mu - 3 (rho - 1))))
    and tan Psi_0 = 3 (rho - 1) / (2 mu - 3 (rho - 1)). For |rho - 1| << mu it tends to 11/8 |1 - rho|."""
    mu, r = np.asarray(mu, float), np.asarray(rho, float) - 1.0
    per_kappa = np.sqrt((2 * mu - 3 * r) ** 2 + 9 * r**2) / (2 * np.sqrt(mu * (mu - 3 * r)))
    return 11.0 / 8.0 * np.abs(r) / per_kappa


def _bisect_locking(combos, make_case, lo0, hi0, steps, workers, progress, desc, transient_of):
    """Bisection on kappa for every combo at once (one batch per step)."""
    lo, hi = dict(lo0), dict(hi0)
    for step in range(steps):
        cases = [make_case(c, 0.5 * (lo[c] + hi[c])) for c in combos]
        trajs = _run(cases, workers, progress and step == 0, desc)
        for c, tr, case in zip(combos, trajs, cases):
            if _pair_measures(tr, transient_of(case))["locked"]:
                hi[c] = case.physics.kappa
            else:
                lo[c] = case.physics.kappa
    return lo, hi


def sync_n2_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """The locking threshold kappa_c of two N = 2 chains near onset (mu = sigma - 3 small, rho near 1),
    by bisection on kappa with the reduced model, checked with MuJoCo, against
    kappa_c = 11 / (4 sqrt 6) sqrt(mu |1 - rho|)."""
    start = time.perf_counter()
    combos = _pick(size, ((0.1, 0.98),), tuple((m, r) for m in (0.05, 0.1, 0.2) for r in (0.97, 0.99)),
                   tuple((m, r) for m in (0.05, 0.1, 0.2) for r in (0.97, 0.98, 0.99)))
    steps = _pick(size, 5, 9, 12)
    dur = _pick(size, 1500.0, 6000.0, 12000.0)

    def make(c, k, engine="reduced", dt=0.01, duration=dur):
        mu, rho = c
        num = Numerics(dt=dt, mass_ratio=1e-5 if engine == "mujoco" else 1e-4, perturbation=math.sqrt(mu), sample_dt=0.1)
        return Case(Physics(scene="coupled-pair", n=2, sigma=3.0 + mu, rho=rho, kappa=k), num, duration, engine, duration / 2)

    hi0 = {c: 2.0 * float(kappa_c_formula(*c)) for c in combos}
    lo, hi = _bisect_locking(combos, make, {c: 0.0 for c in combos}, hi0, steps, workers, progress, "kappa_c N=2",
                             lambda case: case.duration / 2)
    kc_red = {c: 0.5 * (lo[c] + hi[c]) for c in combos}
    # MuJoCo: quick checks the classification just below and above the reduced threshold for one combo;
    # full bisects every combo (dt small: implicitfast shifts the N = 2 onset by ~dt/2 in mu)
    mj_dt = 0.00125
    mj = {}
    if size == "full":
        mj_dur = _pick(size, 600.0, 3000.0, 6000.0)
        mlo, mhi = _bisect_locking(combos, lambda c, k: make(c, k, "mujoco", mj_dt, mj_dur), {c: 0.7 * kc_red[c] for c in combos},
                                   {c: 1.3 * kc_red[c] for c in combos}, 6, workers, progress, "kappa_c N=2 MuJoCo",
                                   lambda case: case.duration / 2)
        mj = {c: {"kappa_c": 0.5 * (mlo[c] + mhi[c]), "halfwidth": 0.5 * (mhi[c] - mlo[c])} for c in combos}
    else:
        c = combos[0] if size == "tiny" else (0.1, 0.97)
        probe = (0.85, 1.15)
        probe_dur = _pick(size, 1000.0, 3000.0, 3000.0)
        trajs = _run([make(c, f * kc_red[c], "mujoco", mj_dt, probe_dur) for f in probe], workers, progress,
                     "kappa_c N=2 MuJoCo check")
        checks = [_pair_measures(tr, probe_dur / 2)["locked"] for tr in trajs]
        mj = {c: {"probe_factors": list(probe), "locked": checks, "consistent": (not checks[0]) and checks[1]}}
    mus = np.array([c[0] for c in combos])
    rhos = np.array([c[1] for c in combos])
    kc = np.array([kc_red[c] for c in combos])
    half = np.array([0.5 * (hi[c] - lo[c]) for c in combos])
    formula = kappa_c_formula(mus, rhos)
    phase_eq = kappa_c_phase_equation(mus, rhos)
    data = {"mu": mus, "rho": rhos, "kappa_c_reduced": kc, "kappa_c_halfwidth": half, "kappa_c_formula": formula,
            "kappa_c_phase_equation": phase_eq}
    if size == "full":
        data["kappa_c_mujoco"] = np.array([mj[c]["kappa_c"] for c in combos])
    x = np.sqrt(mus * np.abs(1 - rhos))
    prefactor = kc / x
    summary = {"duration": dur, "combos": [list(c) for c in combos],
               "prefactor_formula": 11.0 / (4.0 * math.sqrt(6.0)),
               "prefactor_fit": float(np.sum(kc * x) / np.sum(x * x)),
               "prefactor_mean": float(prefactor.mean()), "prefactor_std": float(prefactor.std()),
               "ratio_sim_over_formula": [float(v) for v in kc / formula],
               "ratio_sim_over_phase_equation": [float(v) for v in kc / phase_eq],
               "kappa_c": [float(v) for v in kc], "kappa_c_formula": [float(v) for v in formula],
               "kappa_c_phase_equation": [float(v) for v in phase_eq],
               "mujoco": {f"{c[0]:g},{c[1]:g}": v for c, v in mj.items()}}
    if len(set(mus)) >= 2 and len(set(rhos)) >= 2:
        A = np.column_stack([np.ones_like(mus), np.log(mus), np.log(np.abs(1 - rhos))])
        coef, cov = fits._lstsq(A, np.log(kc))
        summary["exponent_mu"], summary["exponent_mu_err"] = float(coef[1]), float(math.sqrt(cov[1, 1]))
        summary["exponent_rho"], summary["exponent_rho_err"] = float(coef[2]), float(math.sqrt(cov[2, 2]))
    return Study("sync_n2", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# 8. noise and anisotropic drag, N = 2, sigma = 3.5 (supplement)
# --------------------------------------------------------------------------------------------------
def noise_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Limit cycles (Omega, Theta) of the N = 2 chain at sigma = 3.5 with multiplicative white noise
    of amplitude a on the active force (same seeded noise in both engines); period and amplitude
    variability as measures of irregularity."""
    start = time.perf_counter()
    amps = _pick(size, (0.0, 0.1), (0.0, 0.05, 0.1, 0.2, 0.3), (0.0, 0.02, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4))
    dur = _pick(size, 150.0, 600.0, 2000.0)
    transient = 50.0
    cases, meta = [], []
    for a in amps:
        for eng in ENGINES:
            cases.append(Case(Physics(n=2, sigma=PAPER["noise_sigma"], noise=a), _fast(perturbation=0.5, sample_dt=0.05, seed=1),
                              dur, eng, transient))
            meta.append((a, eng))
    trajs = _run(cases, workers, progress, "noise N=2")
    data = {"noise": np.array(amps)}
    out = {}
    for (a, eng), tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)
        amp = obs.amplitude(tr.t, x, transient)
        osc = obs.is_oscillating(tr.t, x, threshold=1e-2, transient=transient)
        out[(a, eng)] = (amp, _safe(ms.period_variability, tr.t, x, transient) if osc else np.nan,
                         _safe(ms.amplitude_variability, tr.t, x, transient) if osc else np.nan, osc)
        if eng == "mujoco":
            m = tr.t >= transient
            m &= tr.t <= transient + min(150.0, dur - transient)
            om, th = obs.limit_cycle(tr.theta[m])
            data[f"cycle_{a:g}_omega"], data[f"cycle_{a:g}_theta"] = om, th
    summary = {"sigma": PAPER["noise_sigma"], "seed": 1}
    for eng in ENGINES:
        for i, key in enumerate(("amplitude", "period_cv", "amplitude_cv", "sustained")):
            data[f"{key}_{eng}"] = np.array([out[(a, eng)][i] for a in amps])
        cv = data[f"period_cv_{eng}"]
        ok = np.isfinite(cv)
        summary[eng] = {"period_cv": {f"{a:g}": float(v) for a, v in zip(amps, cv)},
                        "amplitude": {f"{a:g}": float(v) for a, v in zip(amps, data[f"amplitude_{eng}"])},
                        "not_sustained": [f"{a:g}" for a, v in zip(amps, data[f"sustained_{eng}"]) if not v],
                        "amplitude_cv": {f"{a:g}": float(v) for a, v in zip(amps, data[f"amplitude_cv_{eng}"])},
                        "irregularity_increases": bool(np.all(np.diff(cv[ok]) > 0)) if ok.sum() >= 2 else None}
    return Study("noise", size, data, summary, time.perf_counter() - start)


def anisotropy_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """N = 2, sigma = 3.5: limit cycles, amplitude and frequency against tau_L / tau_T (both engines),
    and the onset: growth rates of a small kick at sigma = 3 -/+ 0.2 for each ratio (linear theory:
    -/+ 0.2 whatever the ratio), interpolated to the onset sigma."""
    start = time.perf_counter()
    ratios = _pick(size, (1.0, 4.0), (0.5, 1.0, 2.0, 4.0, 8.0), (0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0))
    dur = _pick(size, 150.0, 400.0, 1000.0)
    transient = dur / 2
    cases, meta = [], []
    for r in ratios:
        for eng in ENGINES:
            cases.append(Case(Physics(n=2, sigma=PAPER["anisotropy_sigma"], drag_ratio=r), _fast(perturbation=0.5, sample_dt=0.05),
                              dur, eng, transient))
            meta.append(("cycle", r, 0.0, eng))
            for s in (2.8, 3.2):
                cases.append(Case(Physics(n=2, sigma=s, drag_ratio=r),
                                  Numerics.preset("accurate", perturbation=1e-5, sample_dt=0.05), 25.0, eng, 0.0))
                meta.append(("growth", r, s, eng))
    trajs = _run(cases, workers, progress, "anisotropic drag N=2")
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
    summary = {"sigma": PAPER["anisotropy_sigma"], "linear_rate_at_3.2": float(stab.eigenvalues(2, 3.2)[0].real)}
    for eng in ENGINES:
        amp = np.array([out[("amp", r, eng)] for r in ratios])
        data[f"amplitude_{eng}"] = amp
        data[f"frequency_{eng}"] = np.array([out[("freq", r, eng)] for r in ratios])
        g_lo = np.array([out[("rate", r, 2.8, eng)] for r in ratios])
        g_hi = np.array([out[("rate", r, 3.2, eng)] for r in ratios])
        onset = 2.8 + 0.4 * g_lo / (g_lo - g_hi)
        data[f"rate_2.8_{eng}"], data[f"rate_3.2_{eng}"], data[f"onset_{eng}"] = g_lo, g_hi, onset
        summary[eng] = {"amplitude": {f"{r:g}": float(a) for r, a in zip(ratios, amp)},
                        "amplitude_decreasing": bool(np.all(np.diff(amp) < 0)),
                        "onset": {f"{r:g}": float(o) for r, o in zip(ratios, onset)},
                        "onset_max_dev": float(np.max(np.abs(onset - 3.0)))}
    return Study("anisotropy", size, data, summary, time.perf_counter() - start)


STUDIES = {
    "stability": stability_study,
    "growth": growth_study,
    "hopf": hopf_study,
    "normal_form": normal_form_study,
    "snapping": snapping_study,
    "rotation": rotation_study,
    "sync": sync_study,
    "tongue": tongue_study,
    "sync_n2": sync_n2_study,
    "noise": noise_study,
    "anisotropy": anisotropy_study,
}
"""Every study by name, in the order reproduce runs them."""


def load_study(folder: Path, name: str) -> Study:
    """Read back a saved study (NPZ + JSON)."""
    folder = Path(folder)
    meta = json.loads((folder / f"{name}.json").read_text())
    with np.load(folder / f"{name}.npz") as f:
        data = {k: f[k] for k in f.files}
    return Study(name, meta["size"], data, meta["summary"], meta.get("wall_s", 0.0))

"""The locking threshold kappa_c of two N = 2 chains near onset (mu = sigma - 3 small, rho near 1), by bisection on
kappa with the reduced model, checked with MuJoCo, against the supplement's kappa_c = 11/(4 sqrt 6) sqrt(mu |1 - rho|)
and its own phase equation.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import fits
from ..batch import Case
from ..core.params import Numerics
from ..scenes import coupled_pair
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick, run
from .paper import PAPER
from .sync import kappa_c_formula, kappa_c_phase_equation, pair_measures


@dataclass(frozen=True)
class N2MujocoCheck(Summary):
    """MuJoCo against the reduced kappa_c of one (mu, rho): full size bisects (kappa_c, halfwidth);
    smaller sizes probe just below and above the reduced threshold (probe_factors, locked, consistent)."""

    kappa_c: float | None = None
    halfwidth: float | None = None
    probe_factors: list[float] | None = None
    locked: list[bool] | None = None
    consistent: bool | None = None


@dataclass(frozen=True)
class SyncN2Summary(Summary):
    duration: float
    combos: list[tuple[float, float]]
    """(mu, rho) of each point."""
    prefactor_formula: float
    prefactor_fit: float
    prefactor_mean: float
    prefactor_std: float
    ratio_sim_over_formula: list[float]
    ratio_sim_over_phase_equation: list[float]
    kappa_c: list[float]
    """Reduced model, by bisection."""
    kappa_c_formula: list[float]
    kappa_c_phase_equation: list[float]
    mujoco: dict[str, N2MujocoCheck]
    """By "mu,rho"."""
    exponent_mu: float | None = None
    exponent_mu_err: float | None = None
    exponent_rho: float | None = None
    exponent_rho_err: float | None = None


# --------------------------------------------------------------------------------------------------
# N = 2 near onset
# --------------------------------------------------------------------------------------------------
def _bisect_locking(combos, make_case, lo0, hi0, steps, workers, progress, desc, transient_of):
    """Bisection on kappa for every combo at once (one batch per step, each with its own progress line, so that
    every step's time shows)."""
    lo, hi = dict(lo0), dict(hi0)
    for step in range(steps):
        cases = [make_case(c, 0.5 * (lo[c] + hi[c])) for c in combos]
        trajs = run(cases, workers, progress, f"{desc} (bisection step {step + 1}/{steps})")
        for c, tr, case in zip(combos, trajs, cases):
            if pair_measures(tr, transient_of(case))["locked"]:
                hi[c] = case.physics.kappa
            else:
                lo[c] = case.physics.kappa
    return lo, hi


SYNC_N2 = registry.declare("sync_n2", summary=SyncN2Summary, order=90, budget=11.5)


@SYNC_N2.run
def sync_n2_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """The locking threshold kappa_c of two N = 2 chains near onset (mu = sigma - 3 small, rho near 1),
    by bisection on kappa with the reduced model, checked with MuJoCo, against
    kappa_c = 11 / (4 sqrt 6) sqrt(mu |1 - rho|)."""
    start = time.perf_counter()
    combos = pick(
        size,
        ((0.1, 0.98),),
        tuple((m, r) for m in (0.05, 0.1, 0.2) for r in (0.97, 0.99)),
        tuple((m, r) for m in (0.05, 0.1, 0.2) for r in (0.97, 0.98, 0.99)),
    )
    # the bisection's bracket: (0, top x the formula's kappa_c). At quick every combo locks at the formula's kappa_c
    # (the simulated one is 0.35-0.6 of it), so 8 steps from (0, formula) probe what 9 steps from (0, 2 x formula) do
    # after their first, which locks them all
    top, steps = pick(size, (2.0, 5), (1.0, 8), (2.0, 12))
    dur = pick(size, 1500.0, 4000.0, 12000.0)

    def make(c, k, engine="reduced", dt=0.01, duration=dur):
        mu, rho = c
        num = Numerics(
            dt=dt, mass_ratio=1e-5 if engine == "mujoco" else 1e-4, perturbation=math.sqrt(mu), sample_dt=0.1
        )
        return Case(
            coupled_pair.SCENE.physics(n=2, sigma=3.0 + mu, rho=rho, kappa=k), num, duration, engine, duration / 2
        )

    hi0 = {c: top * float(kappa_c_formula(*c)) for c in combos}
    lo, hi = _bisect_locking(
        combos,
        make,
        {c: 0.0 for c in combos},
        hi0,
        steps,
        workers,
        progress,
        "kappa_c N=2",
        lambda case: case.duration / 2,
    )
    kc_red = {c: 0.5 * (lo[c] + hi[c]) for c in combos}
    # MuJoCo: quick checks the classification just below and above the reduced threshold for one combo;
    # full bisects every combo (dt small: implicitfast shifts the N = 2 onset by ~dt/2 in mu)
    mj_dt = 0.00125
    if size == "full":
        mj_dur = pick(size, 600.0, 3000.0, 6000.0)
        mlo, mhi = _bisect_locking(
            combos,
            lambda c, k: make(c, k, "mujoco", mj_dt, mj_dur),
            {c: 0.7 * kc_red[c] for c in combos},
            {c: 1.3 * kc_red[c] for c in combos},
            6,
            workers,
            progress,
            "kappa_c N=2 MuJoCo",
            lambda case: case.duration / 2,
        )
        mj = {c: N2MujocoCheck(kappa_c=0.5 * (mlo[c] + mhi[c]), halfwidth=0.5 * (mhi[c] - mlo[c])) for c in combos}
    else:
        c = combos[0] if size == "tiny" else (0.1, 0.97)
        probe = (0.85, 1.15)
        probe_dur = pick(size, 1000.0, 1000.0, 3000.0)  # quick: ~2 slips in the window at 0.85 x, none at 1.15 x
        # dt = 2 mj_dt: its onset shift (~dt/2 = 0.00125 in mu, ~0.6% in kappa_c at mu = 0.1) is far inside the probes'
        # ±15% (at dt = 0.00125 too: 2.95 slips at 0.85 x, none at 1.15 x, against 2.97 and none at 0.0025, 1500 tau)
        trajs = run(
            [make(c, f * kc_red[c], "mujoco", 2 * mj_dt, probe_dur) for f in probe],
            workers,
            progress,
            "kappa_c N=2 MuJoCo check",
        )
        checks = [pair_measures(tr, probe_dur / 2)["locked"] for tr in trajs]
        mj = {c: N2MujocoCheck(probe_factors=list(probe), locked=checks, consistent=(not checks[0]) and checks[1])}
    mus = np.array([c[0] for c in combos])
    rhos = np.array([c[1] for c in combos])
    kc = np.array([kc_red[c] for c in combos])
    half = np.array([0.5 * (hi[c] - lo[c]) for c in combos])
    formula = kappa_c_formula(mus, rhos)
    phase_eq = kappa_c_phase_equation(mus, rhos)
    data = {
        "mu": mus,
        "rho": rhos,
        "kappa_c_reduced": kc,
        "kappa_c_halfwidth": half,
        "kappa_c_formula": formula,
        "kappa_c_phase_equation": phase_eq,
    }
    if size == "full":
        data["kappa_c_mujoco"] = np.array([mj[c].kappa_c for c in combos])
    x = np.sqrt(mus * np.abs(1 - rhos))
    prefactor = kc / x
    exponents = {}
    if len(set(mus)) >= 2 and len(set(rhos)) >= 2:
        A = np.column_stack([np.ones_like(mus), np.log(mus), np.log(np.abs(1 - rhos))])
        coef, cov = fits._lstsq(A, np.log(kc))
        exponents = {
            "exponent_mu": float(coef[1]),
            "exponent_mu_err": float(math.sqrt(cov[1, 1])),
            "exponent_rho": float(coef[2]),
            "exponent_rho_err": float(math.sqrt(cov[2, 2])),
        }
    summary = SyncN2Summary(
        duration=dur,
        combos=[tuple(c) for c in combos],
        prefactor_formula=PAPER.kappa_c_n2_prefactor,
        prefactor_fit=float(np.sum(kc * x) / np.sum(x * x)),
        prefactor_mean=float(prefactor.mean()),
        prefactor_std=float(prefactor.std()),
        ratio_sim_over_formula=[float(v) for v in kc / formula],
        ratio_sim_over_phase_equation=[float(v) for v in kc / phase_eq],
        kappa_c=[float(v) for v in kc],
        kappa_c_formula=[float(v) for v in formula],
        kappa_c_phase_equation=[float(v) for v in phase_eq],
        mujoco={f"{c[0]:g},{c[1]:g}": v for c, v in mj.items()},
        **exponents,
    )
    return Study("sync_n2", size, data, summary, time.perf_counter() - start)


@SYNC_N2.figure
@plots.styled
def sync_n2_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, ax = plt.subplots(figsize=(6, 4.5))
    x = np.sqrt(d["mu"] * np.abs(1 - d["rho"]))
    xx = np.linspace(0, x.max() * 1.15, 50)
    printed = r"$\frac{11}{4\sqrt{6}}\sqrt{\mu|1-\rho|}$"  # PAPER.kappa_c_n2_printed, typeset
    ax.plot(
        xx, s.prefactor_formula * xx, "k--", lw=1, label=f"supplement: {printed} (prefactor {s.prefactor_formula:.3f})"
    )
    ax.plot(xx, s.prefactor_fit * xx, "C3-", lw=0.8, label=f"fit through 0: prefactor {s.prefactor_fit:.3f}")
    ax.errorbar(
        x, d["kappa_c_reduced"], yerr=d["kappa_c_halfwidth"], fmt="x", color="C3", label="reduced model (bisection)"
    )
    ax.plot(x, d["kappa_c_phase_equation"], "+", color="C2", ms=9, label="supplement's phase equation, solved exactly")
    if "kappa_c_mujoco" in d:
        ax.plot(x, d["kappa_c_mujoco"], **plots.ENGINE_STYLE["mujoco"])
    rhos = sorted(set(np.round(d["rho"], 6)))
    for xi, yi, yp, mu, rho in zip(x, d["kappa_c_reduced"], d["kappa_c_phase_equation"], d["mu"], d["rho"]):
        # label above the higher of the two markers for the larger |1 - rho|, below the lower one otherwise
        up = np.isclose(rho, rhos[0])
        ax.annotate(
            f"μ={mu:g}\nρ={rho:g}",
            (xi, max(yi, yp) if up else min(yi, yp)),
            fontsize=7,
            ha="center",
            va="bottom" if up else "top",
            xytext=(0, 5 if up else -6),
            textcoords="offset points",
            color="0.3",
        )
    ax.set_xlabel(r"$\sqrt{\mu|1-\rho|}$")
    ax.set_ylabel(r"locking threshold $\kappa_c$")
    ax.set_ylim(-0.005, ax.get_ylim()[1])
    ax.legend(loc="upper left")
    ax.set_title(r"N = 2 pair near onset ($\mu=\sigma_1-3$, $\rho=C_2/C_1$)")
    fig.tight_layout()
    return [plots.save(fig, out, "sync_n2_kappa_c.png")]

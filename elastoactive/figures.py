"""Figures of the studies (matplotlib, Agg backend), one function per study, each writing PNGs
that mirror the paper's panels. Every function takes a `Study` and an output folder and returns
the paths it wrote."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .analysis.measures import chain_positions  # noqa: E402
from .analysis.normal_form import landau_limit_cycle  # noqa: E402
from .paper import PAPER  # noqa: E402

if TYPE_CHECKING:  # typing only: the studies import both engines (start-up time)
    from .studies import Study

STABLE = dict(color="0.88", zorder=0)
ENGINE_STYLE = {
    "mujoco": dict(marker="o", ls="none", mfc="none", color="C0", label="MuJoCo"),
    "reduced": dict(marker="x", ls="none", color="C3", label="reduced model"),
}


def _save(fig, out: Path, name: str) -> Path:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    fig.savefig(path, dpi=130, bbox_inches="tight")
    plt.close(fig)
    return path


def _log_ticks(ax, values, axis: str = "x") -> None:
    """Plain tick labels at the given values on a log axis (no 2 x 10^0 clutter)."""
    a = ax.xaxis if axis == "x" else ax.yaxis
    a.set_minor_formatter(matplotlib.ticker.NullFormatter())
    (ax.set_xticks if axis == "x" else ax.set_yticks)(list(values))
    (ax.set_xticklabels if axis == "x" else ax.set_yticklabels)([f"{v:g}" for v in values])


def _engines(data: dict, prefix: str):
    return [e for e in ("mujoco", "reduced") if f"{prefix}_{e}" in data]


# ------------------------------------------------------------------------------------------------
def stability(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    paths = []
    fig, axes = plt.subplots(2, 2, figsize=(9, 6.5))
    for row, (n, sc) in enumerate(((2, s.sigma_c_2), (7, s.sigma_c_7))):
        sig = d[f"eig_sigma_{n}"]
        for col, (part, lab) in enumerate((("re", "Re"), ("im", "Im"))):
            ax = axes[row, col]
            ax.axvspan(sig[0], sc, **STABLE)
            ax.plot(sig, d[f"eig_{part}_{n}"], ".", ms=1.5, color="k")
            ax.axvline(sc, color="C3", lw=0.8, ls="--")
            if part == "re":
                ax.axhline(0, color="0.5", lw=0.6)
                top = d[f"eig_re_{n}"][:, 0]
                ax.set_ylim(-1.5 * abs(top).max(), 1.3 * max(top.max(), 0.01))
            ax.set_xlabel(r"$\sigma$")
            ax.set_ylabel(rf"{lab} $\lambda\,\tau$")
            ax.set_title(rf"N = {n}: {lab} of the eigenvalues ($\sigma_c$ = {sc:.4f})", fontsize=9)
    fig.suptitle("Fig. 3c-d: eigenvalues of the linearised chain against sigma (grey: stable)")
    fig.tight_layout()
    paths.append(_save(fig, out, "fig3cd_eigenvalues.png"))

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    n, sc = d["n"], d["sigma_c"]
    a1.loglog(n, sc, "o", ms=3, color="C0", label=r"$\sigma_c(N)$ (linear stability)")
    a1.loglog(n, s.continuum_onset / n.astype(float) ** 3, "k-", lw=1, label=rf"$S_c/N^3$, $S_c$ = {s.continuum_onset:.2f} (continuum)")
    a1.set_xlabel("N")
    a1.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    a1.set_ylabel(r"$\sigma_c$")
    a1.legend(fontsize=8)
    a1.set_title(rf"Fig. A-size: slope for N $\geq$ {s.n_fit_min}: {s.exponent_large_n:.3f}", fontsize=9)
    inv = 1.0 / n
    a2.plot(inv, d["n3_sigma_c"], "o", ms=3, label=r"$N^3\sigma_c$")
    p = s.fit_n3.params
    xx = np.linspace(0, 1.0 / s.n_fit_min, 100)
    a2.plot(xx, p["limit"] + p["b1"] * xx + p["b2"] * xx**2, "C1-", label=f"fit a + b/N + c/N², a = {p['limit']:.2f}")
    a2.axhline(s.continuum_onset, color="k", lw=0.8, ls="--", label=f"continuum onset {s.continuum_onset:.2f}")
    lo, hi = PAPER.continuum_bracket
    a2.axhspan(lo, hi, color="C2", alpha=0.12, label=f"~{PAPER.continuum_onset:g} (filament codes: {lo:g} decays, {hi:g} grows)")
    a2.set_xlabel("1/N")
    a2.set_ylabel(r"$N^3\sigma_c$")
    a2.set_xlim(0, 0.52)
    a2.legend(fontsize=7)
    a2.set_title("N³σ_c against 1/N, extrapolated to N → ∞", fontsize=9)
    fig.tight_layout()
    paths.append(_save(fig, out, "figA_size_effect.png"))
    return paths


def growth(study: Study, out: Path) -> list[Path]:
    d = study.data
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    th = d["rate_theory"]
    lim = np.abs(th).max() * 1.2
    a1.plot([-lim, lim], [-lim, lim], "k-", lw=0.6)
    for eng in _engines(d, "rate"):
        a1.plot(th, d[f"rate_{eng}"], **ENGINE_STYLE[eng])
    a1.set_xscale("symlog", linthresh=1e-3)
    a1.set_yscale("symlog", linthresh=1e-3)
    a1.set_xlabel(r"Re $\lambda$ (eigenvalue)")
    a1.set_ylabel("measured growth rate")
    a1.legend(fontsize=8)
    a1.set_title(r"small kicks at $\sigma_c(1 \mp \epsilon)$, N = " + ", ".join(str(int(x)) for x in d["per_n_n"]), fontsize=9)
    nn = d["per_n_n"]
    a2.loglog(nn, d["per_n_sigma_c_linear"], "k-", lw=1, label="linear stability")
    for eng in ("mujoco", "reduced"):
        if f"per_n_sigma_c_{eng}" in d:
            a2.loglog(nn, d[f"per_n_sigma_c_{eng}"], **ENGINE_STYLE[eng])
    a2.set_xlabel("N")
    _log_ticks(a2, nn)
    a2.set_ylabel(r"$\sigma_c$ (rates interpolated to 0)")
    a2.legend(fontsize=8)
    fig.tight_layout()
    return [_save(fig, out, "growth_rates.png")]


def hopf(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    sig = d["sigma"]
    sc = s.sigma_c_linear
    paths = []
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax in (a1, a2):
        ax.axvspan(0, sc, **STABLE)
        ax.set_xlim(sig.min() - 0.02, sig.max() + 0.02)
        ax.set_xlabel(r"$\sigma$")
    for eng in _engines(d, "amplitude"):
        a1.plot(sig, d[f"amplitude_{eng}"], **ENGINE_STYLE[eng])
        a2.plot(sig, d[f"frequency_{eng}"], **ENGINE_STYLE[eng])
    pl = s.mujoco.power_law
    plc = s.mujoco.power_law_corrected
    if plc:
        p = plc.params
        xx = np.linspace(p["onset"] + 1e-7, s.fit_sigma_max_corrected, 200)
        a1.plot(xx, p["prefactor"] * (xx - p["onset"]) ** p["beta"] * (1 + p["c"] * (xx - p["onset"])), "C0-", lw=1,
                label=rf"fit $a\Delta^\beta(1+c\Delta)$: $\sigma_c$={p['onset']:.5f}, $\beta$={p['beta']:.3f}")
    a1.axvline(sc, color="C3", ls="--", lw=0.8, label=f"linear stability {sc:.4f}")
    a1.set_ylabel(r"amplitude of $\Theta$ (rad)")
    a1.legend(fontsize=7, loc="lower left", bbox_to_anchor=(0.12, 0.02))
    a1.set_title("Fig. 3a: N = 7, amplitude of the beat", fontsize=9)
    if pl:
        ins = a1.inset_axes([0.62, 0.1, 0.35, 0.42])
        for eng in _engines(d, "amplitude"):
            ok = d[f"sustained_{eng}"].astype(bool)
            ins.loglog(sig[ok] - pl.params["onset"], d[f"amplitude_{eng}"][ok], **{**ENGINE_STYLE[eng], "ms": 3})
        xx = np.geomspace(1e-3, 1, 50)
        ins.loglog(xx, pl.params["prefactor"] * xx**PAPER.hopf_exponent, "k--", lw=0.7)
        ins.set_xlabel(r"$\sigma-\sigma_c$", fontsize=7)
        ins.tick_params(labelsize=6)
        ins.set_title(f"log-log; dashed: slope {PAPER.hopf_exponent:g} (paper)", fontsize=6)
        ins.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ins.xaxis.set_major_locator(matplotlib.ticker.LogLocator(numticks=4))
    lin = s.mujoco.freq_linear_all
    if lin:
        xx = np.linspace(sc, sig.max(), 50)
        a2.plot(xx, lin.params["intercept"] + lin.params["slope"] * xx, "k-", lw=0.7,
                label=f"linear fit, R² = {lin.r2:.4f}")
    a2.plot([sc], [s.f_c_linear], "r*", ms=10, label=f"onset (linear stability) f τ = {s.f_c_linear:.5f}")
    a2.set_ylabel(r"$f\tau$")
    a2.legend(fontsize=7)
    a2.set_title("Fig. 3b: N = 7, frequency", fontsize=9)
    fig.tight_layout()
    paths.append(_save(fig, out, "fig3ab_hopf.png"))

    keys = sorted({k.split("_")[1] for k in d if k.startswith("cycle_") and k.endswith("_omega")}, key=float)
    if keys:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
        big = keys[-1]
        t = d[f"series_{big}_t"]
        a1.plot(t - t[0], d[f"series_{big}_theta"], label=r"$\Theta=\theta_N-\theta_1$")
        a1.plot(t - t[0], d[f"series_{big}_omega"], label=r"$\Omega=\langle\theta_i\rangle$")
        a1.set_xlabel(r"$t/\tau$")
        a1.set_ylabel("rad")
        a1.legend(fontsize=8)
        a1.set_title(rf"Fig. 2e: time series, N = 7, $\sigma$ = {big} (MuJoCo)", fontsize=9)
        for k in keys:
            a2.plot(d[f"cycle_{k}_omega"], d[f"cycle_{k}_theta"], lw=1, label=rf"$\sigma$ = {k}")
        a2.set_xlabel(r"$\Omega$ (rad)")
        a2.set_ylabel(r"$\Theta$ (rad)")
        a2.legend(fontsize=8)
        a2.set_title("Fig. 2f: limit cycles (MuJoCo)", fontsize=9)
        fig.tight_layout()
        paths.append(_save(fig, out, "fig2_limit_cycles.png"))
    return paths


def normal_form(study: Study, out: Path) -> list[Path]:
    d = study.data
    mu = d["mu"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    mm = np.linspace(0, mu.max() * 1.1, 100)
    for c, where, style in ((PAPER.landau_supplement, "supplement", "k-"), (PAPER.landau_main, "main text", "k--")):
        z2, om = landau_limit_cycle(mm, c.at_onset, c.slope)
        lab = f"{where} c = {c.printed_at_onset}"
        a1.plot(mm, z2, style, lw=1, label=lab)
        a2.plot(mm, om, style, lw=1, label=lab)
    for key, style in (("reduced", ENGINE_STYLE["reduced"]), ("mujoco", {**ENGINE_STYLE["mujoco"], "label": "MuJoCo (dt → 0)"})):
        a1.plot(mu, d[f"z2_{key}"], **style)
        a2.plot(mu, d[f"omega_{key}"], **style)
    a1.set_xlabel(r"$\mu=\sigma-3$")
    a1.set_ylabel(r"$\langle|z|^2\rangle$")
    a1.legend(fontsize=7)
    a1.set_title(r"N = 2 limit cycle: $\langle|z|^2\rangle \to \mu/(-\mathrm{Re}\,c)$", fontsize=9)
    a2.set_xlabel(r"$\mu$")
    a2.set_ylabel(r"$\omega\tau$")
    a2.legend(fontsize=7)
    a2.set_title(r"$\omega \to 1 + \mathrm{Im}\,c\,\langle|z|^2\rangle$", fontsize=9)
    fig.tight_layout()
    return [_save(fig, out, "normal_form_n2.png")]


def snapping(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    paths = []
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for s_, c in zip(s.n7_sigmas, ("C0", "C1")):
        for eng in ("mujoco", "reduced"):
            st = {**ENGINE_STYLE[eng], "color": c, "label": rf"$\sigma$={s_} {ENGINE_STYLE[eng]['label']}"}
            a1.plot(d["delta"], d[f"snap_{s_:g}_{eng}"], **st)
            a2.plot(d["delta"], d[f"freq_{s_:g}_{eng}"], **st)
    a1.set_xlabel(r"compression $\delta$")
    a1.set_ylabel(r"std of $\theta_3$ (rad)")
    a1.set_title("Fig. 4c: self-snapping amplitude, N = 7", fontsize=9)
    a1.legend(fontsize=7)
    a2.set_xlabel(r"compression $\delta$")
    a2.set_ylabel(r"$f\tau$")
    a2.set_title("Fig. 4d: self-snapping frequency, N = 7", fontsize=9)
    fig.tight_layout()
    paths.append(_save(fig, out, "fig4cd_snapping.png"))

    if "example_theta" in d:
        fig, ax = plt.subplots(figsize=(6, 3))
        th = d["example_theta"]
        idx = np.linspace(0, th.shape[0] - 1, 9).astype(int)[:-1]  # eight frames over one period
        for k, i in enumerate(idx):
            x, y = chain_positions(th[i])
            ax.plot(np.r_[0, x], np.r_[0, y], "-o", ms=3, color=plt.cm.viridis(k / len(idx)))
        ax.set_aspect("equal")
        ax.set_xlabel("x / l (colour: time within the period)")
        ax.set_ylabel("y / l")
        ax.set_title(rf"Fig. 4b: one snapping period, N = 7, $\sigma$ = {PAPER.snapping_sigma:g}, $\delta$ = 0.1 (MuJoCo)",
                     fontsize=9)
        paths.append(_save(fig, out, "fig4b_snapping_shapes.png"))

    engines = _engines(d, "map_snap")
    if engines:
        fig, axes = plt.subplots(1, len(engines), figsize=(5.2 * len(engines), 4), squeeze=False)
        for ax, eng in zip(axes[0], engines):
            m = ax.pcolormesh(d["map_delta"], d["map_sigma"], d[f"map_snap_{eng}"], shading="nearest", cmap="magma")
            fig.colorbar(m, ax=ax, label=r"std of $\theta_3$ (rad)")
            thr = s.engine(eng).sigma_snap_n9
            if thr:
                ax.plot([s.threshold_delta], [thr], "c*", ms=12, label=rf"threshold at $\delta$={s.threshold_delta}: $\sigma$={thr:.3f}")
                ax.legend(fontsize=7, loc="upper left")
            ax.set_xlabel(r"$\delta$")
            ax.set_ylabel(r"$\sigma$")
            ax.set_title(f"Fig. A-snapping map, N = {PAPER.snapping_map_n} ({ENGINE_STYLE[eng]['label']})", fontsize=9)
        fig.tight_layout()
        paths.append(_save(fig, out, "figA_snapping_map.png"))
    return paths


def rotation(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    sig = d["sigma"]
    a1.axvspan(0, s.sigma_r_linear, **STABLE)
    for eng in ("mujoco", "reduced"):
        a1.plot(sig, np.abs(d[f"rate_{eng}"]), **ENGINE_STYLE[eng])
        seeds = d[f"seed_rate_{eng}"]
        x = np.full(seeds.size, s.sigma_seeds)
        if eng == "mujoco":
            a1.plot(x[seeds > 0] + 0.01, seeds[seeds > 0], "^", color="C2", ms=6, label=f"seeds, counter-clockwise ({(seeds > 0).sum()})")
            a1.plot(x[seeds < 0] + 0.01, -seeds[seeds < 0], "v", color="C4", ms=6, label=f"seeds, clockwise ({(seeds < 0).sum()}, |rate| shown)")
    a1.axvline(s.sigma_r_linear, color="C3", ls="--", lw=0.8, label=f"linear threshold {s.sigma_r_linear:.4f}")
    a1.set_xlabel(r"$\sigma$")
    a1.set_ylabel(r"|rotation rate| (rad/$\tau$)")
    a1.legend(fontsize=7)
    a1.set_title("Freely rotating pin, N = 7: steady rotation", fontsize=9)
    shapes = d["shape_mujoco"]
    turning = np.abs(d["rate_mujoco"]) > 1e-4
    picks = [i for i in np.flatnonzero(turning)][:: max(1, int(turning.sum() // 5))]
    for i in picks:
        sh = shapes[i] * np.sign(d["rate_mujoco"][i])  # same sense of rotation for all
        x, y = chain_positions(sh)
        a2.plot(np.r_[0, x], np.r_[0, y], "-o", ms=3, label=rf"$\sigma$ = {sig[i]:g}")
    a2.set_aspect("equal")
    a2.set_xlabel("x / l (frame turning with pendulum 1)")
    a2.set_ylabel("y / l")
    a2.legend(fontsize=7)
    a2.set_title("steady shapes (MuJoCo), rotation mirrored to one sense", fontsize=9)
    fig.tight_layout()
    return [_save(fig, out, "figA_rotating_pin.png")]


def sync(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    paths = []
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for k in d.get("psi_kappas", []):
        t, psi = d[f"psi_{k:g}_t"], d[f"psi_{k:g}"]
        a1.plot(t, psi, label=rf"$\kappa$ = {k:g}")
    a1.set_xlabel(r"$t/\tau$")
    a1.set_ylabel(r"$\Psi=\Phi_2-\Phi_1$ (rad)")
    a1.legend(fontsize=8)
    a1.set_title(rf"Fig. 5e: phase difference, N = 7, $\sigma_1$ = {PAPER.sync_sigma_1:g}, $\sigma_2$ = {PAPER.sync_sigma_2:g} (MuJoCo)",
                 fontsize=9)
    kap = d["kappa"]
    for eng in ("mujoco", "reduced"):
        a2.plot(kap, np.abs(d[f"mismatch_{eng}"]), **ENGINE_STYLE[eng])
        kc = s.engine(eng).kappa_c
        if np.isfinite(kc if kc is not None else np.nan):
            a2.axvline(kc, color=ENGINE_STYLE[eng]["color"], lw=0.8, ls=":")
    if "alt_kappa" in d:
        a2.plot(d["alt_kappa"], np.abs(d["alt_mismatch"]), "s-", color="C2", ms=4, mfc="none",
                label="what-if: C2 = C1, F2 = 0.75 F1 (reduced)")
    a2.axvline(PAPER.kappa_c_7, color="k", ls="--", lw=0.8, label=rf"paper $\kappa_c$ = {PAPER.kappa_c_7:g}")
    a2.set_xscale("symlog", linthresh=0.02)
    a2.set_xlim(0, kap.max() * 1.2)
    a2.set_xlabel(r"$\kappa$")
    a2.set_ylabel(r"|frequency mismatch| (cycles/$\tau$)")
    a2.legend(fontsize=7)
    a2.set_title(rf"Fig. 5f: mismatch; $\kappa_c$ (MuJoCo) = {s.mujoco.kappa_c:.3g}", fontsize=9)
    fig.tight_layout()
    paths.append(_save(fig, out, "fig5ef_sync.png"))
    return paths


def tongue(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    engines = s.engines
    fig, axes = plt.subplots(1, len(engines), figsize=(5.5 * len(engines), 4), squeeze=False)
    for ax, eng in zip(axes[0], engines):
        mism = np.abs(d[f"mismatch_{eng}"]).T
        mism = np.where(d[f"locked_{eng}"].T, 0.0, mism)
        m = ax.pcolormesh(d["rho"], d["kappa"], mism, shading="nearest", cmap="viridis")
        fig.colorbar(m, ax=ax, label=r"|mismatch| (cycles/$\tau$), 0 = locked")
        ax.plot(d["rho"], d[f"kappa_c_{eng}"], "w.-", label=r"$\kappa_c(\rho)$ (grid)")
        ax.set_xscale("log")
        ax.set_xticks(d["rho"])
        ax.set_xticklabels([f"{r:.3g}" for r in d["rho"]], fontsize=7)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel(rf"$\rho = C_2/C_1$ ($\sigma_2 = {PAPER.sync_sigma_1:g}/\rho$)")
        ax.set_ylabel(r"$\kappa$")
        ax.legend(fontsize=7)
        ax.set_title(f"Fig. 5f inset: Arnold tongue, N = 7 ({ENGINE_STYLE[eng]['label']})", fontsize=9)
    fig.tight_layout()
    return [_save(fig, out, "fig5f_tongue.png")]


def sync_n2(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    x = np.sqrt(d["mu"] * np.abs(1 - d["rho"]))
    xx = np.linspace(0, x.max() * 1.1, 50)
    ax.plot(xx, s.prefactor_formula * xx, "k--", lw=1, label=f"paper: {PAPER.kappa_c_n2_printed}")
    ax.plot(xx, s.prefactor_fit * xx, "C3-", lw=0.8, label=f"fit through 0: prefactor {s.prefactor_fit:.3f}")
    ax.errorbar(x, d["kappa_c_reduced"], yerr=d["kappa_c_halfwidth"], fmt="x", color="C3", label="reduced model (bisection)")
    ax.plot(x, d["kappa_c_phase_equation"], "+", color="C2", ms=8, label="supplement's phase equation, solved exactly")
    if "kappa_c_mujoco" in d:
        ax.plot(x, d["kappa_c_mujoco"], **ENGINE_STYLE["mujoco"])
    for xi, yi, mu, rho in zip(x, d["kappa_c_reduced"], d["mu"], d["rho"]):
        ax.annotate(f"μ={mu:g},ρ={rho:g}", (xi, yi), fontsize=6, xytext=(3, -8), textcoords="offset points")
    ax.set_xlabel(r"$\sqrt{\mu|1-\rho|}$")
    ax.set_ylabel(r"$\kappa_c$")
    ax.legend(fontsize=7)
    ax.set_title("N = 2 pair near onset: locking threshold", fontsize=9)
    fig.tight_layout()
    return [_save(fig, out, "sync_n2_kappa_c.png")]


def noise(study: Study, out: Path) -> list[Path]:
    d = study.data
    amps = d["noise"]
    fig, axes = plt.subplots(1, len(amps), figsize=(3.2 * len(amps), 3.2), squeeze=False, sharex=True, sharey=True)
    for ax, a in zip(axes[0], amps):
        ax.plot(d[f"cycle_{a:g}_omega"], d[f"cycle_{a:g}_theta"], lw=0.6)
        ax.set_title(f"a = {a:g}, period CV {d['period_cv_mujoco'][list(amps).index(a)]:.3f}", fontsize=8)
        ax.set_xlabel(r"$\Omega$")
    axes[0, 0].set_ylabel(r"$\Theta=\theta_2-\theta_1$")
    fig.suptitle(rf"Fig. A-noise: N = 2, $\sigma$ = {study.summary.sigma:g}, multiplicative noise (MuJoCo)", fontsize=10)
    fig.tight_layout()
    return [_save(fig, out, "figA_noise.png")]


def anisotropy(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(14, 4))
    for r in d["ratio"]:
        a1.plot(d[f"cycle_{r:g}_omega"], d[f"cycle_{r:g}_theta"], lw=1, label=rf"$\tau_L/\tau_T$ = {r:g}")
    a1.set_xlabel(r"$\Omega$")
    a1.set_ylabel(r"$\Theta$")
    a1.legend(fontsize=7)
    a1.set_title(rf"Fig. A-anisotropy: N = 2, $\sigma$ = {s.sigma:g} (MuJoCo)", fontsize=9)
    for eng in ("mujoco", "reduced"):
        a2.plot(d["ratio"], d[f"amplitude_{eng}"], **ENGINE_STYLE[eng])
        a3.plot(d["ratio"], d[f"onset_{eng}"], **ENGINE_STYLE[eng])
    a2.set_xscale("log")
    _log_ticks(a2, d["ratio"])
    a2.set_xlabel(r"$\tau_L/\tau_T$")
    a2.set_ylabel(r"amplitude of $\Theta$ (rad)")
    a2.legend(fontsize=7)
    a3.axhline(PAPER.sigma_c_2, color="k", lw=0.8, ls="--", label=f"linear stability: {PAPER.sigma_c_2:g}")
    a3.set_xscale("log")
    _log_ticks(a3, d["ratio"])
    a3.set_ylim(PAPER.sigma_c_2 - 0.1, PAPER.sigma_c_2 + 0.1)
    a3.set_xlabel(r"$\tau_L/\tau_T$")
    a3.set_ylabel(rf"onset $\sigma$ (growth rates at {s.probe_sigmas[0]:g}, {s.probe_sigmas[1]:g})")
    a3.legend(fontsize=7)
    fig.tight_layout()
    return [_save(fig, out, "figA_anisotropy.png")]


FIGURES = {
    "stability": stability,
    "growth": growth,
    "hopf": hopf,
    "normal_form": normal_form,
    "snapping": snapping,
    "rotation": rotation,
    "sync": sync,
    "tongue": tongue,
    "sync_n2": sync_n2,
    "noise": noise,
    "anisotropy": anisotropy,
}
"""Figure function of each study, by study name."""


def make_figures(study: Study, out: Path) -> list[Path]:
    return FIGURES[study.name](study, out)

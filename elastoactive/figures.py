"""Figures of the studies (matplotlib, Agg backend), one function per study, each writing PNGs
that mirror the paper's panels. Every function takes a `Study` and an output folder and returns
the paths it wrote.

The figures are sized to stay readable when the README shows two of them side by side (about 480
px wide each): two-panel figures are at most ~9.5 in wide and the fonts are set by `STYLE`."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from .analysis.measures import chain_positions  # noqa: E402
from .analysis.normal_form import landau_limit_cycle  # noqa: E402
from .paper import PAPER  # noqa: E402

if TYPE_CHECKING:  # typing only: the studies import both engines (start-up time)
    from .studies import Study

STYLE = {
    "font.size": 11,
    "axes.titlesize": 11,
    "axes.labelsize": 12,
    "xtick.labelsize": 10,
    "ytick.labelsize": 10,
    "legend.fontsize": 9,
    "legend.framealpha": 0.92,
    "figure.titlesize": 11.5,
}
"""Font sizes of every figure (applied only while a figure function runs)."""

STABLE = dict(color="0.88", zorder=0)
ENGINE_STYLE = {
    "mujoco": dict(marker="o", ls="none", mfc="none", color="C0", label="MuJoCo"),
    "reduced": dict(marker="x", ls="none", color="C3", label="reduced model"),
}
OMEGA_DEF = r"$\Omega=\langle\theta_i\rangle$"
"""The mean polarisation, as docs/model.md defines it: the mean of the absolute angles."""


def _styled(func):
    """Run a figure function with the module's font sizes (without touching global rcParams)."""

    @functools.wraps(func)
    def wrapper(study, out):
        with plt.rc_context(STYLE):
            return func(study, out)

    return wrapper


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
    a.set_minor_locator(matplotlib.ticker.NullLocator())
    (ax.set_xticks if axis == "x" else ax.set_yticks)(list(values))
    (ax.set_xticklabels if axis == "x" else ax.set_yticklabels)([f"{v:g}" for v in values])


def _engines(data: dict, prefix: str):
    return [e for e in ("mujoco", "reduced") if f"{prefix}_{e}" in data]


def _edges(v, log: bool = False) -> np.ndarray:
    """Cell edges around grid values v (increasing): midpoints between neighbours (geometric
    midpoints on a log axis), the outer edges half a step beyond the end values."""
    v = np.asarray(v, dtype=float)
    x = np.log(v) if log else v
    if x.size == 1:
        e = np.array([x[0] - 0.5, x[0] + 0.5])
    else:
        mid = 0.5 * (x[1:] + x[:-1])
        e = np.r_[x[0] - (mid[0] - x[0]), mid, x[-1] + (x[-1] - mid[-1])]
    return np.exp(e) if log else e


def _stable_patch(label: str = r"stable (linear stability, $\sigma<\sigma_c$)") -> Patch:
    return Patch(facecolor=STABLE["color"], edgecolor="none", label=label)


def _add_handle(ax, handle, **legend_kw):
    """The axis's legend with one extra handle (e.g. a shaded band) appended."""
    h, lab = ax.get_legend_handles_labels()
    return ax.legend(h + [handle], lab + [handle.get_label()], **legend_kw)


# ------------------------------------------------------------------------------------------------
@_styled
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
            ax.set_title(rf"N = {n}: {lab} $\lambda$ ($\sigma_c$ = {sc:.4f}, red)")
    fig.suptitle(r"Fig. 3c-d: eigenvalues $\lambda$ of the linearised chain against $\sigma$"
                 "\n" r"(grey: stable, $\sigma<\sigma_c$; red dashes: onset $\sigma_c$)")
    fig.tight_layout()
    paths.append(_save(fig, out, "fig3cd_eigenvalues.png"))

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4))
    n, sc = d["n"], d["sigma_c"]
    a1.loglog(n, sc, "o", ms=3, color="C0", label=r"$\sigma_c(N)$, linear stability")
    a1.loglog(n, s.continuum_onset / n.astype(float) ** 3, "k-", lw=1,
              label=rf"$S_c/N^3$, $S_c$ = {s.continuum_onset:.2f} (continuum)")
    a1.set_xlabel("N")
    _log_ticks(a1, [v for v in (2, 5, 10, 20, 50, 100, 200) if n.min() <= v <= n.max()])
    a1.set_ylabel(r"onset $\sigma_c$")
    a1.legend()
    a1.set_title(rf"Fig. A-size: log-log slope for N $\geq$ {s.n_fit_min}: {s.exponent_large_n:.3f}")
    inv = 1.0 / n
    a2.plot(inv, d["n3_sigma_c"], "o", ms=3, label=r"$N^3\sigma_c$, linear stability")
    p = s.fit_n3.params
    xx = np.linspace(0, 1.0 / s.n_fit_min, 100)
    a2.plot(xx, p["limit"] + p["b1"] * xx + p["b2"] * xx**2, "C1-",
            label=rf"fit $a+b/N+c/N^2$, $a$ = {p['limit']:.2f}")
    a2.axhline(s.continuum_onset, color="k", lw=0.8, ls="--", label=f"continuum onset {s.continuum_onset:.2f}")
    lo, hi = PAPER.continuum_bracket
    a2.axhspan(lo, hi, color="C2", alpha=0.12,
               label=f"filament literature ~{PAPER.continuum_onset:g} ({lo:g} decays, {hi:g} grows)")
    a2.set_xlabel("1/N")
    a2.set_ylabel(r"$N^3\sigma_c$")
    a2.set_xlim(0, 0.52)
    a2.set_ylim(0, 1.08 * max(hi, d["n3_sigma_c"].max()))  # room for the legend at the lower left
    a2.legend(loc="lower left")
    a2.set_title(r"$N^3\sigma_c$ against $1/N$, extrapolated to $N\to\infty$")
    fig.tight_layout()
    paths.append(_save(fig, out, "figA_size_effect.png"))
    return paths


@_styled
def growth(study: Study, out: Path) -> list[Path]:
    d = study.data
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4))
    th = d["rate_theory"]
    lim = np.abs(th).max() * 1.2
    a1.plot([-lim, lim], [-lim, lim], "k-", lw=0.6, label="equal")
    for eng in _engines(d, "rate"):
        a1.plot(th, d[f"rate_{eng}"], **ENGINE_STYLE[eng])
    a1.set_xscale("symlog", linthresh=1e-3)
    a1.set_yscale("symlog", linthresh=1e-3)
    a1.set_xlabel(r"Re $\lambda$, linear stability ($1/\tau$)")
    a1.set_ylabel(r"measured growth rate ($1/\tau$)")
    a1.legend(loc="upper left")
    a1.set_title(r"small kicks at $\sigma_c(1\mp\epsilon)$, N = " + ", ".join(str(int(x)) for x in d["per_n_n"])
                 + "\n" r"(symlog axes: linear within $\pm10^{-3}$)")
    nn = d["per_n_n"]
    a2.loglog(nn, d["per_n_sigma_c_linear"], "k-", lw=1, label="linear stability")
    for eng in ("mujoco", "reduced"):
        if f"per_n_sigma_c_{eng}" in d:
            a2.loglog(nn, d[f"per_n_sigma_c_{eng}"], **ENGINE_STYLE[eng])
    a2.set_xlabel("N")
    _log_ticks(a2, nn)
    a2.set_ylabel(r"onset $\sigma_c$")
    a2.legend()
    a2.set_title("onset: where the rate, interpolated\nbetween the two kicks, is 0")
    fig.tight_layout()
    return [_save(fig, out, "growth_rates.png")]


def _last_period(t, *ys, f):
    """The samples of the last period 1/f of a record (all of it if f is not a frequency or the
    record is shorter than one period), with one sample more so that the loop closes."""
    t = np.asarray(t)
    if not (np.isfinite(f) and f > 0) or t[-1] - t[0] < 1.0 / f:
        return (t, *ys)
    dt = np.median(np.diff(t))
    m = t >= t[-1] - 1.0 / f - 1.01 * dt
    return (t[m], *(np.asarray(y)[m] for y in ys))


@_styled
def hopf(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    sig = d["sigma"]
    sc = s.sigma_c_linear
    paths = []
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4.2))
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
                label="fit " r"$a\Delta^\beta(1+c\Delta)$, $\Delta=\sigma-\sigma_c$:" "\n"
                      rf"$\sigma_c$ = {p['onset']:.5f}, $\beta$ = {p['beta']:.3f}")
    a1.axvline(sc, color="C3", ls="--", lw=0.8, label=rf"$\sigma_c$, linear stability: {sc:.4f}")
    a1.set_ylabel(r"amplitude of $\Theta=\theta_N-\theta_1$ (rad)")
    _add_handle(a1, _stable_patch(), loc="upper left", bbox_to_anchor=(0.06, 1.0))
    a1.set_ylim(-0.1, 1.7 * np.nanmax([d[f"amplitude_{e}"].max() for e in _engines(d, "amplitude")]))
    a1.set_title("Fig. 3a: N = 7, amplitude of the beat")
    if pl:
        ins = a1.inset_axes([0.6, 0.14, 0.37, 0.3])
        for eng in _engines(d, "amplitude"):
            ok = d[f"sustained_{eng}"].astype(bool)
            ins.loglog(sig[ok] - pl.params["onset"], d[f"amplitude_{eng}"][ok], **{**ENGINE_STYLE[eng], "ms": 3})
        xx = np.geomspace(1e-3, 1, 50)
        ins.loglog(xx, pl.params["prefactor"] * xx**PAPER.hopf_exponent, "k--", lw=0.7)
        ins.set_xlabel(r"$\sigma-\sigma_c$", fontsize=8, labelpad=1)
        ins.tick_params(labelsize=7, pad=1)
        ins.set_title(f"log-log; dashes: slope {PAPER.hopf_exponent:g} (paper)", fontsize=7.5, pad=2)
        amax = max(d[f"amplitude_{e}"].max() for e in _engines(d, "amplitude"))
        _log_ticks(ins, [v for v in (0.1, 0.3, 1, 3, 10) if v <= 1.5 * amax], axis="y")
        ins.xaxis.set_major_locator(matplotlib.ticker.LogLocator(numticks=4))
    lin = s.mujoco.freq_linear_all
    if lin:
        xx = np.linspace(sc, sig.max(), 50)
        a2.plot(xx, lin.params["intercept"] + lin.params["slope"] * xx, "k-", lw=0.7,
                label=f"straight-line fit (MuJoCo), R² = {lin.r2:.4f}")
    a2.plot([sc], [s.f_c_linear], "*", color="gold", mec="k", mew=0.6, ms=13, zorder=5,
            label=rf"onset, linear stability: $f\tau$ = {s.f_c_linear:.5f}")
    a2.set_ylabel(r"beat frequency $f\tau$ (cycles per $\tau$)")
    _add_handle(a2, _stable_patch(), loc="upper left")
    a2.set_title("Fig. 3b: N = 7, frequency of the beat")
    fig.tight_layout()
    paths.append(_save(fig, out, "fig3ab_hopf.png"))

    keys = sorted({k.split("_")[1] for k in d if k.startswith("cycle_") and k.endswith("_omega")}, key=float)
    if keys:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4))
        big = keys[-1]
        t = d[f"series_{big}_t"]
        a1.plot(t - t[0], d[f"series_{big}_theta"], label=r"$\Theta=\theta_N-\theta_1$")
        a1.plot(t - t[0], d[f"series_{big}_omega"], label=OMEGA_DEF)
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
        a2.set_xlabel(OMEGA_DEF + " (rad)")
        a2.set_ylabel(r"$\Theta=\theta_N-\theta_1$ (rad)")
        a2.legend(loc="upper left")
        a2.set_title("Fig. 2f: limit cycles, one period each (MuJoCo)")
        fig.tight_layout()
        paths.append(_save(fig, out, "fig2_limit_cycles.png"))
    return paths


@_styled
def normal_form(study: Study, out: Path) -> list[Path]:
    d = study.data
    mu = d["mu"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4.2))
    mm = np.linspace(0, mu.max() * 1.1, 100)
    for c, where, style in ((PAPER.landau_supplement, "supplement", "k-"), (PAPER.landau_main, "main text", "k--")):
        z2, om = landau_limit_cycle(mm, c.at_onset, c.slope)
        lab = f"{where}: c = {c.printed_at_onset}"
        a1.plot(mm, z2, style, lw=1, label=lab)
        a2.plot(mm, om, style, lw=1, label=lab)
    for key, style in (("reduced", ENGINE_STYLE["reduced"]), ("mujoco", {**ENGINE_STYLE["mujoco"], "label": "MuJoCo (dt → 0)"})):
        a1.plot(mu, d[f"z2_{key}"], **style)
        a2.plot(mu, d[f"omega_{key}"], **style)
    for ax in (a1, a2):
        ax.set_xlabel(r"$\mu=\sigma-3$")
        ax.legend(loc="upper left")
    a1.set_ylabel(r"$\langle|z|^2\rangle$ (rad$^2$)")
    a1.set_title(r"limit cycle: $\langle|z|^2\rangle \to \mu/(-\mathrm{Re}\,c)$")
    a2.set_ylabel(r"angular frequency $\omega\tau$ (rad per $\tau$)")
    a2.set_title(r"$\omega \to 1 + \mathrm{Im}\,c\,\langle|z|^2\rangle$")
    fig.suptitle(r"N = 2 near onset, Landau-Stuart form $\tau\dot z=(i+\mu)z+c|z|^2z$, "
                 r"$z=\theta_1+i\sqrt{(1+\mu)/(1-\mu)}\,\theta_2$")
    fig.tight_layout()
    return [_save(fig, out, "normal_form_n2.png")]


@_styled
def snapping(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    paths = []
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4))
    for s_, c in zip(s.n7_sigmas, ("C0", "C1")):
        for eng in ("mujoco", "reduced"):
            st = {**ENGINE_STYLE[eng], "color": c, "label": rf"$\sigma$ = {s_:g}, {ENGINE_STYLE[eng]['label']}"}
            a1.plot(d["delta"], d[f"snap_{s_:g}_{eng}"], **st)
            a2.plot(d["delta"], d[f"freq_{s_:g}_{eng}"], **st)
    a1.set_xlabel(r"compression $\delta$")
    a1.set_ylabel(r"snapping amplitude: std of $\theta_3$ (rad)")
    a1.set_title("Fig. 4c: self-snapping amplitude, N = 7")
    a1.legend(loc="upper left")
    a2.set_xlabel(r"compression $\delta$")
    a2.set_ylabel(r"snapping frequency $f\tau$ (cycles per $\tau$)")
    a2.set_title("Fig. 4d: self-snapping frequency, N = 7\n" r"(no snapping at $\delta$ = 0)")
    fig.tight_layout()
    paths.append(_save(fig, out, "fig4cd_snapping.png"))

    if "example_theta" in d:
        fig, ax = plt.subplots(figsize=(6.5, 3.2))
        th = d["example_theta"]
        idx = np.linspace(0, th.shape[0] - 1, 9).astype(int)[:-1]  # eight frames over one period
        cmap = plt.cm.viridis
        for k, i in enumerate(idx):
            x, y = chain_positions(th[i])
            ax.plot(np.r_[0, x], np.r_[0, y], "-o", ms=3, color=cmap(k / len(idx)))
        ax.set_aspect("equal")
        ax.set_xlabel("x / l")
        ax.set_ylabel("y / l")
        sm = matplotlib.cm.ScalarMappable(cmap=cmap, norm=matplotlib.colors.Normalize(0, 1))
        fig.colorbar(sm, ax=ax, label="time / period", shrink=0.8, pad=0.02)
        ax.set_title(rf"Fig. 4b: one snapping period, N = 7, $\sigma$ = {PAPER.snapping_sigma:g}, "
                     r"$\delta$ = 0.1 (MuJoCo)" "\n" r"(both ends pinned; 8 frames, $T/8$ apart)")
        paths.append(_save(fig, out, "fig4b_snapping_shapes.png"))

    engines = _engines(d, "map_snap")
    if engines:
        fig, axes = plt.subplots(1, len(engines), figsize=(5.2 * len(engines), 4), squeeze=False)
        dd, ss = d["map_delta"], d["map_sigma"]
        for ax, eng in zip(axes[0], engines):
            m = ax.pcolormesh(_edges(dd), _edges(ss), d[f"map_snap_{eng}"], cmap="magma")
            fig.colorbar(m, ax=ax, label=r"snapping amplitude: std of $\theta_3$ (rad)")
            gx, gy = np.meshgrid(dd, ss)
            ax.plot(gx.ravel(), gy.ravel(), ".", color="0.6", ms=2.5, label="simulated (cell centres)")
            thr = s.engine(eng).sigma_snap_n9
            if thr:
                ax.plot([s.threshold_delta], [thr], "c*", ms=12, mec="k", mew=0.5,
                        label=rf"threshold at $\delta$ = {s.threshold_delta:g}: $\sigma$ = {thr:.3f}")
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1)
            ax.set_xlabel(r"compression $\delta$")
            ax.set_ylabel(r"$\sigma$")
            ax.set_title(f"Fig. A-snapping map, N = {PAPER.snapping_map_n} ({ENGINE_STYLE[eng]['label']})")
        fig.tight_layout()
        paths.append(_save(fig, out, "figA_snapping_map.png"))
    return paths


@_styled
def rotation(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4.2))
    sig = d["sigma"]
    a1.axvspan(0, s.sigma_r_linear, **STABLE)
    for eng in ("mujoco", "reduced"):
        a1.plot(sig, np.abs(d[f"rate_{eng}"]), **ENGINE_STYLE[eng])
        seeds = d[f"seed_rate_{eng}"]
        x = np.full(seeds.size, s.sigma_seeds)
        if eng == "mujoco":
            a1.plot(x[seeds > 0] + 0.03, seeds[seeds > 0], "^", color="C2", ms=6,
                    label=rf"{seeds.size} random starts at $\sigma$ = {s.sigma_seeds:g}: {(seeds > 0).sum()} turn ccw")
            a1.plot(x[seeds < 0] + 0.06, -seeds[seeds < 0], "v", color="C4", ms=6,
                    label=f"... and {(seeds < 0).sum()} turn cw (|rate| shown)")
    a1.axvline(s.sigma_r_linear, color="C3", ls="--", lw=0.8, label=f"linear threshold {s.sigma_r_linear:.4f}")
    a1.set_xlabel(r"$\sigma$")
    a1.set_ylabel(r"|rotation rate| $|\dot\theta_1|$ (rad/$\tau$)")
    _add_handle(a1, _stable_patch("still (linear stability)"), loc="upper left")
    a1.set_ylim(-0.02, 1.6 * np.abs(d["rate_mujoco"]).max())  # room for the legend
    a1.set_title("Freely rotating pin, N = 7: steady rotation")
    shapes = d["shape_mujoco"]
    turning = np.abs(d["rate_mujoco"]) > 1e-4
    picks = [i for i in np.flatnonzero(turning)][:: max(1, int(turning.sum() // 5))]
    for i in picks:
        sh = shapes[i] * np.sign(d["rate_mujoco"][i])  # same sense of rotation for all
        x, y = chain_positions(sh)
        a2.plot(np.r_[0, x], np.r_[0, y], "-o", ms=3, label=rf"$\sigma$ = {sig[i]:g}")
    a2.plot([0], [0], "ks", ms=6, zorder=5, label="pin")
    a2.set_aspect("equal")
    a2.set_xlabel("x / l (frame turning with pendulum 1)")
    a2.set_ylabel("y / l")
    a2.legend(loc="center left", bbox_to_anchor=(1.01, 0.5))
    a2.set_title("steady shapes (MuJoCo),\nrotation mirrored to one sense")
    fig.tight_layout()
    return [_save(fig, out, "figA_rotating_pin.png")]


@_styled
def sync(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    paths = []
    kap = d["kappa"]
    fig = plt.figure(figsize=(10, 4.4))
    gs = fig.add_gridspec(2, 2, width_ratios=[1, 1.1], height_ratios=[5, 1], hspace=0.08, wspace=0.28)
    a1 = fig.add_subplot(gs[:, 0])
    a2 = fig.add_subplot(gs[0, 1])
    a3 = fig.add_subplot(gs[1, 1], sharex=a2)
    locked_mj = d["locked_mujoco"].astype(bool)
    for k in d.get("psi_kappas", []):
        t, psi = d[f"psi_{k:g}_t"], d[f"psi_{k:g}"]
        i = np.flatnonzero(np.isclose(kap, k))
        state = "" if not i.size else (" (locked)" if locked_mj[i[0]] else " (slipping)")
        a1.plot(t, psi, lw=1.2, label=rf"$\kappa$ = {k:g}{state}")
    a1.set_xlabel(r"$t/\tau$")
    a1.set_ylabel(r"$\Psi=\Phi_2-\Phi_1$ (rad)")
    a1.legend(loc="lower left")
    a1.set_title(rf"Fig. 5e: phase difference, N = 7, $\sigma_1$ = {PAPER.sync_sigma_1:g}, "
                 rf"$\sigma_2$ = {PAPER.sync_sigma_2:g}" "\n" r"($\rho=C_2/C_1$ = 4/3; MuJoCo)")

    # mismatch: log-log for the pairs that slip; the locked runs (mismatch ~ 0) in the strip below;
    # kappa = 0 (uncoupled) as a horizontal line, since a log axis has no 0
    pos = kap > 0
    kmin = kap[pos].min() if pos.any() else 0.01
    series = [(eng, kap, d[f"mismatch_{eng}"], d[f"locked_{eng}"].astype(bool), ENGINE_STYLE[eng]) for eng in ("mujoco", "reduced")]
    if "alt_kappa" in d:
        series.append(("alt", d["alt_kappa"], d["alt_mismatch"], d["alt_locked"].astype(bool),
                       dict(marker="s", ls="-", color="C2", ms=4, mfc="none", label="what-if: $C_2=C_1$, $F_2=0.75F_1$ (reduced)")))
    for eng, kk, mm, lk, style in series:
        slip = (kk > 0) & ~lk
        a2.plot(kk[slip], np.abs(mm[slip]), **style)
        a3.plot(kk[(kk > 0) & lk], np.zeros(np.count_nonzero((kk > 0) & lk)), **{**style, "ls": "none", "label": None})
        zero = np.flatnonzero(kk == 0)
        if zero.size and eng != "reduced":
            a2.axhline(abs(mm[zero[0]]), color=style["color"] if eng == "alt" else "0.45", ls=":", lw=1)
    a2.plot([], [], ":", color="0.45", label=r"$\kappa$ = 0 (uncoupled), each pair")
    kc = {eng: s.engine(eng).kappa_c for eng in ("mujoco", "reduced")}
    kc = {e: v for e, v in kc.items() if v is not None and np.isfinite(v)}
    if kc:
        same = len(set(round(v, 6) for v in kc.values())) == 1
        for eng, v in list(kc.items())[: 1 if same else None]:
            lab = (rf"$\kappa_c$ = {v:.3g} (both engines)" if same else rf"$\kappa_c$ = {v:.3g} ({ENGINE_STYLE[eng]['label']})")
            for ax in (a2, a3):
                ax.axvline(v, color="C4" if same else ENGINE_STYLE[eng]["color"], lw=1.2, ls="-.", label=lab if ax is a2 else None)
    alt = s.alt_same_stiffness
    if alt is not None and np.isfinite(alt.kappa_c):
        for ax in (a2, a3):
            ax.axvline(alt.kappa_c, color="C2", lw=1, ls="-.", label=rf"what-if $\kappa_c$ = {alt.kappa_c:.2g}" if ax is a2 else None)
    for ax in (a2, a3):
        ax.axvline(PAPER.kappa_c_7, color="k", ls="--", lw=1, label=rf"paper's $\kappa_c$ = {PAPER.kappa_c_7:g}" if ax is a2 else None)
    a2.set_xscale("log")
    a2.set_yscale("log")
    xmax = max(kap.max(), d["alt_kappa"].max() if "alt_kappa" in d else 0, PAPER.kappa_c_7)
    a2.set_xlim(min([kmin, *kc.values()]) / 1.6, xmax * 1.6)
    yl = a2.get_ylim()
    a2.set_ylim(yl[0] / 8, yl[1] * 2)  # room for the legend under the data
    a2.set_ylabel(r"$|f_2-f_1|$ (cycles/$\tau$)")
    a2.legend(loc="lower right", fontsize=7.5)
    a2.tick_params(labelbottom=False)
    a2.set_title("Fig. 5f: frequency mismatch of the pair")
    a3.set_yticks([])
    a3.set_ylim(-1, 1)
    a3.set_ylabel("locked", rotation=0, ha="right", va="center")
    a3.set_xlabel(r"coupling $\kappa=Kl^2/C_1$ ($\kappa$ = 0: dotted lines)")
    fig.subplots_adjust(left=0.07, right=0.98, top=0.86, bottom=0.13)
    paths.append(_save(fig, out, "fig5ef_sync.png"))
    return paths


@_styled
def tongue(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    engines = s.engines
    rho, kap = d["rho"], d["kappa"]
    fig, axes = plt.subplots(1, len(engines), figsize=(5.6 * len(engines), 4.4), squeeze=False)
    for ax, eng in zip(axes[0], engines):
        locked = d[f"locked_{eng}"].astype(bool).T
        mism = np.ma.masked_where(locked, np.abs(d[f"mismatch_{eng}"]).T)
        re, ke = _edges(rho, log=True), _edges(kap)
        ax.pcolormesh(re, ke, np.where(locked, 1.0, np.nan), cmap=matplotlib.colors.ListedColormap(["0.85"]), vmin=0, vmax=1)
        m = ax.pcolormesh(re, ke, mism, cmap="viridis", vmin=0)
        fig.colorbar(m, ax=ax, label=r"$|f_2-f_1|$ when slipping (cycles/$\tau$)")
        gx, gy = np.meshgrid(rho, kap)
        ax.plot(gx.ravel(), gy.ravel(), "k.", ms=2)
        kc = d[f"kappa_c_{eng}"]
        ok = np.isfinite(kc)
        ax.plot(rho[ok], kc[ok], "o-", color="C3", ms=5, lw=1.3, label=r"$\kappa_c(\rho)$: lowest grid $\kappa$ that locks")
        if (~ok).any():
            ax.plot(rho[~ok], np.full((~ok).sum(), 0.5 * (kap.max() + ke[-1])), "^", color="C3", ms=8,
                    label=rf"no locking up to $\kappa$ = {kap.max():g}")
        h, lab = ax.get_legend_handles_labels()
        lp = Patch(facecolor="0.85", edgecolor="0.6", label="locked")
        ax.legend([lp] + h, [lp.get_label()] + lab, loc="upper center", bbox_to_anchor=(0.5, -0.17))
        ax.set_xscale("log")
        ax.set_xlim(re[0], re[-1])
        ax.set_ylim(ke[0], ke[-1])
        ticks = rho if rho.size <= 8 else [v for v in (0.25, 0.5, 1, 2, 4, 8) if re[0] <= v <= re[-1]]
        _log_ticks(ax, ticks)
        ax.set_xticklabels([f"{r:.3g}" for r in ticks])
        ax.set_xlabel(rf"$\rho = C_2/C_1$ (log scale; $\sigma_2 = {PAPER.sync_sigma_1:g}/\rho$)")
        ax.set_ylabel(r"coupling $\kappa$")
        ax.set_title(f"Fig. 5f inset: Arnold tongue, N = 7, $\\sigma_1$ = {PAPER.sync_sigma_1:g}\n"
                     f"({ENGINE_STYLE[eng]['label']}; cells centred on the simulated points)")
    fig.tight_layout()
    return [_save(fig, out, "fig5f_tongue.png")]


@_styled
def sync_n2(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    fig, ax = plt.subplots(figsize=(6, 4.5))
    x = np.sqrt(d["mu"] * np.abs(1 - d["rho"]))
    xx = np.linspace(0, x.max() * 1.15, 50)
    printed = r"$\frac{11}{4\sqrt{6}}\sqrt{\mu|1-\rho|}$"  # PAPER.kappa_c_n2_printed, typeset
    ax.plot(xx, s.prefactor_formula * xx, "k--", lw=1, label=f"supplement: {printed} (prefactor {s.prefactor_formula:.3f})")
    ax.plot(xx, s.prefactor_fit * xx, "C3-", lw=0.8, label=f"fit through 0: prefactor {s.prefactor_fit:.3f}")
    ax.errorbar(x, d["kappa_c_reduced"], yerr=d["kappa_c_halfwidth"], fmt="x", color="C3", label="reduced model (bisection)")
    ax.plot(x, d["kappa_c_phase_equation"], "+", color="C2", ms=9, label="supplement's phase equation, solved exactly")
    if "kappa_c_mujoco" in d:
        ax.plot(x, d["kappa_c_mujoco"], **ENGINE_STYLE["mujoco"])
    rhos = sorted(set(np.round(d["rho"], 6)))
    for xi, yi, yp, mu, rho in zip(x, d["kappa_c_reduced"], d["kappa_c_phase_equation"], d["mu"], d["rho"]):
        # label above the higher of the two markers for the larger |1 - rho|, below the lower one otherwise
        up = np.isclose(rho, rhos[0])
        ax.annotate(f"μ={mu:g}\nρ={rho:g}", (xi, max(yi, yp) if up else min(yi, yp)), fontsize=7, ha="center",
                    va="bottom" if up else "top", xytext=(0, 5 if up else -6), textcoords="offset points", color="0.3")
    ax.set_xlabel(r"$\sqrt{\mu|1-\rho|}$")
    ax.set_ylabel(r"locking threshold $\kappa_c$")
    ax.set_ylim(-0.005, ax.get_ylim()[1])
    ax.legend(loc="upper left")
    ax.set_title(r"N = 2 pair near onset ($\mu=\sigma_1-3$, $\rho=C_2/C_1$)")
    fig.tight_layout()
    return [_save(fig, out, "sync_n2_kappa_c.png")]


@_styled
def noise(study: Study, out: Path) -> list[Path]:
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
            ax.set_xlabel(OMEGA_DEF + " (rad)")
        else:
            ax.tick_params(labelbottom=False)
        if i % ncol == 0:
            ax.set_ylabel(r"$\Theta=\theta_2-\theta_1$ (rad)")
        else:
            ax.tick_params(labelleft=False)
    extra = flat[len(amps)]
    for eng in _engines(d, "period_cv"):
        cv = d[f"period_cv_{eng}"]
        ok = np.isfinite(cv)
        extra.plot(np.asarray(amps)[ok], cv[ok], **ENGINE_STYLE[eng])
    bad = ~np.isfinite(d["period_cv_mujoco"])
    if bad.any():
        for a in np.asarray(amps)[bad]:
            extra.axvline(a, color="0.6", ls=":", lw=1)
        extra.plot([], [], ":", color="0.6", label="no sustained beat")
    extra.set_xlabel("noise amplitude a")
    extra.set_ylabel("period CV (std / mean)")
    extra.set_title("irregularity of the period")
    extra.set_xlim(-0.05 * max(amps), 1.08 * max(amps))
    top = np.nanmax([np.nanmax(np.r_[d[f"period_cv_{e}"], 0.0]) for e in _engines(d, "period_cv")] + [1e-3])
    extra.set_ylim(-0.05 * top, 1.6 * top)  # room for the legend above the points
    extra.legend(loc="upper left")
    for ax in flat[len(amps) + 1:]:
        ax.set_visible(False)
    fig.suptitle(rf"Fig. A-noise: N = 2, $\sigma$ = {study.summary.sigma:g}, active force $F_a(1+\eta)$ with "
                 r"$\langle\eta(t)\eta(t')\rangle=a^2\delta(t-t')$" "\n"
                 r"limit cycles over 150 $\tau$ after the transient (MuJoCo); $\Omega$: mean polarisation")
    fig.tight_layout()
    return [_save(fig, out, "figA_noise.png")]


@_styled
def anisotropy(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    fig, axes = plt.subplots(2, 2, figsize=(9.5, 7.4))
    (a1, a2), (a3, a4) = axes
    for r in d["ratio"]:
        om, th = d[f"cycle_{r:g}_omega"], d[f"cycle_{r:g}_theta"]
        (line,) = a1.plot(om, th, lw=1.2)
        j = int(np.argmax(th))
        a1.annotate(f"{r:g}", (om[j], th[j]), xytext=(0, 1), textcoords="offset points", ha="center", va="bottom",
                    fontsize=8.5, color=line.get_color(), fontweight="bold")
    a1.set_xlabel(OMEGA_DEF + " (rad)")
    a1.set_ylabel(r"$\Theta=\theta_2-\theta_1$ (rad)")
    a1.set_ylim(a1.get_ylim()[0], a1.get_ylim()[1] + 0.08)
    a1.set_title(rf"limit cycles, N = 2, $\sigma$ = {s.sigma:g} (MuJoCo)" "\n" r"labels: drag ratio $\tau_L/\tau_T$")
    for eng in ("mujoco", "reduced"):
        a2.plot(d["ratio"], d[f"amplitude_{eng}"], **ENGINE_STYLE[eng])
        if f"frequency_{eng}" in d:
            a3.plot(d["ratio"], d[f"frequency_{eng}"], **ENGINE_STYLE[eng])
        a4.plot(d["ratio"], d[f"onset_{eng}"], **ENGINE_STYLE[eng])
    for ax in (a2, a3, a4):
        ax.set_xscale("log")
        _log_ticks(ax, d["ratio"])
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
    a4.set_title(rf"onset: growth rates at $\sigma$ = {s.probe_sigmas[0]:g}, {s.probe_sigmas[1]:g}" "\n" "interpolated to 0")
    fig.suptitle("Fig. A-anisotropy: N = 2 with drag anisotropy (longitudinal / transverse drag)")
    fig.tight_layout()
    return [_save(fig, out, "figA_anisotropy.png")]


@_styled
def inertia(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    m = d["mass_ratio"]
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(13.5, 4.2))
    exp = np.asarray(d["experiment_mass_ratio"])
    for n, c in ((2, "C0"), (7, "C3")):
        a1.plot(m, d[f"sigma_c_{n}"] / float(d[f"sigma_c0_{n}"]), color=c, label=f"N = {n}")
        a2.plot(m, d[f"f_c_{n}"] / float(d[f"f_c0_{n}"]), color=c, label=f"N = {n}")
        m1 = float(d[f"shift_mass_ratio_{n}"])
        for ax in (a1, a2):
            ax.axvline(m1, color=c, ls=":", lw=1)
    a1.axhline(1 - 0.01, color="k", ls="--", lw=0.8, label="1% shift")
    for ax in (a1, a2):
        ax.axvspan(exp.min(), exp.max(), color="C2", alpha=0.25, label="experiment (7 g bug, assumed)")
        ax.set_xscale("log")
        ax.set_xlabel(r"mass ratio $m/(\gamma\tau)$")
        ax.legend(loc="lower left")
    a1.set_ylabel(r"$\sigma_c(m)/\sigma_c(0)$")
    a1.set_title("onset (dotted: 1% shift mass ratio)")
    a2.set_ylabel(r"$f_c(m)/f_c(0)$")
    a2.set_title("onset frequency")
    sm = d["sim_mass_ratio"]
    for eng in _engines(d, "sim_frequency"):
        a3.plot(sm, d[f"sim_frequency_{eng}"], **ENGINE_STYLE[eng])
    a3.set_xscale("log")
    a3.set_xlabel(r"mass ratio $m/(\gamma\tau)$")
    a3.set_ylabel(r"$f\tau$ of the beat")
    a3.set_title(rf"N = 7, $\sigma$ = {s.sim_sigma:g}: simulated beat")
    a3.legend()
    fig.suptitle("Inertia: linear stability with mass (analysis.flutter) and simulated beats")
    fig.tight_layout()
    return [_save(fig, out, "figA_inertia.png")]


@_styled
def noise_readings(study: Study, out: Path) -> list[Path]:
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
            st = dict(marker="o" if eng == "mujoco" else "x", mfc="none" if eng == "mujoco" else None,
                      ls="-" if eng == "mujoco" else "--", color=f"C{i}")
            ax.plot(amps[ok], cv[ok], label=f"{r.reading} ({'MuJoCo' if eng == 'mujoco' else 'reduced'})", **st)
            for a in amps[~ok]:
                ax.plot([a], [0], marker="v", color=f"C{i}", ms=9, ls="none")
    ax.plot([], [], "v", color="0.4", label="beat dies (plotted at 0)")
    ax.set_xlabel("noise amplitude a")
    ax.set_ylabel("period CV (std / mean)")
    ax.set_title(rf"Claim 21 under each reading: N = {s.n}, $\sigma$ = {s.sigma:g}")
    ax.legend(fontsize=7.5, ncol=2)
    fig.tight_layout()
    return [_save(fig, out, "figA_noise_readings.png")]


@_styled
def long_chain(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(14.0, 4.2))
    for key, label, style in (("free", "without contact (passes through itself)", dict(color="C0")),
                              ("contact", "with self-contact", dict(color="C3"))):
        if f"t_{key}" in d:
            t = d[f"t_{key}"]
            a1.plot(t - t[0], d[f"Theta_{key}"], label=label, **style)
    a1.set_xlabel(r"$t/\tau$ (last four beats)")
    a1.set_ylabel(r"$\Theta = \theta_N - \theta_1$ (rad)")
    a1.set_title(rf"N = {s.n}, $\sigma$ = {s.sigma:g} (MuJoCo)")
    a1.legend(loc="lower right")
    runs = {(r.contact, r.engine): r for r in s.runs if r.sigma == s.sigma}
    k = np.arange(1, 6)
    width = 0.2
    bars = [("Theta, free", runs[False, "mujoco"].harmonics, "C0", None),
            ("Theta, contact", runs[True, "mujoco"].harmonics, "C3", None),
            (rf"$\theta_{{{s.n // 2 + 1}}}$, free", runs[False, "mujoco"].harmonics_mid, "C0", "//"),
            (rf"$\theta_{{{s.n // 2 + 1}}}$, contact", runs[True, "mujoco"].harmonics_mid, "C3", "//")]
    for i, (label, h, colour, hatch) in enumerate(bars):
        a2.bar(k + (i - 1.5) * width, np.nan_to_num(h), width, color=colour, alpha=0.85 if hatch is None else 0.45,
               hatch=hatch, label=label, edgecolor="k", lw=0.4)
    a2.set_yscale("log")
    a2.set_ylim(1e-4, 2)
    a2.set_xticks(k)
    a2.set_xlabel("harmonic k")
    a2.set_ylabel(r"$A_k / A_1$")
    a2.set_title("spectrum: contact raises the odd harmonics")
    a2.legend(fontsize=8, loc="upper right")
    sig = d["sigma"]
    a3.plot(sig, d["crossing_fraction_free"], "o-", color="C0", label="links crossing, without contact")
    a3.plot(sig, d["contact_fraction_contact"], "s-", color="C3", mfc="none", label="contact_fraction, with contact")
    a3.plot(sig, np.array(d["harmonics_contact"])[:, 2], "^--", color="C3", label=r"$A_3/A_1$ with contact")
    a3.plot(sig, np.array(d["harmonics_free"])[:, 2], "^--", color="C0", mfc="none", label=r"$A_3/A_1$ without")
    a3.set_xlabel(r"$\sigma$")
    a3.set_ylabel("share of samples / harmonic ratio")
    a3.set_title(f"N = {s.n} over sigma (MuJoCo)")
    a3.legend(fontsize=8)
    fig.suptitle("The supplement's long chain: self-contact and the higher harmonics")
    fig.tight_layout()
    return [_save(fig, out, "figA_long_chain.png")]


DISH_COLOURS = {"rest": "0.85", "spin": "C1", "orbit": "C0", "crawl": "C2", "beat": "C3", "irregular": "k"}
"""Colour of each state of analysis.dish.dish_state in the phase diagram."""


@_styled
def dish(study: Study, out: Path) -> list[Path]:
    d, s = study.data, study.summary
    names = [str(n) for n in d["state_names"]]
    sig, trap = np.asarray(d["sigma"]), np.asarray(d["trap"])
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11.0, 4.4))
    cmap = ListedColormap([DISH_COLOURS[n] for n in names])
    a1.pcolormesh(_edges(trap, log=True), _edges(sig, log=True), d["state"], cmap=cmap, vmin=-0.5,
                  vmax=len(names) - 0.5, shading="flat")
    for p in s.checks:
        if p.engine == "mujoco":
            a1.plot(p.trap, p.sigma, "o", mfc="none", mec="w", ms=9, mew=1.5)
    a1.axhline(s.supplement_sigma, color="w", ls=":", lw=1)
    a1.set_xscale("log")
    a1.set_yscale("log")
    a1.set_xlabel(r"trap $k l^2 / C_1$")
    a1.set_ylabel(r"$\sigma$")
    a1.set_title(f"N = {s.n} in the dish (reduced model; rings: MuJoCo checks)")
    present = [n for i, n in enumerate(names) if np.any(d["state"] == i)]
    a1.legend(handles=[Patch(color=DISH_COLOURS[n], label=n) for n in present], loc="upper left", fontsize=8)
    scan = d["scan_trap"]
    a2.plot(scan, np.abs(d["scan_rotation_rate"]), "o-", color="C0", ms=4, label=r"|body rotation| $|\dot\theta_1|$")
    a2.plot(scan, np.abs(d["scan_orbit_rate"]), "x--", color="C3", label="|orbit rate| of the centre of mass")
    lo, hi = s.supplement_orbit_traps
    if np.isfinite(lo):
        a2.axvspan(lo, hi, color=DISH_COLOURS["orbit"], alpha=0.15, label="goes round the centre (orbit)")
    for p in s.checks:
        if p.engine == "mujoco" and p.sigma == s.supplement_sigma:
            a2.plot(p.trap, abs(p.rotation_rate), "s", mfc="none", color="k", ms=8)
    a2.plot([], [], "s", mfc="none", color="k", label="MuJoCo")
    a2.set_xscale("log")
    a2.set_xlabel(r"trap $k l^2 / C_1$")
    a2.set_ylabel(r"rad / $\tau$")
    ax = a2.twinx()
    ax.plot(scan, d["scan_orbit_radius"], ":", color="C2")
    ax.set_yscale("log")
    ax.set_ylabel("orbit radius / l (dotted)", color="C2")
    a2.set_title(rf"the supplement's $\sigma$ = {s.supplement_sigma:g}")
    a2.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    return [_save(fig, out, "figA_dish.png")]


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
    "inertia": inertia,
    "noise_readings": noise_readings,
    "long_chain": long_chain,
    "dish": dish,
}
"""Figure function of each study, by study name."""


def make_figures(study: Study, out: Path) -> list[Path]:
    return FIGURES[study.name](study, out)

"""The Arnold tongue of the coupled pair (Fig. 5f): |frequency mismatch| and locking over (rho, kappa) for N = 7,
sigma_1 = 0.8 (quick: reduced model; full: both engines), and the critical kappa against rho.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import synchronisation as syn
from ..batch import Case
from ..scenes import coupled_pair
from . import plotting as plots
from . import registry
from .base import ENGINES, EngineParts, Study, Summary, fast, pick, run
from .paper import PAPER
from .sync import pair_measures


@dataclass(frozen=True)
class TongueEngine(Summary):
    kappa_c_by_rho: dict[str, float]
    """Grid kappa_c (inf: none of the grid locks) by rho (formatted .4g)."""
    tongue_widens: bool
    kappa_c_min_rho: float


@dataclass(frozen=True)
class TongueSummary(EngineParts):
    engines: list[str]
    duration: float
    mujoco: TongueEngine | None = None
    reduced: TongueEngine | None = None


# --------------------------------------------------------------------------------------------------
# Arnold tongue
# --------------------------------------------------------------------------------------------------
TONGUE = registry.declare("tongue", summary=TongueSummary, order=80, budget=5.5)


@TONGUE.run
def tongue_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """|frequency mismatch| and locking over (rho, kappa) for N = 7, sigma_1 = 0.8 (quick: reduced
    model; full: both engines)."""
    start = time.perf_counter()
    rhos = pick(
        size,
        (0.5, 1.0, 3.0),
        (0.5, 0.75, 1.0, PAPER.sync_rho, 2.0, 3.0),
        tuple(np.r_[np.geomspace(0.4, 4.0, 15), PAPER.sync_rho]),
    )
    rhos = tuple(sorted(set(round(float(r), 6) for r in rhos)))
    kappas = pick(
        size,
        (0.0, 0.1, 0.5),
        (0.0, 0.07, 0.15, 0.3, 0.6),
        (0.0, 0.01, 0.02, 0.035, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 0.8, 1.1, 1.5),
    )
    engines = pick(size, ("reduced",), ("reduced",), ENGINES)
    dur = pick(size, 600.0, 1800.0, 6000.0)
    cases, meta = [], []
    for r in rhos:
        for k in kappas:
            for eng in engines:
                cases.append(
                    Case(
                        coupled_pair.SCENE.physics(n=7, sigma=PAPER.sync_sigma_1, rho=r, kappa=k),
                        fast(perturbation=0.3, sample_dt=0.2),
                        dur,
                        eng,
                        dur / 2,
                    )
                )
                meta.append((r, k, eng))
    trajs = run(cases, workers, progress, "Arnold tongue")
    data = {"rho": np.array(rhos), "kappa": np.array(kappas)}
    grids = {
        eng: (np.full((len(rhos), len(kappas)), np.nan), np.zeros((len(rhos), len(kappas)), bool)) for eng in engines
    }
    for (r, k, eng), tr in zip(meta, trajs):
        m = pair_measures(tr, dur / 2)
        i, j = rhos.index(r), kappas.index(k)
        grids[eng][0][i, j] = m["mismatch"]
        grids[eng][1][i, j] = m["locked"]
    parts = {}
    for eng in engines:
        data[f"mismatch_{eng}"], data[f"locked_{eng}"] = grids[eng]
        kc = np.array([syn.locking_threshold(kappas, row)[1] for row in grids[eng][1]])
        data[f"kappa_c_{eng}"] = kc
        r = np.array(rhos)
        parts[eng] = TongueEngine(
            kappa_c_by_rho={f"{x:.4g}": float(y) for x, y in zip(rhos, kc)},
            tongue_widens=bool(np.all(np.diff(kc[r >= 1]) >= 0) and np.all(np.diff(kc[r <= 1]) <= 0)),
            kappa_c_min_rho=float(r[int(np.argmin(kc))]),
        )
    summary = TongueSummary(engines=list(engines), duration=dur, **parts)
    return Study("tongue", size, data, summary, time.perf_counter() - start)


@TONGUE.figure
@plots.styled
def tongue_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    mpl = plots.matplotlib()
    d, s = study.data, study.summary
    engines = s.engines
    rho, kap = d["rho"], d["kappa"]
    fig, axes = plt.subplots(1, len(engines), figsize=(5.6 * len(engines), 4.4), squeeze=False)
    for ax, eng in zip(axes[0], engines):
        locked = d[f"locked_{eng}"].astype(bool).T
        mism = np.ma.masked_where(locked, np.abs(d[f"mismatch_{eng}"]).T)
        re, ke = plots.edges(rho, log=True), plots.edges(kap)
        ax.pcolormesh(re, ke, np.where(locked, 1.0, np.nan), cmap=mpl.colors.ListedColormap(["0.85"]), vmin=0, vmax=1)
        m = ax.pcolormesh(re, ke, mism, cmap="viridis", vmin=0)
        fig.colorbar(m, ax=ax, label=r"$|f_2-f_1|$ when slipping (cycles/$\tau$)")
        gx, gy = np.meshgrid(rho, kap)
        ax.plot(gx.ravel(), gy.ravel(), "k.", ms=2)
        kc = d[f"kappa_c_{eng}"]
        ok = np.isfinite(kc)
        ax.plot(
            rho[ok], kc[ok], "o-", color="C3", ms=5, lw=1.3, label=r"$\kappa_c(\rho)$: lowest grid $\kappa$ that locks"
        )
        if (~ok).any():
            ax.plot(
                rho[~ok],
                np.full((~ok).sum(), 0.5 * (kap.max() + ke[-1])),
                "^",
                color="C3",
                ms=8,
                label=rf"no locking up to $\kappa$ = {kap.max():g}",
            )
        h, lab = ax.get_legend_handles_labels()
        lp = plots.patch(facecolor="0.85", edgecolor="0.6", label="locked")
        ax.legend([lp] + h, [lp.get_label()] + lab, loc="upper center", bbox_to_anchor=(0.5, -0.17))
        ax.set_xscale("log")
        ax.set_xlim(re[0], re[-1])
        ax.set_ylim(ke[0], ke[-1])
        ticks = rho if rho.size <= 8 else [v for v in (0.25, 0.5, 1, 2, 4, 8) if re[0] <= v <= re[-1]]
        plots.log_ticks(ax, ticks)
        ax.set_xticklabels([f"{r:.3g}" for r in ticks])
        ax.set_xlabel(rf"$\rho = C_2/C_1$ (log scale; $\sigma_2 = {PAPER.sync_sigma_1:g}/\rho$)")
        ax.set_ylabel(r"coupling $\kappa$")
        ax.set_title(
            f"Fig. 5f inset: Arnold tongue, N = 7, $\\sigma_1$ = {PAPER.sync_sigma_1:g}\n"
            f"({plots.ENGINE_STYLE[eng]['label']}; cells centred on the simulated points)"
        )
    fig.tight_layout()
    return [plots.save(fig, out, "fig5f_tongue.png")]

"""What the studies' figures share: fonts, engine markers, saving, log ticks and cell edges.

matplotlib (Agg back end) loads on the first figure drawn, not when a study module is imported:
`pyplot()` and `matplotlib()` give the modules. The figures are sized to stay readable when the
README shows two of them side by side (about 480 px wide each): two-panel figures are at most
~9.5 in wide and the fonts are set by `STYLE`. matplotlib is imported inside `matplotlib()`, the drawing's boundary:
a study that is run and saved without its figures never loads it.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from ..io.outputs import atomic_file

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
"""Shading of the linearly stable range."""
ENGINE_STYLE = {
    "mujoco": dict(marker="o", ls="none", mfc="none", color="C0", label="MuJoCo"),
    "reduced": dict(marker="x", ls="none", color="C3", label="reduced model"),
}
OMEGA_DEF = r"$\Omega=\langle\theta_i\rangle$"
"""The mean polarisation, as docs/model.md defines it: the mean of the absolute angles."""


def matplotlib():
    """The matplotlib package, on the Agg back end (no display)."""
    import matplotlib as mpl  # start-up time: matplotlib loads with the first figure

    mpl.use("Agg")
    import matplotlib.pyplot  # noqa: F401  (loads the sub-modules the figures use: ticker, colors, cm, patches)

    return mpl


def pyplot():
    """matplotlib.pyplot, on the Agg back end."""
    return matplotlib().pyplot


def styled(func):
    """Run a figure function with the module's font sizes (without touching global rcParams)."""

    @functools.wraps(func)
    def wrapper(study, out):
        with pyplot().rc_context(STYLE):
            return func(study, out)

    return wrapper


def save(fig, out: Path, name: str) -> Path:
    """Write `fig` as out/name (PNG, 130 dpi) and close it."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    try:
        with atomic_file(path) as tmp:  # a failed write (full disk) names the file; the umask gives the mode
            fig.savefig(tmp, dpi=130, bbox_inches="tight", format=path.suffix.lstrip(".") or "png")
    finally:
        pyplot().close(fig)
    return path


def log_ticks(ax, values, axis: str = "x") -> None:
    """Plain tick labels at the given values on a log axis (no 2 x 10^0 clutter)."""
    ticker = matplotlib().ticker
    a = ax.xaxis if axis == "x" else ax.yaxis
    a.set_minor_formatter(ticker.NullFormatter())
    a.set_minor_locator(ticker.NullLocator())
    (ax.set_xticks if axis == "x" else ax.set_yticks)(list(values))
    (ax.set_xticklabels if axis == "x" else ax.set_yticklabels)([f"{v:g}" for v in values])


def engines(data: dict, prefix: str) -> list[str]:
    """The engines whose `<prefix>_<engine>` array the study's data hold."""
    return [e for e in ("mujoco", "reduced") if f"{prefix}_{e}" in data]


def edges(v, log: bool = False) -> np.ndarray:
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


def patch(**kw):
    """A legend handle: a filled rectangle (matplotlib.patches.Patch)."""
    return matplotlib().patches.Patch(**kw)


def stable_patch(label: str = r"stable (linear stability, $\sigma<\sigma_c$)"):
    """The legend handle of the STABLE shading."""
    return patch(facecolor=STABLE["color"], edgecolor="none", label=label)


def add_handle(ax, handle, **legend_kw):
    """The axis's legend with one extra handle (e.g. a shaded band) appended."""
    h, lab = ax.get_legend_handles_labels()
    return ax.legend(h + [handle], lab + [handle.get_label()], **legend_kw)

"""The flutter onset with hydrodynamic interactions against the local drag, as a function of the bead radius a / l, in
free space and on the wall (beyond the paper: its chains feel only their own lab-frame drag).

The clamped 3D chain of N links (analysis.stability_fluid: the straight chain's linear operator through the fluid's
mobility, its onset found by root-finding, not assumed) in free space (the Rotne-Prager-Yamakawa mobility, its clamp
point at the origin) and standing on a no-slip wall along its normal (the Rotne-Prager-Blake mobility, base height
h = 0.5 l: the scene cilium), at each bead radius, beside the local drag's onset (analysis.stability.onset: every bead
its own drag gamma = 6 pi mu a, the unit of time tau = gamma l^2 / C). The in-plane / out-of-plane degeneracy of the 3D
chain: its two planes' spectra (analysis.stability_fluid.branches_fluid) at the onset, which symmetry keeps equal for
one chain in free space or along the wall's normal, and not for a pair side by side (the cilia-pair scene, d = 3 l:
only the mirror across the pair's plane survives).
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import stability
from ..analysis.stability_fluid import branches_fluid, linear_operator_fluid, onset_fluid
from ..reduced.blas import one_blas_thread
from ..reduced.fluid import Beds
from ..scenes.cilium import ROTATION
from . import cilia_runs as cr
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick
from .claim_rows import Claim, fmt, verdict

GEOMETRIES = ("free", "wall")
LIMIT = 0.05
"""The smallest radius's onset is within this (relative) of the local drag's: the interactions' limit a / l -> 0."""
DEGENERATE = 1e-10
"""The planes' spectra are degenerate when their relative splitting is below this (round-off: ~1e-15)."""
PAIR_SPACING = 3.0
"""The pair's spacing d (l): the cilia-pair scene's default."""
SOURCE = "beyond the paper: the linear operator of the straight chain with a mobility among its beads"


@dataclass(frozen=True)
class FluidOnset:
    """The onset of one geometry at one bead radius."""

    geometry: str
    radius: float
    sigma_c: float
    omega_c: float
    splitting: float
    """The planes' spectra's relative splitting at the onset (0: degenerate)."""
    coupling: float
    """The planes' coupling in the operator (0: they decouple)."""


@dataclass(frozen=True)
class FluidOnsetSummary(Summary):
    n: int
    base_height: float
    local_sigma_c: float
    local_omega_c: float
    onsets: list[FluidOnset]
    pair: FluidOnset
    """A pair on the wall at PAIR_SPACING, a / l = cilia_runs.RADIUS."""


FLUID_ONSET = registry.declare("fluid_onset", summary=FluidOnsetSummary, order=220, budget=0.5)


def _grid(size: str) -> tuple[int, tuple[float, ...]]:
    """(N, bead radii a / l) of this size."""
    return pick(
        size,
        (5, (0.01, 0.1)),
        (7, (0.01, 0.02, 0.05, 0.1, 0.2, 0.3)),
        (7, (0.005, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4)),
    )


def beds_of(geometry: str, n: int, radius: float, chains: int = 1) -> Beds:
    """The straight chain(s) of this geometry: free space (clamped at the origin along x) or on the wall (the cilia's
    bases, PAIR_SPACING apart)."""
    if geometry == "free":
        return Beds(n, 1.0, np.zeros((1, 3)), np.eye(3), "rpy", radius).checked()
    return Beds(n, 1.0, cr.row_bases(chains, PAIR_SPACING), ROTATION, "rpb", radius).checked()


def _onset(geometry: str, beds: Beds) -> FluidOnset:
    sigma_c, omega_c = onset_fluid(beds)
    planes = branches_fluid(linear_operator_fluid(beds, sigma_c))
    return FluidOnset(geometry, float(beds.radius), sigma_c, omega_c, planes.splitting, planes.coupling)


@FLUID_ONSET.run
def fluid_onset_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Every geometry at every radius, the local drag's onset, the pair's (one process: each onset is a few
    eigenproblems of a 2N x 2N operator)."""
    clock = time.perf_counter()
    n, radii = _grid(size)
    local_sigma_c, local_omega_c = stability.onset(n)
    with one_blas_thread():  # small eigenproblems: threaded BLAS only spins (reduced.blas)
        onsets = [_onset(g, beds_of(g, n, a)) for g in GEOMETRIES for a in radii]
        pair = _onset("wall pair", beds_of("wall", n, cr.RADIUS, chains=2))
    shape = (len(GEOMETRIES), len(radii))
    data = {
        "radius": np.array(radii),
        "sigma_c": np.array([o.sigma_c for o in onsets]).reshape(shape),
        "omega_c": np.array([o.omega_c for o in onsets]).reshape(shape),
        "splitting": np.array([o.splitting for o in onsets]).reshape(shape),
    }
    summary = FluidOnsetSummary(n, cr.BASE_HEIGHT, local_sigma_c, local_omega_c, onsets, pair)
    return Study("fluid_onset", size, data, summary, time.perf_counter() - clock)


@FLUID_ONSET.figure
@plots.styled
def fluid_onset_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, axes = plt.subplots(1, 2, figsize=(10.0, 4.0))
    for ax, key, local, label in (
        (axes[0], "sigma_c", s.local_sigma_c, r"$\sigma_c$"),
        (axes[1], "omega_c", s.local_omega_c, r"$\omega_c\tau$"),
    ):
        for g, geometry in enumerate(GEOMETRIES):
            name = "free space (RPY)" if geometry == "free" else f"on the wall, h = {s.base_height:g} l (RPB)"
            ax.plot(d["radius"], d[key][g] / local, "-o", label=name)
        ax.axhline(1.0, color="0.5", lw=0.8, label="local drag")
        ax.set_xscale("log")
        ax.set_xlabel("bead radius a / l")
        ax.set_ylabel(f"{label} / local drag's")
        ax.legend(fontsize=7)
    axes[0].set_title(f"flutter onset through the fluid, N = {s.n} (local: {s.local_sigma_c:.4g})", fontsize=9)
    axes[1].set_title(f"frequency at onset (local: {s.local_omega_c:.4g})", fontsize=9)
    fig.tight_layout()
    return [plots.save(fig, out, "figH_fluid_onset.png")]


@FLUID_ONSET.claims
def fluid_onset_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    radii = sorted({o.radius for o in s.onsets})
    engine = f"analysis.stability_fluid, N = {s.n}, a / l = {', '.join(fmt(a, 3) for a in radii)}"
    rows = []
    smallest = [o for o in s.onsets if o.radius == radii[0]]
    gaps = [abs(o.sigma_c / s.local_sigma_c - 1.0) for o in smallest]
    rows.append(
        Claim(
            "as a / l -> 0 the onset through the fluid tends to the local drag's (the interactions fall like a / r, "
            "the wall's like a / h)",
            SOURCE,
            "-",
            f"at a / l = {fmt(radii[0], 3)}: sigma_c = "
            + ", ".join(f"{fmt(o.sigma_c, 5)} ({o.geometry})" for o in smallest)
            + f" against the local {fmt(s.local_sigma_c, 5)}; largest gap {fmt(max(gaps), 2)}",
            verdict(max(gaps) < LIMIT),
            f"within {LIMIT:.0%}; {engine}",
        )
    )
    for geometry, where in (("free", "in free space"), ("wall", f"on the wall (h = {s.base_height:g} l)")):
        these = [o for o in s.onsets if o.geometry == geometry]
        ratio = [o.sigma_c / s.local_sigma_c for o in these]
        rows.append(
            Claim(
                f"{where} the interactions lower the onset below the local drag's, the more the larger a / l",
                SOURCE,
                "-",
                "sigma_c / local = "
                + ", ".join(f"{fmt(r, 4)} (a {fmt(o.radius, 2)})" for r, o in zip(ratio, these, strict=True))
                + "; omega_c / local = "
                + ", ".join(fmt(o.omega_c / s.local_omega_c, 4) for o in these),
                verdict(all(r < 1 for r in ratio) and all(np.diff(ratio) < 0), partly=any(r < 1 for r in ratio)),
                f"the local drag's sigma_c = {fmt(s.local_sigma_c, 5)}, omega_c tau = {fmt(s.local_omega_c, 5)}; "
                f"{engine}",
                judged_from="quick",
            )
        )
    worst = max(o.splitting for o in s.onsets)
    rows.append(
        Claim(
            "the in-plane / out-of-plane degeneracy survives for one chain in free space and along the wall's "
            "normal, and breaks for a pair side by side",
            SOURCE,
            "-",
            f"one chain: largest splitting {fmt(worst, 2)}, coupling "
            f"{fmt(max(o.coupling for o in s.onsets), 2)}; the pair (d = {fmt(PAIR_SPACING, 3)}, a / l = "
            f"{fmt(s.pair.radius, 3)}): splitting {fmt(s.pair.splitting, 3)}, coupling {fmt(s.pair.coupling, 2)}, "
            f"sigma_c {fmt(s.pair.sigma_c, 5)}",
            verdict(worst < DEGENERATE and s.pair.splitting > DEGENERATE),
            f"degenerate below {DEGENERATE:g} (relative); the planes' spectra of the operator at the onset "
            f"(analysis.stability_fluid.branches_fluid); {engine}",
        )
    )
    return rows

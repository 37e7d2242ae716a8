"""The single cilium on the wall through the fluid: beat or whirl, its frequency and amplitude against sigma (beyond the
paper: its chains move on a table, with the local drag).

A cilium of N links (scene `cilium`: the clamped 3D chain standing along the wall's normal, its base at h = 0.5 l, bead
radius a / l = 0.1, the Rotne-Prager-Blake mobility) at loads sigma / sigma_c above the onset through the fluid
(analysis.stability_fluid.onset_fluid), from three starts (studies.cilia_runs.push): planar (in the plane of the clamp
axis, which the wall's mirror symmetry keeps invariant), tilted (planar plus 1e-3 out of the plane: is the planar beat
stable out of its plane?) and a helix. Each run is classed by analysis.motion3d over its last MEASURED_PERIODS
expected periods. Beside it the helix with the local drag (the clamped-3d chain's model, no fluid, no wall) at the same
sigma: what the fluid does to the whirl's rate.

The literature's filaments are continuous. Clarke, Hwang and Keaveny (Phys. Rev. Fluids 2024; Westwood's weakly
nonlinear analysis, arXiv 2406.18756) clamp a filament normal to a wall with one follower force at its tip: a
supercritical double Hopf bifurcation, planar beating (unstable) and whirling (stable) born together at onset. Ling,
Guo and Kanso (J. R. Soc. Interface 2018, arXiv 1808.01583) distribute compressive follower forces along it: a Hopf
bifurcation to non-planar spinning (whirling), then planar waves at higher forces. This chain is a discrete N-bead
version of the distributed case (one follower force on every bead, a bending spring at every joint and at the
clamp), with spheres of radius a and the Rotne-Prager-Blake mobility instead of slender-body theory.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.motion3d import measure3d
from ..analysis.stability_fluid import onset_fluid
from ..batch import default_workers
from ..io.executor import imap
from ..reduced.fluid import Beds
from ..scenes.cilium import ROTATION
from . import cilia_runs as cr
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick
from .claim_rows import Claim, fmt, verdict

STATES = ("rest", "beat", "whirl", "other")
"""analysis.motion3d's states, in the order of the data's state codes."""
RUN_PERIODS = 30
"""Length of each run in expected periods (cilia_runs.FREQUENCY_EXPONENT's law; the tilted start leaves its plane
and whirls within ~20 at 1.5 sigma_c)."""
MEASURED_PERIODS = 8
"""The last this many expected periods are measured."""
SOURCE = "beyond the paper: a follower-force chain clamped normal to a no-slip wall, through the fluid"
LITERATURE = (
    "Clarke, Hwang & Keaveny PRF 2024 (tip follower force): whirling stable, planar beating unstable at onset; "
    "Ling, Guo & Kanso 2018 (distributed forces): Hopf to whirling, planar waves at higher force"
)


@dataclass(frozen=True)
class CiliumRun:
    """One run: a load, a start (or the local drag's helix), the state it reached and its numbers."""

    load: float
    """sigma / sigma_c (sigma_c through the fluid)."""
    sigma: float
    start: str
    """cilia_runs.STARTS, or 'local helix' (the helix without the fluid)."""
    state: str
    frequency: float
    """f tau of the tip's displacement along its major axis."""
    whirl_rate: float
    """Cycles per tau, signed."""
    tip_amplitude: float
    """Half the tip's excursion along its major axis (l)."""
    tip_aspect: float
    out_of_plane: float
    """The largest |z| (chain frame) of any tangent over the run (0: the run stayed in its plane)."""
    wall_s: float


@dataclass(frozen=True)
class CiliumStatesSummary(Summary):
    n: int
    radius: float
    base_height: float
    sigma_c: float
    """The onset through the fluid (analysis.stability_fluid.onset_fluid)."""
    f_c: float
    """omega_c / 2 pi at the onset."""
    loads: list[float]
    runs: list[CiliumRun]


CILIUM_STATES = registry.declare("cilium_states", summary=CiliumStatesSummary, order=222, budget=1)


def _grid(size: str) -> tuple[int, tuple[float, ...]]:
    """(N, loads sigma / sigma_c) of this size."""
    return pick(size, (5, (3.0,)), (5, (1.5, 3.0, 6.0)), (7, (1.5, 3.0, 6.0, 12.0)))


def _run(task: tuple[int, float, float, float, str]) -> CiliumRun:
    """One run (a worker's task): N, load, sigma_c, f_c, start."""
    n, load, sigma_c, f_c, start = task
    clock = time.perf_counter()
    sigma = load * sigma_c
    period = cr.expected_period(f_c, load)
    duration = RUN_PERIODS * period
    ts = np.linspace(0.0, duration, RUN_PERIODS * cr.SAMPLES_PER_PERIOD + 1)
    if start == "local helix":
        beds = Beds(n, sigma, cr.row_bases(1, 1.0), ROTATION).checked()
        path = cr.run(beds, ts, cr.push(n, "helix")[None])[:, 0]
    else:
        path = cr.run(cr.wall_beds(n, sigma, cr.row_bases(1, 1.0)), ts, cr.push(n, start)[None])[:, 0]
    m = measure3d(ts, path, transient=duration - MEASURED_PERIODS * period)
    return CiliumRun(
        load, sigma, start, m.state, float(m.frequency or np.nan), m.whirl_rate, m.tip_amplitude, m.tip_aspect,
        float(np.abs(path[..., 2]).max()), time.perf_counter() - clock,
    )  # fmt: skip


@CILIUM_STATES.run
def cilium_states_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Every start at every load through the fluid, and the helix with the local drag."""
    clock = time.perf_counter()
    n, loads = _grid(size)
    sigma_c, omega_c = onset_fluid(cr.wall_beds(n, 1.0, cr.row_bases(1, 1.0)))
    f_c = omega_c / (2 * np.pi)
    starts = (*cr.STARTS, "local helix")
    tasks = [(n, load, sigma_c, f_c, start) for load in loads for start in starts]
    tasks.sort(key=lambda t: t[1])  # the longest runs (lowest load) first
    w = default_workers() if workers is None else workers
    runs = [r for _, r in imap(_run, tasks, max(1, w))]
    runs.sort(key=lambda r: (r.load, starts.index(r.start)))
    shape = (len(loads), len(starts))

    def grid(name: str) -> np.ndarray:
        return np.array([getattr(r, name) for r in runs], dtype=float).reshape(shape)

    data = {
        "loads": np.array(loads),
        "sigma": np.array(loads) * sigma_c,
        "state": np.array([STATES.index(r.state) for r in runs]).reshape(shape),
        **{k: grid(k) for k in ("frequency", "whirl_rate", "tip_amplitude", "tip_aspect", "out_of_plane")},
    }
    summary = CiliumStatesSummary(n, cr.RADIUS, cr.BASE_HEIGHT, sigma_c, f_c, list(loads), runs)
    return Study("cilium_states", size, data, summary, time.perf_counter() - clock)


STARTS_SHOWN = (*cr.STARTS, "local helix")


@CILIUM_STATES.figure
@plots.styled
def cilium_states_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    loads, state = d["loads"], d["state"]
    fig, axes = plt.subplots(1, 3, figsize=(14.0, 4.0))
    markers = {"rest": ("o", "0.6"), "beat": ("s", "C0"), "whirl": ("*", "C3"), "other": ("x", "k")}
    ax = axes[0]
    for y in range(len(STARTS_SHOWN)):
        for j, load in enumerate(loads):
            name = STATES[int(state[j, y])]
            ax.scatter(load, y, marker=markers[name][0], color=markers[name][1], s=70)
    for name, (marker, colour) in markers.items():
        ax.scatter([], [], marker=marker, color=colour, label=name)
    ax.set_yticks(range(len(STARTS_SHOWN)))
    ax.set_yticklabels([f"{x} start" if x != "local helix" else "helix, local drag" for x in STARTS_SHOWN])
    ax.set_xscale("log")
    ax.set_xticks(loads, [f"{x:g}" for x in loads], minor=False)
    ax.minorticks_off()
    ax.set_ylim(-0.5, len(STARTS_SHOWN) + 0.5)
    ax.set_xlabel(r"load $\sigma/\sigma_c$")
    ax.set_title(f"state reached (cilium on the wall, N = {s.n}, a/l = {s.radius:g})", fontsize=9)
    ax.legend(fontsize=7, loc="upper center", ncol=4)
    ax = axes[1]
    styles = {"planar": "--s", "tilted": ":^", "helix": "-*", "local helix": "-.o"}
    for y, start in enumerate(STARTS_SHOWN):
        ax.plot(d["sigma"], d["frequency"][:, y], styles[start], color=f"C{y}", mfc="none", label=start)
    ax.axhline(s.f_c, color="0.5", lw=0.8, label=r"$\omega_c/2\pi$ (onset)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\sigma$")
    ax.set_ylabel(r"$f\tau$")
    ax.legend(fontsize=7)
    ax = axes[2]
    for y, start in enumerate(STARTS_SHOWN):
        ax.plot(d["sigma"], d["tip_amplitude"][:, y], styles[start], color=f"C{y}", mfc="none", label=start)
    ax.set_xscale("log")
    ax.set_xlabel(r"$\sigma$")
    ax.set_ylabel(r"tip amplitude ($l$, half the major axis)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figH_cilium_states.png")]


def _of(s: CiliumStatesSummary, start: str) -> list[CiliumRun]:
    return [r for r in s.runs if r.start == start]


@CILIUM_STATES.claims
def cilium_states_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    engine = (
        f"reduced engine, N = {s.n}, a/l = {s.radius:g}, h = {s.base_height:g}, loads "
        f"{', '.join(fmt(x, 3) for x in s.loads)} sigma_c (sigma_c = {fmt(s.sigma_c, 5)} through the fluid)"
    )
    rows = []
    helix = _of(s, "helix")
    whirls = [r for r in helix if r.state == "whirl"]
    rows.append(
        Claim(
            "a follower-force cilium on the wall whirls from a non-planar start at every load tested",
            f"{SOURCE}; {LITERATURE}",
            "-",
            f"whirl in {len(whirls)} of {len(helix)} runs; f tau {fmt(min(r.frequency for r in helix), 3)}-"
            f"{fmt(max(r.frequency for r in helix), 3)}",
            verdict(len(whirls) == len(helix), partly=bool(whirls)),
            f"state over the last {MEASURED_PERIODS} of {RUN_PERIODS} expected periods (analysis.motion3d); {engine}",
        )
    )
    planar = _of(s, "planar")
    kept = [r for r in planar if r.state == "beat" and r.out_of_plane == 0.0]
    rows.append(
        Claim(
            "the plane of the clamp axis is invariant on the wall: a planar start beats in it",
            SOURCE,
            "-",
            f"planar beat in {len(kept)} of {len(planar)} runs; largest |z| of a tangent "
            f"{fmt(max(r.out_of_plane for r in planar), 2)}",
            verdict(len(kept) == len(planar), partly=bool(kept)),
            f"the wall's images keep the mirror symmetry y -> -y; {engine}",
        )
    )
    tilted = _of(s, "tilted")
    left = [r for r in tilted if r.state == "whirl"]
    rows.append(
        Claim(
            "the planar beat is unstable out of its plane and the whirl is the attractor (as Clarke, Hwang & Keaveny "
            "find at onset for a tip-driven filament)",
            f"{SOURCE}; Clarke, Hwang & Keaveny PRF 2024",
            "-",
            f"a planar start tilted by {cr.TILT:g} ends whirling in {len(left)} of {len(tilted)} runs "
            f"(states: {', '.join(r.state for r in tilted)})",
            verdict(len(left) == len(tilted), partly=bool(left)),
            f"their filament is continuous with one follower force at its tip; this chain's force is on every bead; "
            f"{engine}",
        )
    )
    highest = max(s.loads)
    top = [r for r in tilted + helix if r.load == highest]
    rows.append(
        Claim(
            "at higher force the whirl gives way to planar waves (Ling, Guo & Kanso, distributed follower forces)",
            f"{SOURCE}; Ling, Guo & Kanso 2018",
            "-",
            f"at {fmt(highest, 3)} sigma_c the tilted start and the helix: {', '.join(r.state for r in top)}",
            "yes" if top and all(r.state == "beat" for r in top) else "no",
            f"differs where 'no': up to {fmt(highest, 3)} sigma_c this discrete chain still whirls (their filament is "
            f"continuous, under slender-body theory, with a distributed axial force density); {engine}",
            judged_from="quick",
        )
    )
    beats = {r.load: r for r in planar if r.state == "beat"}
    pairs = [(beats[r.load], r) for r in whirls if r.load in beats]
    if pairs:
        ratios = [abs(w.whirl_rate) / b.frequency for b, w in pairs]
        amp = [w.tip_amplitude / b.tip_amplitude for b, w in pairs]
        rows.append(
            Claim(
                "on the wall the whirl turns faster than the planar beat oscillates, with a smaller tip excursion",
                SOURCE,
                "-",
                f"|whirl rate| / beat f = {fmt(min(ratios), 3)}-{fmt(max(ratios), 3)}; whirl / beat amplitude "
                f"{fmt(min(amp), 3)}-{fmt(max(amp), 3)}",
                verdict(all(x > 1 for x in ratios) and all(x < 1 for x in amp)),
                engine,
            )
        )
    if len(whirls) >= 2:
        sig = np.array([r.sigma for r in whirls])
        f = np.array([abs(r.whirl_rate) for r in whirls])
        a = np.array([r.tip_amplitude for r in whirls])
        slope = float(np.polyfit(np.log(sig), np.log(f), 1)[0])
        rising = bool(np.all(np.diff(f) > 0))
        falling = bool(np.all(np.diff(a) < 0))
        rows.append(
            Claim(
                "the whirl's frequency rises and its tip excursion falls as sigma grows",
                SOURCE,
                "-",
                f"f tau {', '.join(fmt(x, 3) for x in f)} at sigma {', '.join(fmt(x, 3) for x in sig)} (log-log "
                f"slope {fmt(slope, 3)}); amplitude {', '.join(fmt(x, 3) for x in a)} l; onset f_c = "
                f"{fmt(s.f_c, 3)}",
                verdict(rising and falling, partly=rising or falling),
                engine,
                judged_from="quick",
            )
        )
    local = {r.load: r for r in _of(s, "local helix") if r.state == "whirl"}
    both = [(local[r.load], r) for r in whirls if r.load in local]
    if both:
        ratios = [abs(w.whirl_rate) / abs(lo.whirl_rate) for lo, w in both]
        rows.append(
            Claim(
                "through the fluid on the wall the whirl turns faster than with the local drag at the same sigma (the "
                "beads' interactions lower the chain's drag more than the wall raises it)",
                SOURCE,
                "-",
                f"rate through the fluid / local drag's = {', '.join(fmt(x, 4) for x in ratios)} at "
                f"{', '.join(fmt(lo.load, 3) for lo, _ in both)} sigma_c",
                verdict(all(x > 1 for x in ratios), partly=any(x > 1 for x in ratios)),
                f"the local drag: every bead its own drag gamma = 6 pi mu a = 1, no wall (the clamped-3d chain); "
                f"{engine}",
            )
        )
    return rows

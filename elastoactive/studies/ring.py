"""The ring: what a chain closed on itself and held at one particle does against sigma, in both engines.

Beyond the paper (its outlook's "more intricate geometrical connections between active particles"). Two ring
sizes: N = 7, which turns as a rigid regular polygon about the pin at every sigma tried, and N = 24, which beats
while it turns at small sigma and turns rigidly again at large sigma; and the N = 7 ring free in the plane (pin = free),
which turns steadily about its centre of drag without drifting. Each point runs in MuJoCo and in the reduced model
from the same start; the claim rows compare the two. matplotlib.ticker is imported inside ring_figures, the drawing's
boundary (studies.plotting).
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..batch import Case, run_cases
from ..core.params import Numerics
from ..scenes import ring
from . import plotting as plots
from . import registry
from .base import ENGINES, Study, Summary, pick
from .claim_rows import Claim, fmt, verdict

SIZES_N = (7, 24)
"""The ring sizes: the paper's chain length, and a ring long enough to deform while it turns."""
BEATING = 0.1
"""Theta amplitude (rad) above which a ring is said to beat (a rigid ring's Theta is constant: ~1e-6 or less)."""


@dataclass(frozen=True)
class RingSummary(Summary):
    sigma_small: list[float]
    """The sigmas of the N = 7 ring."""
    sigma_large: list[float]
    """The sigmas of the N = 24 ring."""
    sigma_free: list[float]
    """The sigmas of the free N = 7 ring."""
    rigid_amplitude_mujoco: float
    """Largest Theta amplitude of the N = 7 ring over its sigmas (rad), MuJoCo."""
    rigid_amplitude_reduced: float
    rate_per_sigma_mujoco: float
    """N = 7: rotation rate / sigma at the smallest sigma (rad / tau per unit sigma)."""
    rate_per_sigma_reduced: float
    rate_difference: float
    """Largest relative difference of the rotation rates between the engines, over every point."""
    beating_mujoco: list[float]
    """Sigmas at which the N = 24 ring beats (Theta amplitude > BEATING), MuJoCo."""
    beating_reduced: list[float]
    free_rate_ratio_mujoco: float
    """Free N = 7 ring: largest |rotation rate / (sigma N sin(2 pi / N) / (N + 1)) - 1| over its sigmas (the rigid
    regular polygon's rate about its centre of drag), MuJoCo."""
    free_rate_ratio_reduced: float
    free_rate_difference: float
    """Free N = 7 ring: largest relative difference of the rotation rates between the engines."""
    free_drift: float
    """Free N = 7 ring: largest centre drift speed (l / tau) over its sigmas and both engines."""
    free_rigid_amplitude: float
    """Free N = 7 ring: largest Theta amplitude (rad) over its sigmas and both engines."""


def _duration_24(size: str, sigma: float) -> float:
    """Run length of the N = 24 ring (its second half measured): two beats of the slow beat at sigma < 1 (period
    ~48 tau at sigma = 0.5; it grows within ~50 tau); at larger sigma several beats, or the rigid turn once the
    start's beat has died (by ~60 tau at sigma = 8 in MuJoCo)."""
    if size == "full":
        return 800.0
    return 140.0 if sigma < 1.0 else 100.0


def _numerics(n: int, sigma: float) -> Numerics:
    """MuJoCo's step: dt x the straight chain's fastest overdamped rate within the gate's accuracy bound (0.2);
    that rate grows with sigma and N (~123/tau for N = 24 at sigma = 8, where dt = 0.001), so the slower N = 24
    rings (sigma <= 4) take dt = 0.002."""
    return Numerics(dt=0.002 if n == SIZES_N[1] and sigma <= 4.0 else 0.001, sample_dt=0.1)


RINGS = registry.declare("rings", summary=RingSummary, order=180, budget=8.5)


@RINGS.run
def ring_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Rotation rate and Theta's beat against sigma for rings of N = 7 and 24, both engines."""
    start = time.perf_counter()
    small = pick(size, (0.8, 3.0), (0.2, 3.0, 30.0), (0.1, 0.2, 0.4, 0.8, 1.5, 3.0, 6.0, 10.0, 20.0, 40.0, 80.0))
    large = pick(size, (0.5, 8.0), (0.5, 2.0, 8.0), (0.1, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0))
    free = pick(size, (0.8,), (0.2, 3.0), (0.1, 0.8, 3.0, 10.0, 30.0))  # the free N = 7 ring
    rigid_duration = pick(size, 40.0, 40.0, 800.0)  # the N = 7 rings: rigid from the start, their rate settled in tau
    grid = [(SIZES_N[0], s, ring.PINNED, rigid_duration) for s in small]
    grid += [(SIZES_N[1], s, ring.PINNED, _duration_24(size, s)) for s in large]
    grid += [(SIZES_N[0], s, ring.FREE, rigid_duration) for s in free]  # the free ring, after the pinned ones
    cases = [
        Case(ring.SCENE.physics(n=n, sigma=s, pin=pin), _numerics(n, s), duration, eng, duration / 2)
        for n, s, pin, duration in grid
        for eng in ENGINES
    ]
    results = [r.results for r in run_cases(cases, workers=workers, progress=progress, desc="rings")]
    data = {"sigma_small": np.array(small), "sigma_large": np.array(large), "sigma_free": np.array(free)}
    for k, eng in enumerate(ENGINES):
        mine = results[k :: len(ENGINES)]
        for n, count, offset in ((SIZES_N[0], len(small), 0), (SIZES_N[1], len(large), len(small))):
            part = mine[offset : offset + count]
            data[f"rate_{n}_{eng}"] = np.array([r.rotation_rate for r in part])
            data[f"amplitude_{n}_{eng}"] = np.array([r.amplitude for r in part])
            data[f"frequency_{n}_{eng}"] = np.array([np.nan if r.frequency is None else r.frequency for r in part])
        loose = mine[len(small) + len(large) :]
        data[f"rate_free_{eng}"] = np.array([r.rotation_rate for r in loose])
        data[f"drift_free_{eng}"] = np.array([r.extra["centre_drift"] for r in loose])
        data[f"amplitude_free_{eng}"] = np.array([r.amplitude for r in loose])
    n_free = SIZES_N[0]
    rigid = np.array(free) * n_free * np.sin(2.0 * np.pi / n_free) / (n_free + 1)  # a rigid regular ring's |rate|
    rates = {eng: np.r_[data[f"rate_7_{eng}"], data[f"rate_24_{eng}"]] for eng in ENGINES}
    summary = RingSummary(
        sigma_small=[float(s) for s in small],
        sigma_large=[float(s) for s in large],
        sigma_free=[float(s) for s in free],
        rigid_amplitude_mujoco=float(np.max(data["amplitude_7_mujoco"])),
        rigid_amplitude_reduced=float(np.max(data["amplitude_7_reduced"])),
        rate_per_sigma_mujoco=float(data["rate_7_mujoco"][0] / small[0]),
        rate_per_sigma_reduced=float(data["rate_7_reduced"][0] / small[0]),
        rate_difference=float(np.max(np.abs(rates["mujoco"] - rates["reduced"]) / np.abs(rates["reduced"]))),
        beating_mujoco=[float(s) for s, a in zip(large, data["amplitude_24_mujoco"]) if a > BEATING],
        beating_reduced=[float(s) for s, a in zip(large, data["amplitude_24_reduced"]) if a > BEATING],
        free_rate_ratio_mujoco=float(np.max(np.abs(np.abs(data["rate_free_mujoco"]) / rigid - 1.0))),
        free_rate_ratio_reduced=float(np.max(np.abs(np.abs(data["rate_free_reduced"]) / rigid - 1.0))),
        free_rate_difference=float(
            np.max(np.abs(data["rate_free_mujoco"] - data["rate_free_reduced"]) / np.abs(data["rate_free_reduced"]))
        ),
        free_drift=float(max(np.max(data[f"drift_free_{eng}"]) for eng in ENGINES)),
        free_rigid_amplitude=float(max(np.max(data[f"amplitude_free_{eng}"]) for eng in ENGINES)),
    )
    return Study("rings", size, data, summary, time.perf_counter() - start)


@RINGS.figure
@plots.styled
def ring_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    from matplotlib.ticker import NullFormatter  # start-up time: matplotlib loads only to draw

    d = study.data
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4.0))
    for n, key, colour in zip(SIZES_N, ("sigma_small", "sigma_large"), ("C0", "C1")):
        for eng in ENGINES:
            style = dict(plots.ENGINE_STYLE[eng], color=colour, label=f"N = {n}, {plots.ENGINE_STYLE[eng]['label']}")
            a1.loglog(d[key], np.abs(d[f"rate_{n}_{eng}"]), **style)
            a2.semilogx(d[key], d[f"amplitude_{n}_{eng}"], **style)
        a1.loglog(d[key], np.abs(d[f"rate_{n}_reduced"]), "-", color=colour, lw=0.6)
        a2.semilogx(d[key], d[f"amplitude_{n}_reduced"], "-", color=colour, lw=0.6)
    for ax in (a1, a2):
        ax.xaxis.set_minor_formatter(NullFormatter())
    a1.set_xlabel(r"$\sigma$")
    a1.set_ylabel(r"|rotation rate| $|\dot\theta_1|$ (rad/$\tau$)")
    a1.set_title("The ring turns about its pin")
    a1.legend(fontsize=7)
    a2.axhline(BEATING, color="0.6", ls=":", lw=0.8, label=f"beat threshold {BEATING:g} rad")
    a2.set_xlabel(r"$\sigma$")
    a2.set_ylabel(r"amplitude of $\Theta = \theta_N - \theta_1$ (rad)")
    a2.set_title("... rigidly (N = 7), or beating (N = 24)")
    a2.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figB_ring.png")]


def rate_per_sigma(study: Study, engine: str) -> str:
    """The N = 7 ring's rotation rate / sigma over every sigma it ran at, as a claim quotes it: one value where it
    does not change (to 4 digits), else its range with the sigma of each end (it is not constant: the polygon
    deforms as sigma grows)."""
    sigma = np.asarray(study.data["sigma_small"], dtype=float)
    ratio = np.asarray(study.data[f"rate_7_{engine}"], dtype=float) / sigma
    if not np.all(np.isfinite(ratio)):
        return "-"
    lo, hi = int(np.argmin(np.abs(ratio))), int(np.argmax(np.abs(ratio)))
    if f"{ratio[lo]:.4f}" == f"{ratio[hi]:.4f}":
        return f"{ratio[lo]:.4f}"
    return f"{ratio[lo]:.4f} (sigma {fmt(sigma[lo])}) to {ratio[hi]:.4f} (sigma {fmt(sigma[hi])})"


@RINGS.claims
def ring_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    outlook = "outlook: more intricate connections (not simulated)"
    return [
        Claim(
            "A ring held at one particle turns about it as a rigid polygon (N = 7)",
            outlook,
            f"Theta amplitude <= {fmt(s.rigid_amplitude_mujoco, 2)} rad for sigma {fmt(min(s.sigma_small))}-"
            f"{fmt(max(s.sigma_small))}; rate / sigma = {rate_per_sigma(study, 'mujoco')}",
            f"<= {fmt(s.rigid_amplitude_reduced, 2)} rad; {rate_per_sigma(study, 'reduced')}",
            verdict(max(s.rigid_amplitude_mujoco, s.rigid_amplitude_reduced) < 1e-3 and s.rate_difference < 0.01),
            f"the follower forces sum to zero round a closed ring, their torque does not; rates of the two engines "
            f"within {100 * s.rate_difference:.2g}% at every point (N = 7 and 24)",
        ),
        Claim(
            "A longer ring deforms and beats while it turns (N = 24)",
            outlook,
            f"beats at sigma = {', '.join(fmt(x) for x in s.beating_mujoco) or 'none'}",
            f"{', '.join(fmt(x) for x in s.beating_reduced) or 'none'}",
            verdict(bool(s.beating_mujoco) and s.beating_mujoco == s.beating_reduced),
            f"Theta amplitude > {BEATING:g} rad; at the largest sigma it turns rigidly again",
        ),
        Claim(
            "A free ring (no pin) turns steadily about its centre of drag and does not drift (N = 7)",
            outlook,
            f"rate within {100 * s.free_rate_ratio_mujoco:.2g}% of sigma N sin(2 pi/N) / (N + 1)",
            f"within {100 * s.free_rate_ratio_reduced:.2g}%",
            verdict(
                max(s.free_rate_ratio_mujoco, s.free_rate_ratio_reduced) < 0.05
                and s.free_rate_difference < 0.01
                and s.free_drift < 1e-3
                and s.free_rigid_amplitude < 1e-2
            ),
            f"the rigid regular polygon's rate with the root's bead (N + 1 drag points); centre drift <= "
            f"{fmt(s.free_drift, 2)} l/tau, Theta amplitude <= {fmt(s.free_rigid_amplitude, 2)} rad; engines within "
            f"{100 * s.free_rate_difference:.2g}%",
        ),
    ]

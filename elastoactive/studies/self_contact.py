"""Self-contact: the supplement's N = 17 chain and its "higher harmonics ... due to self-contact".

long_chain_study:
- N = 17 pinned at one end, a sigma sweep (the supplement's 0.8 among them), with and without self-contact
  (MuJoCo): does the chain pass through itself without contact (non-adjacent links crossing), and what does
  contact do to the spectrum of Theta and of a mid-chain angle (harmonics 1-5 relative to the fundamental)?
- the engines side by side where contact happens: the reduced model's steep penalty against MuJoCo's
  near-hard contact (N = 17, the sweep's sigmas);
- the contact's convergence: overlap and results as dt and the mass ratio shrink (MuJoCo);
- winding: N = 7 at sigma = 50 winds many turns through itself without contact; what contact makes of it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import observables as obs
from ..analysis import spectrum
from ..batch import Case
from ..core.errors import ParameterError
from ..core.params import Numerics
from ..reduced.contact import capsule_clearance, contact_pairs, link_distance
from ..results import HARMONICS, Results
from ..scenes import one_pinned
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick, run_measured
from .claim_rows import Claim, fmt, verdict
from .paper import PAPER

__all__ = ["ContactRun", "ConvergenceRow", "LongChainSummary", "link_crossings", "long_chain_study"]

LONG_N = PAPER.long_chain_n
"""The supplement's long chain (17)."""
LONG_SIGMA = PAPER.long_chain_sigma
"""The supplement's sigma for it (0.8)."""
MID = LONG_N // 2
"""Index of the mid-chain angle whose spectrum is reported (theta_9 of 17)."""
WIND_N, WIND_SIGMA = 7, 50.0
"""The chain that winds through itself without contact."""
WIND_NUMERICS = Numerics(dt=0.0002, mass_ratio=1e-4)
"""MuJoCo's numerics for the winding chain: its straight state's modes grow at 870/tau, which the default dt = 0.0025
does not resolve (dt x rate = 2.2; the pre-flight gate refuses it as `run` does); this is the setting the gate
offers (dt x rate = 0.17)."""


def gated_numerics(physics) -> Numerics:
    """The default numerics where MuJoCo's pre-flight check passes them, else the setting it offers (the largest dt
    dividing the sample spacing that passes, at the same mass): the long chain's straight state at sigma >= 2 grows
    faster than the default dt resolves (N = 17, sigma = 2: dt x rate = 0.23 > 0.2)."""
    from ..engines.timestep import check_timestep, passing_setting, stability_limits  # engine boundary: loads MuJoCo

    numerics = Numerics()
    try:
        check_timestep(physics, numerics, suggest=False)
    except ParameterError:
        setting = passing_setting(physics, stability_limits(physics, numerics), numerics)
        if setting is None:
            raise
        return Numerics(dt=setting[0], mass_ratio=setting[1])
    return numerics


CROSSING = 1e-9
"""l: non-adjacent links closer than this intersect (the chain passes through itself)."""


def link_crossings(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per sample of a chain theta (T, N) pinned at the origin: the smallest distance between non-adjacent links
    (whole links, particle to particle) and the smallest distance between non-adjacent particles (|i - j| >= 2)."""
    theta = np.atleast_2d(np.asarray(theta, dtype=float))
    links = link_distance(theta)
    ends = np.cumsum(np.stack([np.cos(theta), np.sin(theta)], axis=-1), axis=1)
    particles = np.full(theta.shape[0], np.inf)
    for i, j in contact_pairs(theta.shape[1]):
        gap = ends[:, i] - ends[:, j]
        particles = np.minimum(particles, np.hypot(gap[:, 0], gap[:, 1]))
    return links, particles


@dataclass(frozen=True)
class ContactRun(Summary):
    """One run of the long chain (or the winding chain)."""

    n: int
    sigma: float
    contact: bool
    engine: str
    duration: float
    amplitude: float
    frequency: float
    """f tau of Theta (NaN when not measured)."""
    periodic: bool
    harmonics: tuple[float, ...]
    """Harmonics 1-5 of Theta relative to the fundamental (NaN without a periodic beat)."""
    harmonics_mid: tuple[float, ...]
    """The same for the mid-chain angle theta_{MID+1}."""
    crossing_fraction: float
    """Share of the measured samples in which non-adjacent links intersect (passing through itself)."""
    min_link_distance: float
    min_particle_distance: float
    """Smallest distance between non-adjacent particles over the measured window, in l."""
    contact_fraction: float
    """Share of the measured samples with overlapping capsules (NaN without contact)."""
    min_clearance: float
    """Smallest capsule clearance (negative: overlap depth), in l."""
    theta_span: float
    """max - min of Theta over the whole run (winding: 2 pi per turn)."""
    wall_s: float


@dataclass(frozen=True)
class ConvergenceRow(Summary):
    """The contact's convergence (MuJoCo): N = 17, sigma = 0.8, one dt and mass ratio."""

    dt: float
    mass_ratio: float
    overlap: float
    """Deepest capsule overlap over the measured window, in l."""
    amplitude: float
    frequency: float
    harmonic_3: float
    contact_fraction: float
    wall_s: float


@dataclass(frozen=True)
class LongChainSummary(Summary):
    n: int
    sigma: float
    runs: list[ContactRun]
    convergence: list[ConvergenceRow]
    winding: list[ContactRun]
    passes_through: bool
    """Whether the N = 17, sigma = 0.8 chain without contact passes through itself (links cross)."""
    odd_harmonics_raised: bool
    """Whether contact raises Theta's 3rd and 5th harmonics at N = 17, sigma = 0.8 (MuJoCo)."""
    contact_onset_sigma: float
    """Smallest sigma of the sweep at which the chain without contact passes through itself (NaN: none)."""
    engines_max_rel_diff: float
    """Largest |MuJoCo / reduced - 1| of amplitude and frequency with contact, over the compared sigmas."""


def _run(tr, r: Results, transient: float) -> ContactRun:
    """The run of trajectory `tr`, measured by results.measure over the same transient (`r`, from the workers)."""
    p = tr.physics
    steady = tr.t - tr.t[0] >= transient
    links, particles = link_crossings(tr.theta[steady])
    if p.contact:  # results.measure has them, over the same window
        fraction, clearance = r.contact_fraction, r.min_clearance
    else:  # how deep the capsules would overlap without contact (-2R: the chain passes through itself)
        fraction, clearance = math.nan, float(capsule_clearance(tr.theta[steady], p.contact_radius).min())
    big = obs.curvature(tr.theta)
    mid = spectrum.harmonics(tr.t, tr.theta[:, min(MID, p.n - 1)], transient, HARMONICS)
    return ContactRun(
        p.n,
        p.sigma,
        p.contact,
        tr.engine,
        float(tr.t[-1]),
        float(r.amplitude),
        math.nan if r.frequency is None else float(r.frequency),
        bool(r.periodic),
        tuple(float(h) for h in r.harmonics),
        tuple(float(h) for h in mid),
        float(np.mean(links < CROSSING)),
        float(links.min()),
        float(particles.min()),
        fraction,
        clearance,
        float(big.max() - big.min()),
        float(tr.wall_time_s),
    )


LONG_CHAIN = registry.declare("long_chain", summary=LongChainSummary, order=140, budget=14.5)


@LONG_CHAIN.run
def long_chain_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """N = 17 with and without contact over sigma (MuJoCo; the reduced model with contact alongside), the contact's
    convergence in dt and mass ratio, and the N = 7 chain at sigma = 50 that winds through itself."""
    start = time.perf_counter()
    sigmas = pick(size, (LONG_SIGMA,), (0.2, 0.4, 0.8), (0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0, 1.2, 1.6, 2.0, 3.0))
    duration = pick(size, 150.0, 160.0, 1200.0)  # quick: the second half holds three beats at sigma = 0.8
    touching = pick(size, (LONG_SIGMA,), (LONG_SIGMA,), sigmas)  # with contact (quick: where the claim reads it)
    compared = pick(size, (), (LONG_SIGMA,), (0.4, 0.6, 0.8, 1.2))
    steps = pick(
        size,
        ((0.0025, 1e-4), (0.00125, 1e-4)),
        ((0.0025, 1e-4), (0.0025, 1e-5), (0.00125, 1e-4)),  # dt halved, mass ratio divided by 10: each alone
        tuple((dt, m) for dt in (0.0025, 0.00125, 0.000625, 0.0003125) for m in (1e-4, 1e-5, 1e-6)),
    )
    conv_duration = pick(size, 100.0, 100.0, 600.0)
    wind_duration = pick(size, 40.0, 24.0, 200.0)  # quick: 4 beats measured with contact; ~120 rad of winding without
    scene = one_pinned.SCENE
    cases, meta = [], []
    for s in sigmas:
        for contact in (False, True) if s in touching else (False,):
            physics = scene.physics(n=LONG_N, sigma=s, contact=contact)
            cases.append(Case(physics, gated_numerics(physics), duration, "mujoco", duration / 2))
            meta.append(("sweep", contact, duration))
    for s in compared:
        cases.append(
            Case(scene.physics(n=LONG_N, sigma=s, contact=True), Numerics(), duration, "reduced", duration / 2)
        )
        meta.append(("sweep", True, duration))
    for dt, m in steps:
        cases.append(
            Case(
                scene.physics(n=LONG_N, sigma=LONG_SIGMA, contact=True),
                Numerics(dt=dt, mass_ratio=m),
                conv_duration,
                "mujoco",
                conv_duration / 2,
            )
        )
        meta.append(("convergence", True, conv_duration))
    for contact in (False, True):
        for engine in ("mujoco",) + (("reduced",) if contact else ()):
            cases.append(
                Case(
                    scene.physics(n=WIND_N, sigma=WIND_SIGMA, contact=contact),
                    WIND_NUMERICS,
                    wind_duration,
                    engine,
                    wind_duration / 2,
                )
            )
            meta.append(("winding", contact, wind_duration))
    done = run_measured(cases, workers, progress, "long chain, self-contact", keep_trajectory=True)
    runs, winding, conv = [], [], []
    data: dict = {}
    for (kind, contact, dur), case, one in zip(meta, cases, done):
        tr = one.trajectory
        item = _run(tr, one.results, dur / 2)
        if kind == "sweep":
            runs.append(item)
        elif kind == "winding":
            winding.append(item)
        else:
            conv.append(
                ConvergenceRow(
                    case.numerics.dt,
                    case.numerics.mass_ratio,
                    -item.min_clearance,
                    item.amplitude,
                    item.frequency,
                    item.harmonics[2],
                    item.contact_fraction,
                    item.wall_s,
                )
            )
        if kind == "sweep" and case.physics.sigma == LONG_SIGMA and case.engine == "mujoco":
            key = "contact" if contact else "free"
            keep = tr.t >= tr.t[-1] - 4.0 / max(item.frequency, 1e-3) if math.isfinite(item.frequency) else tr.t >= 0
            data[f"t_{key}"] = tr.t[keep]
            data[f"Theta_{key}"] = obs.curvature(tr.theta)[keep]
            data[f"mid_{key}"] = tr.theta[keep, MID]
            data[f"shape_{key}"] = tr.theta[-1]
    mj = {(r.sigma, r.contact): r for r in runs if r.engine == "mujoco"}
    for key in ("amplitude", "frequency", "crossing_fraction", "contact_fraction"):
        for contact in (False, True):
            data[f"{key}_{'contact' if contact else 'free'}"] = np.array(
                [getattr(mj[s, contact], key) if (s, contact) in mj else math.nan for s in sigmas]
            )
    for contact in (False, True):
        missing = (math.nan,) * HARMONICS
        data[f"harmonics_{'contact' if contact else 'free'}"] = np.array(
            [mj[s, contact].harmonics if (s, contact) in mj else missing for s in sigmas]
        )
        data[f"harmonics_mid_{'contact' if contact else 'free'}"] = np.array(
            [mj[s, contact].harmonics_mid if (s, contact) in mj else missing for s in sigmas]
        )
    data["sigma"] = np.array(sigmas)
    free, touch = mj[LONG_SIGMA, False], mj[LONG_SIGMA, True]
    diffs = []
    for r in runs:
        if r.engine == "reduced":
            m = mj[r.sigma, True]
            diffs += [abs(m.amplitude / r.amplitude - 1), abs(m.frequency / r.frequency - 1)]
    onset = [s for s in sigmas if mj[s, False].crossing_fraction > 0]
    summary = LongChainSummary(
        LONG_N,
        LONG_SIGMA,
        runs,
        conv,
        winding,
        passes_through=free.crossing_fraction > 0,
        odd_harmonics_raised=bool(touch.harmonics[2] > free.harmonics[2] and touch.harmonics[4] > free.harmonics[4]),
        contact_onset_sigma=float(min(onset)) if onset else math.nan,
        engines_max_rel_diff=float(np.nanmax(diffs)) if diffs else math.nan,
    )
    return Study("long_chain", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# figures
# --------------------------------------------------------------------------------------------------
@LONG_CHAIN.figure
@plots.styled
def long_chain_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(14.0, 4.2))
    for key, label, style in (
        ("free", "without contact (passes through itself)", dict(color="C0")),
        ("contact", "with self-contact", dict(color="C3")),
    ):
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
    bars = [
        ("Theta, free", runs[False, "mujoco"].harmonics, "C0", None),
        ("Theta, contact", runs[True, "mujoco"].harmonics, "C3", None),
        (rf"$\theta_{{{s.n // 2 + 1}}}$, free", runs[False, "mujoco"].harmonics_mid, "C0", "//"),
        (rf"$\theta_{{{s.n // 2 + 1}}}$, contact", runs[True, "mujoco"].harmonics_mid, "C3", "//"),
    ]
    for i, (label, h, colour, hatch) in enumerate(bars):
        a2.bar(
            k + (i - 1.5) * width,
            np.nan_to_num(h),
            width,
            color=colour,
            alpha=0.85 if hatch is None else 0.45,
            hatch=hatch,
            label=label,
            edgecolor="k",
            lw=0.4,
        )
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
    return [plots.save(fig, out, "figA_long_chain.png")]


# --------------------------------------------------------------------------------------------------
# claim rows
# --------------------------------------------------------------------------------------------------
def _pct(x: float) -> str:
    return f"{100 * x:.0f}%"


def _harm(h, ks=(2, 4)) -> str:
    """'A3 0.079, A5 0.0064' from a harmonics tuple (indices 2 and 4: the 3rd and 5th)."""
    return ", ".join(f"A{k + 1} {fmt(h[k], 2)}" for k in ks)


@LONG_CHAIN.claims
def long_chain_claims(st: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = st.summary
    at = {(r.contact, r.engine): r for r in s.runs if r.sigma == s.sigma}
    free, touch, red = at[False, "mujoco"], at[True, "mujoco"], at.get((True, "reduced"))
    conv = sorted(s.convergence, key=lambda c: (c.mass_ratio, -c.dt))
    table = "; ".join(
        f"dt {c.dt:g}, m {c.mass_ratio:g}: overlap {c.overlap:.2g} l, A {c.amplitude:.4f}, f {c.frequency:.4g}"
        for c in conv
    )
    wind = {(w.contact, w.engine): w for w in s.winding}
    rows = [
        Claim(
            f"N = {s.n}, sigma = {s.sigma:g}: higher harmonics, 'due to self-contact' (the supplement's speculation)",
            f'"{PAPER.long_chain_words}"',
            f"without contact: Theta {_harm(free.harmonics)} (relative to A1), links cross in "
            f"{_pct(free.crossing_fraction)} of the samples (it passes through itself); with contact: "
            f"{_harm(touch.harmonics)}, in contact {_pct(touch.contact_fraction)} of the time; mid-chain "
            f"theta_{s.n // 2 + 1}: {_harm(free.harmonics_mid)} -> {_harm(touch.harmonics_mid)}",
            "-"
            if red is None
            else f"with contact (penalty): {_harm(red.harmonics)}, A {red.amplitude:.4f}, f {red.frequency:.4g} "
            f"(MuJoCo {touch.amplitude:.4f}, {touch.frequency:.4g})",
            verdict(s.passes_through and s.odd_harmonics_raised),
            "Yes, self-contact explains them: the beat of Theta is odd-symmetric, so only odd harmonics exist; "
            f"contact multiplies A3/A1 by {touch.harmonics[2] / free.harmonics[2]:.1f} and A5/A1 by "
            f"{touch.harmonics[4] / free.harmonics[4]:.0f} and lowers the amplitude {free.amplitude:.3f} -> "
            f"{touch.amplitude:.3f} rad and f tau {free.frequency:.4g} -> {touch.frequency:.4g}. Without contact the "
            f"chain passes through itself from sigma = {s.contact_onset_sigma:g} on (of the sweep). Contact "
            f"convergence (MuJoCo): {table}",
        )
    ]
    if (False, "mujoco") in wind and (True, "mujoco") in wind:
        wf, wc, wr = wind[False, "mujoco"], wind[True, "mujoco"], wind.get((True, "reduced"))
        rows.append(
            Claim(
                f"N = {wf.n}, sigma = {wf.sigma:g}: without contact the chain winds through itself",
                "- (not in the paper)",
                f"Theta spans {wf.theta_span:.0f} rad without contact ({wf.theta_span / (2 * math.pi):.0f} turns, "
                f"links crossing in {_pct(wf.crossing_fraction)} of the samples); {wc.theta_span:.1f} rad with it, a "
                + ("periodic" if wc.periodic else "non-periodic")
                + f" beat at f tau {wc.frequency:.3g}",
                "-" if wr is None else f"with contact: Theta spans {wr.theta_span:.1f} rad, f tau {wr.frequency:.3g}",
                verdict(wc.theta_span < 0.5 * wf.theta_span),
                "contact stops the winding: the chain coils against itself and beats; deepest overlap "
                f"{-wc.min_clearance:.2g} l (MuJoCo; forces ~ sigma N), links still cross in "
                f"{_pct(wc.crossing_fraction)} of the samples near the joints, which the 0.7 l capsules leave bare",
            )
        )
    return rows

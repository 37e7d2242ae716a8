"""The paper's outlook: the mechanical response to a small periodic tip force below onset (docs/outlook.md,
section 2).

Gain and phase of the tip's displacement against the drive's frequency, from both engines with the tip-drive term
against the linear transfer function G(omega) (analysis.response); the resonance's half width against
sigma_c - sigma from G. Above onset (entrainment): the beat's frequency under the tip force against the drive's
detuning, in both engines, against Adler's locking range from G's residue.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import fits
from ..analysis import observables as obs
from ..analysis import response as rs
from ..analysis import stability as stab
from ..batch import Case
from ..core.params import Numerics
from ..scenes import one_pinned
from . import plotting as plots
from . import registry
from .base import ENGINES, EngineParts, Study, Summary, pick, run
from .claim_rows import Claim, verdict

TARGET = 1e-3
"""Tip displacement (l) the drive aims at: its amplitude is TARGET / |G(omega)| (linear, well above the solver's
tolerance)."""
SETTLE = {"tiny": 8.0, "quick": 5.0, "full": 8.0}
"""Transient discarded by size, in units of 1 / gamma (the least stable mode's decay time): its remains are ~e^-5 =
6.7e-3 (quick) or e^-8 = 3e-4 of it, inside AGREEMENT."""
WINDOW = {"tiny": 4, "quick": 1, "full": 4}
"""Drive periods fitted after the transient, by size."""
AGREEMENT = 0.02
"""Simulation against transfer function: |G_sim / G - 1| within this."""
MUJOCO_DT = {"quick": 0.01}
"""MuJoCo's step for the drives by size (others: the default): at the quick size (N = 7) four times the default (the
'fast' preset's), where the chain's fastest rate (~12 / tau) and the drive (omega <= 0.08 / tau) stay resolved and the
first-order error in G (~1e-3) stays far inside AGREEMENT at a quarter of the cost; the tiny size's N = 2 at
omega ~ 1 / tau keeps the default."""
ENGINE_NAMES = {"mujoco": "MuJoCo", "reduced": "reduced"}
FREQUENCIES = (0.25, 0.5, "low", 0.9, 1.0, 1.1, "high", 1.5, 2.0)
"""Drive frequencies in units of the resonance's peak omega, and its two half-power points."""


@dataclass(frozen=True)
class ResponseEngine(Summary):
    """One engine's driven runs against G."""

    max_gain_error: float
    """Largest |(|G_sim| / |G|) - 1| over the drive frequencies."""
    max_phase_error: float
    """Largest |arg G_sim - arg G| (rad)."""
    max_complex_error: float
    """Largest |G_sim / G - 1|."""
    sim_half_power: list[float]
    """|G_sim|^2 / |G_sim(peak)|^2 at the two half-power points of G (0.5 if the simulation resonates as G does)."""
    longitudinal_gain: float
    """Longitudinal drive at the peak frequency: the tip's longitudinal displacement at the drive's frequency over
    the force (no linear response: second order in the small angles)."""


@dataclass(frozen=True)
class ResponseSummary(EngineParts):
    n: int
    ratio: float
    """sigma / sigma_c of the simulated drives."""
    sigma: float
    peak_omega: float
    peak_gain: float
    half_width: float
    gamma: float
    """-Re lambda of the least stable pair."""
    width_exponent: float
    """Slope of log(half width) against log(sigma_c - sigma) (1: linear)."""
    width_per_distance: float
    """half width / (sigma_c - sigma) at the smallest distance."""
    gamma_per_distance: float
    """-d Re lambda / d sigma at the onset (the width's limiting slope)."""
    peak_exponent: float
    """Slope of log(peak gain) against log(sigma_c - sigma) (-1: the gain diverges as 1 / distance)."""
    mujoco: ResponseEngine
    reduced: ResponseEngine


RESPONSE = registry.declare("response", summary=ResponseSummary, order=170, budget=7.5)


def _omegas(res: rs.Resonance) -> list[float]:
    named = {"low": res.low, "high": res.high}
    return [
        float(named[f]) if isinstance(f, str) else f * res.omega
        for f in FREQUENCIES
        if not (isinstance(f, str) and not math.isfinite(named[f]))
    ]


def _case(
    n: int,
    sigma: float,
    omega: float,
    amplitude: float,
    gamma: float,
    sample_dt: float,
    engine: str,
    size: str,
    direction: str = "transverse",
) -> tuple[Case, float]:
    period = 2 * math.pi / omega
    settle = SETTLE[size] / gamma
    duration = math.ceil((settle + WINDOW[size] * period) / sample_dt) * sample_dt
    physics = one_pinned.SCENE.physics(
        n=n, sigma=sigma, drive_amplitude=amplitude, drive_frequency=omega / (2 * math.pi), drive_direction=direction
    )
    coarse = {"dt": MUJOCO_DT[size]} if engine == "mujoco" and size in MUJOCO_DT else {}
    numerics = Numerics(sample_dt=sample_dt, perturbation=1e-4, **coarse)
    begin = math.floor((duration - WINDOW[size] * period) / sample_dt + 1e-9) * sample_dt  # a sample: whole periods
    return Case(physics, numerics, duration, engine), begin


def _fit(traj, start: float, omega: float, amplitude: float, direction: str = "transverse") -> complex:
    keep = traj.t >= start - 1e-9
    n = traj.physics.n
    x = rs.tip_displacement(traj.theta[keep, :n], direction)
    return rs.harmonic_response(traj.t[keep], x, omega, amplitude).gain


@RESPONSE.run
def response_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Gain and phase of the tip against the drive frequency (both engines vs G(omega)), the resonance's width
    against sigma_c - sigma (G), and a longitudinal drive."""
    start = time.perf_counter()
    n = pick(size, 2, 7, 7)
    ratio = 0.9
    sample_dt = pick(size, 0.05, 0.5, 0.25)
    sigma_c, _ = stab.critical_sigma(n)
    sigma = ratio * sigma_c
    res = rs.resonance(n, sigma)
    lam = stab.eigenvalues(n, sigma)[0]
    gamma = -lam.real
    omegas = _omegas(res)
    theory = rs.tip_transfer(n, sigma, omegas)
    amps = [TARGET / abs(g) for g in theory]
    long_amp = TARGET / res.gain
    cases, starts = [], []
    for eng in ENGINES:
        for w, amp in zip(omegas, amps):
            case, begin = _case(n, sigma, w, amp, gamma, sample_dt, eng, size)
            cases.append(case)
            starts.append(begin)
        case, begin = _case(n, sigma, res.omega, long_amp, gamma, sample_dt, eng, size, "longitudinal")
        cases.append(case)
        starts.append(begin)
    trajs = run(cases, workers, progress, "tip drive")
    per = len(omegas) + 1
    sims, longitudinal = {}, {}
    for k, eng in enumerate(ENGINES):
        part, begins = trajs[k * per : (k + 1) * per], starts[k * per : (k + 1) * per]
        sims[eng] = np.array([_fit(tr, b, w, a) for tr, b, w, a in zip(part, begins, omegas, amps)])
        longitudinal[eng] = abs(_fit(part[-1], begins[-1], res.omega, long_amp, "longitudinal"))

    fine = np.geomspace(omegas[0] / 2, omegas[-1] * 1.5, pick(size, 200, 600, 1200))
    curve = rs.tip_transfer(n, sigma, fine)
    distances = np.geomspace(pick(size, 0.02, 0.005, 0.002), 0.15, pick(size, 6, 14, 24))
    widths, peaks, gammas = [], [], []
    for d in distances:
        r = rs.resonance(n, (1 - d) * sigma_c)
        widths.append(r.half_width)
        peaks.append(r.gain)
        gammas.append(-stab.eigenvalues(n, (1 - d) * sigma_c)[0].real)
    widths, peaks, gammas = np.array(widths), np.array(peaks), np.array(gammas)
    small = distances <= 0.05
    width_law = fits.power_law_fit(distances[small] * sigma_c, widths[small])
    peak_law = fits.power_law_fit(distances[small] * sigma_c, peaks[small])
    eps = 1e-6
    slope = (stab.eigenvalues(n, sigma_c * (1 - eps))[0].real - stab.eigenvalues(n, sigma_c)[0].real) / (-eps * sigma_c)
    i_peak = omegas.index(res.omega)
    data = {
        "omega": np.array(omegas),
        "gain_theory": np.abs(theory),
        "phase_theory": np.angle(theory),
        "fine_omega": fine,
        "fine_gain": np.abs(curve),
        "fine_phase": np.angle(curve),
        "distance": distances,
        "half_width": widths,
        "peak_gain": peaks,
        "gamma": gammas,
    }
    parts = {}
    for eng, sim in sims.items():
        data[f"gain_{eng}"], data[f"phase_{eng}"] = np.abs(sim), np.angle(sim)
        parts[eng] = ResponseEngine(
            max_gain_error=float(np.max(np.abs(np.abs(sim) / np.abs(theory) - 1))),
            max_phase_error=float(np.max(np.abs(np.angle(sim / theory)))),
            max_complex_error=float(np.max(np.abs(sim / theory - 1))),
            sim_half_power=[
                float(abs(sim[omegas.index(w)]) ** 2 / abs(sim[i_peak]) ** 2)
                for w in (res.low, res.high)
                if w in omegas
            ],
            longitudinal_gain=float(longitudinal[eng]),
        )
    summary = ResponseSummary(
        n=int(n),
        ratio=ratio,
        sigma=float(sigma),
        peak_omega=res.omega,
        peak_gain=res.gain,
        half_width=res.half_width,
        gamma=float(gamma),
        width_exponent=width_law["exponent"],
        width_per_distance=float(widths[0] / (distances[0] * sigma_c)),
        gamma_per_distance=float(slope),
        peak_exponent=peak_law["exponent"],
        **parts,
    )
    return Study("response", size, data, summary, time.perf_counter() - start)


@RESPONSE.figure
@plots.styled
def response_figure(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(13, 4))
    a1.loglog(d["fine_omega"], d["fine_gain"], "k-", lw=1, label=r"transfer function $|G(\omega)|$")
    for eng in plots.engines(d, "gain"):
        a1.loglog(d["omega"], d[f"gain_{eng}"], **plots.ENGINE_STYLE[eng])
    a1.axvspan(
        s.peak_omega - s.half_width,
        s.peak_omega + s.half_width,
        color="C0",
        alpha=0.12,
        label=rf"half width {s.half_width:.3g}/$\tau$",
    )
    a1.set_xlabel(r"drive $\omega\,\tau$")
    a1.set_ylabel(r"gain $|y_N| / |F_y|$ ($l^2/C_1$)")
    a1.legend(fontsize=8)
    a1.set_title(rf"N = {s.n}, $\sigma$ = {s.ratio:g} $\sigma_c$: gain")
    a2.semilogx(d["fine_omega"], d["fine_phase"], "k-", lw=1, label="transfer function")
    for eng in plots.engines(d, "phase"):
        a2.semilogx(d["omega"], d[f"phase_{eng}"], **plots.ENGINE_STYLE[eng])
    a2.set_xlabel(r"drive $\omega\,\tau$")
    a2.set_ylabel("phase lead of the tip (rad)")
    a2.legend(fontsize=8)
    a2.set_title(f"phase (largest error {max(s.mujoco.max_phase_error, s.reduced.max_phase_error):.1e} rad)")
    sc = d["distance"]
    a3.loglog(sc, d["half_width"], "o-", ms=3, label="half width of $|G|^2$")
    a3.loglog(sc, d["gamma"], "k--", lw=1, label=r"$-$Re $\lambda$ (least stable pair)")
    a3.set_xlabel(r"$(\sigma_c - \sigma) / \sigma_c$")
    a3.set_ylabel(r"$\omega\,\tau$")
    a3.legend(fontsize=8)
    a3.set_title(f"resonance width: slope {s.width_exponent:.3f}")
    fig.suptitle("Linear response to a transverse tip force below onset: both engines against G(omega)")
    fig.tight_layout()
    return [plots.save(fig, out, "response_tip.png")]


@RESPONSE.claims
def response_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    outlook = "outlook: 'mechanical responses such as longitudinal or transverse excitations'"

    def column(e: ResponseEngine) -> str:
        return (
            f"|G_sim / G - 1| <= {e.max_complex_error:.1e} over {len(FREQUENCIES)} frequencies; |G|^2 at G's "
            "half-power points " + ", ".join(f"{h:.4f}" for h in e.sim_half_power) + " of the peak's"
        )

    ok = all(s.engine(e).max_complex_error < AGREEMENT for e in ENGINES)
    rows = [
        Claim(
            "Below onset a transverse tip force gets the linear operator's response (gain and phase)",
            outlook,
            column(s.mujoco),
            column(s.reduced),
            verdict(ok),
            f"N = {s.n}, sigma = {s.ratio:g} sigma_c, drives from 0.25 to 2 times the peak at omega = "
            f"{s.peak_omega:.4g}/tau (|G| = {s.peak_gain:.4g}) against G(omega) = e_N^T (i omega - M)^-1 e_N (tip "
            "displacement over tip force): "
            + "; ".join(
                f"{ENGINE_NAMES[e]} gain within {100 * s.engine(e).max_gain_error:.2g}%, phase within "
                f"{s.engine(e).max_phase_error:.1e} rad"
                for e in ENGINES
            )
            + ". A longitudinal force of the same size at the peak frequency moves the tip along the chain by "
            + " and ".join(f"{s.engine(e).longitudinal_gain:.1e}" for e in ENGINES)
            + " l per unit force (MuJoCo, reduced) at the drive's frequency: no linear response (it enters as "
            "-F_x theta_j, a parametric drive, and the straight chain stays straight).",
        )
    ]
    rows.append(
        Claim(
            "The resonance sharpens as sigma -> sigma_c: its width vanishes linearly in sigma_c - sigma",
            outlook,
            "-",
            f"width ~ (sigma_c - sigma)^{s.width_exponent:.3f}",
            verdict(abs(s.width_exponent - 1) < 0.05 and abs(s.width_per_distance / s.gamma_per_distance - 1) < 0.05),
            f"half width at half maximum of |G|^2 against sigma_c - sigma (N = {s.n}, from G): exponent "
            f"{s.width_exponent:.3f}, width / (sigma_c - sigma) = {s.width_per_distance:.4g} at the closest point "
            f"against -d Re lambda / d sigma = {s.gamma_per_distance:.4g} at the onset; at {s.ratio:g} sigma_c the "
            f"width {s.half_width:.4g} against gamma = {s.gamma:.4g}; the peak gain grows as (sigma_c - "
            f"sigma)^{s.peak_exponent:.3f}.",
        )
    )
    return rows


# --------------------------------------------------------------------------------------------------
# above onset: entrainment by the tip force
# --------------------------------------------------------------------------------------------------
ENTRAIN_N = 2
ENTRAIN_SIGMA = 3.3
"""N = 2 at 1.1 sigma_c: a beat at f tau ~ 0.153 (6.5 tau a period), so that a tongue needs seconds, not hours."""
ENTRAIN_FREE = 400.0
"""Duration of the free beat that gives its frequency and tip amplitude (tau; the transient is its first half)."""
ENTRAIN_RUN = {"tiny": (200.0, 75.0), "quick": (500.0, 200.0), "full": (1600.0, 400.0)}
"""Duration of a driven run and the transient before the beat's frequency is measured (tau), by size. Quick: a lock
at 0.9 Adler half widths relaxes at ~0.44 times the half width (~47 tau at A = 0.05), so 200 tau leave ~e^-4 of the
start's phase, which moves f_beat by ~5e-5 over the 300 tau window, inside LOCKED."""
LOCKED = 1e-4
"""|f_beat / f_drive - 1| below this over the window: locked (one phase slip in the window shifts it by one over the
periods the window holds: 5e-2 at the tiny size's 19, 2.2e-2 at the quick size's 46)."""


@dataclass(frozen=True)
class TongueEdge(Summary):
    """One drive amplitude: the locked detunings against Adler's estimate (detunings relative to the free beat's f)."""

    amplitude: float
    adler: float
    """|R| A / a over the free beat's angular frequency."""
    locked_low: float
    """The most negative detuning of the scan that locks, and the next one out, which does not."""
    unlocked_low: float
    locked_high: float
    unlocked_high: float
    engines_agree: bool
    """Both engines lock at the same detunings."""


@dataclass(frozen=True)
class EntrainmentSummary(Summary):
    n: int
    sigma: float
    free_frequency: float
    """f tau of the free beat (reduced engine)."""
    tip_amplitude: float
    duration: float
    transient: float
    residue: float
    """|R| of G's leading pair."""
    edges: list[TongueEdge]


ENTRAINMENT = registry.declare("entrainment", summary=EntrainmentSummary, order=175, budget=5)


def _beat_mismatch(traj, drive_frequency: float, transient: float) -> float:
    keep = traj.t >= transient
    beat = obs.frequency(traj.t[keep], obs.curvature(traj.theta[keep]))
    return float(beat / drive_frequency - 1.0)


@ENTRAINMENT.run
def entrainment_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """Above onset (N = 2 at 1.1 sigma_c): the beat's frequency under a tip force of several amplitudes against the
    drive's detuning, in both engines; the locked band against Adler's estimate |R| A / a."""
    start = time.perf_counter()
    n, sigma = ENTRAIN_N, ENTRAIN_SIGMA
    numerics = Numerics(sample_dt=0.05)
    duration, transient = pick(size, *(ENTRAIN_RUN[k] for k in ("tiny", "quick", "full")))
    free = run(
        [Case(one_pinned.SCENE.physics(n=n, sigma=sigma), numerics, ENTRAIN_FREE, "reduced")],
        workers,
        progress,
        "free beat",
    )[0]
    steady = free.t >= ENTRAIN_FREE / 2
    tip = rs.tip_displacement(free.theta[steady])
    a = float(0.5 * (tip.max() - tip.min()))
    f0 = float(obs.frequency(free.t[steady], obs.curvature(free.theta[steady])))
    amplitudes = pick(size, (0.1,), (0.05, 0.1), (0.025, 0.05, 0.1))
    # detunings in units of Adler's half width: quick brackets each edge by one point inside and one outside
    scan = np.array(pick(size, (0.8, 1.25), (0.9, 1.1), (0.6, 0.8, 0.9, 0.95, 1.05, 1.1, 1.25, 1.5)))
    centre = pick(size, (0.0,), (), (0.0,))  # quick: only the edges' brackets (the claim reads nothing else)
    fractions = np.concatenate([-scan[::-1], centre, scan])
    cases, meta = [], []
    for amp in amplitudes:
        adler = rs.adler_half_width(n, sigma, amp, a) / (2 * math.pi * f0)
        for frac in fractions:
            fd = f0 * (1 + frac * adler)
            for eng in ENGINES:
                physics = one_pinned.SCENE.physics(n=n, sigma=sigma, drive_amplitude=amp, drive_frequency=fd)
                cases.append(Case(physics, numerics, duration, eng))
                meta.append((amp, adler, frac, fd, eng))
    trajs = run(cases, workers, progress, "entrainment")
    mismatch = {(amp, frac, eng): _beat_mismatch(tr, fd, transient) for (amp, _, frac, fd, eng), tr in zip(meta, trajs)}
    data = {"fractions": fractions, "amplitudes": np.array(amplitudes)}
    edges = []
    for amp in amplitudes:
        adler = rs.adler_half_width(n, sigma, amp, a) / (2 * math.pi * f0)
        locked = {}
        for eng in ENGINES:
            mm = np.array([mismatch[(amp, frac, eng)] for frac in fractions])
            data[f"mismatch_{eng}_{amp:g}"] = mm
            locked[eng] = np.abs(mm) < LOCKED
        lock = locked["reduced"]
        inside = fractions[lock]
        low_out = fractions[(~lock) & (fractions < 0)]
        high_out = fractions[(~lock) & (fractions > 0)]
        edges.append(
            TongueEdge(
                amplitude=float(amp),
                adler=float(adler),
                locked_low=float(inside.min() * adler) if inside.size else math.nan,
                unlocked_low=float(low_out.max() * adler) if low_out.size else math.nan,
                locked_high=float(inside.max() * adler) if inside.size else math.nan,
                unlocked_high=float(high_out.min() * adler) if high_out.size else math.nan,
                engines_agree=bool(np.array_equal(locked["mujoco"], locked["reduced"])),
            )
        )
    summary = EntrainmentSummary(
        n=n,
        sigma=sigma,
        free_frequency=f0,
        tip_amplitude=a,
        duration=duration,
        transient=transient,
        residue=abs(rs.tip_residue(n, sigma)),
        edges=edges,
    )
    return Study("entrainment", size, data, summary, time.perf_counter() - start)


@ENTRAINMENT.figure
@plots.styled
def entrainment_figure(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for i, e in enumerate(s.edges):
        x = d["fractions"] * e.adler
        for eng in ENGINES:
            y = d[f"mismatch_{eng}_{e.amplitude:g}"]
            style = dict(plots.ENGINE_STYLE[eng], color=f"C{i}")
            style["label"] = f"A = {e.amplitude:g}, {style['label']}"
            ax.plot(x, y, **style)
        ax.axvspan(-e.adler, e.adler, color=f"C{i}", alpha=0.1, label=f"Adler |R| A / a, A = {e.amplitude:g}")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xlabel(r"detuning $f_{drive} / f_0 - 1$")
    ax.set_ylabel(r"$f_{beat} / f_{drive} - 1$")
    ax.legend(fontsize=8)
    ax.set_title(rf"N = {s.n}, $\sigma$ = {s.sigma:g} (above onset): entrainment by a tip force")
    fig.tight_layout()
    return [plots.save(fig, out, "entrainment_tongue.png")]


@ENTRAINMENT.claims
def entrainment_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    outlook = "outlook: 'mechanical responses such as longitudinal or transverse excitations'"

    def bracketed(e: TongueEdge) -> bool:  # Adler's edges lie between the last locked and first unlocked detunings
        return (e.unlocked_low <= -e.adler <= e.locked_low) and (e.locked_high <= e.adler <= e.unlocked_high)

    ok = all(bracketed(e) for e in s.edges)
    agree = all(e.engines_agree for e in s.edges)
    text = "; ".join(
        f"A = {e.amplitude:g}: locked from {e.locked_low:+.4f} to {e.locked_high:+.4f} (unlocked at "
        f"{e.unlocked_low:+.4f}, {e.unlocked_high:+.4f}) against Adler +-{e.adler:.4f}"
        for e in s.edges
    )
    return [
        Claim(
            "Above onset a tip force entrains the beat inside an Arnold tongue (Adler's width from the linear residue)",
            outlook,
            "locks at the same detunings" if agree else "locks at other detunings",
            text,
            verdict(ok and agree),
            f"N = {s.n}, sigma = {s.sigma:g} (sigma_c = 3): free beat f tau = {s.free_frequency:.5f}, tip amplitude "
            f"a = {s.tip_amplitude:.4f} l; detunings relative to f tau. Adler: |Omega - omega_beat| <= |R| A / a with "
            f"|R| = {s.residue:.4f} the residue of G at its leading pair (the non-isochronicity, which widens the "
            f"tongue by sqrt(1 + alpha^2), left out). Locked: |f_beat / f_drive - 1| < {LOCKED:g} after "
            f"{s.transient:g} tau of {s.duration:g}.",
        )
    ]

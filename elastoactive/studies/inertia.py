"""Inertia: how far the paper's overdamped idealisation holds (issue 'Relax the paper's two idealisations').

inertia_study:
- linear stability with inertia (analysis.flutter, a quadratic eigenvalue problem): sigma_c and the onset
  frequency against the mass ratio m / (gamma tau) for N = 2 and N = 7, and the mass ratio where sigma_c
  first moves by 1% from its overdamped value;
- Ziegler's double pendulum computed by the same stability code against the closed forms (undamped,
  vanishing joint damping, vanishing lab-frame drag);
- simulated beats of N = 7 at sigma = 0.8 against the mass ratio in both engines (MuJoCo at its default
  dt; the reduced engine switches to its inertial model outside the overdamped limit);
- the experiment's own mass ratio from the paper's gamma, F_a, link pitch and sigma, with an assumed
  Hexbug mass (HEXBUG_MASS_KG: not in the paper).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis import flutter as fl
from ..analysis import observables as obs
from ..batch import Case
from ..core.params import Numerics
from ..scenes import one_pinned
from . import plotting as plots
from . import registry
from .base import ENGINES, Study, Summary, pick, run
from .claim_rows import Claim, verdict
from .paper import PAPER

__all__ = ["HEXBUG_MASS_KG", "ExperimentScales", "InertiaSummary", "experiment_scales", "inertia_study"]

HEXBUG_MASS_KG = 0.007
"""ASSUMPTION (not in the paper): the mass of one Hexbug Nano, about 7 g as commonly quoted. The rubber
links and the bug's own rotational inertia are left out."""

SHIFT_FRACTION = 0.01
"""The onset shift that defines the edge of the overdamped limit (1%)."""

SIM_SIGMA = 0.8
"""sigma of the simulated N = 7 beats (Fig. 2e-f's simulation)."""


@dataclass(frozen=True)
class ExperimentScales(Summary):
    """The experiment's time scale and mass ratio, from the paper's numbers and an assumed bug mass."""

    mass_kg: float
    """Assumed Hexbug Nano mass."""
    pitch_m: float
    """Link pitch l = L / 7."""
    gamma: float
    """Drag coefficient, N s/m (paper)."""
    force_n: float
    """Active force F_a, N (paper)."""
    sigmas: tuple[float, ...]
    """The experiment's elasto-active numbers (paper)."""
    tau_s: tuple[float, ...]
    """tau = gamma l^2 / C = gamma l sigma / F_a (C = F_a l / sigma) for each sigma, in seconds."""
    mass_ratio: tuple[float, ...]
    """m / (gamma tau) for each sigma."""
    mass_ratio_max: float
    """The largest (stiffest chain, smallest sigma)."""
    sigma_c_7_shift_at_max: float
    """Relative shift of sigma_c(N = 7) at mass_ratio_max (linear stability with inertia)."""


def experiment_scales(mass_kg: float = HEXBUG_MASS_KG) -> ExperimentScales:
    """tau and m / (gamma tau) of the experiment's chains (PAPER's gamma, F_a, pitch, sigmas; `mass_kg` assumed)."""
    pitch, g, f = PAPER.link_pitch_m, PAPER.drag_n_s_per_m, PAPER.active_force_n
    sigmas = tuple(PAPER.experiment_sigmas)
    taus = tuple(g * pitch * s / f for s in sigmas)
    ratios = tuple(mass_kg / (g * t) for t in taus)
    m_max = max(ratios)
    s0 = fl.critical_sigma(7, 0.0)[0]
    shift = fl.critical_sigma(7, m_max)[0] / s0 - 1.0
    return ExperimentScales(mass_kg, pitch, g, f, sigmas, taus, ratios, m_max, float(shift))


@dataclass(frozen=True)
class ZieglerCheck(Summary):
    label: str
    parameter: float
    """The vanishing damping (joint c or lab-frame drag gamma) it was computed at (0: undamped)."""
    computed: float
    """P_c from analysis.flutter's eigenvalues, in C / l."""
    closed_form: float
    """The closed form at the same damping."""
    limit: float
    """The closed form's limit (the structural-mechanics value)."""


@dataclass(frozen=True)
class InertiaSimPoint(Summary):
    mass_ratio: float
    duration: float
    amplitude: dict[str, float]
    """Amplitude of Theta by engine."""
    frequency: dict[str, float]
    """f tau by engine."""
    linear_f_c: float
    """f_c tau of the onset mode at this mass (linear stability; the beat at sigma = 0.8 is slower)."""


@dataclass(frozen=True)
class InertiaSummary(Summary):
    sigma_c_0: dict[str, float]
    """Overdamped sigma_c by N ("2", "7")."""
    shift_mass_ratio: dict[str, float]
    """Smallest mass ratio where sigma_c moves by SHIFT_FRACTION, by N."""
    sigma_c_at_largest_mass: dict[str, float]
    largest_mass_ratio: float
    ziegler: list[ZieglerCheck]
    ziegler_max_rel_err: float
    """Largest |computed / closed form - 1| over the Ziegler checks."""
    sim_sigma: float
    sim: list[InertiaSimPoint]
    engines_max_rel_diff: float
    """Largest |MuJoCo / reduced - 1| of amplitude and frequency over the simulated points."""
    experiment: ExperimentScales
    overdamped_justified: bool
    """Whether the experiment's largest mass ratio lies below the N = 7 1% shift mass ratio."""


def _ziegler(eps: float) -> list[ZieglerCheck]:
    p_u, _ = fl.ziegler_critical_load()
    p_c, _ = fl.ziegler_critical_load(damping=eps)
    p_g, _ = fl.ziegler_critical_load(drag=eps)
    return [
        ZieglerCheck("undamped", 0.0, p_u, fl.ZIEGLER_UNDAMPED, PAPER.ziegler_undamped),
        ZieglerCheck("joint damping c -> 0", eps, p_c, fl.ziegler_damped_load(eps), PAPER.ziegler_damped_limit),
        ZieglerCheck("lab-frame drag -> 0", eps, p_g, fl.ziegler_drag_load(eps), fl.ZIEGLER_DRAG_LIMIT),
    ]


def _duration(base: float, m: float) -> float:
    """Run length: `base`, times sqrt(m) for heavy chains (the beat period grows ~ sqrt(m)), rounded to 10 tau."""
    return base if m <= 1.0 else 10.0 * math.ceil(base * math.sqrt(m) / 10.0 - 1e-9)


INERTIA = registry.declare("inertia", summary=InertiaSummary, order=130, budget=6)


@INERTIA.run
def inertia_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """sigma_c(m), f_c(m) for N = 2, 7; the 1% mass ratio; Ziegler's loads; N = 7 beats vs m in both engines;
    the experiment's own mass ratio."""
    start = time.perf_counter()
    masses = np.logspace(-4, 2, pick(size, 13, 25, 73))
    sims = pick(size, (1e-4, 0.5), (1e-4, 0.1, 0.5, 2.0, 10.0), (1e-4, 0.01, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0))
    base = pick(size, 150.0, 250.0, 800.0)
    data: dict = {"mass_ratio": masses}
    s0, shift, s_big = {}, {}, {}
    for n in (2, 7):
        sc, om = fl.critical_sigma_curve(n, masses)
        data[f"sigma_c_{n}"], data[f"f_c_{n}"] = sc, om / (2 * np.pi)
        m1, _, s_0 = fl.onset_shift_mass_ratio(n, SHIFT_FRACTION)
        s0[str(n)], shift[str(n)], s_big[str(n)] = s_0, m1, float(sc[-1])
        data[f"sigma_c0_{n}"] = s_0
        data[f"f_c0_{n}"] = fl.critical_sigma(n, 0.0)[1] / (2 * np.pi)
        data[f"shift_mass_ratio_{n}"] = m1
    zieg = _ziegler(1e-4)
    cases, meta = [], []
    for m in sims:
        dur = _duration(base, m)
        for eng in ENGINES:
            cases.append(
                Case(
                    one_pinned.SCENE.physics(n=7, sigma=SIM_SIGMA),
                    Numerics(mass_ratio=m, sample_dt=0.05),
                    dur,
                    eng,
                    dur / 2,
                )
            )
            meta.append((m, dur, eng))
    trajs = run(cases, workers, progress, "inertia N=7")
    res = {}
    for (m, dur, eng), tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)  # Theta = theta_N - theta_1, as results.measure
        res[(m, eng)] = (obs.amplitude(tr.t, x, dur / 2), obs.frequency(tr.t, x, dur / 2), dur)
    points = []
    for m in sims:
        points.append(
            InertiaSimPoint(
                float(m),
                res[(m, "mujoco")][2],
                {e: float(res[(m, e)][0]) for e in ENGINES},
                {e: float(res[(m, e)][1]) for e in ENGINES},
                fl.critical_sigma(7, m)[1] / (2 * np.pi),
            )
        )
    for eng in ENGINES:
        data[f"sim_amplitude_{eng}"] = np.array([p.amplitude[eng] for p in points])
        data[f"sim_frequency_{eng}"] = np.array([p.frequency[eng] for p in points])
    data["sim_mass_ratio"] = np.array(sims)
    diffs = [abs(p.amplitude["mujoco"] / p.amplitude["reduced"] - 1) for p in points]
    diffs += [abs(p.frequency["mujoco"] / p.frequency["reduced"] - 1) for p in points]
    exp = experiment_scales()
    data["experiment_mass_ratio"] = np.array(exp.mass_ratio)
    summary = InertiaSummary(
        sigma_c_0=s0,
        shift_mass_ratio=shift,
        sigma_c_at_largest_mass=s_big,
        largest_mass_ratio=float(masses[-1]),
        ziegler=zieg,
        ziegler_max_rel_err=max(abs(z.computed / z.closed_form - 1) for z in zieg),
        sim_sigma=SIM_SIGMA,
        sim=points,
        engines_max_rel_diff=float(np.nanmax(diffs)) if diffs else math.nan,
        experiment=exp,
        overdamped_justified=bool(exp.mass_ratio_max < shift["7"]),
    )
    return Study("inertia", size, data, summary, time.perf_counter() - start)


# --------------------------------------------------------------------------------------------------
# figures
# --------------------------------------------------------------------------------------------------
@INERTIA.figure
@plots.styled
def inertia_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
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
    for eng in plots.engines(d, "sim_frequency"):
        a3.plot(sm, d[f"sim_frequency_{eng}"], **plots.ENGINE_STYLE[eng])
    a3.set_xscale("log")
    a3.set_xlabel(r"mass ratio $m/(\gamma\tau)$")
    a3.set_ylabel(r"$f\tau$ of the beat")
    a3.set_title(rf"N = 7, $\sigma$ = {s.sim_sigma:g}: simulated beat")
    a3.legend()
    fig.suptitle("Inertia: linear stability with mass (analysis.flutter) and simulated beats")
    fig.tight_layout()
    return [plots.save(fig, out, "figA_inertia.png")]


# --------------------------------------------------------------------------------------------------
# claim rows
# --------------------------------------------------------------------------------------------------
@INERTIA.claims
def inertia_claims(st: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = st.summary
    e = s.experiment
    x7, x2 = s.shift_mass_ratio["7"], s.shift_mass_ratio["2"]
    rows = [
        Claim(
            f"Overdamped limit: inertia shifts the onset by < 1% below mass ratio {x7:.3g} (N = 7; {x2:.3g} for N = 2)",
            "no inertia (assumed)",
            "-",
            f"1% shift at m/(gamma tau) = {x7:.4g} (N = 7), {x2:.4g} (N = 2); experiment {min(e.mass_ratio):.3g}-"
            f"{e.mass_ratio_max:.3g} -> sigma_c(7) shifts {100 * e.sigma_c_7_shift_at_max:+.2g}%",
            verdict(s.overdamped_justified),
            "linear stability with inertia (quadratic eigenproblem, analysis.flutter). Experiment: tau = gamma l^2 / C "
            f"= gamma l sigma / F_a with gamma = {e.gamma:g} N s/m, F_a = {1e3 * e.force_n:g} mN, l = L/7 = "
            f"{100 * e.pitch_m:.2g} cm (paper) and sigma = {', '.join(f'{x:g}' for x in e.sigmas)} -> tau = "
            f"{min(e.tau_s):.2f}-{max(e.tau_s):.2f} s; ASSUMED bug mass m = {1e3 * e.mass_kg:g} g (Hexbug Nano, "
            f"commonly quoted; not in the paper) -> m/(gamma tau) = {min(e.mass_ratio):.3g}-{e.mass_ratio_max:.3g}, "
            f"{x7 / e.mass_ratio_max:.0f}x below the N = 7 1% mass ratio: the overdamped model was justified for the "
            f"onset. At m = {s.largest_mass_ratio:g}: sigma_c = {s.sigma_c_at_largest_mass['7']:.4g} (N = 7), "
            f"{s.sigma_c_at_largest_mass['2']:.4g} (N = 2; the undamped flutter load 2 is the heavy limit)",
        )
    ]
    z = {c.label: c for c in s.ziegler}
    u, d, g = z["undamped"], z["joint damping c -> 0"], z["lab-frame drag -> 0"]
    rows.append(
        Claim(
            "Ziegler's column: flutter at 7/2 - sqrt 2 (undamped), 41/28 with vanishing damping",
            f"{PAPER.ziegler_undamped:.6f}, {PAPER.ziegler_damped_limit:.6f} C/l (Ziegler 1952; literature)",
            "-",
            f"{u.computed:.6f}; {d.computed:.6f} (c = {d.parameter:g}); lab-frame drag {g.parameter:g}: "
            f"{g.computed:.6f}",
            verdict(abs(u.computed - u.limit) < 1e-6 and abs(d.computed - d.limit) < 1e-6),
            "the chain's stability code on Ziegler's double pendulum (masses 2m, m, tip load, point masses) against "
            f"the closed forms: max relative error {s.ziegler_max_rel_err:.1g}; joint damping c: 41/28 + c^2/2; this "
            f"model's lab-frame drag tends to (15 - 3 sqrt 5)/4 = {g.limit:.6f} (a -0.6% paradox, against -30% for "
            "joint damping)",
        )
    )
    amp = lambda eng: ", ".join(
        f"m = {p.mass_ratio:g}: A {p.amplitude[eng]:.4f}, f {p.frequency[eng]:.4g}" for p in s.sim
    )  # noqa: E731
    rows.append(
        Claim(
            f"MuJoCo = inertial model at finite mass (N = 7, sigma = {s.sim_sigma:g})",
            "- (overdamped only)",
            amp("mujoco"),
            amp("reduced"),
            verdict(s.engines_max_rel_diff < 0.01),
            "MuJoCo at its default dt = 0.0025 against the reduced engine's inertial model at the same mass: "
            f"amplitude and f tau agree within {100 * s.engines_max_rel_diff:.2g}%; runs lengthened ~ sqrt(m) above m "
            "= 1 (the beat slows: its period grows ~ sqrt(m))",
        )
    )
    return rows

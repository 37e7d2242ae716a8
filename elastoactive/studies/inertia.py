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
from dataclasses import dataclass

import numpy as np

from ..analysis import flutter as fl
from ..analysis import observables as obs
from ..batch import Case
from ..paper import PAPER
from ..params import Numerics
from ..scenes import one_pinned
from .base import ENGINES, Study, Summary, pick, run

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
    l, g, f = PAPER.link_pitch_m, PAPER.drag_n_s_per_m, PAPER.active_force_n
    sigmas = tuple(PAPER.experiment_sigmas)
    taus = tuple(g * l * s / f for s in sigmas)
    ratios = tuple(mass_kg / (g * t) for t in taus)
    m_max = max(ratios)
    s0 = fl.critical_sigma(7, 0.0)[0]
    shift = fl.critical_sigma(7, m_max)[0] / s0 - 1.0
    return ExperimentScales(mass_kg, l, g, f, sigmas, taus, ratios, m_max, float(shift))


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


def inertia_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """sigma_c(m), f_c(m) for N = 2, 7; the 1% mass ratio; Ziegler's loads; N = 7 beats vs m in both engines;
    the experiment's own mass ratio."""
    start = time.perf_counter()
    masses = np.logspace(-4, 2, pick(size, 13, 37, 73))
    sims = pick(size, (1e-4, 0.5), (1e-4, 0.1, 0.5, 2.0, 10.0), (1e-4, 0.01, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0))
    base = pick(size, 150.0, 400.0, 800.0)
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
            cases.append(Case(one_pinned.SCENE.physics(n=7, sigma=SIM_SIGMA), Numerics(mass_ratio=m, sample_dt=0.05),
                              dur, eng, dur / 2))
            meta.append((m, dur, eng))
    trajs = run(cases, workers, progress, "inertia N=7")
    res = {}
    for (m, dur, eng), tr in zip(meta, trajs):
        x = obs.curvature(tr.theta)  # Theta = theta_N - theta_1, as results.measure
        res[(m, eng)] = (obs.amplitude(tr.t, x, dur / 2), obs.frequency(tr.t, x, dur / 2), dur)
    points = []
    for m in sims:
        points.append(InertiaSimPoint(
            float(m), res[(m, "mujoco")][2], {e: float(res[(m, e)][0]) for e in ENGINES},
            {e: float(res[(m, e)][1]) for e in ENGINES}, fl.critical_sigma(7, m)[1] / (2 * np.pi)))
    for eng in ENGINES:
        data[f"sim_amplitude_{eng}"] = np.array([p.amplitude[eng] for p in points])
        data[f"sim_frequency_{eng}"] = np.array([p.frequency[eng] for p in points])
    data["sim_mass_ratio"] = np.array(sims)
    diffs = [abs(p.amplitude["mujoco"] / p.amplitude["reduced"] - 1) for p in points]
    diffs += [abs(p.frequency["mujoco"] / p.frequency["reduced"] - 1) for p in points]
    exp = experiment_scales()
    data["experiment_mass_ratio"] = np.array(exp.mass_ratio)
    summary = InertiaSummary(
        sigma_c_0=s0, shift_mass_ratio=shift, sigma_c_at_largest_mass=s_big, largest_mass_ratio=float(masses[-1]),
        ziegler=zieg, ziegler_max_rel_err=max(abs(z.computed / z.closed_form - 1) for z in zieg),
        sim_sigma=SIM_SIGMA, sim=points, engines_max_rel_diff=float(np.nanmax(diffs)) if diffs else math.nan,
        experiment=exp, overdamped_justified=bool(exp.mass_ratio_max < shift["7"]))
    return Study("inertia", size, data, summary, time.perf_counter() - start)

"""Self-aligning active units on the paper's one-pinned chain: what it does against sigma and l_a (new results).

Beyond the paper (its outlook: non-follower forces; the units of Baconnier et al., Nature Physics 18, 1234 (2022)).
The units start along the follower direction of the straight chain, so at t = 0 the two laws exert the same force.

Linear stability (exact, numbers from the reduced right-hand side): psi' = M theta' with M = N_perp^T J / l_a, so the
Jacobian on (theta, psi) is [I; M] [A, B] (A = d theta'/d theta, B = d theta'/d psi): N zero eigenvalues (a manifold
of equilibria: any polarity with its static shape) and those of the N x N operator A + B M. The straight state's
onset sigma_sa(l_a) is where the largest real part of A + B M crosses 0; for N = 1 it is l_a / (1 + l_a) (theta' =
(sigma - 1) theta - sigma phi, phi' = -theta' / l_a). The follower chain's onset sigma_c (a Hopf bifurcation) is that
of A alone at the same sigma.

Simulations (MuJoCo, batched): a grid of sigma x l_a, each run classified from its second half as rest (the straight
state), static (a bent shape held still, the polarity frozen), rotating (a rigid shape turning) or moving (winding
or beating); one point also runs in the reduced model and the claim rows compare the two.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..batch import Case
from ..core.params import Numerics, Physics
from ..engines import polarity
from ..engines.reduced import jacobian as follower_jacobian
from ..engines.reduced import system_of
from ..terms.self_aligning import SELF_ALIGNING
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick, run
from .claim_rows import Claim, fmt, verdict

N = 7
STATES = ("rest", "static", "rotating", "moving")
STILL = 1e-3
"""Largest angle change (rad) over the last tenth of a run for it to count as still."""
REST = 0.05
"""Largest angle (rad) of a still chain at rest in the straight state."""


def jacobian(physics: Physics, step: float = 1e-6) -> np.ndarray:
    """Central-difference Jacobian of the reduced right-hand side on (theta, psi) at the straight state, every
    polarity along the follower direction (psi = pi)."""
    f = polarity.rhs(physics, system_of(physics), beta=1.0)
    y0 = np.concatenate([np.zeros(physics.n_angles), np.full(polarity.unit_indices(physics).size, np.pi)])
    out = np.empty((y0.size, y0.size))
    for k in range(y0.size):
        e = np.zeros_like(y0)
        e[k] = step
        out[:, k] = (f(0.0, y0 + e) - f(0.0, y0 - e)) / (2 * step)
    return out


def growth(n: int, sigma: float, la: float, law: str = SELF_ALIGNING) -> float:
    """Largest real part of the straight state's eigenvalues: of A + B M for self-aligning units (A, B: the theta
    rows of `jacobian`; M from its psi rows, which are M [A, B]), of the follower chain's Jacobian otherwise."""
    if law != SELF_ALIGNING:
        return float(np.max(np.linalg.eigvals(follower_jacobian(Physics(n=n, sigma=sigma))(0.0, np.zeros(n))).real))
    jac = jacobian(Physics(n=n, sigma=sigma, active=SELF_ALIGNING, alignment_length=la))
    top = jac[:n]
    m = jac[n:] @ np.linalg.pinv(top)
    return float(np.max(np.linalg.eigvals(top[:, :n] + top[:, n:] @ m).real))


def onset(n: int, la: float, law: str = SELF_ALIGNING, high: float = 5.0) -> float:
    """Smallest sigma in (0, high] at which the straight state is unstable (bisection on `growth`)."""
    lo, hi = 1e-4, high
    if growth(n, hi, la, law) <= 0:
        return float("nan")
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if growth(n, mid, la, law) > 0 else (mid, hi)
    return hi


def classify(t: np.ndarray, theta: np.ndarray) -> str:
    """rest, static, rotating or moving, from the last tenth of a run."""
    last = theta[t >= t[0] + 0.9 * (t[-1] - t[0])]
    change = np.abs(last - last[0]).max()
    if change < STILL:
        return "rest" if np.abs(last).max() < REST else "static"
    shape = last - last[:, :1]  # angles relative to the first link: constant for a rigid rotation
    return "rotating" if np.abs(shape - shape[0]).max() < STILL * 10 else "moving"


@dataclass(frozen=True)
class SelfAligningSummary(Summary):
    sigma: list[float]
    alignment_length: list[float]
    states: list[list[str]]
    """states[i][j]: the state at alignment_length[i], sigma[j] (MuJoCo)."""
    onset: list[float]
    """The straight state's onset sigma_sa at each alignment length (linear stability, N = 7)."""
    onset_single: list[float]
    """The same for N = 1, against the analytic l_a / (1 + l_a)."""
    follower_onset: float
    """The follower chain's sigma_c (N = 7), from the same Jacobian's A block."""
    check_angle_difference: float
    """Largest angle difference (rad) between the engines at the checked point."""
    check_point: list[float]
    """(l_a, sigma) of the point run in both engines."""


SELF_ALIGNING_STUDY = registry.declare("self_aligning", summary=SelfAligningSummary, order=190, budget=5)


@SELF_ALIGNING_STUDY.run
def self_aligning_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """States of the one-pinned chain with self-aligning units on a sigma x l_a grid, the straight state's onset."""
    start = time.perf_counter()
    sigmas = pick(size, (0.1, 0.8), (0.1, 0.3, 0.8, 1.5), (0.05, 0.1, 0.2, 0.3, 0.5, 0.8, 1.2, 1.5, 2.0))
    las = pick(size, (0.5, 16.0), (0.5, 2.0, 16.0), (0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0))
    duration = pick(size, 40.0, 100.0, 400.0)
    numerics = Numerics()
    grid = [(la, s) for la in las for s in sigmas]
    check = (2.0, 0.8) if (2.0, 0.8) in grid else grid[-1]
    cases = [
        Case(Physics(n=N, sigma=s, active=SELF_ALIGNING, alignment_length=la), numerics, duration, "mujoco")
        for la, s in grid
    ]
    cases.append(
        Case(
            Physics(n=N, sigma=check[1], active=SELF_ALIGNING, alignment_length=check[0]),
            numerics,
            min(duration, 40.0),
            "reduced",
        )
    )
    trajs = run(cases, workers, progress, "self-aligning")
    states = [classify(tr.t, tr.theta) for tr in trajs[:-1]]
    reduced = trajs[-1]
    mujoco = trajs[grid.index(check)]
    common = min(reduced.t.size, mujoco.t.size)
    diff = float(np.abs(mujoco.theta[:common] - reduced.theta[:common]).max())
    onsets = [onset(N, la) for la in las]
    single = [onset(1, la) for la in las]
    data = {
        "sigma": np.array(sigmas),
        "alignment_length": np.array(las),
        "onset": np.array(onsets),
        "onset_single": np.array(single),
        "state": np.array([STATES.index(s) for s in states]).reshape(len(las), len(sigmas)),
    }
    summary = SelfAligningSummary(
        sigma=[float(s) for s in sigmas],
        alignment_length=[float(x) for x in las],
        states=[states[i * len(sigmas) : (i + 1) * len(sigmas)] for i in range(len(las))],
        onset=[float(x) for x in onsets],
        onset_single=[float(x) for x in single],
        follower_onset=onset(N, 1.0, law="follower"),
        check_angle_difference=diff,
        check_point=[float(check[0]), float(check[1])],
    )
    return Study("self_aligning", size, data, summary, time.perf_counter() - start)


@SELF_ALIGNING_STUDY.figure
@plots.styled
def self_aligning_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    fig, ax = plt.subplots(figsize=(6.0, 4.2))
    markers = {"rest": ("o", "0.6"), "static": ("s", "C0"), "rotating": ("^", "C2"), "moving": ("*", "C3")}
    for i, la in enumerate(d["alignment_length"]):
        for j, sigma in enumerate(d["sigma"]):
            name = STATES[int(d["state"][i, j])]
            ax.scatter(
                sigma,
                la,
                marker=markers[name][0],
                color=markers[name][1],
                s=70,
                label=name if name not in ax.get_legend_handles_labels()[1] else None,
            )
    ax.plot(d["onset"], d["alignment_length"], "k-", lw=1, label=r"onset $\sigma_{sa}(l_a)$, N = 7")
    ax.plot(d["onset_single"], d["alignment_length"], "k:", lw=1, label=r"N = 1: $l_a / (1 + l_a)$")
    ax.axvline(s.follower_onset, color="C1", ls="--", lw=1, label=rf"follower $\sigma_c$ = {s.follower_onset:.3f}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\sigma = F_a l / C_1$")
    ax.set_ylabel(r"alignment length $l_a / l$")
    ax.set_title("One-pinned chain (N = 7) with self-aligning units (MuJoCo)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figC_self_aligning.png")]


@SELF_ALIGNING_STUDY.claims
def self_aligning_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    outlook = "outlook: non-follower forces (not simulated)"
    exact = [la / (1 + la) for la in s.alignment_length]
    single_error = max(abs(a - b) / b for a, b in zip(s.onset_single, exact))
    below = [la for la, x in zip(s.alignment_length, s.onset) if x < s.follower_onset]
    moving = sorted(
        {
            (la, sg)
            for la, row in zip(s.alignment_length, s.states)
            for sg, st in zip(s.sigma, row)
            if st in ("moving", "rotating")
        }
    )
    return [
        Claim(
            "Self-aligning units destabilise the straight chain below the follower onset (new result)",
            outlook,
            "sigma_sa(l_a) = "
            + ", ".join(f"{fmt(x, 3)} (l_a = {fmt(la)})" for la, x in zip(s.alignment_length, s.onset)),
            f"N = 1: {', '.join(fmt(x, 4) for x in s.onset_single)} = l_a / (1 + l_a) within {single_error:.1g}",
            verdict(len(below) == len(s.alignment_length) and single_error < 1e-3),
            f"follower sigma_c = {s.follower_onset:.4f} (N = 7); linear stability of the reduced model",
        ),
        Claim(
            "Beyond onset the chain bends and either freezes (long l_a) or keeps moving (short l_a) (new result)",
            outlook,
            f"moving or rotating at (l_a, sigma) = {', '.join(f'({fmt(a)}, {fmt(b)})' for a, b in moving) or 'none'}",
            f"angles within {s.check_angle_difference:.2g} rad of MuJoCo at (l_a, sigma) = "
            f"({fmt(s.check_point[0])}, {fmt(s.check_point[1])}) over 40 tau",
            verdict(s.check_angle_difference < 0.05),
            "states from the last tenth of each MuJoCo run; the polarity freezes with the shape",
        ),
    ]

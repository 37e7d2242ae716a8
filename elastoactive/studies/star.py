"""The star: do k elasto-active arms on one hub synchronise through it, and in which pattern, against the hub's
stiffness.

Beyond the paper (its outlook's "more intricate geometrical connections between active particles"): k one-pinned
arms (N = 7, sigma = 0.8) on a hub turning on a spring hub_stiffness K_h (C1) against its drag (1 gamma l^2), swept
from a free hub (K_h = 0) to a clamped one (K_h -> infinity: k independent chains). The reduced model runs the whole
grid; MuJoCo runs a few points, and the claim rows compare the two there. Every arm starts from its own seeded push,
so no synchrony is put in by hand. These are new results, not the paper's. analysis.star_stability (scipy) is imported
inside _onset_claim, the linear analysis's boundary: only the claim rows need it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..batch import Case, run_cases
from ..core.params import Numerics
from ..scenes import star
from . import plotting as plots
from . import registry
from .base import Study, Summary, pick
from .claim_rows import Claim, fmt, verdict

N, SIGMA, HUB_DRAG = 7, 0.8, 1.0
"""The arms (the paper's one-pinned chain) and the hub's drag of every point."""
NEW = "new (beyond the paper)"
"""The paper column of every row: the paper has no star."""


@dataclass(frozen=True)
class StarSummary(Summary):
    arms: list[int]
    hub_stiffness: list[float]
    """K_h of the turning hub's points (the clamped hub is one more point per k)."""
    states: dict[str, list[str]]
    """Reduced model: the arms' state at each K_h, per k ("2", "3", ...), then "clamped" last."""
    in_phase: dict[str, list[float]]
    """Reduced model: the K_h > 0 at which the k arms beat in phase, per k."""
    frequency: dict[str, list[float]]
    """Reduced model: the arms' mean beat frequency f tau at each K_h, then the clamped hub's, per k."""
    amplitude: dict[str, list[float]]
    hub_amplitude: dict[str, list[float]]
    free_hub: dict[str, str]
    """What the arms do on a free hub (K_h = 0), per k: their state, or "spin" when they turn rigidly with it."""
    spin_rate: dict[str, float]
    """|mean d phi / dt| (rad / tau) of a free hub, per k."""
    clamped_spread: float
    """Largest relative spread of the arms' amplitudes and frequencies on a clamped hub (k independent chains)."""
    checks: list[dict]
    """MuJoCo against the reduced model: per point k, K_h, both states, the largest relative differences."""


# the study is named after its scene
STAR = registry.declare(star.SCENE.name, summary=StarSummary, order=190, budget=3.5)


def _physics(k: int, hub_stiffness: float | None):
    if hub_stiffness is None:
        return star.SCENE.physics(n=N, sigma=SIGMA, arms=k, hub=star.HUB_CLAMPED)
    return star.SCENE.physics(n=N, sigma=SIGMA, arms=k, hub_stiffness=hub_stiffness, hub_drag=HUB_DRAG)


def _point(results) -> dict:
    extra = results.extra
    rate = extra["hub_rate"]
    frequency = [0.0 if f is None else f for f in results.frequency]  # null: a spinning star's arms turn, no beat
    return dict(
        state="spin" if extra["sync_state"] == "rest" and abs(rate) > 1e-3 else extra["sync_state"],
        frequency=float(np.mean(frequency)),
        amplitude=float(np.mean(results.amplitude)),
        hub_amplitude=float(extra["hub_amplitude"]),
        hub_rate=float(rate),
        sync_order=float(extra["sync_order"]),
        spread=max(_relative_spread(results.amplitude), _relative_spread(frequency)),
    )


def _relative_spread(values) -> float:
    """The arms' spread of a value relative to its mean: 0 where every arm has the same value, zero included (a
    spinning star's arms all have frequency 0), infinite where they differ about a zero mean."""
    values = np.asarray(values, dtype=float)
    spread, mean = float(np.ptp(values)), float(np.mean(values))
    if mean != 0:
        return abs(spread / mean)
    return 0.0 if spread == 0 else math.inf


@STAR.run
def star_study(size: str = "quick", workers=None, progress: bool = True) -> Study:
    """The arms' synchronised state, beat and hub swing against the hub's stiffness, k = 2, 3 (and 4 at full size)."""
    start = time.perf_counter()
    arms = pick(size, (2, 3), (2, 3), (2, 3, 4))
    # the weaker the hub's coupling (large K_h), the longer the arms take to lock: K_h = 10 needs ~1000 tau for k = 2
    stiffness = pick(size, (0.0, 1.0), (0.0, 0.3, 1.0, 3.0), (0.0, 0.1, 0.3, 1.0, 3.0, 10.0))
    duration = pick(size, 300.0, 500.0, 1500.0)
    checked = pick(size, (1.0,), (1.0,), (0.0, 1.0, 10.0))
    check_duration = pick(size, 200.0, 200.0, 1500.0)
    reduced = Numerics(sample_dt=0.1)
    grid = [(k, K) for k in arms for K in (*stiffness, None)]
    cases = [Case(_physics(k, K), reduced, duration, "reduced", duration / 2) for k, K in grid]
    checks = [(k, K) for k in pick(size, (3,), (3,), arms) for K in checked]
    cases += [
        Case(_physics(k, K), Numerics(sample_dt=0.1), check_duration, engine, check_duration / 2)
        for k, K in checks
        for engine in ("mujoco", "reduced")
    ]
    results = [r.results for r in run_cases(cases, workers=workers, progress=progress, desc="star arms")]
    points = [_point(r) for r in results[: len(grid)]]
    data: dict[str, np.ndarray] = {"hub_stiffness": np.array(stiffness)}
    by_k: dict[str, list[dict]] = {}
    for (k, _), p in zip(grid, points):
        by_k.setdefault(str(k), []).append(p)
    for k, ps in by_k.items():
        for name in ("frequency", "amplitude", "hub_amplitude", "sync_order", "hub_rate"):
            data[f"{name}_{k}"] = np.array([p[name] for p in ps])
    rows = []
    for i, (k, K) in enumerate(checks):
        mj, rd = (_point(r) for r in results[len(grid) + 2 * i : len(grid) + 2 * i + 2])
        diff = max(abs(mj[x] - rd[x]) / max(abs(rd[x]), 1e-9) for x in ("frequency", "amplitude", "hub_amplitude"))
        rows.append(
            dict(
                arms=k,
                hub_stiffness=K,
                mujoco=mj["state"],
                reduced=rd["state"],
                difference=float(diff),
                frequency_mujoco=mj["frequency"],
                frequency_reduced=rd["frequency"],
            )
        )
    summary = StarSummary(
        arms=list(arms),
        hub_stiffness=[float(K) for K in stiffness],
        states={k: [p["state"] for p in ps] for k, ps in by_k.items()},
        in_phase={
            k: [float(K) for K, p in zip(stiffness, ps) if K > 0 and p["state"] == "in-phase"] for k, ps in by_k.items()
        },
        frequency={k: [p["frequency"] for p in ps] for k, ps in by_k.items()},
        amplitude={k: [p["amplitude"] for p in ps] for k, ps in by_k.items()},
        hub_amplitude={k: [p["hub_amplitude"] for p in ps] for k, ps in by_k.items()},
        free_hub={k: ps[0]["state"] for k, ps in by_k.items()},
        spin_rate={k: abs(ps[0]["hub_rate"]) for k, ps in by_k.items()},
        clamped_spread=float(max(ps[-1]["spread"] for ps in by_k.values())),
        checks=rows,
    )
    return Study(star.SCENE.name, size, data, summary, time.perf_counter() - start)


@STAR.figure
@plots.styled
def star_figures(study: Study, out: Path) -> list[Path]:
    plt = plots.pyplot()
    d, s = study.data, study.summary
    K = np.asarray(d["hub_stiffness"])
    shown = K > 0  # a log axis: the free hub is a row of the table
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.5, 4.0))
    for i, k in enumerate(s.arms):
        colour = f"C{i}"
        f = d[f"frequency_{k}"]
        a1.semilogx(K[shown], f[:-1][shown], "o-", color=colour, label=f"k = {k}, turning hub (reduced)")
        a1.axhline(f[-1], color=colour, ls=":", lw=0.8, label=f"k = {k}, clamped hub")
        a2.loglog(K[shown], d[f"hub_amplitude_{k}"][:-1][shown], "o-", color=colour, label=f"k = {k}")
        for row in s.checks:
            if row["arms"] == k and row["hub_stiffness"] > 0:
                a1.semilogx(
                    [row["hub_stiffness"]], [row["frequency_mujoco"]], "x", color=colour, ms=9, label=f"k = {k}, MuJoCo"
                )
    a1.set_xlabel(r"hub stiffness $K_h$ ($C_1$)")
    a1.set_ylabel(r"beat frequency $f\tau$ (arms in phase)")
    a1.set_title("The hub slows the in-phase beat")
    a1.legend(fontsize=7)
    a2.set_xlabel(r"hub stiffness $K_h$ ($C_1$)")
    a2.set_ylabel(r"hub swing: half peak-to-peak of $\phi$ (rad)")
    a2.set_title("... and swings with it")
    a2.legend(fontsize=7)
    fig.tight_layout()
    return [plots.save(fig, out, "figB_star.png")]


@STAR.claims
def star_claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    ks = [str(k) for k in s.arms]
    stiff = [K for K in s.hub_stiffness if K > 0]
    all_in_phase = all(s.in_phase[k] == stiff for k in ks)
    checks_agree = all(r["mujoco"] == r["reduced"] for r in s.checks)
    worst = max(r["difference"] for r in s.checks)
    checked = "; ".join(f"k = {r['arms']}, K_h = {fmt(r['hub_stiffness'])}: {r['mujoco']}" for r in s.checks)
    checked_reduced = "; ".join(f"{r['reduced']}" for r in s.checks)
    slow = {k: s.frequency[k][s.hub_stiffness.index(1.0)] / s.frequency[k][-1] for k in ks if 1.0 in s.hub_stiffness}
    free = ", ".join(
        f"k = {k}: {s.free_hub[k]}" + (f" at {fmt(s.spin_rate[k], 3)} rad/tau" if s.free_hub[k] == "spin" else "")
        for k in ks
    )
    return [
        Claim(
            "A star on a clamped hub is k independent one-pinned chains",
            NEW,
            "tests/scenes/test_star.py: every arm's amplitude and frequency = the one-pinned chain's to 0.1%",
            f"arms' amplitudes and frequencies within {100 * s.clamped_spread:.2g}% of each other "
            f"(f tau = {', '.join(fmt(s.frequency[k][-1], 4) for k in ks)})",
            verdict(s.clamped_spread < 1e-3),
            "the arms share nothing; their phases keep what the seeded start gave them (no state is selected)",
        ),
        Claim(
            f"A turning hub locks the arms in phase (K_h = {fmt(min(stiff))}-{fmt(max(stiff))}, k = {', '.join(ks)})",
            NEW,
            checked,
            f"{checked_reduced}; in phase at every K_h > 0: "
            f"{'yes' if all_in_phase else ', '.join(f'k = {k}: {s.in_phase[k]}' for k in ks)}",
            verdict(all_in_phase and checks_agree and worst < 0.01),
            f"from seeded, different pushes; R_1 = 1; frequency, amplitude and hub swing of the engines within "
            f"{100 * worst:.2g}%; no antiphase or splay state was found at K_h > 0",
        ),
        Claim(
            "The in-phase beat is slower and larger than a lone arm's, and the hub swings with it",
            NEW,
            "-",
            "; ".join(
                f"k = {k}: f(K_h = 1) / f(clamped) = {fmt(slow[k], 3)}, amplitude "
                f"{fmt(s.amplitude[k][s.hub_stiffness.index(1.0)], 3)} vs {fmt(s.amplitude[k][-1], 3)} rad, "
                f"hub {fmt(s.hub_amplitude[k][s.hub_stiffness.index(1.0)], 3)} rad"
                for k in slow
            ),
            verdict(all(v < 1 for v in slow.values())),
            "the arms bend together and turn the hub: a softer hub is a softer clamp for the in-phase mode",
        ),
        Claim(
            "On a free hub (K_h = 0) two arms beat in antiphase; three or more spin as a rigid star",
            NEW,
            "-",
            free,
            verdict(s.free_hub.get("2") == "antiphase" and all(s.free_hub[k] == "spin" for k in ks if int(k) >= 3)),
            "k = 2: the arms form one 2N chain through the hub, beating mirror-symmetrically with the hub nearly "
            "still; k >= 3: the follower forces' torque turns the hub and the straight arms with it",
        ),
        Claim(
            "The hub couples the arms like the pair's spring, kappa_eff = 1 / (K_h + k), without detuning",
            NEW,
            "-",
            f"kappa_eff = {fmt(1 / (max(stiff) + 2), 3)}-{fmt(1 / (min(stiff) + 2), 3)} (k = 2) all lock",
            verdict(all_in_phase),
            "eliminating a fast hub (hub_drag -> 0) leaves clamps K_h / (K_h + k) and springs 1 / (K_h + k) between "
            "every pair of first links; identical arms have no detuning, so unlike the pair (kappa_c = 0.078 at "
            "rho = 4/3, study tongue) no threshold appears: the hub selects the in-phase state",
        ),
        _onset_claim(ks, stiff, all_in_phase),
    ]


def _onset_claim(ks: list[str], stiff: list[float], all_in_phase: bool) -> Claim:
    """The linear operator about the straight star (analysis.star_stability) at the study's hubs: which mode leaves
    the straight state first, against the in-phase locking the study simulates at sigma = SIGMA."""
    from ..analysis import star_stability  # start-up time: scipy

    onsets = {(k, K): star_stability.star_onset(N, int(k), K, HUB_DRAG) for k in ks for K in stiff}
    first = {mode for _, _, mode in onsets.values()}
    lone = star_stability.mode_onsets(N, 2, None, None)["in-phase"][0]
    text = "; ".join(
        f"k = {k}: sigma_c = {fmt(onsets[(k, min(stiff))][0], 4)}-{fmt(onsets[(k, max(stiff))][0], 4)}" for k in ks
    )
    return Claim(
        f"The in-phase mode leaves the straight star first (linear operator, N = {N}, K_h = "
        f"{fmt(min(stiff))}-{fmt(max(stiff))})",
        NEW,
        "-",
        f"{text}; first: {', '.join(sorted(first))}",
        verdict(first == {star_stability.IN_PHASE} and all_in_phase),
        f"antiphase and splay modes leave the hub still and keep the one-pinned onset {fmt(lone, 6)}; the "
        f"in-phase mode, bordered by the hub, goes first at every K_h, as the simulations at sigma = {SIGMA:g} "
        "lock in phase",
    )

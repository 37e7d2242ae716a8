r"""Section I of scripts/benchmark.py: the clamped filament in three dimensions, started out of plane, in PyElastica (a
Cosserat rod) beside the reduced 3D chain and the whirl's continuum limit, every number against that limit.

The problem, in the chain's dimensionless names (docs/model3d.md, docs/filament.md): a filament of length L = N l,
bending stiffness B = C l (isotropic), clamped along e_x at one end, under a uniform follower load f = F_a / l per
length along its tangent toward the clamp, S = f L^3 / B = N^3 sigma = FILAMENT_S (100, above the onset 76.10), and
lab-frame drag zeta = gamma_T / l per length, the same along and across the filament (drag ratio gamma_L / gamma_T =
1). Times in the filament's unit zeta L^4 / B = N^4 tau. Both start from the same non-planar shape, the tangent
t(s) proportional to (1, START s, START s^2) (s = arc length / L).

- PyElastica: CosseratRod.straight_rod with L = 1, B = E pi r^4 / 4 = 1 (the rod of section F, ELASTICA_ROD), bent
  into the start shape (positions and directors, the directors turned by the least rotation from the clamp's), held by
  OneEndFixedBC (node 0 and the first element's directors); the follower load as a forcing class (-f dl t_e on the
  node at the end of element e, as the chain's particle at the end of its link); the drag as AnalyticalLinearDamper's
  physical protocol with the translational constant zeta times each node's length share (dl, dl / 2 at the ends), so
  every node's velocity decays as m dv/dt = -zeta dl v, integrated exactly over each step (no stiffness limit from
  the drag: the small mass sets the overdamped limit). AnisotropicFrictionalPlane is a contact friction with a ground
  and is not this drag. The rotational constant dl^3 (a torque per length dl^2, vanishing with the element) damps the
  rod's fast twist and shear vibrations only. Timestep: PositionVerlet at ELASTICA_ROD's cfl times min(dl, r) /
  sqrt(E / rho): the axial wave's limit dl / sqrt(E / rho), or the cross-section's shear rocking (frequency
  2 sqrt(alpha_c G / rho) / r, limit 1.76 r / sqrt(E / rho) at G = E / 3) when the radius is the smaller (r = 0.01
  at 50 elements diverged on the axial limit alone).
- The reduced 3D chain (elastoactive.reduced.chain3d) at sigma = S / N^3 from the same start (tangents sampled at the
  links' midpoints), by solve3d's automatic method as `elastoactive run clamped-3d --engine reduced` runs it: LSODA
  with the analytic Jacobian (the chain is stiff in time like the planar one: its fastest relaxation stays ~16 / tau
  while its period grows like N^4). A chain converges to the filament like 1/N, so the chains of EXTRAPOLATED (each
  one simulation) are extrapolated in 1/N (analysis.filament.richardson, second order through three N), their CPU
  summed: the row at PyElastica's accuracy.
- The continuum: the whirl found by Newton's method along a ladder of N (analysis.whirl.ladder, started from the
  chain's settled whirl), extrapolated in 1/N (scripts/whirl_continuum.py; docs/model3d.md section 6).

Each simulation is classified by analysis.motion3d (beat, whirl, other) on its last PERIODS[1] periods, and measured
there: a whirl's |Omega| as the slope of the tip's unwrapped azimuth about e_x (exact for a rigid turn; a beat's as
2 pi x the tip's frequency), and the tip's distance from the clamp axis over L.

PyElastica is imported inside the functions that run it (the engine's boundary): it is an optional dependency, and
without it the section prints a note in place of its rows.
"""

from __future__ import annotations

import platform
import time
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

import numpy as np
from bench_common import CORES, ROOT, load, log
from benchmark_filament import ELASTICA_ROD, FILAMENT_S, elastica_classes, elastica_rod

from elastoactive.analysis.filament import richardson
from elastoactive.analysis.motion3d import measure3d
from elastoactive.analysis.whirl import find_whirl, ladder
from elastoactive.io.outputs import git_commit, provenance, write_text
from elastoactive.reduced.chain3d import Chain3D, solve3d

START = 0.3
"""The out-of-plane start: t(s) proportional to (1, START s, START s^2), s in [0, 1] (the helix of
scripts/whirl_continuum.py)."""
PERIODS = (16, 8)
"""Whirl periods run from the start, and the last ones measured (the chain at N = 20 and 40 has settled to 1e-8 in
Omega after 10; analysis.motion3d counts the tip's crossings over the last half of what it is given, so the window
holds 8 periods for 4 counted)."""
OMEGA_GUESS = 278.0
"""A whirl's |Omega| at S = 100 in B / (zeta L^4), close enough to size runs and their sampling."""
SAMPLES_PER_PERIOD = 200
CHAIN_TOL = dict(rtol=1e-8, atol=1e-10)
"""The chain's tolerances (the scene's defaults; the rate is then steady to ~1e-8)."""
EXTRAPOLATED = ((20, 40), (14, 20, 28))
"""The chains extrapolated in 1/N: first order through two N (the previous table's row), second order through three."""
LADDER = (10, 14, 20, 28, 40, 56)
"""The Newton ladder's N (docs/model3d.md section 6)."""


@dataclass(frozen=True)
class Row:
    """One way of computing the filament's state from the out-of-plane start."""

    tool: str
    resolution: str
    state: str
    omega: float
    """|Omega| in B / (zeta L^4) (the whirl's angular rate, or a beat's angular frequency)."""
    radius: float
    """The tip's mean distance from the clamp axis over L."""
    settled: float
    """|Omega| change between the two halves of the measured window, relative (how far from steady)."""
    wall_s: float
    cpu_s: float
    per_period_s: float
    """Wall time per period of the state (simulations); the whole wall time for the ladder."""
    omega_err: float = float("nan")
    radius_err: float = float("nan")
    omega_bar: float = 0.0
    radius_bar: float = 0.0


def start_tangents(s: np.ndarray) -> np.ndarray:
    """The start's unit tangents (len(s), 3) at arc lengths s / L."""
    t = np.column_stack([np.ones_like(s), START * s, START * s * s])
    return t / np.linalg.norm(t, axis=1)[:, None]


@dataclass(frozen=True)
class Measured:
    """A simulation's steady state over its measured window."""

    state: str
    """analysis.motion3d's name of it: beat, whirl, other, rest."""
    omega: float
    """Signed angular rate about e_x of a whirl (the slope of the tip's unwrapped azimuth, > 0 from +y to +z); for
    any other state 2 pi x the tip's frequency."""
    radius: float
    """The tip's mean distance from the clamp axis over L."""
    settled: float
    """|Omega| change between the two halves of the window, relative (how far from steady)."""


def _rate(t: np.ndarray, links: np.ndarray, state: str, frequency: float) -> float:
    if state != "whirl":
        return 2 * np.pi * frequency
    tip = links.sum(axis=1)
    azimuth = np.unwrap(np.arctan2(tip[:, 2], tip[:, 1]))
    return float(np.polyfit(t, azimuth, 1)[0])


def _measure(t: np.ndarray, links: np.ndarray, length: float) -> Measured:
    """The steady state over the record t (filament time), links (T, n, 3) the link vectors whose sum is the tip."""
    whole = measure3d(t, links, transient=0.0)
    half = t.size // 2
    first, second = (
        _rate(t[part], links[part], whole.state, measure3d(t[part], links[part], transient=0.0).frequency)
        for part in (slice(0, half), slice(half, None))
    )
    settled = abs(second / first - 1) if first != 0 else float("nan")
    return Measured(whole.state, _rate(t, links, whole.state, whole.frequency), whole.tip_radius / length, settled)


def _least_rotation(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The rotation matrix taking unit u to unit v about u x v (Rodrigues)."""
    w = np.cross(u, v)
    c = float(u @ v)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    return np.eye(3) + k + k @ k / (1 + c)


def elastica_run(n_elem: int, periods: float, mass_per_length: float | None = None, radius: float | None = None):
    """PyElastica's rod from the start over `periods` whirl periods: (t, link vectors (T, n_elem, 3), wall s, cpu s of
    the integration). The engine's boundary: pyelastica is imported here (an optional bench dependency)."""
    import elastica as ea  # the optional bench dependency, at its engine's boundary (module docstring)

    Filament, Follower = elastica_classes(ea)

    rod, wave_speed = elastica_rod(ea, n_elem, radius, mass_per_length)
    r, dl = ELASTICA_ROD["radius"] if radius is None else radius, 1.0 / n_elem
    tangents = start_tangents((np.arange(n_elem) + 0.5) * dl)
    rod.position_collection[:, 1:] = np.cumsum(tangents * dl, axis=0).T
    base = rod.director_collection[..., 0].copy()  # rows d1, d2, d3 = e_z, e_x x e_z, e_x
    for e in range(n_elem):
        turn = _least_rotation(np.array([1.0, 0, 0]), tangents[e])
        rod.director_collection[..., e] = base @ turn.T  # each director row turned: d_i -> turn d_i
    sim = Filament()
    sim.append(rod)
    sim.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,), constrained_director_idx=(0,))
    sim.add_forcing_to(rod).using(Follower, load=FILAMENT_S * dl)
    share = np.full(n_elem + 1, dl)
    share[[0, -1]] = dl / 2
    dt = ELASTICA_ROD["cfl"] * min(dl, r) / wave_speed
    sim.dampen(rod).using(
        ea.AnalyticalLinearDamper, translational_damping_constant=share, rotational_damping_constant=dl**3, time_step=dt
    )
    period = 2 * np.pi / OMEGA_GUESS
    every = max(1, int(period / SAMPLES_PER_PERIOD / dt))
    times, links = [], []

    class Record(ea.CallBackBaseClass):
        def make_callback(self, system, time, current_step):
            if current_step % every == 0:
                times.append(time)
                links.append(np.diff(system.position_collection, axis=1).T.copy())

    sim.collect_diagnostics(rod).using(Record)
    sim.finalize()
    steps = int(periods * period / dt)
    w0, c0 = time.perf_counter(), time.process_time()
    ea.integrate(ea.PositionVerlet(), sim, steps * dt, steps, progress_bar=False)
    return np.array(times), np.array(links), time.perf_counter() - w0, time.process_time() - c0


def chain_run(n: int, periods: float):
    """The reduced 3D chain of n links from the start over `periods` whirl periods: (t in filament time, tangents
    (T, n, 3), wall s, cpu s, the method solve3d chose)."""
    chain = Chain3D(n=n, sigma=FILAMENT_S / n**3)
    t0 = start_tangents((np.arange(n) + 0.5) / n)
    duration = periods * 2 * np.pi / OMEGA_GUESS * n**4
    ts = np.linspace(0.0, duration, int(periods * SAMPLES_PER_PERIOD) + 1)
    # compiled (right-hand side, Jacobian) and the start's eigenvalues once (the first LAPACK call loads its threads):
    # not counted
    solve3d(chain, ts[:3], t0, method="LSODA", budget=lambda _method, _eig: None, **CHAIN_TOL)
    chosen = []
    w0, c0 = time.perf_counter(), time.process_time()
    path = solve3d(chain, ts, t0, budget=lambda method, _eig: chosen.append(method), **CHAIN_TOL)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    return ts / n**4, path, wall, cpu, chosen[0]


def _window(t: np.ndarray) -> np.ndarray:
    return t >= t[-1] - PERIODS[1] * 2 * np.pi / OMEGA_GUESS


def bench_elastica(elements, mass_check: int | None) -> list[Row] | str:
    """PyElastica at each element count (and, at mass_check elements, with half the mass and half the radius: the
    overdamped limit's and the extensibility's share of the error). A note when pyelastica is not installed."""
    try:
        import elastica  # noqa: F401  (is the optional bench dependency installed?)
    except ImportError:
        return "pyelastica is not installed (`pip install -e .[bench]`): its rows are skipped"
    elastica_run(elements[0], 0.05)  # its kernels compile on first use: not counted
    runs = [(n, None, None, "") for n in elements]
    if mass_check:
        m, r = ELASTICA_ROD["mass_per_length"], ELASTICA_ROD["radius"]
        runs += [(mass_check, m / 2, None, f", mass {m / 2:g} per length"), (mass_check, None, r / 2, f", r {r / 2:g}")]
    rows = []
    for n_elem, mass, radius, label in runs:
        t, links, wall, cpu = elastica_run(n_elem, PERIODS[0], mass, radius)
        resolution = f"{n_elem} elements{label}"
        if not np.isfinite(links).all():
            rows.append(Row("PyElastica", resolution, "diverged", *[float("nan")] * 3, wall, cpu, wall / PERIODS[0]))
            log(f"PyElastica {n_elem}{label}: diverged")
            continue
        keep = _window(t)
        got = _measure(t[keep], links[keep], 1.0)
        state, omega, rad, settled = got.state, abs(got.omega), got.radius, got.settled
        rows.append(Row("PyElastica", resolution, state, omega, rad, settled, wall, cpu, wall / PERIODS[0]))
        log(f"PyElastica {n_elem}{label}: {state} Omega {omega:.3f} R/L {rad:.5f} ({wall:.1f} s wall, {cpu:.1f} s cpu)")
    return rows


def bench_chain(ns) -> tuple[list[Row], np.ndarray, float]:
    """The reduced 3D chain at each N; also the last chain's final shape and rate (the ladder's first guess)."""
    rows = []
    for n in ns:
        t, tangents, wall, cpu, method = chain_run(n, PERIODS[0])
        keep = _window(t)
        got = _measure(t[keep], tangents[keep], float(n))
        state, omega, rad, settled, signed = got.state, abs(got.omega), got.radius, got.settled, got.omega
        rows.append(
            Row(f"reduced 3D chain ({method})", f"N = {n}", state, omega, rad, settled, wall, cpu, wall / PERIODS[0])
        )
        log(f"chain N = {n} ({method}): {state} Omega {omega:.3f} R/L {rad:.5f} ({wall:.1f} s wall, {cpu:.1f} s cpu)")
        guess, rate = tangents[-1], signed / n**4
    return rows, guess, rate


def extrapolated(rows: list[Row], ns) -> Row:
    """The chains at ns (rows by resolution "N = n") extrapolated in 1/N; their times summed."""
    chains = [next(r for r in rows if r.resolution == f"N = {n}") for n in ns]
    order = "first" if len(ns) == 2 else "second" if len(ns) == 3 else f"{len(ns) - 1}th"
    wall, cpu = sum(r.wall_s for r in chains), sum(r.cpu_s for r in chains)
    return Row(
        f"the {len(ns)} chains extrapolated in 1/N ({order} order)",
        f"N = {', '.join(map(str, ns))}",
        "whirl" if all(r.state == "whirl" for r in chains) else "/".join(r.state for r in chains),
        richardson(ns, [r.omega for r in chains]).value,
        richardson(ns, [r.radius for r in chains]).value,
        max(r.settled for r in chains),
        wall,
        cpu,
        wall / PERIODS[0],
    )


def bench_ladder(guess: np.ndarray, rate: float) -> Row:
    """The whirl by Newton along LADDER from a settled chain's shape (turned about e_x to put its tip on +y: holding the
    tip's z fixes the turn only where z changes with it, and Newton stalls with the tip near the z axis), extrapolated
    to the continuum."""
    w0, c0 = time.perf_counter(), time.process_time()
    n0 = guess.shape[0]
    tip = guess.sum(axis=0)
    turn = -np.arctan2(tip[2], tip[1])  # the tip onto +y: find_whirl holds the tip's z, a good phase condition there
    c, s = np.cos(turn), np.sin(turn)
    guess = guess @ np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]]).T
    first = find_whirl(Chain3D(n=n0, sigma=FILAMENT_S / n0**3), guess, rate)
    result = ladder(FILAMENT_S, LADDER, first.tangents, first.omega * (n0 / LADDER[0]) ** 4)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    log(f"ladder: Omega {result.omega.value:.4f} +- {result.omega.error:.1g}, R/L {result.radius.value:.6f}")
    return Row(
        "Newton's whirl, ladder extrapolated in 1/N",
        f"N = {', '.join(map(str, LADDER))}",
        "whirl" if all(s.growth < 0 for s in result.states) else "whirl (unstable)",
        abs(result.omega.value),
        result.radius.value,
        0.0,
        wall,
        cpu,
        wall,
        omega_bar=result.omega.error,
        radius_bar=result.radius.error,
    )


def bench_elastica3d(quick: bool) -> dict:
    log(f"3D filament (load {load()})")
    extrapolations = EXTRAPOLATED[1:] if quick else EXTRAPOLATED
    chain, guess, rate = bench_chain(sorted({n for ns in extrapolations for n in ns}))
    chain += [extrapolated(chain, ns) for ns in extrapolations]
    continuum = bench_ladder(guess, rate)
    elastica = bench_elastica((50,) if quick else (50, 100, 200), None if quick else 50)

    def scored(row: Row) -> Row:
        return Row(
            **{
                **row.__dict__,
                "omega_err": row.omega / continuum.omega - 1,
                "radius_err": row.radius / continuum.radius - 1,
            }
        )

    try:
        pyelastica = metadata.version("pyelastica")
    except metadata.PackageNotFoundError:
        pyelastica = None
    return {
        "provenance": {**provenance(), "git_commit": git_commit(ROOT)},
        "pyelastica": pyelastica,
        "continuum": continuum,
        "chain": [scored(r) for r in chain],
        "elastica": elastica if isinstance(elastica, str) else [scored(r) for r in elastica],
        "load": load(),
    }


def elastica3d_report(res: dict) -> str:
    c: Row = res["continuum"]
    lines = [
        "# Benchmark: the clamped filament in 3D from an out-of-plane start, PyElastica beside the reduced 3D chain",
        "",
        f"Generated by `scripts/benchmark.py --elastica3d` on {time.strftime('%Y-%m-%d %H:%M')} "
        f"({platform.processor() or platform.machine()}, {CORES} cores shared with other work; load at the end "
        f"{res['load']}). S = f L^3 / B = N^3 sigma = {FILAMENT_S:g}, isotropic bending, drag ratio 1, start "
        f"t(s) ~ (1, {START} s, {START} s^2); Omega in B / (zeta L^4) (= N^4 / tau), R = the tip's distance from the "
        f"clamp axis. Each simulation runs {PERIODS[0]} periods and is measured over the last {PERIODS[1]}. The "
        f"reference is the continuum whirl: |Omega| = {c.omega:.3f} +- {c.omega_bar:.1g}, R / L = {c.radius:.5f} +- "
        f"{c.radius_bar:.1g}. Versions: "
        + ", ".join(
            f"{k} {v}" for k, v in {**res["provenance"]["versions"], "pyelastica": res["pyelastica"]}.items() if v
        )
        + f"; git {res['provenance']['git_commit']}.",
        "",
        "| tool | resolution | state reached | abs Omega | Omega error | R / L error | settled to | wall s "
        "(cpu s) | wall s per period |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    sims = ([] if isinstance(res["elastica"], str) else res["elastica"]) + res["chain"]
    if isinstance(res["elastica"], str):
        lines.append(f"| PyElastica | - | - | - | - | - | - | skipped: {res['elastica']} | - |")
    for r in sims:
        lines.append(
            f"| {r.tool} | {r.resolution} | {r.state} | {r.omega:.3f} | {100 * r.omega_err:+.2f}% | "
            f"{100 * r.radius_err:+.2f}% | {r.settled:.0e} | {r.wall_s:.1f} ({r.cpu_s:.1f}) | {r.per_period_s:.2f} |"
        )
    lines.append(
        f"| {c.tool} | {c.resolution} | {c.state} | {c.omega:.3f} | +- {100 * c.omega_bar / c.omega:.1g}% "
        f"(estimate) | +- {100 * c.radius_bar / c.radius:.1g}% (estimate) | - | {c.wall_s:.1f} ({c.cpu_s:.1f}) | "
        "(whole ladder) |"
    )
    reference = [r for r in sims if r.tool == "PyElastica" and r.resolution == "100 elements"]
    if reference:
        lines.append("")
        for r in res["chain"]:
            if "extrapolated" in r.tool:
                lines.append(
                    f"CPU against PyElastica at 100 elements ({reference[0].cpu_s:.1f} s): {r.tool}, {r.resolution}, "
                    f"{r.cpu_s:.2f} s, {reference[0].cpu_s / r.cpu_s:.0f}x less."
                )
    return "\n".join(lines) + "\n"


def write_elastica3d(out: Path, quick: bool) -> int:
    """Run section I, write its report atomically to out and print it."""
    text = elastica3d_report(bench_elastica3d(quick))
    out.parent.mkdir(parents=True, exist_ok=True)
    write_text(out, text)
    print(text)
    return 0

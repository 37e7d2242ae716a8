"""Section F of scripts/benchmark.py: the clamped filament, PyElastica beside the reduced engine and the ladder of
`elastoactive filament`, at equal accuracy against the extrapolated continuum (docs/filament.md)."""

from __future__ import annotations

import platform
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
from bench_common import CLI, CORES, load, log

# ------------------------------------------------------------------------------------------------
# F. the filament: PyElastica beside the reduced engine and the ladder, at equal accuracy
# ------------------------------------------------------------------------------------------------
FILAMENT_S = 100.0
"""The clamped filament's follower load f L^3 / B of section F (above the onset 76.10)."""
FILAMENT_PERIODS = (24, 16)
"""Beat periods run by the reduced engine's command line, and the transient among them (from the default 0.01 rad
kick the beat has grown and settled after ~12)."""
ELASTICA_PERIODS = (14, 4)
"""Beat periods run by PyElastica, and the last ones measured (it starts from a small bend: grown by ~8)."""
ELASTICA_ROD = dict(radius=0.02, mass_per_length=1e-4, cfl=0.7)
"""PyElastica's rod: bending stiffness B = E pi r^4 / 4 = 1 with r = 0.02 (axial stiffness 4B / r^2 = 1e4: strain
~1% under the load f L = 100), a small mass (inertial time 1e-4 against a beat period of 0.025) and PositionVerlet
at 0.7 of the axial wave's CFL limit (0.9 diverged)."""


def _filament_period(n: int) -> float:
    """The beat period of the chain of n at S = 100 in tau, close enough to size its run (omega ~ 249 / N^4)."""
    return 2 * np.pi * n**4 / 249.0


def bench_filament_ladder() -> dict:
    """`elastoactive filament --S 100 --json` as a whole process: the extrapolated continuum and its wall time."""
    import json

    t0 = time.perf_counter()
    out = subprocess.run(
        [CLI, "filament", "--S", str(FILAMENT_S), "--json", "--quiet"], capture_output=True, text=True, check=True
    ).stdout
    result = json.loads(out)
    result["process_s"] = time.perf_counter() - t0
    return result


def bench_filament_reduced(ns, continuum: dict, tmp: Path) -> list[dict]:
    """`elastoactive run one-pinned --engine reduced --n N --sigma S/N^3` (no numerics but the recording spacing),
    whole process, FILAMENT_PERIODS beats: omega N^4 and the amplitude from its summary against the continuum."""
    import json

    rows = []
    periods, transient = FILAMENT_PERIODS
    for n in ns:
        period = _filament_period(n)
        sample = 0.0025 * max(1, round(period / 200 / 0.0025))
        out = tmp / f"reduced-{n}"
        cmd = [
            CLI,
            "run",
            "one-pinned",
            "--engine",
            "reduced",
            "--n",
            str(n),
            "--sigma",
            repr(FILAMENT_S / n**3),
            "--duration",
            repr(periods * period),
            "--transient",
            repr(transient * period),
            "--sample-dt",
            repr(sample),
            "--quiet",
            "--out",
            str(out),
            "--force",
        ]
        t0 = time.perf_counter()
        subprocess.run(cmd, capture_output=True, text=True, check=True)
        wall = time.perf_counter() - t0
        s = json.loads((out / "summary.json").read_text())
        omega = 2 * np.pi * s["results"]["frequency"] * n**4
        rows.append(
            {
                "n": n,
                "omega": omega,
                "amplitude": s["results"]["amplitude"],
                "method": s["solver"]["method"],
                "per_period_s": wall / periods,
                "omega_err": omega / continuum["omega"] - 1,
                "amp_err": s["results"]["amplitude"] / continuum["amplitude"] - 1,
            }
        )
        log(f"reduced N = {n}: {rows[-1]['per_period_s']:.3f} s per period ({rows[-1]['method']})")
    return rows


def elastica_rod(ea, n_elem: int, radius: float | None = None, mass_per_length: float | None = None):
    """PyElastica's straight rod of length 1 along x, normal z, in `n_elem` elements, with bending stiffness E I = 1 and
    shear modulus E / 3, of ELASTICA_ROD's radius and mass per length unless given; and its axial wave speed
    sqrt(E A / (rho A)), which sets the explicit integrator's step. `ea` is the imported elastica module."""
    r = ELASTICA_ROD["radius"] if radius is None else radius
    m = ELASTICA_ROD["mass_per_length"] if mass_per_length is None else mass_per_length
    area, inertia = np.pi * r**2, np.pi * r**4 / 4
    young = 1.0 / inertia
    rod = ea.CosseratRod.straight_rod(
        n_elem,
        np.zeros(3),
        np.array([1.0, 0, 0]),
        np.array([0, 0, 1.0]),
        1.0,
        r,
        m / area,
        youngs_modulus=young,
        shear_modulus=young / 3.0,
    )
    return rod, float(np.sqrt(young * area / m))


def elastica_classes(ea):
    """PyElastica's simulator class for one clamped, forced, damped rod and the chain's follower force as its forcing
    (-load t_e on the node at the end of each element e, load = f dl); `ea` is the imported elastica module (an
    optional bench dependency, imported by the caller at its engine's boundary)."""

    class Filament(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping, ea.CallBacks):
        pass

    class Follower(ea.NoForces):
        """-load t_e on the node at the end of each element e (the chain's follower force)."""

        def __init__(self, load):
            super().__init__()
            self.load = load

        def apply_forces(self, system, time=0.0):
            system.external_forces[:, 1:] -= self.load * system.tangents

    return Filament, Follower


def _elastica_run(n_elem: int, periods: float) -> tuple[np.ndarray, np.ndarray, float]:
    """PyElastica's clamped rod (length 1, B = 1) under the distributed follower load S and drag zeta = 1 per
    length: (t, Theta = tip tangent angle - base tangent angle, wall s of the integration)."""
    import elastica as ea

    Filament, Follower = elastica_classes(ea)
    rod, wave_speed = elastica_rod(ea, n_elem)
    dl = 1.0 / n_elem
    sim = Filament()
    sim.append(rod)
    sim.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,), constrained_director_idx=(0,))
    sim.add_forcing_to(rod).using(Follower, load=FILAMENT_S * dl)
    dt = ELASTICA_ROD["cfl"] * dl / wave_speed
    sim.dampen(rod).using(
        ea.AnalyticalLinearDamper, translational_damping_constant=dl, rotational_damping_constant=dl**3, time_step=dt
    )
    period = 2 * np.pi / 249.0
    every = max(1, int(period / 400 / dt))
    record = ([], [])

    class Record(ea.CallBackBaseClass):
        def make_callback(self, system, time, current_step):
            if current_step % every == 0:
                tg = system.tangents
                record[0].append(time)
                record[1].append(np.arctan2(tg[1, -1], tg[0, -1]) - np.arctan2(tg[1, 0], tg[0, 0]))

    sim.collect_diagnostics(rod).using(Record)
    rod.position_collection[1] += 0.02 * np.linspace(0.0, 1.0, n_elem + 1) ** 2  # a small bend to start from
    sim.finalize()
    t0 = time.perf_counter()
    ea.integrate(ea.PositionVerlet(), sim, periods * period, int(periods * period / dt), progress_bar=False)
    return np.array(record[0]), np.array(record[1]), time.perf_counter() - t0


def bench_filament_elastica(elements, continuum: dict) -> list[dict] | str:
    """PyElastica at each element count: omega and amplitude of the last ELASTICA_PERIODS[1] beats against the
    continuum, warm wall time per beat period. A note instead when pyelastica is not installed."""
    try:
        import elastica  # noqa: F401
    except ImportError:
        return "pyelastica is not installed (`pip install -e .[bench]`): its rows are skipped"
    from elastoactive.analysis.filament import beat

    _elastica_run(elements[0], 0.05)  # its kernels compile on first use: not counted
    rows = []
    periods, measured = ELASTICA_PERIODS
    for n_elem in elements:
        t, theta, wall = _elastica_run(n_elem, periods)
        keep = t >= t[-1] - (measured + 0.5) * 2 * np.pi / 249.0
        b = beat(t[keep], theta[keep])
        omega = 2 * np.pi / b.period
        rows.append(
            {
                "elements": n_elem,
                "omega": omega,
                "amplitude": b.amplitude,
                "per_period_s": wall / periods,
                "omega_err": omega / continuum["omega"] - 1,
                "amp_err": b.amplitude / continuum["amplitude"] - 1,
            }
        )
        log(f"PyElastica {n_elem} elements: {rows[-1]['per_period_s']:.2f} s per period")
    return rows


def bench_filament(quick: bool) -> dict:
    log(f"filament (load {load()})")
    ladder = bench_filament_ladder()
    continuum = {"omega": ladder["omega"]["value"], "amplitude": ladder["amplitude"]["value"]}
    with tempfile.TemporaryDirectory() as tmp:
        reduced = bench_filament_reduced((40, 80) if quick else (40, 80, 160), continuum, Path(tmp))
    elastica = bench_filament_elastica((50,) if quick else (50, 100), continuum)
    return {"ladder": ladder, "continuum": continuum, "reduced": reduced, "elastica": elastica, "load": load()}


def filament_report(fil: dict) -> str:
    lad, c = fil["ladder"], fil["continuum"]
    periods = FILAMENT_PERIODS[0]
    lines = [
        "# Benchmark: the clamped filament, PyElastica beside the reduced engine",
        "",
        f"Generated by `scripts/benchmark.py --filament` on {time.strftime('%Y-%m-%d %H:%M')} "
        f"({platform.processor() or platform.machine()}, {CORES} cores shared with other work; load at the end "
        f"{fil['load']}). The clamped filament under a distributed follower force at S = f L^3 / B = "
        f"{FILAMENT_S:g} with drag zeta: omega in B / (zeta L^4), amplitude = half the peak-to-peak of Theta (tip "
        "angle minus base angle). The reference is the continuum extrapolated by `elastoactive filament` (Richardson "
        f"in 1/N over N = {', '.join(str(r['n']) for r in lad['rungs'])}): omega = {c['omega']:.3f} +- "
        f"{lad['omega']['error']:.2g}, amplitude {c['amplitude']:.5f} +- {lad['amplitude']['error']:.1g} rad; the "
        f"onset extrapolates to {lad['onset']['value']:.4f} (continuum eigenproblem "
        f"{lad['continuum_onset']['S_c']:.4f}).",
        "",
        "| tool and path | resolution | omega error | amplitude error | wall time per beat period |",
        "|---|---|---|---|---|",
    ]
    if isinstance(fil["elastica"], str):
        lines.append(f"| PyElastica | - | - | - | skipped: {fil['elastica']} |")
    else:
        for r in fil["elastica"]:
            lines.append(
                f"| PyElastica (follower force and drag as forcing and an analytical damper, small mass, "
                f"PositionVerlet at {ELASTICA_ROD['cfl']} of its CFL limit) | {r['elements']} elements | "
                f"{100 * r['omega_err']:+.2f}% | {100 * r['amp_err']:+.2f}% | {r['per_period_s']:.2f} s |"
            )
    for r in fil["reduced"]:
        lines.append(
            f"| `elastoactive run one-pinned --engine reduced` (its automatic method: {r['method']}; whole "
            f"process over {periods} periods) | N = {r['n']} | {100 * r['omega_err']:+.2f}% | "
            f"{100 * r['amp_err']:+.2f}% | {r['per_period_s']:.3f} s |"
        )
    ladder_rungs = ", ".join(str(r["n"]) for r in lad["rungs"])
    lines.append(
        f"| `elastoactive filament --S {FILAMENT_S:g}` (ladder N = {ladder_rungs}, extrapolated; whole "
        f"process) | continuum | +- {100 * lad['omega']['error'] / c['omega']:.1g}% (estimate) | +- "
        f"{100 * lad['amplitude']['error'] / c['amplitude']:.1g}% (estimate) | {lad['process_s']:.1f} s "
        "for the whole ladder |"
    )
    n80 = [r for r in fil["reduced"] if r["n"] == 80]
    lines += [
        "",
        "Targets (issue: long chains as filaments):",
        "- `run one-pinned --engine reduced --n 80 --sigma 100/80^3` with no numerics given: "
        + (
            f"{n80[0]['per_period_s']:.3f} s per beat period (target < 0.5 s; was ~75 s with the explicit method)."
            if n80
            else "not run."
        ),
        f"- the filament limit at S = 100 within 0.1% in under 60 s: `elastoactive filament` took "
        f"{lad['process_s']:.1f} s, estimated error {100 * lad['omega']['error'] / c['omega']:.1g}% (omega) "
        f"and {100 * lad['amplitude']['error'] / c['amplitude']:.1g}% (amplitude).",
        "",
        "MuJoCo rows are not rerun here (section D of the main benchmark measures its long-chain cost).",
    ]
    return "\n".join(lines) + "\n"

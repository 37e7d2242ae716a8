"""Cross-validation: the same case in MuJoCo and in the reduced model, error against run time."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .analysis.reduced import simulate_reduced
from .analysis import observables as obs
from .params import Numerics, Physics
from .results import default_transient, measure
from .simulate import simulate_mujoco

# The paper's cases (issue 2): scene, parameters, duration in tau.
PAPER_CASES: tuple[tuple[Physics, float], ...] = (
    (Physics(scene="one-pinned", n=7, sigma=0.8), 300.0),
    (Physics(scene="two-pinned", n=7, sigma=0.8, delta=0.1), 300.0),
    (Physics(scene="rotating-pin", n=7, sigma=0.8), 300.0),
    (Physics(scene="coupled-pair", n=7, sigma=0.8, rho=4 / 3, kappa=0.5), 600.0),
    (Physics(scene="coupled-pair", n=7, sigma=0.8, rho=4 / 3, kappa=2.0), 600.0),
)

REFERENCE_TOLERANCE = dict(rtol=1e-10, atol=1e-12)
MIN_WINDOW = 20.0  # tau: the pointwise comparison covers at least this much of the start


def comparison_window(reference, physics: Physics) -> float:
    """End of the transient for the pointwise angle comparison: the time the reference's
    Theta takes to reach 90% of its steady excursion (growth of the beat, forming of the bend),
    and at least MIN_WINDOW. Later, trajectories part by slow phase drift, which the frequency
    error measures; comparing them pointwise there would count the same error again, growing
    with the length of the run."""
    theta = reference.chain(0)
    return max(MIN_WINDOW, obs.settling_time(reference.t, obs.curvature(theta)))


def _error(value, reference, floor: float) -> float:
    """Relative error, or absolute error where the reference is below `floor`."""
    value, reference = np.atleast_1d(np.asarray(value, float)), np.atleast_1d(np.asarray(reference, float))
    scale = np.where(np.abs(reference) > floor, np.abs(reference), 1.0)
    return float(np.max(np.abs(value - reference) / scale))


@dataclass
class Comparison:
    physics: Physics
    numerics: Numerics
    duration: float
    mujoco: dict
    reduced: dict
    mujoco_wall_s: float
    reduced_wall_s: float
    errors: dict
    constraint_violation: float | None

    def worst(self) -> float:
        """Largest of the relative errors checked against the 1% target."""
        return max(self.errors[k] for k in ("amplitude", "frequency", "rotation_rate", "angle") if k in self.errors)


def compare(physics: Physics, numerics: Numerics = Numerics(), duration: float = 300.0,
            transient: float | None = None, reference=None) -> Comparison:
    """Run both engines from the same initial state and measure MuJoCo's error."""
    transient = default_transient(duration) if transient is None else transient
    mj = simulate_mujoco(physics, numerics, duration)
    red = reference if reference is not None else simulate_reduced(physics, numerics, duration, **REFERENCE_TOLERANCE)
    a, b = measure(mj, transient), measure(red, transient)
    errors = {}
    if physics.scene == "rotating-pin":
        errors["rotation_rate"] = _error(a["rotation_rate"], b["rotation_rate"], 1e-6)
    else:
        errors["amplitude"] = _error(a["amplitude"], b["amplitude"], 1e-3)
        errors["frequency"] = _error(a["frequency"], b["frequency"], 1e-3)
    if "snap_amplitude" in a:
        errors["snap_amplitude"] = _error(a["snap_amplitude"], b["snap_amplitude"], 1e-3)
    if "frequency_mismatch" in a:
        errors["frequency_mismatch_abs"] = abs(np.nan_to_num(a["frequency_mismatch"]) - np.nan_to_num(b["frequency_mismatch"]))
    n = min(mj.t.size, red.t.size)
    window = comparison_window(red, physics)
    early = mj.t[:n] <= window
    diff = np.abs(mj.theta[:n][early] - red.theta[:n][early]).max()
    errors["angle_rad"] = float(diff)
    errors["angle"] = float(diff / max(np.abs(red.theta[:n][early]).max(), 1e-12))
    errors["window"] = window
    return Comparison(physics, numerics, duration, a, b, mj.wall_time_s, red.wall_time_s, errors,
                      mj.info.get("constraint_violation"))


def format_table(rows: list[Comparison]) -> str:
    """Markdown table, one line per case."""
    head = ("| case | MuJoCo wall s | reduced wall s | amplitude err | frequency err | rotation-rate err "
            "| max angle diff over transient [0, T] | pin violation |")
    lines = [head, "|" + "---|" * 8]
    for c in rows:
        p = c.physics
        case = f"{p.scene} N={p.n} sigma={p.sigma:g}"
        if p.scene == "two-pinned":
            case += f" delta={p.delta:g}"
        if p.scene == "coupled-pair":
            case += f" rho={p.rho:.4g} kappa={p.kappa:g}"
        e = c.errors
        pct = lambda k: f"{100 * e[k]:.3f}%" if k in e else "-"
        viol = f"{c.constraint_violation:.1e}" if c.constraint_violation is not None else "-"
        lines.append(
            f"| {case} | {c.mujoco_wall_s:.2f} | {c.reduced_wall_s:.2f} | {pct('amplitude')} | {pct('frequency')} "
            f"| {pct('rotation_rate')} | {e['angle_rad']:.2e} rad = {pct('angle')} of max angle, T = {e['window']:.0f} | {viol} |"
        )
    return "\n".join(lines)


CONVERGENCE_DT = (0.02, 0.01, 0.005, 0.0025, 0.00125)
CONVERGENCE_MASS = (1e-2, 1e-3, 1e-4, 1e-5)


def convergence(physics: Physics, duration: float, *, dts=CONVERGENCE_DT, masses=CONVERGENCE_MASS,
                fixed_dt: float = 0.00125, fixed_mass: float = 1e-5) -> list[Comparison]:
    """Errors as dt shrinks (mass fixed small) and as the mass ratio shrinks (dt fixed small)."""
    sample_dt = 0.04  # a whole number of steps for every dt in the study
    reference = simulate_reduced(physics, Numerics(sample_dt=sample_dt), duration, **REFERENCE_TOLERANCE)
    rows = [compare(physics, Numerics(dt=dt, mass_ratio=fixed_mass, sample_dt=sample_dt), duration, reference=reference)
            for dt in dts]
    rows += [compare(physics, Numerics(dt=fixed_dt, mass_ratio=m, sample_dt=sample_dt), duration, reference=reference)
             for m in masses]
    return rows


def format_convergence(rows: list[Comparison]) -> str:
    lines = ["| dt | mass ratio | amplitude err | frequency err | rotation-rate err | angle diff (transient) | pin violation | MuJoCo wall s |",
             "|" + "---|" * 8]
    for c in rows:
        e = c.errors
        pct = lambda k: f"{100 * e[k]:.4f}%" if k in e else "-"
        viol = f"{c.constraint_violation:.1e}" if c.constraint_violation is not None else "-"
        lines.append(f"| {c.numerics.dt:g} | {c.numerics.mass_ratio:g} | {pct('amplitude')} | {pct('frequency')} "
                     f"| {pct('rotation_rate')} | {pct('angle')} | {viol} | {c.mujoco_wall_s:.2f} |")
    return "\n".join(lines)

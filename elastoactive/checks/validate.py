"""Cross-validation: the same case in MuJoCo and in the reduced model, error against run time.

At the default mass ratio (1e-4, inside the overdamped limit) MuJoCo is checked against the paper's
overdamped model. At a finite mass (`inertial_cases`, `validate --mass-ratio M`) it is checked against the
reduced model's inertial counterpart at the same mass (elastoactive/reduced/equations.py): the paper's cases
with longer runs for heavy chains, whose beats are slower (f tau = 0.0178 at m = 10 for N = 7, sigma = 0.8).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import terms
from ..analysis import observables as obs
from ..core import observables, registry
from ..core.errors import SimulationDiverged
from ..core.params import Numerics, Physics
from ..engines.mujoco import simulate_mujoco
from ..engines.reduced import simulate_reduced
from ..engines.timestep import PIN_DT3_PER_MASS
from ..gate import preflight
from ..results import Results, default_transient, measure
from ..scenes.base import ValidationCase


def validation_cases(scene: str | None = None) -> list[ValidationCase]:
    """The registered scenes' validation cases (the paper's cases) and the registered terms' (elastoactive.terms), or
    one scene's."""
    chosen = registry.scenes() if scene is None else (registry.get(scene),)
    cases = [case for s in chosen for case in s.validation_cases()]
    return cases + [
        case
        for t in terms.terms()
        for case in t.validation_cases(Physics)
        if scene is None or case.physics.scene == scene
    ]


def inertial_duration(duration: float, mass_ratio: float) -> float:
    """Run length at a finite mass: the case's own duration, times sqrt(mass_ratio) above 1, rounded up to 10 tau
    (the heavy chains settle later, over ~50-80 tau at m = 10, and beat slower, so the measured half needs
    more time: 950 and 1900 tau at m = 10)."""
    if mass_ratio <= 1.0:
        return float(duration)
    return 10.0 * math.ceil(float(duration) * math.sqrt(mass_ratio) / 10.0 - 1e-9)


def inertial_gap(physics: Physics) -> str:
    """Why the reduced engine's inertial model does not cover `physics` (Scene.inertial_model, Term.inertial_model:
    a network, the free ring, a plug-in term's node forces, a moving clamp, self-aligning units), '' where it does."""
    if not physics.scene_def.inertial_model(physics):
        return f"the reduced model of {physics.scene} with these parameters is overdamped only"
    missing = [t.name for t in physics.active_terms() if not t.inertial_model(physics)]
    if missing:
        return f"the inertial reduced model leaves out the {', '.join(missing)} term{'s' * (len(missing) > 1)}"
    return ""


def inertial_plan(mass_ratio: float, scene: str | None = None) -> list[tuple[ValidationCase, str]]:
    """Every validation case (validation_cases) at a finite mass, its duration lengthened for heavy chains
    (inertial_duration), with the reason it cannot run there (inertial_gap; '' for a case that runs). A case that
    cannot run is reported as not run, never left out."""
    return [
        (ValidationCase(c.physics, inertial_duration(c.duration, mass_ratio), c.convergence), inertial_gap(c.physics))
        for c in validation_cases(scene)
    ]


def inertial_cases(mass_ratio: float, scene: str | None = None) -> list[ValidationCase]:
    """The validation cases that run at a finite mass (inertial_plan, those with no gap). Run them with
    compare(..., numerics at that mass, inertial=True)."""
    return [case for case, gap in inertial_plan(mass_ratio, scene) if not gap]


REFERENCE_TOLERANCE = dict(rtol=1e-10, atol=1e-12)
MIN_WINDOW = 20.0  # tau: the pointwise comparison covers at least this much of the start


def comparison_window(reference, physics: Physics) -> float:
    """End of the transient for the pointwise angle comparison: the time the reference's
    Theta takes to reach 90% of its steady excursion (growth of the beat, forming of the bend),
    and at least MIN_WINDOW. Later, trajectories part by slow phase drift, which the frequency
    error measures; comparing them pointwise there would count the same error again, growing
    with the length of the run."""
    signal = physics.scene_def.beat_signals(reference)[0]  # the first chain's Theta, or a network's signal
    return max(MIN_WINDOW, obs.settling_time(reference.t, signal))


def _error(value, reference, floor: float) -> float:
    """Relative error, or absolute error where the reference is below `floor`."""
    value, reference = np.atleast_1d(np.asarray(value, float)), np.atleast_1d(np.asarray(reference, float))
    both = ~(np.isnan(value) | np.isnan(reference))  # chains measured by both engines
    value, reference = value[both], reference[both]
    scale = np.where(np.abs(reference) > floor, np.abs(reference), 1.0)
    return float(np.max(np.abs(value - reference) / scale)) if both.any() else math.nan


def observable_errors(physics: Physics, value: Results, reference: Results) -> dict[str, float]:
    """Errors of the scene's observables against a reference: relative for those validate holds to its
    tolerance (Scene.compared) and the scene's other relative ones, absolute where their spec says so
    (elastoactive.core.observables: Observable.error)
    (stored as NAME_abs)."""
    scene = physics.scene_def
    errors: dict[str, float] = {}
    for name in dict.fromkeys((*scene.compared, *scene.observable_names())):
        kind = observables.spec_or_default(name)
        if kind.error == "none":
            continue
        a, b = _values(value.value(name)), _values(reference.value(name))
        if np.all(np.isnan(a)) and np.all(np.isnan(b)):
            continue  # measured by neither engine (e.g. a frequency over too short a window)
        if np.any(np.isnan(a) != np.isnan(b)):  # measured by one engine only: no agreement to claim
            errors[name] = math.inf
        elif kind.error == "absolute":
            errors[f"{name}_abs"] = float(np.max(np.abs(np.nan_to_num(a) - np.nan_to_num(b))))
        else:
            errors[name] = _error(a, b, kind.floor)
    return errors


def _values(value) -> np.ndarray:
    """An observable (number, None, or one per chain) as a float array, None as NaN."""
    items = value if isinstance(value, (tuple, list)) else (value,)
    return np.array([np.nan if v is None else v for v in items], dtype=float)


def angle_errors(traj, reference) -> dict[str, float]:
    """Largest angle difference over the reference's transient window (absolute, and relative to the
    largest angle there; the scene's kind says what it compares: Scene.state_difference, a network's node positions
    relative to the largest displacement from rest); the trajectories must share their sample times."""
    n = min(traj.t.size, reference.t.size)
    if not np.allclose(traj.t[:n], reference.t[:n], rtol=0, atol=1e-9):
        raise ValueError("the trajectory and the reference are not sampled at the same times")
    window = comparison_window(reference, reference.physics)
    early = reference.t[:n] <= window
    diff, scale = reference.physics.scene_def.state_difference(traj, reference, early)  # angles, or node positions
    return {"angle_rad": diff, "angle": diff / max(scale, 1e-12), "window": float(window)}


@dataclass
class Comparison:
    physics: Physics
    numerics: Numerics
    duration: float
    mujoco: Results | None
    reduced: Results | None
    mujoco_wall_s: float
    reduced_wall_s: float
    errors: dict
    constraint_violation: float | None
    note: str = ""  # why a setting has no errors (a run that stopped)
    statistics: dict | None = None  # irregular beats: cycle statistics of both engines (cycle_statistics)

    @property
    def ran(self) -> bool:
        """Whether both engines ran the case (a row with a note says why they did not)."""
        return not self.note

    def worst(self) -> float:
        """Largest of the relative errors checked against the 1% target (NaN for a case that did not run). For an
        irregular beat single numbers
        mean little: the steady observables count only through their statistical agreement (z <= Z_AGREE
        counts as 0, anything else as inf), the transient angles as usual."""
        if not self.ran:
            return math.nan
        if self.statistics is not None:
            agree = self.statistics["z"] <= Z_AGREE
            return max(self.errors.get("angle", 0.0), 0.0 if agree else math.inf)
        return max(self.errors[k] for k in (*self.physics.scene_def.compared, "angle") if k in self.errors)


Z_AGREE = 3.0
"""Irregular beats agree when their mean cycle frequencies and amplitudes differ by at most this many
standard errors (combined over both engines)."""


def cycle_statistics(traj_a, traj_b, transient: float) -> dict:
    """Mean cycle frequency and amplitude of Theta in each engine with their standard errors (from the
    cycle-to-cycle spread), per chain, and the largest z-score of their differences."""
    rows, z = [], 0.0
    for k in range(traj_a.physics.n_chains):
        stats = []
        for traj in (traj_a, traj_b):
            x = obs.curvature(traj.chain(k))
            c = obs.cycles(traj.t, x, transient)
            f = obs.frequency(traj.t, x, transient)
            amp = obs.amplitude(traj.t, x, transient)
            n = max(c.count, 1)
            stats.append(
                (
                    f,
                    f * np.nan_to_num(c.period_spread) / math.sqrt(n),
                    amp,
                    amp * np.nan_to_num(c.amplitude_spread) / math.sqrt(n),
                    c.count,
                )
            )
        (fa, sfa, aa, saa, na), (fb, sfb, ab, sab, nb) = stats
        zf = abs(fa - fb) / max(math.hypot(sfa, sfb), 1e-12)
        za = abs(aa - ab) / max(math.hypot(saa, sab), 1e-12)
        z = max(z, zf, za)
        rows.append({"frequency": (fa, sfa, fb, sfb), "amplitude": (aa, saa, ab, sab), "cycles": (na, nb)})
    return {"chains": rows, "z": z}


def compare(
    physics: Physics,
    numerics: Numerics = Numerics(),
    duration: float = 300.0,
    transient: float | None = None,
    reference=None,
    inertial: bool | None = None,
    timestep: bool = True,
) -> Comparison:
    """Run both engines from the same initial state and measure MuJoCo's error. The reduced model is the
    overdamped or the inertial one at numerics.mass_ratio as engines.reduced.regime decides (inertial: the
    override of simulate_reduced). The MuJoCo run passes the gate first (timestep=False: all of it but the
    timestep check, for a study of how the error grows with dt)."""
    transient = default_transient(duration) if transient is None else transient
    run = preflight(physics, numerics, duration, "mujoco", timestep=timestep, given=False)
    physics, numerics, duration = run.physics, run.numerics, run.duration
    mj = simulate_mujoco(physics, numerics, duration)
    red = (
        reference
        if reference is not None
        else simulate_reduced(physics, numerics, duration, inertial=inertial, **REFERENCE_TOLERANCE)
    )
    a, b = measure(mj, transient), measure(red, transient)
    errors = observable_errors(physics, a, b)
    errors.update(angle_errors(mj, red))
    irregular = a.periodic is False or b.periodic is False
    return Comparison(
        physics,
        numerics,
        duration,
        a,
        b,
        mj.wall_time_s,
        red.wall_time_s,
        errors,
        mj.info.get("constraint_violation"),
        statistics=cycle_statistics(mj, red, transient) if irregular else None,
    )


_SHOWN = ("amplitude", "frequency", "rotation_rate")
"""Observables with a column of their own in format_table (the others a scene compares share one)."""


def format_table(rows: list[Comparison]) -> str:
    """Markdown table, one line per case."""
    head = (
        "| case | MuJoCo wall s | reduced wall s | amplitude err | frequency err | rotation-rate err | other err "
        "| max angle diff over transient [0, T] | pin violation |"
    )
    lines = [head, "|" + "---|" * 9]
    for c in rows:
        case = c.physics.scene_def.label(c.physics)
        if not c.ran:
            lines.append(f"| {case} | {c.note} ||||||||")
            continue
        if c.statistics is not None:
            case += f" (irregular beat: compared as cycle statistics, z = {c.statistics['z']:.2g})"
        e = c.errors
        pct = lambda k: f"{100 * e[k]:.3f}%" if k in e else "-"
        viol = f"{c.constraint_violation:.1e}" if c.constraint_violation is not None else "-"
        other = ", ".join(f"{k} {pct(k)}" for k in c.physics.scene_def.compared if k in e and k not in _SHOWN) or "-"
        unit, what = c.physics.scene_def.state_units, c.physics.scene_def.state_name  # rad and angle on a chain
        lines.append(
            f"| {case} | {c.mujoco_wall_s:.2f} | {c.reduced_wall_s:.2f} | {pct('amplitude')} | {pct('frequency')} "
            f"| {pct('rotation_rate')} | {other} | {e['angle_rad']:.2e} {unit} = {pct('angle')} of max {what}, "
            f"T = {e['window']:.0f} | {viol} |"
        )
    return "\n".join(lines)


def not_run(case: ValidationCase, numerics: Numerics, reason: str) -> Comparison:
    """A table row for a case the engines could not run at this setting, saying why."""
    return Comparison(
        case.physics, numerics, case.duration, None, None, math.nan, math.nan, {}, None, note=f"not run: {reason}"
    )


def verdict(rows: list[Comparison], tolerance: float) -> tuple[str, bool]:
    """The closing line of a validation and whether it passed: the largest relative error of the cases that ran
    against `tolerance`, and how many cases did not run (a validation with a case not run says so; one with no
    case run does not pass)."""
    ran = [r for r in rows if r.ran]
    skipped = len(rows) - len(ran)
    if not ran:
        return f"no case ran ({skipped} not run: see the table): nothing validated", False
    worst = max(r.worst() for r in ran)
    passed = worst <= tolerance
    line = f"largest relative error {100 * worst:.3f}% (tolerance {100 * tolerance:g}%): {'PASS' if passed else 'FAIL'}"
    if skipped:
        line += f" on the {len(ran)} of {len(rows)} cases that ran; {skipped} NOT RUN at this setting (see the table)"
    return line, passed


CONVERGENCE_DT = (0.02, 0.01, 0.005, 0.0025, 0.00125)
CONVERGENCE_MASS = (1e-2, 1e-3, 1e-4, 1e-5)


def convergence(
    physics: Physics,
    duration: float,
    *,
    dts=CONVERGENCE_DT,
    masses=CONVERGENCE_MASS,
    fixed_dt: float = 0.00125,
    fixed_mass: float = 1e-5,
) -> list[Comparison]:
    """Errors as dt shrinks (mass fixed small) and as the mass ratio shrinks (dt fixed small).

    A pinned scene's dt series runs at the smallest mass ratio whose soft pin holds at the largest dt
    (diagnose.PIN_DT3_PER_MASS); a setting that stops anyway is a row saying why, not an abort."""
    if physics.scene_def.pinned:
        fixed_mass = max(fixed_mass, float(f"{1.01 * max(dts) ** 3 / PIN_DT3_PER_MASS:.1g}"))
    sample_dt = 0.04  # a whole number of steps for every dt in the study
    # the overdamped model: this study measures how MuJoCo approaches it as dt and the mass ratio shrink
    reference = simulate_reduced(
        physics, Numerics(sample_dt=sample_dt), duration, inertial=False, **REFERENCE_TOLERANCE
    )
    settings = [Numerics(dt=dt, mass_ratio=fixed_mass, sample_dt=sample_dt) for dt in dts]
    settings += [Numerics(dt=fixed_dt, mass_ratio=m, sample_dt=sample_dt) for m in masses]
    rows = []
    for numerics in settings:
        try:
            rows.append(compare(physics, numerics, duration, reference=reference, timestep=False))
        except SimulationDiverged as err:  # e.g. a pin that cannot hold at the coarsest dt: a row, not an abort
            rows.append(
                Comparison(
                    physics,
                    numerics,
                    duration,
                    None,
                    None,
                    math.nan,
                    math.nan,
                    {},
                    None,
                    note=f"stopped: {_first_clause(str(err))}",
                )
            )
    return rows


def _first_clause(message: str) -> str:
    return message.split(":")[0] if len(message) > 120 else message


def format_convergence(rows: list[Comparison]) -> str:
    lines = [
        "| dt | mass ratio | amplitude err | frequency err | rotation-rate err | angle diff (transient) "
        "| pin violation | MuJoCo wall s |",
        "|" + "---|" * 8,
    ]
    for c in rows:
        e = c.errors
        if c.note:
            lines.append(f"| {c.numerics.dt:g} | {c.numerics.mass_ratio:g} | {c.note} ||||||")
            continue
        pct = lambda k: f"{100 * e[k]:.4f}%" if k in e else "-"
        viol = f"{c.constraint_violation:.1e}" if c.constraint_violation is not None else "-"
        lines.append(
            f"| {c.numerics.dt:g} | {c.numerics.mass_ratio:g} | {pct('amplitude')} | {pct('frequency')} "
            f"| {pct('rotation_rate')} | {pct('angle')} | {viol} | {c.mujoco_wall_s:.2f} |"
        )
    return "\n".join(lines)

"""Stiff and extreme cases: does every setting either agree with the reduced model or stop loudly?

A cell is (physics, numerics, integrator). It is run the way `elastoactive run` runs it:
diagnose.check_timestep first (pre-flight), then simulate_mujoco, then a comparison with the reduced
model from the same initial state. The outcome is one of

  agrees    the run matches the reduced model within TOLERANCE (below)
  refused   check_timestep raised ParameterError (a clear, named error before running)
  diverged  simulate_mujoco raised SimulationDiverged (a clear, named error while running)
  WRONG     the run finished but does not match: a silent wrong answer (a finding)
  NaN       the run returned non-finite angles without raising (must never happen)

Agreement (TOLERANCE):
  * amplitude and frequency of Theta, or the rotation rate (rotating pin): relative error <= 5%;
    judged only where they are reproducible: changing sigma by SIGMA_KICK = 0.1% moves them by less
    than STAT_SENSITIVITY = 1% in the reduced model. Where it moves them more (sensitive,
    chaotic-looking dynamics at high sigma and N), the cell is marked "sensitive";
  * the angles pointwise: max |theta - theta_ref| <= 10% of max |theta_ref| over the transient window
    (validate.comparison_window), cut at the predictability horizon in a chaotic cell (the time the
    sigma-kicked reduced trajectory has moved HORIZON_FRACTION of max |theta_ref| away) and at one period of
    the reference's oscillation (beyond it the pointwise error counts the phase drift again, which
    the frequency error already measures);
  * the pin of the two-pinned chain held to <= 0.02 l (largest distance over the run).

MuJoCo solver warnings that simulate_mujoco does not check (mjWARN_INERTIA: "the effective-metric
solve failed to converge", raised by the discrete integrator on long chains) are recorded per cell.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import mujoco
import numpy as np

from ..core import registry
from ..core.errors import ParameterError, SimulationDiverged
from ..core.params import Numerics, Physics, replace
from ..core.trajectory import Trajectory
from ..engines.mujoco import simulate_mujoco
from ..engines.reduced import simulate_reduced
from ..engines.timestep import INERTIA_RESOLUTION, PIN_DT3_PER_MASS, check_timestep, stability_limits
from ..results import measure
from .accuracy import errors_against
from .validate import comparison_window

TOLERANCE = {"statistics": 0.05, "angle": 0.10, "pin": 0.02}
SIGMA_KICK = 1e-3  # relative change of sigma that defines the predictability horizon
HORIZON_FRACTION = 0.05  # the kicked trajectory has left the reference by this fraction of max |theta_ref|
STAT_SENSITIVITY = 0.01  # statistics that move by more than this under the kick are not judged

REFERENCE = dict(method="numba-DOP853", rtol=1e-10, atol=1e-12)
"""The reduced model's reference. numba-DOP853 explicitly: at sigma >= 10 and N >= 30 the default
method=None picks Radau (spectral radius above STIFF_RADIUS) although the fast modes are growing,
not stiff, and Radau then takes minutes (see docs/performance.md)."""

# The numerics columns of the grid: the project defaults and the extremes Numerics allows.
NUMERICS = {
    "default": dict(dt=0.0025, mass_ratio=1e-4),
    "dt=0.1": dict(dt=0.1, mass_ratio=1e-4),
    "m=1e-7": dict(dt=0.0025, mass_ratio=1e-7),
    "dt=0.1 m=1e-7": dict(dt=0.1, mass_ratio=1e-7),
    "m=1e-2": dict(dt=0.0025, mass_ratio=1e-2),  # where Euler and RK4 can run at all (dt < 2 m)
}
INTEGRATORS = ("implicitfast", "implicit", "discrete", "Euler", "RK4")

WARNINGS = {
    mujoco.mjtWarning.mjWARN_INERTIA: "inertia/effective-metric solve",
    mujoco.mjtWarning.mjWARN_BADQACC: "bad qacc",
}


def cell_duration(physics: Physics) -> float:
    """Run length (tau) of a cell: long enough for the steady state at the paper's parameters, shorter
    where the dynamics are fast (high sigma) or slow to compute (large N)."""
    if physics.sigma >= 50:
        return 2.0 if physics.n <= 10 else 1.0
    if physics.sigma >= 5:
        return 20.0 if physics.n <= 10 else (4.0 if physics.n <= 30 else 1.0)
    if physics.n <= 10:
        return 100.0 * physics.n_chains  # a pair needs longer to lock or slip
    return 20.0 if physics.n <= 30 else 4.0


def physics_grid(quick: bool = False) -> list[Physics]:
    """Every registered scene's extreme cases (Scene.extreme_cases)."""
    return [p for scene in registry.scenes() for p in scene.extreme_cases(quick)]


def describe(physics: Physics) -> str:
    return physics.scene_def.label(physics)


def sample_dt_for(dt: float, duration: float) -> float:
    """A sample spacing that is a whole number of steps: about 0.05 tau (finer for short runs)."""
    target = min(0.05, duration / 40.0)
    return dt * max(1, round(target / dt))


# ------------------------------------------------------------------------------------------------
# reference
# ------------------------------------------------------------------------------------------------
@dataclass
class Reference:
    physics: Physics
    duration: float
    sample_dt: float
    trajectory: object
    horizon: float  # tau; inf when the kicked trajectory never left the reference
    wall_s: float
    kicked_wall_s: float
    stat_change: float = 0.0  # largest relative change of amplitude/frequency/rotation rate under the kick

    @property
    def period(self) -> float:
        """Longest oscillation period of the reference (inf when it does not oscillate)."""

        try:
            f = np.atleast_1d(measure(self.trajectory).frequency).astype(float)
        except (ValueError, KeyError):
            return math.inf
        f = f[f > 0]
        return float(1.0 / f.min()) if f.size else math.inf

    @property
    def regular(self) -> bool:
        """Statistics reproducible: a 0.1% change of sigma changes them by less than STAT_SENSITIVITY."""
        return self.stat_change <= STAT_SENSITIVITY

    def at(self, sample_dt: float):
        """The reference sampled every sample_dt (a whole multiple of self.sample_dt)."""

        k = int(round(sample_dt / self.sample_dt))
        if abs(k * self.sample_dt - sample_dt) > 1e-9 * sample_dt:
            raise ValueError(f"sample_dt {sample_dt} is not a multiple of the reference's {self.sample_dt}")
        tr = self.trajectory
        return Trajectory(t=tr.t[::k], theta=tr.theta[::k], physics=tr.physics, engine=tr.engine, info=tr.info)


def reference(physics: Physics, duration: float, sample_dt: float, seed: int = 0) -> Reference:
    """Tight reduced-model solution and its predictability horizon (sigma changed by SIGMA_KICK)."""

    numerics = Numerics(sample_dt=sample_dt, seed=seed)
    ref = simulate_reduced(physics, numerics, duration, **REFERENCE)
    kicked_physics = replace(physics, sigma=physics.sigma * (1.0 + SIGMA_KICK))
    kicked = simulate_reduced(kicked_physics, numerics, duration, theta0=ref.theta[0], **REFERENCE)
    gap = np.abs(kicked.theta - ref.theta).max(axis=1)
    scale = np.maximum.accumulate(np.abs(ref.theta).max(axis=1))
    left = gap > HORIZON_FRACTION * scale
    horizon = float(ref.t[np.argmax(left)]) if np.any(left) else math.inf
    try:
        e = errors_against(kicked, ref)
        stat_change = max(e.get(k, 0.0) for k in ("amplitude", "frequency", "rotation_rate"))
    except ValueError:
        stat_change = math.inf
    return Reference(physics, duration, sample_dt, ref, horizon, ref.wall_time_s, kicked.wall_time_s, stat_change)


# ------------------------------------------------------------------------------------------------
# one cell
# ------------------------------------------------------------------------------------------------
@dataclass
class CellResult:
    physics: Physics
    numerics: Numerics
    column: str
    duration: float
    outcome: str
    message: str = ""
    errors: dict = field(default_factory=dict)
    wall_s: float = math.nan
    warnings: dict = field(default_factory=dict)
    failed: tuple = ()  # which agreement criteria failed (for WRONG)

    @property
    def ok(self) -> bool:
        """A cell is fine when it agrees or stops with a clear error."""
        return self.outcome in ("agrees", "refused", "diverged")


def judge(errors: dict, ref: Reference) -> tuple[str, ...]:
    """Names of the agreement criteria a run fails (empty: it agrees)."""
    failed = []
    if ref.regular:
        for key in ("amplitude", "frequency", "rotation_rate"):
            if key in errors and not errors[key] <= TOLERANCE["statistics"]:
                failed.append(key)
    if not errors["angle"] <= TOLERANCE["angle"]:
        failed.append("angle")
    if "pin_violation" in errors and not errors["pin_violation"] <= TOLERANCE["pin"]:
        failed.append("pin")
    return tuple(failed)


def compare_to_reference(traj, ref: Reference) -> dict:
    """Errors of a MuJoCo trajectory against the reference (validate.compare's definitions, with the
    pointwise window cut at the predictability horizon)."""

    r = ref.at(traj.t[1] - traj.t[0])
    errors = {}
    try:
        errors = errors_against(traj, r)
    except ValueError as err:  # too short a record for a frequency etc.: pointwise only
        errors["measure_error"] = str(err)
    n = min(traj.t.size, r.t.size)
    window = min(comparison_window(r, ref.physics), ref.horizon, ref.period, traj.t[n - 1])
    early = r.t[:n] <= max(window, r.t[min(1, n - 1)])
    diff = np.abs(traj.theta[:n][early] - r.theta[:n][early]).max()
    errors["angle_rad"] = float(diff)
    errors["angle"] = float(diff / max(np.abs(r.theta[:n][early]).max(), 1e-12))
    errors["window"] = float(window)
    if "constraint_violation" in traj.info:
        errors["pin_violation"] = float(traj.info["constraint_violation"])
    return errors


def run_cell(
    physics: Physics,
    numerics: Numerics,
    ref: Reference,
    column: str = "",
    duration: float | None = None,
    preflight: bool = True,
    accuracy_guard: bool = True,
) -> CellResult:
    """Pre-flight check, MuJoCo run and comparison; never raises for an unstable or refused setting.
    accuracy_guard=False: the pre-flight check without diagnose.check_accuracy (stability only)."""

    duration = ref.duration if duration is None else duration
    res = CellResult(physics, numerics, column, duration, "agrees")
    counts = {w: 0 for w in WARNINGS}

    def on_sample(model, data):
        for w in WARNINGS:
            counts[w] = max(counts[w], data.warning[w].number)

    try:
        if preflight:
            check_timestep(physics, numerics, accuracy=accuracy_guard)
        t0 = time.perf_counter()
        traj = simulate_mujoco(physics, numerics, duration, on_sample=on_sample)
        res.wall_s = time.perf_counter() - t0
    except ParameterError as err:
        res.outcome, res.message = "refused", str(err)
        return res
    except SimulationDiverged as err:
        res.outcome, res.message = "diverged", str(err)
        res.warnings = {WARNINGS[w]: n for w, n in counts.items() if n}
        return res
    res.warnings = {WARNINGS[w]: n for w, n in counts.items() if n}
    if not np.all(np.isfinite(traj.theta)):
        res.outcome, res.message = "NaN", "non-finite angles returned without an error"
        return res
    res.errors = compare_to_reference(traj, ref)
    res.failed = judge(res.errors, ref)
    if res.failed:
        res.outcome = "WRONG"
        res.message = "; ".join(_failure_text(k, res.errors) for k in res.failed)
    return res


def _failure_text(key: str, e: dict) -> str:
    if key == "pin":
        return f"pin violation {e['pin_violation']:.3g} l"
    if key == "angle":
        return f"angle error {100 * e['angle']:.3g}% ({e['angle_rad']:.3g} rad) over [0, {e['window']:.3g}]"
    return f"{key} error {100 * e[key]:.3g}%"


def numerics_for(column: str, integrator: str, duration: float) -> Numerics:
    base = NUMERICS[column]
    return Numerics(integrator=integrator, sample_dt=sample_dt_for(base["dt"], duration), **base)


PER_STEP_US = {  # measured us per step (compiled callback), N = 7 / 30 / 100; for the cost cap below
    "implicitfast": (4, 38, 920),
    "implicit": (6, 74, 1420),
    "discrete": (6, 206, 3470),
    "Euler": (3.3, 15, 130),
    "RK4": (14, 63, 510),
}


def resolved_numerics(physics: Physics, integrator: str, duration: float, limits=None) -> Numerics:
    """The settings check_accuracy asks for: dt = 0.0025 / 2^k at or below half the accuracy limit
    (and below the stability and pin limits), mass ratio at or below half the overdamped bound."""

    limits = stability_limits(physics, Numerics()) if limits is None else limits
    rate = max(limits.accuracy_rate(integrator), 1e-9)
    m = min(1e-4, 0.5 * INERTIA_RESOLUTION / rate)
    target = 0.5 * limits.accuracy_limit(integrator)
    stab = limits.limit(integrator)
    if integrator in ("Euler", "RK4"):
        stab = min(limits.spring_dt, m * (2.0 if integrator == "Euler" else 2.785))
    target = min(target, 0.9 * stab, 0.0025)
    if physics.scene_def.pinned and integrator != "discrete":
        target = min(target, (0.5 * PIN_DT3_PER_MASS * m) ** (1.0 / 3.0))
    dt = 0.0025 / 2 ** max(0, math.ceil(math.log2(0.0025 / target)))
    return Numerics(dt=dt, mass_ratio=m, integrator=integrator, sample_dt=sample_dt_for(dt, duration))


def estimated_cost_s(physics: Physics, numerics: Numerics, duration: float) -> float:
    n_index = 0 if physics.n <= 10 else (1 if physics.n <= 30 else 2)
    per_step = PER_STEP_US[numerics.integrator][n_index] * physics.n_chains
    return duration / numerics.dt * per_step * 1e-6


# ------------------------------------------------------------------------------------------------
# largest stable timestep
# ------------------------------------------------------------------------------------------------
def envelope(reference) -> tuple[np.ndarray, np.ndarray]:
    """(t, running max over particles and earlier times of |theta_ref|): the size a run may reach."""
    return reference.t, np.maximum.accumulate(np.abs(reference.theta).max(axis=1))


BURST_FACTOR, BURST_RAD = 1.5, 0.05


def is_stable(physics: Physics, integrator: str, dt: float, mass_ratio: float, duration: float, env=None) -> bool:
    """True when simulate_mujoco runs `duration` at this dt without SimulationDiverged and, given the
    reference envelope `env` (see envelope), without a spurious burst: an instability of a fast mode
    that the nonlinearity saturates (e.g. the kappa = 1000 pair's coupling mode just beyond its linear
    limit swings theta_1 - phi_1 to 0.7 rad and decays again) is unstable too, not 'stable'."""

    numerics = Numerics(dt=dt, mass_ratio=mass_ratio, integrator=integrator, sample_dt=dt * max(1, round(0.01 / dt)))
    try:
        traj = simulate_mujoco(physics, numerics, max(duration, numerics.sample_dt))
    except SimulationDiverged:
        return False
    if env is not None:
        bound = BURST_FACTOR * np.interp(traj.t, *env) + BURST_RAD
        if np.any(np.abs(traj.theta).max(axis=1) > bound):
            return False
    return True


def largest_stable_dt(
    physics: Physics,
    integrator: str,
    mass_ratio: float,
    duration: float,
    guess: float,
    ceiling: float = 0.1,
    floor: float = 1e-6,
    ratio: float = 1.15,
    env="auto",
) -> tuple[float, float | None]:
    """(largest dt that ran stably, smallest dt that did not) by geometric bracketing around `guess`
    and bisection in log(dt) to within `ratio`; (ceiling, None) when the Numerics ceiling 0.1 is stable.
    env="auto": the burst check against a reduced-model reference (numba-DOP853) of the same run."""
    if isinstance(env, str):
        ref = simulate_reduced(physics, Numerics(dt=1e-3, sample_dt=1e-3), duration, **REFERENCE)
        env = envelope(ref)

    def stable(dt):
        return is_stable(physics, integrator, dt, mass_ratio, duration, env)

    if stable(ceiling):
        return ceiling, None
    hi = ceiling
    lo = min(max(guess, floor), ceiling / ratio)
    while not stable(lo):
        hi = lo
        lo /= 4.0
        if lo < floor:
            return 0.0, hi
    while hi / lo > ratio:
        mid = math.sqrt(lo * hi)
        if stable(mid):
            lo = mid
        else:
            hi = mid
    return lo, hi


def stability_duration(physics: Physics) -> float:
    """Run length for the stability test: long enough for a marginal instability to blow up."""
    return {7: 20.0, 30: 5.0}.get(physics.n, 1.0) if physics.sigma < 50 else (2.0 if physics.n <= 10 else 0.5)

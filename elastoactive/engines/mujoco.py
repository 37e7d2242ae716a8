"""Run a scene in MuJoCo: the production path.

Between two recorded samples MuJoCo runs `steps_per_sample` steps in C (mj_step with nstep);
the follower forces come from the compiled callback, so no Python runs per step. Auto-reset is
off in every scene: a run whose state blows up stops with SimulationDiverged, which names the
likely cause, instead of silently restarting from qpos0.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable

import mujoco
import numpy as np

from ..controllers import follower_forces
from ..core.errors import ParameterError, SimulationDiverged
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory
from ..mjcf.chain import prepare, state_of
from ..terms import polarity_addresses
from . import check_steps
from .cost import announce_cost, reduced_cost
from .monitor import BAD_STATE_WARNINGS, CHECK_EVERY, PROGRESS_EVERY, is_check, runaway, step_last_apart  # noqa: F401 (the batch engine imports them here)
from .monitor import bad_state as _bad_state
from .runner import Meter, StepChunks
from .timestep import divergence_cause

PIN_DRIFT_LIMIT = 0.05  # l: beyond this the two-pinned end has left its pin (the exact model: 0)


def pin_drift_message(violation: float, time: float, numerics: Numerics) -> str:
    """Why a pinned run stopped: its end left the pin (shared with the batched engine)."""
    return (
        f"the pinned chain's end drifted {violation:.3g} l off its pin at t = {time:.4g} tau "
        f"(limit {PIN_DRIFT_LIMIT} l) with dt = {numerics.dt:g}, mass_ratio = {numerics.mass_ratio:g}, "
        f"integrator {numerics.integrator}: the soft pin's hold scales with mass_ratio / dt^2; "
        "reduce dt, raise mass_ratio, or use integrator discrete"
    )


def numerics_info(given: Numerics, used: Numerics) -> dict:
    """What a Trajectory's info records of numerics chosen automatically (Numerics.for_physics): nothing when the
    run used the numerics it was given."""
    if used is given:
        return {}
    return {
        "automatic_numerics": {
            "integrator": used.integrator,
            "dt": float(used.dt),
            "mass_ratio": float(used.mass_ratio),
            "reason": "long chain (Numerics.for_physics)",
        }
    }


def pin_violation(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """Distance between the two sites of the model's first equality (a pinned scene's end and its pin), in l."""
    end = data.site(model.eq_obj1id[0]).xpos
    pin = data.site(model.eq_obj2id[0]).xpos
    return float(np.linalg.norm(end - pin))


def simulate_mujoco(
    physics: Physics,
    numerics: Numerics = Numerics(),
    duration: float = 200.0,
    *,
    theta0: np.ndarray | None = None,
    state0=None,
    progress: bool = False,
    on_sample: Callable[[mujoco.MjModel, mujoco.MjData], None] | None = None,
) -> Trajectory:
    """Simulate a scene for `duration` (in tau); returns angles sampled every numerics.sample_dt. The scene's kind
    runs it (Scene.run_mujoco: a chain's simulate_chain_mujoco, a network's engines.network_mujoco).

    Numerics left at their defaults become numerics.for_physics(physics): for a long chain, explicit drag
    with a matched mass (params.long_chain_numerics; info["automatic_numerics"] records what ran).

    on_sample(model, data) is called at every recorded sample (e.g. to render a frame); it must
    not change the state. theta0 (a chain's angles) or state0 (a network's NetworkState): the state to start from
    instead of the scene's.

    progress=True also estimates the run's wall time first (engines.cost: a few samples stepped on a copy of the
    state; info["estimated_wall_s"]) and, for a long run far slower than the reduced engine would be, says so in
    one line on stderr before it starts.
    """
    if not duration > 0:
        raise ParameterError(f"duration (in tau) must be a positive number, got {duration}")
    return physics.scene_def.run_mujoco(
        physics, numerics, duration, theta0=theta0, state0=state0, progress=progress, on_sample=on_sample
    )


def simulate_chain_mujoco(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    *,
    theta0: np.ndarray | None = None,
    state0=None,
    progress: bool = False,
    on_sample: Callable[[mujoco.MjModel, mujoco.MjData], None] | None = None,
    install_callbacks: bool = True,
) -> Trajectory:
    """The MuJoCo engine's run of a chain scene (ChainScene.run_mujoco; simulate_mujoco says what it does).
    install_callbacks=False: the caller has installed the compiled callbacks for the whole call."""
    if state0 is not None:
        raise ParameterError(f"start: {physics.scene} is a chain scene (its state is its angles, theta0)")
    given, numerics = numerics, numerics.for_physics(physics)  # long chains: automatic numerics (Numerics)
    t = numerics.sample_times(duration)
    check_steps(numerics, duration)
    model, data = prepare(physics, numerics, theta0)
    pinned = physics.scene_def.pinned
    violation = pin_violation(model, data) if pinned else 0.0
    if on_sample is not None:
        on_sample(model, data)

    meter = Meter(duration, f"mujoco {physics.scene}", progress, physics.scene_def.units.time_units)
    estimate = announce_cost(meter, model, data, numerics, t.size - 1, lambda: reduced_cost(physics, given, duration))
    steps = StepChunks(meter, mujoco.mj_step)
    nstep = numerics.steps_per_sample
    qpos = np.empty((t.size, model.nq))
    qpos[0] = data.qpos
    units = polarity_addresses(model) if model.na else None  # the units' polarity psi (terms.polarity_addresses)
    polarity = None if units is None else np.empty((t.size, units.size))
    if polarity is not None:
        polarity[0] = data.act[units]
    start = time.perf_counter()
    with meter, follower_forces() if install_callbacks else contextlib.nullcontext():
        for k in range(1, t.size):
            check = is_check(k, t.size)
            if check:  # the last step apart: how far one step moves the state (monitor.MAX_STEP_CHANGE)
                before = step_last_apart(model, data, nstep, steps)
            else:
                steps(model, data, nstep)
            qpos[k] = data.qpos
            if polarity is not None:
                polarity[k] = data.act[units]
            # a diverged state stays NaN (auto-reset is off), so a periodic check loses nothing
            if check and _bad_state(data):
                raise SimulationDiverged(divergence_cause(physics, numerics, float(data.time), model, data))
            if check and (change := runaway(qpos, k, nstep, before)) is not None:
                raise SimulationDiverged(
                    divergence_cause(physics, numerics, float(data.time), model, data, step_change=change)
                )
            meter.at(float(t[k]))
            if pinned:
                violation = max(violation, pin_violation(model, data))
                if violation > PIN_DRIFT_LIMIT:
                    raise SimulationDiverged(pin_drift_message(violation, float(data.time), numerics))
            if on_sample is not None:
                on_sample(model, data)
    wall = time.perf_counter() - start
    theta, head = state_of(physics, qpos)
    info = {"steps": int((t.size - 1) * nstep), "integrator": numerics.integrator}
    info["us_per_step"] = 1e6 * wall / max(info["steps"], 1)
    if estimate is not None:
        info["estimated_wall_s"] = estimate.wall_s
    if pinned:
        info["constraint_violation"] = violation
    info.update(numerics_info(given, numerics))
    return Trajectory(
        t=t, theta=theta, physics=physics, engine="mujoco", wall_time_s=wall, info=info, head=head, polarity=polarity
    )


__all__ = ["simulate_mujoco", "prepare", "SimulationDiverged"]

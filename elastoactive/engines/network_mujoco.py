"""Run a network scene (scenes.NetworkScene.run_mujoco hands it here) in MuJoCo.

The model comes from elastoactive.mjcf.network; between two recorded samples MuJoCo runs steps_per_sample steps in
C, with the compiled callback installed for the active units, so no Python runs per step. The Trajectory it returns
has the shape of the reduced engine's: `nodes` (T, P, 2), the lab positions of every node (pinned ones at rest),
`polarity` (T, A), the active units' polarities in node order (None without units), and `theta` of shape
(T, 0) (a network has no chain angles).
Auto-reset is off (mjcf/common.xml): a state that blows up stops the run with SimulationDiverged.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable

import mujoco
import numpy as np

from ..controllers import follower_forces
from ..core.errors import ParameterError, SimulationDiverged
from ..core.params import RESOLUTION, Numerics, Physics
from ..core.trajectory import Trajectory
from ..mjcf.network import build_network_model, node_positions, qpos_of_positions, set_polarity
from ..networks.state import NetworkState
from ..reduced import INERTIA_RESOLUTION
from ..terms import polarity_addresses, turning_rate
from ..terms.unit_noise import unit_noise
from . import check_steps
from .cost import announce_cost
from .monitor import MAX_STEP_CHANGE, bad_state, is_check, runaway, step_last_apart
from .network_noise import NoisySteps
from .network_reduced import network_rate, start_state
from .network_step import network_numerics
from .runner import Meter, StepChunks


def check_network_timestep(physics: Physics, numerics: Numerics) -> float:
    """The pre-flight check of a network run (diagnose.check_timestep hands network scenes here): refuses, naming the
    setting, a dt that does not resolve network_rate (dt x rate <= params.RESOLUTION: the springs, the trap and the
    units are explicit, forward-Euler-like; stable below 2) and a mass outside the overdamped limit (mass_ratio x
    rate <= INERTIA_RESOLUTION: the reduced network model is overdamped only). Returns the rate."""
    numerics = network_numerics(physics, numerics)
    rate = network_rate(physics)
    if numerics.dt * rate > RESOLUTION:
        raise ParameterError(
            f"dt = {numerics.dt:g} does not resolve the {physics.scene} network's fastest rate "
            f"{rate:.3g} (gamma / k)^-1 (springs, trap, or the units' turning sigma / l_a): use dt <= "
            f"{RESOLUTION / rate:.3g}"
        )
    if numerics.mass_ratio * rate > INERTIA_RESOLUTION:
        turning = turning_rate(physics)
        cause = (
            f"; the units' turning sigma / l_a sets it: use alignment_length >= "
            f"{physics.sigma * numerics.mass_ratio / INERTIA_RESOLUTION:.3g} or mass_ratio <= "
            f"{INERTIA_RESOLUTION / rate:.3g}"
            if turning >= rate
            else f": use mass_ratio <= {INERTIA_RESOLUTION / rate:.3g}"
        )
        raise ParameterError(
            f"mass_ratio = {numerics.mass_ratio:g} is outside the overdamped limit of the "
            f"{physics.scene} network (m x rate = {numerics.mass_ratio * rate:.2g} > "
            f"{INERTIA_RESOLUTION:g}; the network model is overdamped){cause}"
        )
    return rate


def prepare_network(
    physics: Physics,
    numerics: Numerics,
    network=None,
    positions0: np.ndarray | None = None,
    polarity0: np.ndarray | None = None,
):
    """(network, model, data) at the initial state: node positions (P, 2) and the active units' polarities (A,),
    in node order, as given, else the scene's (Scene.initial_network: what both engines start from)."""
    scene = physics.scene_def
    network = scene.network(physics) if network is None else network
    if positions0 is None or polarity0 is None:
        state = scene.initial_network(physics, numerics)
        positions0 = state.positions if positions0 is None else positions0
        polarity0 = state.polarity if polarity0 is None else polarity0
    model = build_network_model(network, physics, numerics)
    data = mujoco.MjData(model)
    data.qpos[:] = qpos_of_positions(network, positions0)
    set_polarity(model, data, polarity0)
    mujoco.mj_forward(model, data)
    return network, model, data


def _divergence_message(physics: Physics, numerics: Numerics, time_now: float, step_change: float | None = None) -> str:
    """Why a network run stopped: a non-finite state or MuJoCo's limits, or (step_change) a node that moved farther in
    one step than any accurate run does (monitor.MAX_STEP_CHANGE)."""
    what = (
        "the {} network's state became non-finite or exceeded MuJoCo's limits"
        if step_change is None
        else "the {} network's nodes moved " + f"{step_change:.3g} in one step (an accurate run moves less than "
        f"{MAX_STEP_CHANGE:g})"
    ).format(physics.scene)
    return (
        f"{what} at t = {time_now:.4g} "
        f"(dt = {numerics.dt:g}, mass_ratio = {numerics.mass_ratio:g}, integrator {numerics.integrator}): the "
        "springs and the trap are explicit, stable for dt x (fastest relaxation rate) < 2; reduce dt"
    )


def simulate_network_mujoco(
    physics: Physics,
    numerics: Numerics = Numerics(),
    duration: float = 200.0,
    *,
    network=None,
    positions0: np.ndarray | None = None,
    polarity0: np.ndarray | None = None,
    state0: NetworkState | None = None,
    progress: bool = False,
    on_sample: Callable[[mujoco.MjModel, mujoco.MjData], None] | None = None,
    install_callbacks: bool = True,
) -> Trajectory:
    """Simulate a network scene for `duration` (gamma / k); node positions sampled every numerics.sample_dt.

    network: the scene's (Scene.network) unless given; positions0 (P, 2), polarity0 (A,): the scene's initial
    state unless given; state0: a NetworkState of the scene's network to start from instead (checked as the reduced
    engine checks it: network_reduced.start_state). on_sample(model, data) is called at every recorded sample; it
    must not change the state.
    install_callbacks=False: the caller has installed the compiled callbacks for the whole call (a batch's worker
    thread, engines.mujoco_batch: callbacks are global to the process)."""
    if not duration > 0:
        raise ParameterError(f"duration (in tau) must be a positive number, got {duration}")
    given, numerics = numerics, network_numerics(physics, numerics, network)
    t = numerics.sample_times(duration)
    check_steps(numerics, duration)
    if state0 is not None:  # a given start (the scene's network), checked as the reduced engine checks it
        positions0, polarity0 = start_state(physics, numerics, state0)
    network, model, data = prepare_network(physics, numerics, network, positions0, polarity0)
    if on_sample is not None:
        on_sample(model, data)
    meter = Meter(duration, f"mujoco {physics.scene}", progress, physics.scene_def.units.time_units)
    estimate = announce_cost(meter, model, data, numerics, t.size - 1, lambda: None)  # the reduced network: no pilot
    nstep = numerics.steps_per_sample
    qpos = np.empty((t.size, model.nq))
    qpos[0] = data.qpos
    units = polarity_addresses(model)
    polarity = np.empty((t.size, units.size))
    polarity[0] = data.act[units]
    noise = unit_noise(physics, numerics)
    noisy = NoisySteps(noise, numerics.dt, model.nq, units) if noise.active else None  # Python steps only if noisy
    steps = StepChunks(meter, mujoco.mj_step if noisy is None else noisy)
    start = time.perf_counter()
    with meter, follower_forces() if install_callbacks else contextlib.nullcontext():
        for k in range(1, t.size):
            check = is_check(k, t.size)
            if noisy is not None:  # each step kicked by the units' noise (no last step apart: a kick is no runaway)
                steps(model, data, nstep)
                check_runaway = False
            elif check:  # the last step apart: how far one step moves the nodes (monitor.MAX_STEP_CHANGE)
                before = step_last_apart(model, data, nstep, steps)
                check_runaway = True
            else:
                steps(model, data, nstep)
            qpos[k] = data.qpos
            polarity[k] = data.act[units]
            if check and bad_state(data):
                raise SimulationDiverged(_divergence_message(physics, numerics, float(data.time)))
            if check and check_runaway and (change := runaway(qpos, k, nstep, before)) is not None:
                raise SimulationDiverged(_divergence_message(physics, numerics, float(data.time), change))
            meter.at(float(t[k]))
            if on_sample is not None:
                on_sample(model, data)
    wall = time.perf_counter() - start
    steps = int((t.size - 1) * nstep)
    info = {"steps": steps, "integrator": numerics.integrator, "us_per_step": 1e6 * wall / max(steps, 1)}
    if noise.active:
        info["noise"] = noise._asdict() | {"scheme": "Euler-Maruyama (Ito)", "dt": float(numerics.dt)}
    if estimate is not None:
        info["estimated_wall_s"] = estimate.wall_s
    if numerics is not given:
        info["automatic_numerics"] = {
            "integrator": numerics.integrator,
            "dt": float(numerics.dt),
            "mass_ratio": float(numerics.mass_ratio),
            "reason": "network: Euler's implicit drag, dt resolving the units' turning (network_numerics)",
        }
    return Trajectory(
        t=t,
        theta=np.empty((t.size, 0)),
        physics=physics,
        engine="mujoco",
        wall_time_s=wall,
        info=info,
        nodes=node_positions(network, qpos),
        polarity=polarity if units.size else None,
    )


__all__ = ["simulate_network_mujoco", "prepare_network"]

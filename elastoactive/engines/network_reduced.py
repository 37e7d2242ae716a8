"""Run a network scene (scenes.NetworkScene.run_reduced hands it here) in the reduced model: the cross-check of MuJoCo.

The mathematics is elastoactive.reduced.network (the overdamped equations of nodes and self-aligning units, a
compiled right-hand side, its analytic Jacobian); here a Physics becomes the scene's network with sigma and the
alignment length, the initial state comes from the scene (Scene.initial_network, the one MuJoCo starts from too), and
the result is a Trajectory of the MuJoCo engine's shape: `nodes` (T, P, 2) lab positions of every node, `polarity`
(T, A) the active units' angles in node order, `theta` of shape (T, 0).
"""

from __future__ import annotations

import time

import numpy as np

from ..core.errors import ParameterError
from ..core.params import Numerics, Physics
from ..core.trajectory import Trajectory
from ..networks.geometry import turning_scale
from ..networks.state import NetworkState
from ..reduced import INERTIA_RESOLUTION
from ..reduced import network as _model
from ..terms import check_reduced_span, turning_rate
from ..terms.unit_noise import unit_noise
from .network_step import network_numerics
from .runner import EXPLICIT_METHODS, Meter, fixed_step_budget, refuse_rate, resume

METHODS = _model.METHODS
DEFAULT_METHOD = "DOP853"
"""The network model is mildly stiff (fastest rate ~6 k / gamma on a triangular patch of any size): the explicit
DOP853, compiled with the right-hand side, runs a 127-node patch for 1000 gamma / k in under a second of CPU
(docs/performance.md, section 10)."""


def system_of(physics: Physics) -> _model.NetworkSystem:
    """The reduced model of a network scene at these parameters."""
    network = physics.scene_def.network(physics)
    if network is None:
        raise ParameterError(f"{physics.scene} is a chain scene: it has no network model")
    return _model.network_system(network, physics.sigma, physics.alignment_length)


def network_rate(physics: Physics) -> float:
    """The fastest rate a network run's step must resolve (units k / gamma): the largest eigenvalue of the passive
    network's dynamical matrix (springs and trap, explicit in every integrator) or the units' turning Pi = sigma / l_a,
    whichever is larger (reduced.network.stiffest_rate: sparse for a large network); the fastest unit's
    sigma_u / l_u where the units have their own forces or alignment lengths (networks.geometry.turning_scale)."""
    network = physics.scene_def.network(physics)
    springs = _model.stiffest_rate(network)
    return max(springs, turning_rate(physics) * turning_scale(network, physics.alignment_length))


WHOLE_TURNS_RTOL = 1e-8
"""Above this relative tolerance the solver runs with the starting polarities' whole turns taken out (put back in the
record, which continues the start's angles): a ramp's step starts from units that may have turned hundreds of
radians, and DOP853's error control, relative to |psi|, lets them jitter about a fixed point in proportion: at rtol
1e-6 above the named states' still level (docs/performance.md, section 10), at a chain's 1e-9 a thousand times
below it, where runs are left as they were to the bit."""
PINNED_SLACK = 1e-6
"""Largest distance (units a) of a pinned node from its rest position in a given starting state (MuJoCo holds pins to
its constraint's give; they are put back exactly)."""


def start_state(physics: Physics, numerics: Numerics, state0: NetworkState | None = None) -> NetworkState:
    """The state a network run starts from, the same for both engines: `state0` (lab positions (P, 2) of every node,
    the active units' polarities (A,) in node order; pinned nodes must sit at rest) checked against the scene's
    network, else the scene's seeded one (Scene.initial_network). A bad state is refused in one line naming it."""
    if state0 is None:
        return physics.scene_def.initial_network(physics, numerics)
    network = physics.scene_def.network(physics)
    positions = np.asarray(state0.positions, dtype=float)
    polarity = np.asarray(state0.polarity, dtype=float).reshape(-1)
    units = int(np.count_nonzero(network.active))
    if positions.shape != network.positions.shape:
        raise ParameterError(
            f"start: positions must be {network.n_nodes} nodes x 2 for this {physics.scene} network, got shape "
            f"{positions.shape} (a state of another network?)"
        )
    if polarity.size != units:
        raise ParameterError(
            f"start: polarity must hold {units} angles (one per active unit) for this {physics.scene} network, got "
            f"{polarity.size}"
        )
    if not (np.all(np.isfinite(positions)) and np.all(np.isfinite(polarity))):
        raise ParameterError("start: the state holds a non-finite position or polarity")
    moved = np.abs(positions[network.pinned] - network.positions[network.pinned])
    if moved.size and moved.max() > PINNED_SLACK:
        raise ParameterError(
            f"start: a pinned node sits {moved.max():.3g} a from its rest position (a state of another network?)"
        )
    positions = positions.copy()
    positions[network.pinned] = network.positions[network.pinned]
    return NetworkState(positions, polarity)


def simulate_network_reduced(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    *,
    theta0=None,
    state0: NetworkState | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    progress: bool | None = None,
) -> Trajectory:
    """Integrate the network model from `state0` (start_state: default the scene's initial state) and sample every
    numerics.sample_dt; rtol, atol default the scene's reduced_tolerances (scenes.network_kind.NetworkScene); above
    WHOLE_TURNS_RTOL the starting polarities' whole turns are taken out while solving. The engine runner
    (engines.runner) refuses a run past its step limit before it steps and, with progress (None: as run_engine's
    option says), shows it."""
    default_rtol, default_atol = physics.scene_def.reduced_tolerances(physics)
    rtol = default_rtol if rtol is None else rtol
    atol = default_atol if atol is None else atol
    if theta0 is not None:
        raise ParameterError(f"theta0: {physics.scene} is a network (its initial state: Scene.initial_network)")
    method = DEFAULT_METHOD if method is None else method
    if method not in METHODS:
        raise ParameterError(
            f"method must be one of {', '.join(METHODS)} for a network scene (or left out: "
            f"{DEFAULT_METHOD}), got {method!r}"
        )
    if physics.noise > 0:
        raise ParameterError("noise: the network scenes are deterministic (noise must be 0)")
    check_reduced_span(physics, duration)
    rate = network_rate(physics) if "mass_ratio" in numerics.given() else 0.0  # the model is massless: a mass given
    if numerics.mass_ratio * rate > INERTIA_RESOLUTION:  # where its inertia would matter is refused, as MuJoCo does
        raise ParameterError(
            f"mass_ratio = {numerics.mass_ratio:g}: the reduced engine's {physics.scene} network is "
            f"overdamped (m x rate = {numerics.mass_ratio * rate:.2g} > {INERTIA_RESOLUTION:g}); use "
            f"mass_ratio <= {INERTIA_RESOLUTION / rate:.3g}, where the inertia is negligible"
        )
    system = system_of(physics)
    t = numerics.sample_times(duration)
    y0 = _model.pack(system, start_state(physics, numerics, state0))
    noise = unit_noise(physics, numerics)
    units = physics.scene_def.units.time_units
    start = time.perf_counter()
    with Meter(duration, f"reduced {physics.scene}", progress, units) as meter:
        if noise.active:  # Euler-Maruyama at MuJoCo's step, with its draws (terms.unit_noise)
            dt = network_numerics(physics, numerics).dt
            steps = round(float(t[-1]) / dt)
            fixed_step_budget(physics, duration, dt, "the reduced engine's Euler-Maruyama", units)(steps, 1)
            solution = _model.solve_noisy(
                system,
                t,
                y0,
                dt=dt,
                seed=noise.seed,
                translational=noise.translational,
                rotational=noise.rotational,
                loop=_metered(meter),
            )
        else:
            rate = network_rate(physics)
            refuse_rate(
                physics,
                duration,
                rate if method in EXPLICIT_METHODS else 0.0,
                method=method,
                what="the reduced engine's",
                units=units,
                python=method != DEFAULT_METHOD,
            )
            f2 = 2 * system.n_free
            turns = np.zeros(y0.size - f2)
            if rtol > WHOLE_TURNS_RTOL:  # the polarities' whole turns taken out while solving
                turns = 2.0 * np.pi * np.round(y0[f2:] / (2.0 * np.pi))
            solution = _model.solve(
                system,
                t,
                np.concatenate([y0[:f2], y0[f2:] - turns]),
                rtol=rtol,
                atol=atol,
                method=method,
                on_time=meter.at if meter.shows else None,
                loop=_metered(meter),
            )
            solution.y[:, f2:] += turns
    wall = time.perf_counter() - start
    nodes, polarity = _model.unpack(system, solution.y)
    if not np.all(np.isfinite(solution.y)):
        raise ParameterError(f"the {physics.scene} network's state became non-finite (sigma = {physics.sigma:g})")
    info = {"method": method, "rtol": rtol, "atol": atol, "nfev": solution.nfev, "model": "overdamped"}
    if noise.active:
        info = {"method": solution.method, "steps": solution.nfev, "model": "overdamped"}
        info["noise"] = noise._asdict() | {"scheme": "Euler-Maruyama (Ito)", "dt": float(dt)}
    return Trajectory(
        t=t,
        theta=np.empty((t.size, 0)),
        physics=physics,
        engine="reduced",
        wall_time_s=wall,
        info=info,
        nodes=nodes,
        polarity=polarity if polarity.shape[1] else None,
    )


def _metered(meter: Meter):
    """reduced.network's loop contract (run_loop) with the meter told the time reached after every call
    (engines.runner.resume: calls cut to about a progress interval when the meter shows, the same steps bit for
    bit)."""
    return lambda call, paused, reached, steps: resume(call, paused, reached, meter, steps)

"""Run a scene in the reduced model: the cross-check of the MuJoCo engine.

The mathematics is elastoactive.reduced (equations, compiled kernels, solvers), which knows
no scene: here a Physics becomes the scene's ChainSystem (Scene.reduced_system), the initial state
comes from the scene (elastoactive.reduced.initial), the noise from elastoactive.controllers.noise (the counter-based
force factors the MuJoCo engine uses too), and the result is a Trajectory.

Which model runs: the overdamped one (the paper's) or the inertial one (MuJoCo's chain with particles
of mass numerics.mass_ratio, elastoactive/reduced/equations.py). One criterion, `regime`: inside the
overdamped limit, mass_ratio x (fastest overdamped rate at the scene's base state) <= INERTIA_RESOLUTION
(0.1), both engines model the overdamped physics (MuJoCo approximates it with a small mass); outside it,
both model the inertial physics with that mass, and simulate_reduced integrates the inertial model.
elastoactive.engines.timestep classifies MuJoCo runs by the same function. simulate_reduced(inertial=True/False)
overrides it; Trajectory.info records "model" ("overdamped" / "inertial") and "mass_ratio".

The physics-level functions (rhs, jacobian, drag_matrix, ...) are those of the package, applied to
system_of(physics) (overdamped; mass_ratio > 0: the inertial model's, on the state (theta, omega)).
"""

from __future__ import annotations

import time

import numpy as np

from .. import reduced as _math
from ..core.errors import ParameterError
from ..core.params import Numerics, Physics, option
from ..core.registry import initial_angles
from ..core.trajectory import Trajectory
from ..reduced import DEFAULT_BETA, INERTIA_RESOLUTION, STIFF_RADIUS, ChainSystem
from ..reduced.settings import METHODS
from ..terms import check_reduced_span, polarity_term
from . import node_forces
from . import polarity as polarity_engine
from .regime import Regime, base_state, regime  # re-exported: the engine runs the model these choose
from .runner import Meter, fixed_step_budget, solver_budget

__all__ = [
    "DEFAULT_BETA",
    "INERTIA_RESOLUTION",
    "STIFF_RADIUS",
    "Interrupted",
    "Regime",
    "base_state",
    "check_method",
    "drag_matrix",
    "jacobian",
    "regime",
    "rhs",
    "rhs_reference",
    "simulate_reduced",
    "simulate_reference",
    "spectral_radius",
    "stiffness",
    "system_of",
]


def system_of(physics: Physics, mass_ratio: float = 0.0) -> ChainSystem:
    """The reduced model of this physics, as its scene describes it: overdamped (mass_ratio = 0), or the
    inertial model with particles of mass mass_ratio (and the scene's bead inertia)."""
    system = physics.scene_def.reduced_system(physics)
    return system._replace(mass_ratio=float(mass_ratio)) if mass_ratio else system


# ----------------------------------------------------------------------------------------------
# which model: the overdamped limit
# ----------------------------------------------------------------------------------------------
def _use_inertia(physics: Physics, numerics: Numerics, inertial: bool | None) -> tuple[bool, dict]:
    """(whether to run the inertial model, what to record in Trajectory.info) for simulate_reduced's `inertial`;
    refuses what the reduced model does not have (friction between capsules)."""
    if physics.contact and physics.contact_friction > 0:
        raise ParameterError(
            f"contact_friction = {physics.contact_friction:g}: the reduced model's self-contact is "
            "frictionless (a penalty along the capsules' separation); use the MuJoCo engine, or 0"
        )
    if system_of(physics).extended:
        _check_dense_size(
            physics,
            "a free head, a trap or self-contact makes the reduced model dense (O(N^3) per "
            "evaluation, its Jacobian by central differences: 10 tau took 8 s at N = 50, 170 s at 150)",
            "run it with the MuJoCo engine, or on a shorter chain",
        )
    if inertial is None:
        r = regime(physics, numerics)
        if r.inertial:
            _check_dense_size(
                physics,
                r.describe() + f"; its largest mass inside the limit is {r.mass_limit:.2g}; "
                "the reduced engine's inertial model solves a dense mass matrix at every evaluation",
                f"give a smaller {option('mass_ratio')} (the overdamped chain), a smaller {option('sigma')}, or use "
                "MuJoCo",
            )
        key = "inertia_number_bound" if r.rate_is_bound else "inertia_number"
        return r.inertial, {key: r.inertia_number}
    if inertial not in (True, False):
        raise ParameterError(f"inertial must be True, False or None (automatic), got {inertial!r}")
    if inertial:
        _check_dense_size(
            physics,
            "the reduced engine's inertial model solves a dense mass matrix at every evaluation",
            "leave the model to the overdamped limit (inertial=None), or use MuJoCo",
        )
    return bool(inertial), {"inertial_override": bool(inertial)}


DENSE_MAX_ANGLES = 100
"""Most angles the reduced engine integrates on its dense paths: the inertial model (a mass matrix solved at every
evaluation, O(N^3), its Jacobian by 4N evaluations: 10 tau at mass_ratio 1e-4 took 2.9 s at N = 50, 40 s at 100)
and a free head, trap or self-contact (10 tau: 8 s at N = 50, 170 s at 150). Past it a run would not finish in
reasonable time (at N = 1000, over 300 s in the stiffness check alone). The overdamped chain has no such limit
(its O(N) path: N = 1000, 10 tau in ~1 s)."""


def _check_dense_size(physics: Physics, why: str, fix: str) -> None:
    """Refuse, in one line, a dense-path run of more than DENSE_MAX_ANGLES angles: why it is dense, what to do."""
    if physics.n_angles > DENSE_MAX_ANGLES:
        raise ParameterError(f"{why}; it is limited to {DENSE_MAX_ANGLES} angles, here {physics.n_angles}: {fix}")


# ----------------------------------------------------------------------------------------------
# the package's functions on a Physics
# ----------------------------------------------------------------------------------------------
def _with_loads(physics: Physics, factor):
    """The force factors times physics' load factors (factor None: the load factors; all loaded: unchanged)."""
    loads = load_factors(physics)
    if loads is None:
        return factor
    return loads if factor is None else loads * np.asarray(factor, dtype=float).reshape(-1)


def rhs(physics: Physics, *, beta: float = DEFAULT_BETA, factor=None, mass_ratio: float = 0.0):
    """Compiled right-hand side f(t, theta) -> dtheta/dt of the deterministic model (mass_ratio > 0: the
    inertial model's f(t, y) -> dy/dt, y = (theta, omega)).

    factor: optional per-particle force factor (1 + eta_i), default ones; times the load factors of
    physics.loaded (0 on unloaded particles). beta: Baumgarte rate (two-pinned).
    """
    return _math.rhs(system_of(physics, mass_ratio), beta=beta, factor=_with_loads(physics, factor))


def jacobian(physics: Physics, *, beta: float = DEFAULT_BETA, mass_ratio: float = 0.0):
    """Compiled analytic Jacobian J(t, theta) = d(dtheta/dt)/d(theta) of the deterministic model (mass_ratio > 0:
    the inertial model's, on (theta, omega))."""
    return _math.jacobian(system_of(physics, mass_ratio), beta=beta)


def drag_matrix(physics: Physics, theta) -> np.ndarray:
    """D(theta) of the whole system (block diagonal for the pair), from the compiled kernel."""
    return _math.drag_matrix(system_of(physics), theta)


def rhs_reference(physics: Physics, *, beta: float = DEFAULT_BETA, factor=None):
    """Plain-numpy f(t, theta), written straight from the formulas (for tests and benchmarks)."""
    return _math.rhs_reference(system_of(physics), beta=beta, factor=_with_loads(physics, factor))


def spectral_radius(physics: Physics, theta, *, beta: float = DEFAULT_BETA) -> float:
    """Largest |eigenvalue| of the Jacobian at theta."""
    return _math.spectral_radius(system_of(physics), theta, beta=beta)


def stiffness(physics: Physics, theta, *, beta: float = DEFAULT_BETA) -> float:
    """Fastest decay rate max(-Re lambda) of the Jacobian at theta (method=None's stiffness indicator)."""
    return _math.stiffness(system_of(physics), theta, beta=beta)


# ----------------------------------------------------------------------------------------------
# the engine
# ----------------------------------------------------------------------------------------------
def load_factors(physics: Physics) -> np.ndarray | None:
    """Per-particle load factors (1.0 loaded, 0.0 not; chain 1, then chain 2, the same mask on both) of
    physics.loaded, or None when every particle is loaded (the unmasked path, bit for bit as before)."""
    if physics.loaded == "all":
        return None
    return np.tile(physics.load_mask().astype(float), physics.n_chains)


def _loaded_noise(factors, loads: np.ndarray | None):
    """The force factors of the loaded particles spread over all particles (0 on the others). MuJoCo's callback
    numbers the noise of the loaded particles only (sites with a non-zero user value, in order), so `factors`
    gives one column per loaded particle; None loads: factors unchanged."""
    if loads is None:
        return factors
    where = np.flatnonzero(loads)

    def spread(steps: np.ndarray) -> np.ndarray:
        out = np.zeros((np.size(steps), loads.size))
        out[:, where] = factors(steps)
        return out

    return spread


def _initial(physics: Physics, numerics: Numerics, theta0) -> np.ndarray:
    if theta0 is None:
        return initial_angles(physics, numerics)
    theta0 = np.array(theta0, dtype=float).reshape(-1)
    if theta0.size != physics.n_angles:
        raise ParameterError(f"theta0 must have {physics.n_angles} angles, got {theta0.size}")
    return theta0


def check_method(physics: Physics, method: str | None) -> None:
    """Refuse, in one line, a method the reduced engine would not use: an unknown name, or any method for a run
    with noise (its fixed-step schemes take numerics.dt)."""
    if method is None:
        return
    if method not in METHODS:
        raise ParameterError(f"method must be one of {', '.join(METHODS)} (or left out: automatic), got {method!r}")
    if physics.noise > 0:
        raise ParameterError(
            f"method = {method}: with noise the reduced engine takes fixed steps of {option('dt')} "
            f"(Euler-Maruyama or Heun); leave {option('method')} out"
        )


def simulate_reduced(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    *,
    theta0=None,
    state0=None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    beta: float = DEFAULT_BETA,
    inertial: bool | None = None,
    progress: bool = False,
) -> Trajectory:
    """Integrate the reduced model from theta0 (default: initial_angles) and sample every numerics.sample_dt; a
    network scene from state0 (its NetworkState; default: Scene.initial_network). The scene's kind runs it
    (Scene.run_reduced: a chain's simulate_chain_reduced, a network's engines.network_reduced).

    inertial: None (automatic: the inertial model, at rest at t = 0, when numerics.mass_ratio is outside the
    overdamped limit, see `regime`), True (the inertial model at numerics.mass_ratio), False (overdamped).
    Deterministic (noise = 0): adaptive ODE solver; method None picks it (numba-DOP853, or an implicit method
    for stiff systems and long chains near their onset: elastoactive.reduced.solve), or one of METHODS;
    info["method"] records what ran.
    noise > 0: Euler-Maruyama with step numerics.dt and the shared counter-based noise (seed numerics.seed)
    (inertial: the noise force constant over each step dt, as in MuJoCo, RK4 substeps); rtol, atol and
    method are then unused. White noise read as Stratonovich (physics.noise_calculus): stochastic Heun
    instead (the inertial model has no Ito-Stratonovich difference). Coloured noise (noise_correlation
    tau_c > 0): the Ornstein-Uhlenbeck realisation of elastoactive.controllers.noise.ColouredNoise, the one MuJoCo's
    callback applies, constant over each step (Euler steps of the random ODE; dt << tau_c resolves it). info
    records "model" ("overdamped" / "inertial") and "mass_ratio". rtol, atol: default the scene kind's
    Scene.reduced_tolerances (a chain's 1e-9, 1e-11; a large network's 1e-6, 1e-8).
    """
    default_rtol, default_atol = physics.scene_def.reduced_tolerances(physics)
    rtol = default_rtol if rtol is None else rtol
    atol = default_atol if atol is None else atol
    return physics.scene_def.run_reduced(
        physics,
        numerics,
        duration,
        theta0=theta0,
        state0=state0,
        rtol=rtol,
        atol=atol,
        method=method,
        beta=beta,
        inertial=inertial,
        progress=progress,
    )


def simulate_chain_reduced(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    *,
    theta0=None,
    state0=None,
    rtol: float = 1e-9,
    atol: float = 1e-11,
    method: str | None = None,
    beta: float = DEFAULT_BETA,
    inertial: bool | None = None,
    progress: bool = False,
) -> Trajectory:
    """The reduced engine's run of a chain scene (ChainScene.run_reduced; simulate_reduced says what it does)."""
    if state0 is not None:
        raise ParameterError(f"start: {physics.scene} is a chain scene (its state is its angles, theta0)")
    check_method(physics, method)
    use_inertia, record = _use_inertia(physics, numerics, inertial)
    system = system_of(physics, numerics.mass_ratio if use_inertia else 0.0)
    t = numerics.sample_times(duration)
    theta0_given, theta0 = theta0, _initial(physics, numerics, theta0)
    loads = load_factors(physics)
    count = physics.n_angles if loads is None else int(np.count_nonzero(loads))  # particles with a force
    laws = [law for law in (term.node_forces(physics) for term in physics.active_terms()) if law is not None]
    clamp = node_forces.clamp_of(physics)  # a moving clamp (Term.clamp_motion), or None
    if laws or clamp is not None:
        node_forces.check(physics, system, physics.noise > 0)
    polarity = None
    units = polarity_term(physics) is not None  # turning units (engines.polarity): before any other path
    if units:
        polarity_engine.check(physics, system, physics.noise > 0)
        check_reduced_span(physics, duration)
    units_of_time = physics.scene_def.units.time_units
    budget = solver_budget(
        physics,
        duration,
        "the reduced engine's",
        units_of_time,
        start=("perturbation", numerics.perturbation) if theta0_given is None else ("start-from", None),
        base_rate=lambda: physics.scene_def.fastest_overdamped_rate(physics),
    )
    start = time.perf_counter()
    with Meter(duration, f"reduced {physics.scene}", progress, units_of_time) as meter:
        if units:  # the state (theta, psi)
            theta, polarity, info = polarity_engine.solve(
                physics, system, t, theta0, laws, rtol=rtol, atol=atol, beta=beta, on_time=meter.at, budget=budget
            )
        elif physics.noise > 0:
            from ..controllers.noise import ColouredNoise, force_factor  # controllers/__init__ loads mujoco: noisy runs

            dt = numerics.dt
            scheme = "euler"
            if physics.noise_correlation > 0:  # the shared Ornstein-Uhlenbeck realisation, constant over each step
                coloured = ColouredNoise(numerics.seed, count, physics.noise, physics.noise_correlation, dt)
                factors = coloured.force_factor
            else:
                scheme = "heun" if physics.noise_calculus == "stratonovich" and not use_inertia else "euler"

                def factors(steps: np.ndarray) -> np.ndarray:
                    return force_factor(numerics.seed, steps, count, physics.noise, dt)

            theta, info = _math.solve_sde(
                system,
                t,
                theta0,
                dt=dt,
                factors=_loaded_noise(factors, loads),
                beta=beta,
                scheme=scheme,
                on_time=meter.at,
                budget=fixed_step_budget(physics, duration, dt, f"the reduced engine's {scheme} scheme", units_of_time),
            )
            info["seed"] = numerics.seed
            if physics.noise_correlation > 0:
                info["noise_correlation"] = physics.noise_correlation
            else:
                info["noise_calculus"] = physics.noise_calculus
        else:
            try:
                if laws or clamp is not None:  # plug-in terms' forces on the particles, a moving clamp (node_forces)
                    theta, info = node_forces.solve(
                        physics, system, t, theta0, laws, rtol=rtol, atol=atol, beta=beta, loads=loads, clamp=clamp,
                        on_time=meter.at, budget=budget,
                    )  # fmt: skip
                else:
                    theta, info = _math.solve_ode(
                        system, t, theta0, rtol=rtol, atol=atol, method=method, beta=beta, loads=loads,
                        on_time=meter.at, budget=budget,
                    )  # fmt: skip
            except KeyboardInterrupt as err:  # Ctrl-C (numba-DOP853 sees it within ~0.1 s): keep the samples computed
                raise _interrupted(err, system, t, physics, time.perf_counter() - start) from None
    wall = time.perf_counter() - start
    info.update(model="inertial" if use_inertia else "overdamped", mass_ratio=float(numerics.mass_ratio), **record)
    if system.pinned:
        info["beta"] = beta
        info["constraint_violation"] = _math.constraint_violation(system, theta)
    theta, head = _split_head(system, theta)
    if clamp is not None and clamp.translates:  # the moving clamp's position at every sample
        head = np.asarray(clamp.displacement(t), dtype=float).reshape(t.size, 2)
    if head is None and physics.scene_def.head_count(physics):  # a star's clamped hub: phi = 0, as MuJoCo's idle hinge
        head = np.zeros((t.size, physics.scene_def.head_count(physics)))
    return Trajectory(
        t=t, theta=theta, physics=physics, engine="reduced", wall_time_s=wall, info=info, head=head, polarity=polarity
    )


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during simulate_reduced. `trajectory`: the samples computed so far (a Trajectory over the times
    reached; None when the solver does not report them, or none were reached), for a caller that keeps them."""

    def __init__(self, message: str, trajectory: Trajectory | None):
        super().__init__(message)
        self.trajectory = trajectory


def _interrupted(
    err: KeyboardInterrupt, system: ChainSystem, t: np.ndarray, physics: Physics, wall: float
) -> Interrupted:
    """The Interrupted of a Ctrl-C during the deterministic solve (numba-DOP853's Interrupted carries its samples)."""
    samples = getattr(err, "samples", None)
    if samples is None or len(samples) < 2:  # scipy's solvers keep no partial samples; or none was reached yet
        return Interrupted(f"the reduced run was interrupted after {wall:.1f} s, with no samples kept", None)
    theta, head = _split_head(system, np.asarray(samples))
    reached = t[: len(theta)]
    partial = Trajectory(
        t=reached,
        theta=theta,
        physics=physics,
        engine="reduced",
        wall_time_s=wall,
        info={"interrupted": True},
        head=head,
    )
    return Interrupted(
        f"the reduced run was interrupted at t = {reached[-1]:.6g} of {t[-1]:.6g} tau "
        f"({len(reached)} samples computed)",
        partial,
    )


def _split_head(system: ChainSystem, state: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """(angles, head or None) of the solvers' states: a free head's two coordinates, or a star's turning hub's angle,
    come last (ChainSystem.n_head)."""
    if not system.n_head:
        return state, None
    return state[:, : system.n_angles].copy(), state[:, system.n_angles :].copy()


def simulate_reference(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    *,
    theta0=None,
    rtol: float = 1e-9,
    atol: float = 1e-11,
    method: str = "DOP853",
    beta: float = DEFAULT_BETA,
    inertial: bool | None = None,
) -> Trajectory:
    """The plain numpy/scipy baseline: solve_ivp on rhs_reference (deterministic only), for benchmarks;
    inertial as in simulate_reduced (rhs_inertial_reference, from rest)."""
    # start-up time: scipy.integrate costs ~0.4 s to import; the compiled default does not need it
    from scipy.integrate import solve_ivp

    if physics.noise > 0:
        raise ParameterError("simulate_reference integrates the deterministic model only (noise must be 0)")
    use_inertia, record = _use_inertia(physics, numerics, inertial)
    system = system_of(physics, numerics.mass_ratio if use_inertia else 0.0)
    t = numerics.sample_times(duration)
    theta0 = _initial(physics, numerics, theta0)
    start = time.perf_counter()
    loads = load_factors(physics)  # None: every particle loaded
    if use_inertia:
        f = _math.rhs_inertial_reference(system, beta=beta, factor=loads)
        y0 = np.concatenate([theta0, np.zeros(theta0.size)])
    else:
        f, y0 = _math.rhs_reference(system, beta=beta, factor=loads), theta0
        if system.head_free:  # the head starts at the dish's centre, as in simulate_reduced and MuJoCo
            y0 = np.concatenate([theta0, np.zeros(2)])
    sol = solve_ivp(f, (0.0, float(t[-1])), y0, method=method, t_eval=t, rtol=rtol, atol=atol)
    wall = time.perf_counter() - start
    if not sol.success:
        raise RuntimeError(f"solve_ivp ({method}) failed: {sol.message}")
    info = {
        "method": method,
        "rtol": rtol,
        "atol": atol,
        "nfev": int(sol.nfev),
        "rhs": "numpy reference",
        "model": "inertial" if use_inertia else "overdamped",
        "mass_ratio": float(numerics.mass_ratio),
        **record,
    }
    theta, head = _split_head(system, sol.y.T[:, : system.state_size if not use_inertia else theta0.size])
    if system.pinned:
        info["constraint_violation"] = _math.constraint_violation(system, theta)
    return Trajectory(
        t=t, theta=theta, physics=physics, engine="reduced-reference", wall_time_s=wall, info=info, head=head
    )

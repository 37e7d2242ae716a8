"""Run a scene in the reduced (overdamped) model: the cross-check of the MuJoCo engine.

The mathematics is elastoactive.analysis.reduced (equations, compiled kernels, solvers), which knows
no scene: here a Physics becomes the scene's ChainSystem (Scene.reduced_system), the initial state
comes from the scene (elastoactive.initial), the noise from elastoactive.noise (the counter-based
force factors the MuJoCo engine uses too), and the result is a Trajectory.

The physics-level functions (rhs, jacobian, drag_matrix, ...) are those of the package, applied to
system_of(physics).
"""

from __future__ import annotations

import time

import numpy as np

from ..analysis import reduced as _math
from ..analysis.reduced import DEFAULT_BETA, STIFF_RADIUS, ChainSystem
from ..errors import ParameterError
from ..initial import initial_angles
from ..noise import force_factor
from ..params import Numerics, Physics
from ..trajectory import Trajectory

__all__ = [
    "DEFAULT_BETA",
    "STIFF_RADIUS",
    "drag_matrix",
    "jacobian",
    "rhs",
    "rhs_reference",
    "simulate_reduced",
    "simulate_reference",
    "spectral_radius",
    "stiffness",
    "system_of",
]


def system_of(physics: Physics) -> ChainSystem:
    """The reduced model of this physics, as its scene describes it."""
    return physics.scene_def.reduced_system(physics)


# ----------------------------------------------------------------------------------------------
# the package's functions on a Physics
# ----------------------------------------------------------------------------------------------
def rhs(physics: Physics, *, beta: float = DEFAULT_BETA, factor=None):
    """Compiled right-hand side f(t, theta) -> dtheta/dt of the deterministic model.

    factor: optional per-particle force factor (1 + eta_i), default ones. beta: Baumgarte rate (two-pinned).
    """
    return _math.rhs(system_of(physics), beta=beta, factor=factor)


def jacobian(physics: Physics, *, beta: float = DEFAULT_BETA):
    """Compiled analytic Jacobian J(t, theta) = d(dtheta/dt)/d(theta) of the deterministic model."""
    return _math.jacobian(system_of(physics), beta=beta)


def drag_matrix(physics: Physics, theta) -> np.ndarray:
    """D(theta) of the whole system (block diagonal for the pair), from the compiled kernel."""
    return _math.drag_matrix(system_of(physics), theta)


def rhs_reference(physics: Physics, *, beta: float = DEFAULT_BETA, factor=None):
    """Plain-numpy f(t, theta), written straight from the formulas (for tests and benchmarks)."""
    return _math.rhs_reference(system_of(physics), beta=beta, factor=factor)


def spectral_radius(physics: Physics, theta, *, beta: float = DEFAULT_BETA) -> float:
    """Largest |eigenvalue| of the Jacobian at theta."""
    return _math.spectral_radius(system_of(physics), theta, beta=beta)


def stiffness(physics: Physics, theta, *, beta: float = DEFAULT_BETA) -> float:
    """Fastest decay rate max(-Re lambda) of the Jacobian at theta (method=None's stiffness indicator)."""
    return _math.stiffness(system_of(physics), theta, beta=beta)


# ----------------------------------------------------------------------------------------------
# the engine
# ----------------------------------------------------------------------------------------------
def _initial(physics: Physics, numerics: Numerics, theta0) -> np.ndarray:
    if theta0 is None:
        return initial_angles(physics, numerics)
    theta0 = np.array(theta0, dtype=float).reshape(-1)
    if theta0.size != physics.n_angles:
        raise ParameterError(f"theta0 must have {physics.n_angles} angles, got {theta0.size}")
    return theta0


def simulate_reduced(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    *,
    theta0=None,
    rtol: float = 1e-9,
    atol: float = 1e-11,
    method: str | None = None,
    beta: float = DEFAULT_BETA,
) -> Trajectory:
    """Integrate the reduced model from theta0 (default: initial_angles) and sample every numerics.sample_dt.

    Deterministic (noise = 0): adaptive ODE solver (method: see elastoactive.analysis.reduced.solve).
    noise > 0: Euler-Maruyama with step numerics.dt and the shared counter-based noise (seed numerics.seed);
    rtol, atol and method are then unused.
    """
    system = system_of(physics)
    t = numerics.sample_times(duration)
    theta0 = _initial(physics, numerics, theta0)
    start = time.perf_counter()
    if physics.noise > 0:
        dt = numerics.dt

        def factors(steps: np.ndarray) -> np.ndarray:
            return force_factor(numerics.seed, steps, physics.n_angles, physics.noise, dt)

        theta, info = _math.solve_sde(system, t, theta0, dt=dt, factors=factors, beta=beta)
        info["seed"] = numerics.seed
    else:
        theta, info = _math.solve_ode(system, t, theta0, rtol=rtol, atol=atol, method=method, beta=beta)
    wall = time.perf_counter() - start
    if system.pinned:
        info["beta"] = beta
        info["constraint_violation"] = _math.constraint_violation(system, theta)
    return Trajectory(t=t, theta=theta, physics=physics, engine="reduced", wall_time_s=wall, info=info)


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
) -> Trajectory:
    """The plain numpy/scipy baseline: solve_ivp on rhs_reference (deterministic only), for benchmarks."""
    # start-up time: scipy.integrate costs ~0.4 s to import; the compiled default does not need it
    from scipy.integrate import solve_ivp

    if physics.noise > 0:
        raise ParameterError("simulate_reference integrates the deterministic model only (noise must be 0)")
    system = system_of(physics)
    t = numerics.sample_times(duration)
    theta0 = _initial(physics, numerics, theta0)
    start = time.perf_counter()
    sol = solve_ivp(
        _math.rhs_reference(system, beta=beta), (0.0, float(t[-1])), theta0, method=method, t_eval=t, rtol=rtol,
        atol=atol,
    )
    wall = time.perf_counter() - start
    if not sol.success:
        raise RuntimeError(f"solve_ivp ({method}) failed: {sol.message}")
    info = {"method": method, "rtol": rtol, "atol": atol, "nfev": int(sol.nfev), "rhs": "numpy reference"}
    theta = sol.y.T.copy()
    if system.pinned:
        info["constraint_violation"] = _math.constraint_violation(system, theta)
    return Trajectory(t=t, theta=theta, physics=physics, engine="reduced-reference", wall_time_s=wall, info=info)

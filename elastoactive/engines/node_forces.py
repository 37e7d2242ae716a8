"""The reduced model with forces from plug-in terms: a force on every particle, from their positions and the time.

A term the compiled kernels do not know (elastoactive.terms.base.Term.node_forces) gives the force F_i on every
particle as a function of the particles' positions, law(positions), or of the time and the positions,
law(t, positions) for a force that changes in time (a drive): the law's number of parameters tells which
(time_law). Its generalised force on the absolute angle theta_j of a chain
is the virtual work of moving every particle beyond joint j:

    Q_j = sum_{i >= j} F_i . (-sin theta_j, cos theta_j)

and the overdamped model becomes D(theta) theta' = f(theta) + Q(theta), with D and f those of the compiled kernels (the
drag matrix and the chain's own forces). The right-hand side is the compiled one plus D^-1 Q, integrated by scipy's
DOP853 at the engine's tolerances: Python runs once per evaluation (about 80 us at N = 7), so a term that the kernels
know (its fields in the record) stays the fast path. Forces that do not depend on the positions
(terms.base.PeriodicForce: the tip drive) skip Python altogether: without a moving clamp, every law such a force, the
whole run is DOP853 compiled around one compiled right-hand side (reduced.node_kernels.dop853, "numba-DOP853": scipy's
algorithm, its steps to round-off; a 500 tau drive of N = 2 in 0.04 s where scipy around the same compiled right-hand
side took 0.7-1.8 s). The chains' pivots are where MuJoCo puts them (Scene.chain_offset), so both engines see the same
positions.

A term may also move chain 1's clamp (Term.clamp_motion: its point by d(t) with velocity u(t), its spring's rest
angle to phi(t)). The lab-frame drag then acts on the particles' lab velocities u + J_k theta', so every particle
gains the force -Gamma_k(theta) u (Gamma_k = gamma_L e_k e_k^T + gamma_T n_k n_k^T, clamp_drag), the clamp spring
C1 (theta_1 - phi) adds C1 phi to Q_1, and the particles' positions (for the node forces) are shifted by d(t):

    D(theta) theta' = f(theta) + Q(theta) - sum_k J_k^T Gamma_k u(t) + C1 phi(t) e_1     (docs/clamp.md).
"""

from __future__ import annotations

import inspect

import numpy as np

from .. import reduced as _math
from ..core.errors import ParameterError
from ..core.params import Physics, option
from ..core.trajectory import particle_positions
from ..terms.base import PeriodicForce
from .runner import reporting


def positions(physics: Physics, theta: np.ndarray) -> np.ndarray:
    """Positions (particles, 2) of every particle, chain 1 then chain 2, from the absolute angles (the pivots fixed:
    trajectory.particle_positions without a head)."""
    return particle_positions(physics, theta).reshape(physics.n_angles, 2)


def generalised(physics: Physics, theta: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Q_j = sum_{i >= j} F_i . (-sin theta_j, cos theta_j), chain by chain."""
    n = physics.n
    q = np.empty(physics.n_angles)
    for k in range(physics.n_chains):
        part = slice(k * n, (k + 1) * n)
        beyond = np.cumsum(forces[part][::-1], axis=0)[::-1]  # sum over i >= j
        q[part] = -np.sin(theta[part]) * beyond[:, 0] + np.cos(theta[part]) * beyond[:, 1]
    return q


def time_law(law):
    """law as a function of (t, positions): a law of the positions alone (one parameter) is wrapped, a law of two
    parameters is taken to be law(t, positions) already."""
    try:
        count = len(inspect.signature(law).parameters)
    except (TypeError, ValueError):  # a callable without a signature (a builtin): a law of the positions
        count = 1
    if count >= 2:
        return law
    return lambda time, positions: law(positions)


def check(physics: Physics, system, noisy: bool) -> None:
    """Refuse, in one line, what this path does not cover."""
    names = ", ".join(
        t.name
        for t in physics.active_terms()
        if t.node_forces(physics) is not None or t.clamp_motion(physics) is not None
    )
    if noisy:
        raise ParameterError(
            f"the reduced engine adds the forces of {names} to noise-free runs only; set noise 0 or "
            "use the MuJoCo engine"
        )
    if system.inertial:
        raise ParameterError(
            f"the reduced engine adds the forces of {names} to the overdamped model only, and "
            f"mass_ratio = {system.mass_ratio:g} is outside the overdamped limit here; give a smaller "
            f"{option('mass_ratio')} or use the MuJoCo engine"
        )
    if system.pinned or system.head_free or system.hub_free:
        has = "pins its far end" if system.pinned else ("slides its head" if system.head_free else "turns its hub")
        raise ParameterError(
            f"the reduced engine adds the forces of {names} to the overdamped model of a chain "
            f"without pins, a sliding head or a turning hub, and scene {physics.scene} {has}; use the "
            "MuJoCo engine"
        )


def clamp_of(physics: Physics):
    """The prescribed motion of chain 1's clamp (elastoactive.terms.base.ClampMotion) of the active terms, or None;
    two terms moving it are refused."""
    motions = [(t.name, m) for t in physics.active_terms() if (m := t.clamp_motion(physics)) is not None]
    if len(motions) > 1:
        raise ParameterError(f"the terms {', '.join(name for name, _ in motions)} all move the clamp; keep one")
    return motions[0][1] if motions else None


def clamp_drag(physics: Physics, system, theta: np.ndarray, velocity) -> np.ndarray:
    """Forces (particles, 2) -Gamma_k(theta) u of the lab-frame drag on chain 1's particles when its clamp moves with
    velocity u (Gamma_k = gamma_L e_k e_k^T + gamma_T n_k n_k^T about particle k's pendulum); 0 on chain 2."""
    n = physics.n
    c, s = np.cos(theta[:n]), np.sin(theta[:n])
    ux, uy = velocity
    along = system.gamma_l * (c * ux + s * uy)
    across = system.gamma_t * (-s * ux + c * uy)
    forces = np.zeros((physics.n_angles, 2))
    forces[:n, 0] = -(along * c - across * s)
    forces[:n, 1] = -(along * s + across * c)
    return forces


def solve(
    physics: Physics,
    system,
    t: np.ndarray,
    theta0: np.ndarray,
    laws,
    *,
    rtol: float,
    atol: float,
    beta: float,
    loads,
    clamp=None,
    on_time=None,
    budget=None,
) -> tuple[np.ndarray, dict]:
    """Sampled angles (len(t), n_angles) and solver info, the node forces `laws` (callables) added, and the drag
    and clamp-spring terms of a moving clamp (`clamp`: elastoactive.terms.base.ClampMotion, or None). on_time(t) and
    budget(method, None), before the first step: the engine runner's (engines.runner); on_time is told the time at
    every evaluation of the Python path, after every call of the compiled loop. Ctrl-C on the compiled path raises
    reduced.dop853.Interrupted with the samples reached."""
    if laws and clamp is None and not system.n_head and all(isinstance(law, PeriodicForce) for law in laws):
        return _solve_compiled(system, t, theta0, laws, rtol=rtol, atol=atol, beta=beta, loads=loads,
                               on_time=on_time, budget=budget)  # fmt: skip
    # start-up time: scipy.integrate costs ~0.4 s to import; only runs with such a term need it
    from scipy.integrate import solve_ivp

    f = _python(physics, system, beta, loads, laws, clamp)
    if budget is not None:
        budget("DOP853", None)
    f = reporting(f, on_time)
    sol = solve_ivp(f, (0.0, float(t[-1])), theta0, method="DOP853", t_eval=t, rtol=rtol, atol=atol)
    if not sol.success:
        raise ParameterError(f"the reduced engine could not integrate the node forces: {sol.message}")
    return sol.y.T.copy(), {"method": "DOP853 (scipy, node forces)", "rtol": rtol, "atol": atol, "nfev": int(sol.nfev)}


def _solve_compiled(system, t, theta0, laws, *, rtol, atol, beta, loads, on_time, budget) -> tuple[np.ndarray, dict]:
    """solve's run of periodic point forces only: reduced.node_kernels.dop853, the whole run compiled."""
    from ..reduced import node_kernels  # start-up time: numba
    from ..reduced.dop853 import Interrupted, steps_per_call
    from ..reduced.dop853_loop import integrate, reporting_loop

    if budget is not None:
        budget("numba-DOP853", None)

    system = system.typed()
    args = (system, float(beta), system.force_factors(loads), node_kernels.force_table(laws))
    run = integrate(
        node_kernels.dop853, args, t, theta0, rtol, atol, reporting_loop(on_time),
        steps=steps_per_call(system, theta0.size), on_interrupt=Interrupted,
    )  # fmt: skip
    if run.status != 0:
        raise ParameterError(
            f"the reduced engine could not integrate the node forces: the step size fell below round-off at "
            f"t = {run.t:.6g}"
        )
    info = {"method": "numba-DOP853 (node forces)", "rtol": rtol, "atol": atol, "nfev": run.nfev}
    return run.y, {**info, "nsteps": run.naccept, "nreject": run.nreject}


def _python(physics: Physics, system, beta: float, loads, laws, clamp):
    """The right-hand side with any laws (Python per evaluation) and a moving clamp."""
    own = _math.rhs(system, beta=beta, factor=loads)
    laws = [time_law(law) for law in laws]

    moving = clamp is not None and clamp.translates
    n, spring = physics.n, physics.stiffness[0]

    def f(time, theta):
        total = np.zeros((physics.n_angles, 2))
        if laws:  # the particles' positions, for the laws (a moving clamp's point shifts chain 1)
            where = positions(physics, theta)
            if moving:
                where[:n] += clamp.displacement(time)
        if moving:
            total += clamp_drag(physics, system, theta, clamp.velocity(time))
        for law in laws:
            total += law(time, where)
        q = generalised(physics, theta, total)
        if clamp is not None:
            q[0] += spring * clamp.angle(time)
        return own(time, theta) + np.linalg.solve(_math.drag_matrix(system, theta), q)

    return f

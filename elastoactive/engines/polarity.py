"""The reduced model with self-aligning active units: a right-hand side on (theta, psi).

Each loaded particle i carries a unit of force sigma n_i, n_i = (cos psi_i, sin psi_i) (units C1 / l; absolute
polarity angles psi in the lab frame, elastoactive.terms.self_aligning). The overdamped chain is

    D(theta) theta' = f(theta) + sum_i J_i^T sigma n_i,        psi_i' = (1 / l_a) (J_i theta') . n_i_perp,

where D and f are the compiled kernels' drag matrix and the chain's own forces without the follower force (the
compiled right-hand side with every force factor 0 gives D^-1 f), J_i the Jacobian of particle i's position, so
J_i theta' is its velocity, and n_perp = (-sin psi, cos psi). The generalised force of the units is that of any
node force (elastoactive.engines.node_forces.generalised: Q_j = sum_{i >= j} F_i . (-sin theta_j, cos theta_j)).
A pinned chain (two-pinned, the ring) adds the pin's multipliers: the rates of the extra force are the top block
of the saddle point [[D, G^T], [G, 0]] (theta', lam) = (Q, 0), added to the compiled rates (which hold the
Baumgarte term). Other terms' node forces (a tip drive) are added to the units' forces.

Integrated by scipy's DOP853 at the engine's tolerances; Python runs once per evaluation (about 40 us at N = 7,
docs/terms.md). Covered: noise-free overdamped chains (one-pinned, rotating pin, coupled pair, two-pinned, ring);
a free head (the paraboloid), noise, the inertial model and a moving clamp are refused in one line naming MuJoCo.
"""

from __future__ import annotations

import numpy as np

from .. import reduced as _math
from ..core.errors import ParameterError
from ..core.params import Physics
from ..terms import polarity_term
from .node_forces import generalised, positions, time_law
from .runner import reporting


def check(physics: Physics, system, noisy: bool) -> None:
    """Refuse, in one line, what this path does not cover."""
    if noisy:
        raise ParameterError(
            "active = self-aligning: the reduced engine integrates noise-free runs only; set noise 0 "
            "or use the MuJoCo engine"
        )
    if system.inertial:
        raise ParameterError(
            "active = self-aligning: the reduced engine has the overdamped model only; give a mass "
            "ratio inside the overdamped limit or use the MuJoCo engine"
        )
    if system.head_free or system.extended:
        raise ParameterError(
            f"active = self-aligning: the reduced engine does not combine the units with scene "
            f"{physics.scene}'s {' and '.join(system.extensions)}; use the MuJoCo engine"
        )
    if any(getattr(term, "clamp_motion", lambda _: None)(physics) is not None for term in physics.active_terms()):
        raise ParameterError(
            "active = self-aligning: the reduced engine does not combine the units with a moving "
            "clamp; use the MuJoCo engine"
        )


def unit_indices(physics: Physics) -> np.ndarray:
    """The particles (columns of theta) carrying a unit: the loaded ones, chain 1's then chain 2's."""
    return np.flatnonzero(np.tile(physics.load_mask(), physics.n_chains))


def particle_velocities(physics: Physics, theta: np.ndarray, rates: np.ndarray) -> np.ndarray:
    """Velocities (particles, 2) J theta' of every particle: sum_{j <= i} theta_j' (-sin theta_j, cos theta_j), chain
    by chain (the pivots are fixed)."""
    n = physics.n
    steps = np.empty((physics.n_angles, 2))
    steps[:, 0] = -np.sin(theta) * rates
    steps[:, 1] = np.cos(theta) * rates
    return np.cumsum(steps.reshape(physics.n_chains, n, 2), axis=1).reshape(-1, 2)


def rhs(physics: Physics, system, *, beta: float, laws=()):
    """f(t, y) -> y' on y = (theta, psi): theta the n_angles absolute angles, psi one polarity per unit."""
    elastic = _math.rhs(system, beta=beta, factor=np.zeros(physics.n_angles))
    units = unit_indices(physics)
    sigma, inverse_la = float(physics.sigma), 1.0 / float(physics.alignment_length)
    na = physics.n_angles
    laws = [time_law(law) for law in laws]
    pinned = bool(system.pinned)

    def f(time, y):
        theta, psi = y[:na], y[na:]
        c, s = np.cos(psi), np.sin(psi)
        forces = np.zeros((na, 2))
        forces[units, 0] = sigma * c
        forces[units, 1] = sigma * s
        if laws:
            where = positions(physics, theta)
            for law in laws:
                forces += law(time, where)
        q = generalised(physics, theta, forces)
        D = _math.drag_matrix(system, theta)
        if pinned:
            G = _math.pin_jacobian(theta)
            saddle = np.block([[D, G.T], [G, np.zeros((2, 2))]])
            extra = np.linalg.solve(saddle, np.concatenate([q, np.zeros(2)]))[:na]
        else:
            extra = np.linalg.solve(D, q)
        rates = elastic(time, theta) + extra
        v = particle_velocities(physics, theta, rates)[units]
        out = np.empty_like(y)
        out[:na] = rates
        out[na:] = inverse_la * (-v[:, 0] * s + v[:, 1] * c)
        return out

    return f


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
    on_time=None,
    budget=None,
) -> tuple[np.ndarray, np.ndarray, dict]:
    """(sampled angles (len(t), n_angles), sampled polarities (len(t), units), solver info) from theta0, every
    polarity along the follower direction of theta0. on_time(t), at every evaluation, and budget(method, None), before
    the first step: the engine runner's (engines.runner)."""
    from scipy.integrate import solve_ivp  # start-up time: scipy.integrate costs ~0.4 s to import

    mask = np.zeros(physics.n_angles, dtype=bool)
    mask[unit_indices(physics)] = True
    y0 = np.concatenate([theta0, polarity_term(physics).initial_polarity(theta0, mask)])
    if budget is not None:
        budget("DOP853", None)
    f = reporting(rhs(physics, system, beta=beta, laws=laws), on_time)
    sol = solve_ivp(f, (0.0, float(t[-1])), y0, method="DOP853", t_eval=t, rtol=rtol, atol=atol)
    if not sol.success:
        raise ParameterError(f"the reduced engine could not integrate the self-aligning units: {sol.message}")
    y = sol.y.T
    na = physics.n_angles
    info = {"method": "DOP853 (scipy, self-aligning units)", "rtol": rtol, "atol": atol, "nfev": int(sol.nfev)}
    return y[:, :na].copy(), y[:, na:].copy(), info

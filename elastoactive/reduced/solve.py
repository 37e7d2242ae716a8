"""Solving the reduced model of a `ChainSystem`: right-hand side, Jacobian, ODE and SDE integration.

Integration and the choice of method
------------------------------------
The right-hand side and its analytic Jacobian are compiled with numba (kernels.py). The right-hand side
solves D(theta) theta' = f by the O(N) articulated-drag recursion (derived in equations.py) from
kernels.RECURSIVE_MIN_N = 2 particles per chain on, faster than dense Cholesky (O(N^3)) at every N: one
evaluation at N = 100 costs ~3 us instead of ~100 us, and 100 tau of Physics(n=100, sigma=0.05) take ~0.015 s
instead of ~0.4 s. The analytic Jacobian follows the same split: dense, O(N^3), below RECURSIVE_MIN_N; from
there on D^-1 is applied column by column by the recursion, O(N^2) (kernels.eval_jacobian_recursive). The
spectral radius of the linearised operator D^{-1} K is bounded independently of N
(D0^{-1} = B^{-1} B^{-T} with B the lower triangular matrix of ones, so |lambda| <~ 16 for unit springs and drag),
but the slow dynamics of a long chain are slower still: its slowest relaxation and, at the sigma ~ S / N^3 where
it beats, its beat frequency fall like N^-4 (248.9 / N^4 per tau at S = 100). An explicit method's steps are
bounded by the fast rate, so it takes ~ N^4 steps per beat; an implicit one takes steps of the beat's own scale.

The default (method=None) therefore looks at the eigenvalues of the Jacobian at theta0 (_overdamped_method):
- "numba-DOP853", scipy's DOP853 algorithm (same tableau, error estimator, step control, dense output; dop853.py,
  with the tableau copied into dop853_coefficients.py) compiled together with the RHS, which avoids the per-step
  Python overhead of scipy.integrate.solve_ivp: for N = 7, sigma = 0.8, duration 400, rtol 1e-9 it takes 0.042 s
  against 2.1 s for solve_ivp(DOP853) on rhs_reference (0.37 s for solve_ivp on the compiled RHS), with the same
  steps (results agree to 1e-11); 35-53x over the four scenes. Every short chain, every chain well above its
  onset and every short run takes it.
- "Radau" with the compiled analytic Jacobian when the fastest decay rate max(-Re lambda) alone is above
  STIFF_RADIUS (a pair with kappa >~ 1e3, near-singular anisotropic drag).
- "LSODA" (scipy's; its stiff branch is BDF with the analytic Jacobian) when the stiffness ratio (fastest decay
  over the slow dynamics, stiffness_ratio) is above IMPLICIT_RATIO and the run long enough for the explicit steps
  to add up (duration x fastest decay above IMPLICIT_WORK): the long chain near its onset. Measured at S = 100,
  per beat period: N = 80 0.1 s (numba-DOP853: ~100 s), N = 160 0.5 s, N = 320 0.9 s; LSODA beat BDF and Radau
  at every N (fewer steps than Radau, no failures where BDF had them at N = 320). The LU factorisations run on
  one BLAS thread (blas.py).
Any name of METHODS can be given explicitly ("numba-DOP853", "DOP853", "RK45", "Radau", "BDF", "LSODA", ...);
implicit ones get the analytic Jacobian. info["method"] says what ran, with the spectral radius, the stiffness
and the stiffness ratio for method=None.

With noise > 0 the follower forces carry multiplicative white noise and the ODE becomes an Ito SDE,
integrated by fixed-step Euler-Maruyama (solve_sde: step dt, drift at the step start) with per-step
force factors supplied by the caller (the engine, elastoactive.engines.reduced, passes the counter-
based force factors of elastoactive.controllers.noise shared with the MuJoCo engine; particles numbered chain 1
then chain 2). For the two-pinned chain each Euler-Maruyama step is followed by a minimum-norm projection
back onto g = 0 (the noise increments, ~ a sqrt(dt), would otherwise leave an O(a^2 dt) drift that the
Baumgarte term only partly removes).

The inertial model (system.mass_ratio > 0; equations.py) integrates the state (theta, omega), twice as long,
from rest (omega0 = 0; solve_inertial, whose angles solve_ode returns). Its right-hand side solves the mass
matrix by dense Cholesky (O(N^3); kernels.eval_rhs_inertial), its Jacobian takes the accelerations' part by
central differences (kernels.eval_jacobian_inertial). method=None takes numba-DOP853 unless the fastest
decay rate at the start (~ gamma / m for small masses) is above STIFF_RADIUS and STIFF_RATIO x the rates of
the modes that do not decay, then Radau. With noise the force factors are constant over each step dt, as
MuJoCo applies them, and each step is taken by RK4 substeps (h x spectral radius <= RK4_STEP): with
inertia the angles are smooth, so no Ito correction and no projection onto the pins arise. Which model a
scene's mass ratio needs is decided in regime.py (the overdamped limit), applied by the engine.

A free head, a harmonic trap and self-contact (ChainSystem.head_free, trap, contact_radius; equations.py,
contact.py): with any of them on, the right-hand side is kernels.eval_rhs_general (dense over all coordinates),
taken by rhs, numba-DOP853, Euler-Maruyama and Heun alike; `jacobian` (and so `stiffness`, method=None's check and
the implicit methods) is then a central-difference Jacobian of it (the analytic one knows none of these terms).
The positions are the angles, then (head_free) the head's position (x_h, y_h): n_angles + 2 numbers. solve_ode
and solve_sde return them whole, shape (len(t), n_angles + 2), and take the initial positions either whole (theta0
of n_angles + 2 numbers) or as the angles (n_angles numbers) plus the keyword head0 (default: the origin). The
inertial model has the same terms (kernels.eval_rhs_inertial_general; state (positions, rates), state_size numbers;
solve_inertial returns that whole state).
With every extended term off, everything runs exactly as before they existed.

Every function takes the record and calls ChainSystem.typed() on it, so the compiled kernels see one
set of field types and compile once.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..core.errors import ParameterError, SimulationDiverged
from . import SOLVE_NAMES, dop853, kernels
from .blas import one_blas_thread
from .settings import COMPILED_METHODS, DEFAULT_BETA, IMPLICIT_RATIO, IMPLICIT_WORK, SCIPY_METHODS, STIFF_RADIUS
from .system import ChainSystem

__all__ = list(SOLVE_NAMES) + ["DEFAULT_BETA", "IMPLICIT_RATIO", "STIFF_RADIUS"]

IMPLICIT_METHODS = ("Radau", "BDF", "LSODA")
"""The scipy methods that are given the analytic Jacobian."""

_SDE_CHUNK = 20000
"""Euler-Maruyama steps per call of the compiled loop (bounds the memory of the force factors)."""


# ----------------------------------------------------------------------------------------------
# right-hand side, Jacobian, drag matrix, linear stability
# ----------------------------------------------------------------------------------------------
def rhs(system: ChainSystem, *, beta: float, factor=None):
    """Compiled right-hand side f(t, theta) -> dtheta/dt of the model; of the inertial model
    (system.mass_ratio > 0) f(t, y) -> dy/dt with the state y = (theta, omega); with a free head the state is
    (theta, x_h, y_h) (system.state_size numbers).

    factor: optional per-particle force factor (1 + eta_i), default ones. beta: Baumgarte rate (pinned).
    """
    system = system.typed()
    beta = float(beta)
    fac = system.force_factors(factor)
    if system.inertial:
        L, D, X, lam = kernels.state_workspace(system)

        def f_inertial(t, y):
            state = np.ascontiguousarray(y, dtype=float)
            out = np.empty(state.size)
            kernels.eval_state(state, fac, system, beta, out, L, D, X, lam)
            return out

        return f_inertial
    L, D, X, lam = kernels.workspace(system)

    def f(t, theta):
        th = np.ascontiguousarray(theta, dtype=float)
        out = np.empty(th.size)
        kernels.eval_rhs(th, fac, system, beta, out, L, D, X, lam)
        return out

    return f


def jacobian(system: ChainSystem, *, beta: float):
    """Compiled analytic Jacobian J(t, theta) = d(dtheta/dt)/d(theta) of the deterministic model. Of the
    inertial model (system.mass_ratio > 0): J(t, y) = dy'/dy for y = (theta, omega) (or theta alone, at rest),
    with the accelerations' part by central differences (kernels.eval_jacobian_inertial).

    Below kernels.RECURSIVE_MIN_N particles O(N^3) per call (dense Cholesky of D, then D^-1 applied to an N x N
    matrix); from there on O(N^2) (D^-1 applied column by column by the articulated-drag recursion, equal to the
    dense one to round-off), so that the implicit methods that long chains need (solve_ode) stay cheap.

    With a free head, a trap or self-contact (system.extended), the analytic kernel does not apply: the Jacobian
    over the whole state is taken by central differences of the compiled right-hand side (relative step 1e-7)."""
    system = system.typed()
    beta = float(beta)
    if system.extended:  # overdamped or inertial: central differences of the whole state's right-hand side
        return _numeric_jacobian(system, beta, None)
    if system.inertial:  # d(theta, omega)'/d(theta, omega), accelerations by central differences
        L, D, X, lam = kernels.make_inertial_workspace(system.n_chains, system.n)

        def jac_inertial(t, y):
            state = _state(system, y)
            J = np.empty((state.size, state.size))
            kernels.eval_jacobian_inertial(state, system, beta, J, L, D, X, lam)
            return J

        return jac_inertial
    if kernels.uses_recursive(system.n):  # D^-1 by the O(N) recursion, column by column: O(N^2)
        _, U, X, lam = kernels.workspace(system, dense=False)

        def jac(t, theta):
            th = np.ascontiguousarray(theta, dtype=float)
            J = np.empty((th.size, th.size))
            kernels.eval_jacobian_recursive(th, system, beta, J, U, X, lam)
            return J

        return jac
    L, D, X, lam = kernels.workspace(system, dense=True)  # the Jacobian reuses the Cholesky factors

    def jac(t, theta):
        th = np.ascontiguousarray(theta, dtype=float)
        J = np.empty((th.size, th.size))
        kernels.eval_jacobian(th, system, beta, J, L, D, X, lam)
        return J

    return jac


def _block_diagonal(system: ChainSystem, theta: np.ndarray, fill) -> np.ndarray:
    """The system's matrix with one block per chain, fill(theta, offset, n, block) writing each block."""
    n = system.n
    out = np.zeros((system.n_angles, system.n_angles))
    block = np.zeros((n, n))
    for ch in range(system.n_chains):
        fill(theta, ch * n, n, block)
        out[ch * n : (ch + 1) * n, ch * n : (ch + 1) * n] = block
    return out


def drag_matrix(system: ChainSystem, theta) -> np.ndarray:
    """D(theta) of the whole system (block diagonal for a pair), from the compiled kernel. With a free head:
    over the whole state (the angles, then the head; theta of n_angles or state_size numbers), from
    kernels.general_drag, including the head's drag."""
    system = system.typed()
    if system.n_head:  # a free head or a star's hub: over the whole state
        y = _state(system, theta)
        L, C, _, _ = kernels.make_general_workspace(system.n_chains, system.n, y.size)
        kernels._general_geometry(y, system, C)
        kernels.general_drag(system, C, L[1])
        return L[1].copy()
    theta = np.ascontiguousarray(theta, dtype=float)
    return _block_diagonal(
        system, theta, lambda th, off, n, D: kernels.drag_block(th, off, n, system.gamma_l, system.gamma_t, D)
    )


def mass_matrix(system: ChainSystem, theta) -> np.ndarray:
    """M(theta) of the inertial model (block diagonal for a pair): M_jk = m sum_{i >= max(j,k)} cos(th_j - th_k)
    + I delta_jk with m = system.mass_ratio and I = m system.inertia_factor (zero for the overdamped model). With a
    free head: over the angles then the head (theta: the positions, or the angles with the head at the origin)."""
    system = system.typed()
    if system.n_head:  # over the angles and the head or hub (kernels.general_mass: the head's bead, the hub included)
        y = np.ascontiguousarray(theta, dtype=float).reshape(-1)
        nq = system.n_angles + system.n_head
        y = np.concatenate([y[: system.n_angles], np.zeros(system.n_head)]) if y.size == system.n_angles else y[:nq]
        L, C, _, _ = kernels.make_general_workspace(system.n_chains, system.n, y.size)
        kernels._general_geometry(y, system, C)
        kernels.general_mass(system, C, L[1])
        return L[1].copy()
    theta = np.ascontiguousarray(theta, dtype=float)[: system.n_angles]
    return _block_diagonal(
        system, theta, lambda th, off, n, M: kernels.mass_block(th, off, n, system.mass_ratio, system.inertia_factor, M)
    )


def _state(system: ChainSystem, y) -> np.ndarray:
    """The integrated state at y: the angles (overdamped); (theta, omega) for the inertial model, where a
    state of n_angles numbers is taken as angles at rest; with a free head, the angles then the head (then,
    inertial, their rates), where n_angles numbers are the angles with the head at the origin."""
    y = np.ascontiguousarray(y, dtype=float).reshape(-1)
    if system.n_head and y.size == system.n_angles:  # the head at the origin, a star's hub at phi = 0
        y = np.concatenate([y, np.zeros(system.n_head)])
    nq = system.n_angles + system.n_head
    if system.mass_ratio > 0 and y.size == nq:
        return np.concatenate([y, np.zeros(nq)])
    return y


def _loads(system: ChainSystem, loads) -> np.ndarray | None:
    """The per-particle load factors (n_angles entries) of a run, or None when every particle is loaded (loads
    None or all ones: the unchanged, bit-identical path with the analytic Jacobian)."""
    if loads is None:
        return None
    fac = system.force_factors(loads)
    return None if np.all(fac == 1.0) else fac


def _numeric_jacobian(system: ChainSystem, beta: float, loads: np.ndarray):
    """J(t, y) of the model under constant force factors `loads` by central differences of the compiled
    right-hand side (the analytic kernels assume every particle loaded)."""
    f = rhs(system, beta=beta, factor=loads)

    def jac(t, y):
        y = _state(system, y)
        J = np.empty((y.size, y.size))
        for k in range(y.size):
            h = 1e-7 * max(1.0, abs(y[k]))
            yp, ym = y.copy(), y.copy()
            yp[k] += h
            ym[k] -= h
            J[:, k] = (f(t, yp) - f(t, ym)) / (2.0 * h)
        return J

    return jac


def _eigenvalues(system: ChainSystem, theta, beta: float, loads: np.ndarray | None = None) -> np.ndarray:
    jac = jacobian(system, beta=beta) if loads is None else _numeric_jacobian(system, beta, loads)
    return np.linalg.eigvals(jac(0.0, _state(system, theta)))


def spectral_radius(system: ChainSystem, theta, *, beta: float) -> float:
    """Largest |eigenvalue| of the Jacobian at theta (inertial model: at the state theta, or at rest)."""
    return float(np.max(np.abs(_eigenvalues(system, theta, beta))))


def stiffness(system: ChainSystem, theta, *, beta: float) -> float:
    """Fastest decay rate max(-Re lambda) of the Jacobian at theta: the stiffness indicator used by
    method=None. Fast *growing* modes (high sigma or N) are not stiffness: an implicit method does
    not help with them, and Radau was 9-25x slower than the explicit default there."""
    eig = _eigenvalues(system, theta, beta)
    return float(max(0.0, np.max(-eig.real)))


def constraint_violation(system: ChainSystem, theta) -> float:
    """Largest constraint residual max(|g_1|, |g_2|) over the states theta (one state, or one per row);
    0 for a system without pins. States with the free ring's head after the angles are read by their angles."""
    if not system.pinned:
        return 0.0
    theta = np.asarray(theta, dtype=float)
    if theta.shape[-1] > system.n:  # the free ring: the head's two coordinates after the angles
        theta = theta[..., : system.n]
    c = np.cos(theta).sum(axis=-1) - system.n * (1.0 - system.delta)
    s = np.sin(theta).sum(axis=-1)
    return float(np.max(np.maximum(np.abs(c), np.abs(s))))


# ----------------------------------------------------------------------------------------------
# integration
# ----------------------------------------------------------------------------------------------
def _samples_and_state(system: ChainSystem, t, theta0, head0=None) -> tuple[np.ndarray, np.ndarray]:
    """The sample times, checked, and the initial positions: the angles theta0 (n_angles numbers); with a free
    head, the angles then the head: theta0 of n_angles + 2 numbers, or n_angles angles plus head0 (default the
    origin)."""
    t = np.ascontiguousarray(t, dtype=float)
    if t.ndim != 1 or t.size == 0 or t[0] != 0.0 or np.any(np.diff(t) < 0):
        raise ParameterError("t must be a non-empty, non-decreasing 1-D array of sample times starting at 0")
    theta0 = np.array(theta0, dtype=float).reshape(-1)
    if system.head_free:
        if theta0.size == system.n_angles + system.n_head:
            if head0 is not None:
                raise ParameterError("give the head's position either at the end of theta0 or as head0, not both")
            return t, theta0
        if theta0.size == system.n_angles:
            head = np.zeros(2) if head0 is None else np.array(head0, dtype=float).reshape(-1)
            if head.size != 2 or not np.all(np.isfinite(head)):
                raise ParameterError(f"head0 must be a finite point (x_h, y_h), got {head0!r}")
            return t, np.concatenate([theta0, head])
        raise ParameterError(
            f"theta0 must have {system.n_angles} angles (plus head0), or {system.n_angles + 2} "
            f"numbers (the angles, then the head), got {theta0.size}"
        )
    if system.hub_free:  # a star's turning hub: its angle phi after the arms' angles (head0: (phi,), default 0)
        if theta0.size == system.n_angles + 1 and head0 is None:
            return t, theta0
        phi = np.zeros(1) if head0 is None else np.array(head0, dtype=float).reshape(-1)
        if theta0.size != system.n_angles or phi.size != 1 or not np.all(np.isfinite(phi)):
            raise ParameterError(
                f"theta0 must have {system.n_angles} angles (plus head0 = (phi,), the hub's angle), "
                f"or {system.n_angles + 1} numbers (the angles, then phi), got {theta0.size} and "
                f"head0 = {head0!r}"
            )
        return t, np.concatenate([theta0, phi])
    if head0 is not None:
        raise ParameterError("head0: only a system with a free head (head_free) has a head position")
    if theta0.size != system.n_angles:
        raise ParameterError(f"theta0 must have {system.n_angles} angles, got {theta0.size}")
    return t, theta0


def solve_ode(
    system: ChainSystem,
    t,
    theta0,
    *,
    rtol: float,
    atol: float,
    method: str | None = None,
    beta: float,
    loads=None,
    head0=None,
    on_time=None,
    budget=None,
) -> tuple[np.ndarray, dict]:
    """Integrate the deterministic model from theta0 at t = 0; returns (theta at the times t, info).
    The inertial model (system.mass_ratio > 0) starts at rest: solve_inertial, of which the angles are returned.

    With a free head (system.head_free) the positions are (angles, x_h, y_h): theta0 is either all of them
    (n_angles + 2 numbers) or the angles with the head at head0 (default the origin), and the result has shape
    (len(t), n_angles + 2), the head's position in its last two columns (also for the inertial model).

    method: None (automatic: "numba-DOP853", or "Radau" when the linearisation at theta0 is stiff, see
    the module docstring), "numba-DOP853", or any name in SCIPY_METHODS. info holds rtol, atol, method,
    the solver's counts (nfev, njev, nsteps/nlu, status) and, for method=None, spectral_radius and
    stiffness at theta0. Raises SimulationDiverged (one line: what to change) when the solver gives up.

    loads: optional per-particle load factors (n_angles entries: 1 where the particle carries the follower
    force, 0 where it does not; particles of chain 1, then chain 2), the constant force factors of the run.
    None or all ones: every particle loaded, bit for bit the unmasked run. Otherwise the implicit methods
    (and method=None's stiffness check) use a central-difference Jacobian of the masked right-hand side.

    on_time: optional callable given the time reached, for a progress bar: at every right-hand side evaluation of
    scipy's methods, after every call of numba-DOP853's compiled loop (a bounded number of steps); it changes nothing
    that is computed, and what it raises stops the run.
    budget: optional callable budget(method, eig) given the method that runs and the eigenvalues of the Jacobian at
    the start (None where method was given: they are not computed), before the first step: it may refuse the run
    (raise) from the fewest steps these allow.
    """
    system = system.typed()
    t, theta0 = _samples_and_state(system, t, theta0, head0)
    if method is not None and method not in COMPILED_METHODS + SCIPY_METHODS:
        raise ParameterError(f"method must be None, one of {COMPILED_METHODS + SCIPY_METHODS}, got {method!r}")
    if system.inertial:
        y, info = solve_inertial(
            system,
            t,
            theta0,
            rtol=rtol,
            atol=atol,
            method=method,
            beta=beta,
            loads=loads,
            on_time=on_time,
            budget=budget,
        )
        return y[:, : theta0.size].copy(), info
    loads = _loads(system, loads)
    info = {"rtol": rtol, "atol": atol}
    eig = None
    if method is None:
        with one_blas_thread():  # a dense eigenproblem: O(N^3), on a busy machine far slower threaded
            eig = _eigenvalues(system, theta0, beta, loads)
        info["spectral_radius"] = float(np.max(np.abs(eig)))
        info["stiffness"] = float(max(0.0, np.max(-eig.real)))
        info["stiffness_ratio"] = stiffness_ratio(eig)
        method = _overdamped_method(info["stiffness"], info["stiffness_ratio"], float(t[-1]))
    info["method"] = method
    if budget is not None:
        budget(method, eig)
    return _integrate(system, t, theta0, method, rtol, atol, beta, info, loads, on_time)


def stiffness_ratio(eig: np.ndarray) -> float:
    """Fastest decay rate max(-Re lambda) over the rate of the slow dynamics, from the eigenvalues of the Jacobian
    at the start: the slow rate is the largest |lambda| of the modes that do not decay (growing or neutral: what
    the run is about, and what any method must resolve), or, when every mode decays, |lambda| of the least stable
    one. Exact zeros (a free pin's rigid rotation) are left out. inf when nothing but zeros is left."""
    eig = np.asarray(eig, dtype=complex)
    size = np.abs(eig)
    decay = float(max(0.0, np.max(-eig.real))) if eig.size else 0.0
    keep = size > ZERO_MODE * max(1.0, float(np.max(size, initial=0.0)))
    eig, size = eig[keep], size[keep]
    if eig.size == 0:
        return 0.0 if decay == 0.0 else float("inf")
    slow_modes = eig.real >= -1e-9 * size
    slow = float(np.max(size[slow_modes])) if np.any(slow_modes) else float(size[np.argmax(eig.real)])
    return decay / slow


ZERO_MODE = 1e-9
"""Eigenvalues with |lambda| below ZERO_MODE x max(1, spectral radius) are zero modes (stiffness_ratio): exact for
the analytic Jacobian, ~1e-10 for the central-difference one of a free head's rotation about the dish."""


def _overdamped_method(stiffness: float, ratio: float, duration: float) -> str:
    """method=None for the overdamped model: "Radau" when the fastest decay rate alone is stiff (above
    STIFF_RADIUS: a stiff pair coupling, near-singular drag); "LSODA" (implicit BDF with the analytic Jacobian
    once stiff) when the fastest decay is more than IMPLICIT_RATIO times the slow dynamics (a long chain at the
    small sigma ~ S / N^3 where it beats: the ratio grows like N^4, and an explicit method's steps with it) and
    the run is long enough for the explicit steps to add up (duration x stiffness above IMPLICIT_WORK); else
    "numba-DOP853" (short chains, any chain well above its onset, short runs)."""
    if stiffness > STIFF_RADIUS:
        return "Radau"
    if ratio > IMPLICIT_RATIO and duration * stiffness > IMPLICIT_WORK:
        return "LSODA"
    return "numba-DOP853"


def _integrate(
    system: ChainSystem,
    t: np.ndarray,
    y0: np.ndarray,
    method: str,
    rtol: float,
    atol: float,
    beta: float,
    info: dict,
    loads: np.ndarray | None = None,
    on_time=None,
) -> tuple[np.ndarray, dict]:
    """The states at the times t from y0 at t = 0 by `method` (the compiled DOP853 or scipy's solve_ivp on the
    compiled right-hand side, implicit methods with the Jacobian), the solver's counts added to info.
    loads: per-particle load factors (_loads; None: every particle loaded)."""
    if t[-1] == 0.0:
        info.update(nfev=0, njev=0, nsteps=0, status=0)
        return y0[None, :].copy(), info
    if method == "numba-DOP853":
        out, status, nfev, nacc, nrej = dop853.integrate(
            system, t, y0, rtol=rtol, atol=atol, beta=beta, loads=loads, on_time=on_time
        )
        if status != 0:
            raise SimulationDiverged(_gave_up(system, method, "its step size fell below round-off"))
        info.update(nfev=nfev, njev=0, nsteps=nacc, nreject=nrej, status=0)
        return out, info
    # start-up time: scipy.integrate costs ~0.4 s to import; the compiled default does not need it
    from scipy.integrate import solve_ivp

    kw = {}
    if method in IMPLICIT_METHODS:
        kw["jac"] = jacobian(system, beta=beta) if loads is None else _numeric_jacobian(system, beta, loads)
    fun = rhs(system, beta=beta, factor=loads)
    if on_time is not None:
        compiled = fun

        def fun(time, y):  # the same values, the time reported first
            on_time(time)
            return compiled(time, y)

    with one_blas_thread():  # the implicit methods' LU factorisations (blas.py)
        sol = solve_ivp(
            fun,
            (0.0, float(t[-1])),
            y0,
            method=method,
            t_eval=t,
            rtol=rtol,
            atol=atol,
            **kw,
        )
    if not sol.success:
        raise SimulationDiverged(_gave_up(system, method, sol.message.rstrip(".").lower()))
    info.update(nfev=int(sol.nfev), njev=int(sol.njev), nlu=int(sol.nlu), status=int(sol.status))
    return sol.y.T.copy(), info


def _gave_up(system: ChainSystem, method: str, why: str) -> str:
    """One line for a solver that gave up: which, why, at which settings, and what to change."""
    terms = [f"N = {system.n}", f"sigma = {system.sigma:g}"]
    if system.contact_radius > 0:
        terms.append("self-contact")
    if system.inertial:
        terms.append(f"inertial model, mass_ratio = {system.mass_ratio:g}")
    others = [m for m in ("LSODA", "Radau", "numba-DOP853") if m != method]
    return (
        f"the reduced engine's solver {method} gave up ({why}) at {', '.join(terms)}: the motion is too stiff or "
        f"singular for it; try --method {others[0]} (or {others[1]}), a smaller --sigma, or the MuJoCo engine"
    )


STIFF_RATIO = 10.0
"""The inertial model is stiff when its fastest decay rate is above STIFF_RADIUS and STIFF_RATIO x the fastest
rate of the modes that do not decay (see _inertial_method)."""


def _inertial_method(eig: np.ndarray) -> str:
    """method=None for the inertial model: Radau when the fastest decay rate is above STIFF_RADIUS and above
    STIFF_RATIO x every rate of the modes that do not decay (those an explicit method must resolve anyway:
    growing modes, oscillations of a neutral mode), else numba-DOP853. Small masses (the drag's inertial
    relaxation ~ gamma / m against the overdamped rates) are stiff; a mass that is outside the overdamped
    limit only because the growing modes are fast (high sigma or N) is not: there gamma / m is below 10 x
    the fastest overdamped rate, and Radau with its finite-difference Jacobian would be slower."""
    decay = float(max(0.0, np.max(-eig.real)))
    other = eig[eig.real >= -1e-9 * np.abs(eig)]
    resolved = float(np.max(np.abs(other))) if other.size else 0.0
    return "Radau" if decay > STIFF_RADIUS and decay > STIFF_RATIO * resolved else "numba-DOP853"


def solve_inertial(
    system: ChainSystem,
    t,
    theta0,
    *,
    rtol: float,
    atol: float,
    method: str | None = None,
    beta: float,
    omega0=None,
    loads=None,
    head0=None,
    on_time=None,
    budget=None,
) -> tuple[np.ndarray, dict]:
    """Integrate the inertial model (system.mass_ratio > 0) from (theta0, omega0) at t = 0 (omega0 default 0:
    at rest, as MuJoCo starts); returns (the states (theta, omega) at the times t, shape (len(t), 2 n_angles),
    info). method: None (numba-DOP853, or Radau when stiff, see _inertial_method), "numba-DOP853" or a name
    in SCIPY_METHODS (implicit ones get the finite-difference Jacobian, kernels.eval_jacobian_inertial).
    loads: per-particle load factors as in solve_ode. With a free head the positions are (angles, x_h, y_h) (theta0
    whole or with head0, as in solve_ode), omega0 their rates, and the states (positions, rates), 2 (n_angles + 2)
    numbers. on_time, budget: as in solve_ode."""
    system = system.typed()
    if not system.inertial:
        raise ParameterError("solve_inertial integrates the inertial model: system.mass_ratio must be > 0")
    t, theta0 = _samples_and_state(system, t, theta0, head0)
    if method is not None and method not in COMPILED_METHODS + SCIPY_METHODS:
        raise ParameterError(f"method must be None, one of {COMPILED_METHODS + SCIPY_METHODS}, got {method!r}")
    omega0 = np.zeros(theta0.size) if omega0 is None else np.array(omega0, dtype=float).reshape(-1)
    if omega0.size != theta0.size:
        raise ParameterError(f"omega0 must have {theta0.size} rates, got {omega0.size}")
    y0 = np.concatenate([theta0, omega0])
    loads = _loads(system, loads)
    info = {"rtol": rtol, "atol": atol, "model": "inertial", "mass_ratio": system.mass_ratio}
    eig = None
    if method is None:
        with one_blas_thread():  # a dense eigenproblem: O(N^3), on a busy machine far slower threaded
            eig = _eigenvalues(system, y0, beta, loads)
        info["spectral_radius"] = float(np.max(np.abs(eig)))
        info["stiffness"] = float(max(0.0, np.max(-eig.real)))
        method = _inertial_method(eig)
    info["method"] = method
    if budget is not None:
        budget(method, eig)
    return _integrate(system, t, y0, method, rtol, atol, beta, info, loads, on_time)


RK4_STEP = 0.25
"""Largest h x spectral radius of the RK4 substeps of the inertial model with noise (solve_sde)."""


SDE_SCHEMES = ("euler", "heun")
"""solve_sde's schemes: Euler-Maruyama (Ito; also the coloured noise's random ODE) and stochastic Heun
(Stratonovich)."""


def solve_sde(
    system: ChainSystem,
    t,
    theta0,
    *,
    dt: float,
    factors: Callable[[np.ndarray], np.ndarray],
    beta: float,
    scheme: str = "euler",
    head0=None,
    on_time=None,
    budget=None,
) -> tuple[np.ndarray, dict]:
    """Euler-Maruyama (scheme "euler") or stochastic Heun ("heun") from theta0 at t = 0 with step dt; returns
    (theta at the times t, info).

    The sample times must be multiples of dt. factors(steps) gives the force factors (1 + eta) of the
    step indices `steps` (an int64 array), shape (len(steps), n_angles): step k uses factors(...)[k]
    for its drift at the step start (Heun: for its predictor and its corrector, so that white noise is read
    in the Stratonovich sense). Pinned systems are projected back onto the pins after each step. The
    inertial model ignores the scheme (the noise enters its accelerations: no Ito-Stratonovich difference).
    With a free head: theta0 and head0, and the returned states, as in solve_ode (the state ends with the head).
    on_time(time reached) after every _SDE_CHUNK steps, for a progress bar (what it raises stops the run);
    budget(steps, substeps) before the first step, with the run's steps and the inertial model's RK4 substeps per step
    (1 otherwise): it may refuse the run (raise).
    """
    if scheme not in SDE_SCHEMES:
        raise ParameterError(f"scheme must be one of {SDE_SCHEMES}, got {scheme!r}")
    system = system.typed()
    t, theta0 = _samples_and_state(system, t, theta0, head0)
    beta = float(beta)
    dt = float(dt)
    sidx = np.rint(t / dt).astype(np.int64)
    total = int(sidx[-1])
    out = np.empty((t.size, theta0.size))
    if system.inertial:
        return _solve_sde_inertial(system, t, theta0, dt, factors, beta, sidx, total, out, on_time, budget)
    if budget is not None:
        budget(total, 1)
    y = theta0.copy()
    jptr = 0
    step = kernels.heun if scheme == "heun" else kernels.euler_maruyama
    for k0, facs in _factor_chunks(system, total, factors):
        jptr = step(y, k0, facs, dt, system, beta, sidx, out, jptr)
        if on_time is not None:
            on_time((k0 + facs.shape[0]) * dt)
    while jptr < t.size:  # samples at the final step
        out[jptr] = y
        jptr += 1
    if scheme == "heun":
        info = {"method": "stochastic Heun", "dt": dt, "nsteps": total, "nfev": 2 * total}
    else:
        info = {"method": "Euler-Maruyama", "dt": dt, "nsteps": total, "nfev": total}
    return out, info


def _factor_chunks(system: ChainSystem, total: int, factors, chunk: int = _SDE_CHUNK):
    """(first step, force factors of steps first .. first + chunk - 1) up to `total` steps, each
    checked for shape (len(steps), n_angles)."""
    for k0 in range(0, total, chunk):
        steps = np.arange(k0, min(total, k0 + chunk))
        facs = np.ascontiguousarray(factors(steps), dtype=float)
        if facs.shape != (steps.size, system.n_angles):
            raise ParameterError(
                f"factors(steps) must have shape (len(steps), n_angles) = {(steps.size, system.n_angles)}, "
                f"got {facs.shape}"
            )
        yield k0, facs


def _solve_sde_inertial(system, t, theta0, dt, factors, beta, sidx, total, out, on_time=None, budget=None):
    """The inertial model under the step-wise constant noise forces: each step dt (its force factors fixed,
    as in MuJoCo's step) by nsub RK4 substeps, h x (spectral radius at theta0, at rest) <= RK4_STEP. With
    inertia the angles are smooth (the noise enters the accelerations), so there is no Ito correction and
    no projection onto the pins (the Baumgarte term holds them)."""
    radius = spectral_radius(system, theta0, beta=beta)
    nsub = max(1, int(np.ceil(dt * radius / RK4_STEP)))
    if budget is not None:
        budget(total, nsub)
    y = np.concatenate([theta0, np.zeros(theta0.size)])
    jptr = 0
    for k0, facs in _factor_chunks(system, total, factors, max(1, _SDE_CHUNK // nsub)):  # ~_SDE_CHUNK substeps a call
        jptr = kernels.rk4_piecewise(y, k0, facs, dt, nsub, system, beta, sidx, out, jptr)
        if on_time is not None:
            on_time((k0 + facs.shape[0]) * dt)
    while jptr < t.size:
        out[jptr] = y[: theta0.size]
        jptr += 1
    info = {
        "method": "RK4 (noise constant over each step)",
        "dt": dt,
        "substeps": nsub,
        "nsteps": total * nsub,
        "nfev": 4 * total * nsub,
        "model": "inertial",
        "mass_ratio": system.mass_ratio,
    }
    return out, info

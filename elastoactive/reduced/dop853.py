"""DOP853 compiled together with the reduced model's right-hand side.

The algorithm is scipy's solve_ivp(method="DOP853") (E. Hairer and G. Wanner's DOP853: explicit Runge-Kutta of order
8 with 5th- and 3rd-order error estimators, the same error norm, initial step, step-size control and 7th-order dense
output): reduced.dop853_loop's loop, its weighted sums taken by sum_columns, compiled in one driver (_dop853) around the
compiled right-hand side kernels.eval_state, so a step costs no Python call. For the overdamped model (mass_ratio = 0)
that is kernels.eval_rhs, the dense Cholesky path for short chains and the O(N) articulated-drag recursion from
kernels.RECURSIVE_MIN_N particles on (the workspace, kernels.state_arrays, decides), kernels.eval_rhs_general with a
free head, a trap or self-contact (the state then ends with the head's position); for the inertial model
(mass_ratio > 0) kernels.eval_rhs_inertial, whose state (angles, then rates) is twice as long. Taking the same steps as
scipy, it agrees with solve_ivp(DOP853) on the same right-hand side to round-off.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .dop853_loop import dop853_sums, reporting_loop, sum_columns
from .dop853_loop import integrate as integrate_driver
from .kernels import eval_state, state_arrays, uses_recursive
from .system import ChainSystem

__all__ = ["Interrupted", "integrate"]


def integrate(
    system: ChainSystem,
    ts: np.ndarray,
    y0: np.ndarray,
    *,
    rtol: float,
    atol: float,
    beta: float,
    loads=None,
    on_time=None,
):
    """Integrate the deterministic model (force factors 1) from y0 at t = 0 and sample it at ts (y0: the angles
    of the overdamped model, then the head's position with a free head; or angles then rates of the inertial
    one, system.mass_ratio > 0).

    loads: optional per-particle load factors (n_angles entries, 1: the particle carries the follower force,
    0: it does not), the constant force factors of the run; default ones (every particle loaded, bit for bit
    as before: the kernels multiply sigma by the factor, and x 1.0 is exact).

    system: a typed ChainSystem (ChainSystem.typed()); ts: increasing sample times with ts[0] = 0;
    beta: Baumgarte rate (pinned systems). Returns (y, status, nfev, naccept, nreject) with y of shape
    (len(ts), len(y0)); status 0 on success, -1 when the step size fell below the round-off limit.

    The compiled loop runs in calls of a bounded number of steps (STEP_BUDGET) and resumes exactly where it
    stopped (the same steps, bit for bit, as one call), so that Ctrl-C stops a long run within ~0.1 s: it raises
    Interrupted carrying the samples computed so far. on_time(t), when given, is told the time reached after every
    call (a progress bar); what else it raises propagates as it is.
    """
    y0 = np.ascontiguousarray(y0, dtype=float)
    fac = np.ones(y0.size)  # the inertial kernel reads the first n_angles entries
    if loads is not None:
        fac[: system.n_angles] = system.force_factors(loads)
    run = integrate_driver(
        _dop853,
        (system, float(beta), fac),
        ts,
        y0,
        rtol,
        atol,
        reporting_loop(on_time),
        steps=steps_per_call(system, y0.size),
        on_interrupt=Interrupted,
    )
    return run.y, run.status, run.nfev, run.naccept, run.nreject


STEP_BUDGET = 100_000
"""Steps per call of the compiled loop times the cost of one evaluation (the state's size on the O(N) recursive
path, its square on the dense ones): a few ms to a few tens of ms per call, so Ctrl-C is seen within ~0.1 s while
the calls cost nothing measurable (N = 7: ~2000 steps a call)."""


def steps_per_call(system: ChainSystem, size: int) -> int:
    """STEP_BUDGET over the cost of one evaluation of a state of `size` numbers: size on the O(N) recursive path,
    size squared on the dense ones."""
    recursive = not system.inertial and not system.extended and uses_recursive(system.n)
    return STEP_BUDGET // (size if recursive else size**2)


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during integrate; `samples` holds the states of the sample times reached (ts[:len(samples)])."""

    def __init__(self, samples: np.ndarray):
        super().__init__(f"interrupted after {len(samples)} samples")
        self.samples = samples


@njit(cache=True, inline="always")
def _rate(t, y, out, args):
    """kernels.eval_state in dop853_loop's form: args = (fac, system, beta, L, D, X, lam)."""
    fac, system, beta, L, D, X, lam = args
    eval_state(y, fac, system, beta, out, L, D, X, lam)


@njit(cache=True)
def _dop853(y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps, args):
    """dop853_loop's driver around kernels.eval_state, its sums by sum_columns: args = (system, beta, fac), fac the
    constant per-particle force factors (the load factors, ones when every particle is loaded). The workspace is
    allocated at each call (its contents are not carried from one evaluation to the next)."""
    system, beta, fac = args
    L, D, X, lam = state_arrays(system, y.size)
    rate_args = (fac, system, beta, L, D, X, lam)
    sums = sum_columns  # stages and dense output alike
    return dop853_sums(
        _rate, rate_args, sums, sums, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps
    )

"""DOP853 compiled together with the reduced model's right-hand side.

The algorithm is scipy's solve_ivp(method="DOP853") (E. Hairer and G. Wanner's DOP853: explicit
Runge-Kutta of order 8 with 5th- and 3rd-order error estimators, the same error norm, initial step,
step-size control and 7th-order dense output), written as one numba function that calls the
compiled right-hand side (kernels.eval_state) directly, so a step costs no Python call. For the
overdamped model (mass_ratio = 0) that is kernels.eval_rhs, the dense Cholesky path for short chains
and the O(N) articulated-drag recursion from kernels.RECURSIVE_MIN_N particles on (the workspace
allocated here decides), kernels.eval_rhs_general with a free head, a trap or self-contact (the state
then ends with the head's position); for the inertial model (mass_ratio > 0) kernels.eval_rhs_inertial, whose
state (angles, then rates) is twice as long. The
coefficients come from dop853_coefficients.py (a copy of scipy's). Taking the same steps as scipy,
it agrees with solve_ivp(DOP853) on the same right-hand side to round-off.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import dop853_coefficients as coef
from .dop853_coefficients import INTERPOLATOR_POWER, N_STAGES, N_STAGES_EXTENDED
from .kernels import eval_state, is_extended, uses_recursive
from .system import ChainSystem

__all__ = ["Interrupted", "integrate"]

_TABLEAU = (np.ascontiguousarray(coef.A), coef.B, coef.C, coef.E3, coef.E5, coef.D)


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
    ts = np.ascontiguousarray(ts, dtype=float)
    y0 = np.ascontiguousarray(y0, dtype=float)
    out = np.empty((ts.size, y0.size))
    fac = np.ones(y0.size)  # the inertial kernel reads the first n_angles entries
    if loads is not None:
        fac[: system.n_angles] = system.force_factors(loads)
    y, f, clock, counts = y0.copy(), np.empty(y0.size), np.zeros(2), np.zeros(4, dtype=np.int64)
    recursive = not system.inertial and not system.extended and uses_recursive(system.n)  # O(N) per evaluation
    steps = max(1, STEP_BUDGET // (y0.size if recursive else y0.size**2))
    status = PAUSED
    try:
        while status == PAUSED:  # the compiled loop returns every `steps` steps: Ctrl-C is seen in between
            status = _dop853(
                y, f, clock, counts, ts, system, float(beta), float(rtol), float(atol), *_TABLEAU, out, fac, steps
            )
            if on_time is not None:
                on_time(float(clock[0]))
    except KeyboardInterrupt:
        raise Interrupted(out[: int(counts[0])].copy()) from None
    return out, int(status), int(counts[1]), int(counts[2]), int(counts[3])


PAUSED = 1
"""_dop853's status when it returns after its step budget, to be called again."""
STEP_BUDGET = 100_000
"""Steps per call of the compiled loop times the cost of one evaluation (the state's size on the O(N) recursive
path, its square on the dense ones): a few ms to a few tens of ms per call, so Ctrl-C is seen within ~0.1 s while
the calls cost nothing measurable (N = 7: ~2000 steps a call)."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during integrate; `samples` holds the states of the sample times reached (ts[:len(samples)])."""

    def __init__(self, samples: np.ndarray):
        super().__init__(f"interrupted after {len(samples)} samples")
        self.samples = samples


@njit(cache=True)
def _rms(x):
    s = 0.0
    for v in x:
        s += v * v
    return math.sqrt(s / x.size)


@njit(cache=True, inline="always")  # inlined: the step loop's cost stays what it was written out in place
def _stages(first, last, y, h, A, K, ytmp, fac, system, beta, L, D, X, lam):
    """The Runge-Kutta stages K[s], s = first .. last - 1, each from y + h sum_j A[s, j] K[j] (j < s): the method's
    stages (1 .. N_STAGES - 1) and the dense output's extra stages (N_STAGES + 1 .. N_STAGES_EXTENDED - 1)."""
    for s in range(first, last):
        for i in range(y.size):
            acc = 0.0
            for j in range(s):
                acc += A[s, j] * K[j, i]
            ytmp[i] = y[i] + h * acc
        eval_state(ytmp, fac, system, beta, K[s], L, D, X, lam)


@njit(cache=True)
def _dop853(y, f, clock, counts, ts, system, beta, rtol, atol, A, B, C, E3, E5, DD, out, fac, max_steps):
    """scipy's DOP853 (same tableau, error norm, step control and 7th-order dense output), compiled.

    fac: the constant per-particle force factors (the load factors, ones when every particle is loaded).
    Writes the solution at the sample times ts (ts[0] = 0 is the initial y) into out. Resumable: y and f (the state
    and its rate), clock = [t, h_abs] and counts = [next sample, nfev, naccept, nreject] carry the integration from
    one call to the next (counts[0] == 0: start from y at t = 0). Takes at most max_steps steps per call; returns
    0 (done), PAUSED (1: call again) or -1 (the step size fell below the round-off limit).
    """
    ns = N_STAGES
    nse = N_STAGES_EXTENDED
    na = y.size
    nch = system.n_chains
    n = system.n
    # the workspace of eval_rhs (kernels.make_workspace, allocated here, not by a call: the compiled
    # arithmetic of a short chain's run then stays bit for bit what it was before the recursion)
    # the inertial model (mass_ratio > 0) solves its mass matrix densely (kernels.make_inertial_workspace)
    # an extended term (a free head, a trap, self-contact) solves densely over all coordinates
    # (kernels.make_general_workspace; the state: angles, then the head; inertial: then their rates)
    inertial = system.mass_ratio > 0
    if is_extended(system):
        nq = na // 2 if inertial else na  # position coordinates (the inertial state: positions, then rates)
        L = np.zeros((2, nq, nq))
        D = np.zeros((nch * n, 8))
        X = np.zeros((nq, 2))
    else:
        m = n if inertial or not uses_recursive(n) else 0
        L = np.zeros((nch, m, m))
        if inertial:
            D = np.zeros((n, n + 2))
        elif m == n:
            D = np.zeros((n, n))
        else:
            D = np.zeros((nch * n, 4))
        X = np.zeros((n, 2))
    lam = np.zeros(2)
    K = np.zeros((nse, na))
    F = np.zeros((INTERPOLATOR_POWER, na))
    ytmp = np.empty(na)
    y_new = np.empty(na)
    f_new = np.empty(na)
    scale = np.empty(na)
    e3 = np.empty(na)
    e5 = np.empty(na)
    T = ts[-1]
    nsamp = ts.size
    if counts[0] == 0:  # the start: the rate at y, scipy's initial step, the first sample
        t = 0.0
        eval_state(y, fac, system, beta, f, L, D, X, lam)
        nfev = 1
        # initial step (scipy's select_initial_step for solve_ivp, error order 7)
        for i in range(na):
            scale[i] = atol + abs(y[i]) * rtol
            e3[i] = y[i] / scale[i]
            e5[i] = f[i] / scale[i]
        d0 = _rms(e3)
        d1 = _rms(e5)
        if d0 < 1e-5 or d1 < 1e-5:
            h0 = 1e-6
        else:
            h0 = 0.01 * d0 / d1
        h0 = min(h0, T)
        for i in range(na):
            ytmp[i] = y[i] + h0 * f[i]
        eval_state(ytmp, fac, system, beta, f_new, L, D, X, lam)
        nfev += 1
        for i in range(na):
            e3[i] = (f_new[i] - f[i]) / scale[i]
        d2 = _rms(e3) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h_abs = min(100 * h0, h1, T)
        out[0, :] = y
        isamp = 1
        naccept = 0
        nreject = 0
    else:  # resume where the previous call stopped
        t = clock[0]
        h_abs = clock[1]
        isamp = counts[0]
        nfev = counts[1]
        naccept = counts[2]
        nreject = counts[3]
    status = 0
    steps = 0
    while t < T:
        if steps == max_steps:
            status = 1  # PAUSED
            break
        steps += 1
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs < min_step:
            h_abs = min_step
        accepted = False
        rejected = False
        h = 0.0
        t_new = t
        while not accepted:
            if h_abs < min_step:
                status = -1
                break
            h = h_abs
            t_new = t + h
            if t_new > T:
                t_new = T
            h = t_new - t
            h_abs = abs(h)
            K[0, :] = f
            _stages(1, ns, y, h, A, K, ytmp, fac, system, beta, L, D, X, lam)
            for i in range(na):
                acc = 0.0
                for j in range(ns):
                    acc += B[j] * K[j, i]
                y_new[i] = y[i] + h * acc
            eval_state(y_new, fac, system, beta, f_new, L, D, X, lam)
            K[ns, :] = f_new
            nfev += ns
            n5 = 0.0
            n3 = 0.0
            for i in range(na):
                sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
                a5 = 0.0
                a3 = 0.0
                for j in range(ns + 1):
                    a5 += K[j, i] * E5[j]
                    a3 += K[j, i] * E3[j]
                a5 /= sc
                a3 /= sc
                n5 += a5 * a5
                n3 += a3 * a3
            if n5 == 0.0 and n3 == 0.0:
                err = 0.0
            else:
                err = h_abs * n5 / math.sqrt((n5 + 0.01 * n3) * na)
            if err < 1.0:
                if err == 0.0:
                    factor = 10.0
                else:
                    factor = min(10.0, 0.9 * err ** (-1.0 / 8.0))
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                accepted = True
            else:
                h_abs *= max(0.2, 0.9 * err ** (-1.0 / 8.0))
                rejected = True
                nreject += 1
        if status != 0:
            break
        naccept += 1
        # samples in (t, t_new]
        if isamp < nsamp and ts[isamp] < t_new:
            _stages(ns + 1, nse, y, h, A, K, ytmp, fac, system, beta, L, D, X, lam)
            nfev += nse - ns - 1
            for i in range(na):
                dy = y_new[i] - y[i]
                F[0, i] = dy
                F[1, i] = h * K[0, i] - dy
                F[2, i] = 2.0 * dy - h * (f_new[i] + K[0, i])
                for r in range(INTERPOLATOR_POWER - 3):
                    acc = 0.0
                    for j in range(nse):
                        acc += DD[r, j] * K[j, i]
                    F[3 + r, i] = h * acc
        while isamp < nsamp and ts[isamp] <= t_new:
            if ts[isamp] == t_new:
                out[isamp, :] = y_new
            else:
                x = (ts[isamp] - t) / h
                for i in range(na):
                    acc = 0.0
                    for r in range(INTERPOLATOR_POWER - 1, -1, -1):
                        acc += F[r, i]
                        if (INTERPOLATOR_POWER - 1 - r) % 2 == 0:
                            acc *= x
                        else:
                            acc *= 1.0 - x
                    out[isamp, i] = acc + y[i]
            isamp += 1
        t = t_new
        y[:] = y_new
        f[:] = f_new
    clock[0] = t
    clock[1] = h_abs
    counts[0] = isamp
    counts[1] = nfev
    counts[2] = naccept
    counts[3] = nreject
    return status

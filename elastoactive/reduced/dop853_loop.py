"""DOP853 compiled around any compiled right-hand side: the step loop written once, the right-hand side plugged in.

`dop853_steps(rate, args, ...)` is scipy's solve_ivp(method="DOP853") (the tableau of dop853_coefficients, its error
norm, initial step, step-size control and 7th-order dense output) with the right-hand side a compiled function
rate(t, y, out, args) (out = dy/dt at time t and state y, each stage at its own time t + c h, as scipy's; args a tuple
of its parameters; an autonomous model ignores t), resumable in calls of a bounded number of steps
so that Ctrl-C and a progress bar are served between calls. It is inlined (numba inline="always") into a small driver
that each model compiles with its own rate as a global, e.g.

    @njit(cache=True)
    def _dop853_model(y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps, args):
        return dop853_steps(_model_rate, args, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps)

A driver so written is cached like any kernel: numba cannot cache a function that takes another compiled function as
an argument (the dispatcher is a dynamic global, recompiled in every process), while the inlined loop names the rate
only through the driver's global. `integrate(driver, args, ts, y0, ...)` allocates the loop's state and runs it through
a `loop` (run_loop's contract; engines.runner.resume with a meter for progress).

Every compiled DOP853 of the package is a driver of this loop: reduced.fluid's, reduced.network_kernels.dop853 (the
network) and reduced.dop853 (the planar chain). `dop853_sums` is the loop with the order of its weighted sums chosen
(sum_scaled_rows or sum_columns, plugged in as the rate is, for the stages and for the dense output), so that each
driver keeps the round-off of the loop it replaced, bit for bit; dop853_steps sums by sum_scaled_rows throughout.
Taking the same steps as scipy's on the same right-hand side, each agrees with solve_ivp(DOP853) to round-off (the
sums' order is not scipy's).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from numba import njit

from . import dop853_coefficients as coef
from .dop853_coefficients import INTERPOLATOR_POWER, N_STAGES, N_STAGES_EXTENDED

__all__ = [
    "PAUSED",
    "Integrated",
    "STEP_BUDGET",
    "TABLEAU",
    "dop853_steps",
    "dop853_sums",
    "integrate",
    "reporting_loop",
    "run_loop",
    "sum_columns",
    "sum_scaled_rows",
]

PAUSED = 1
"""dop853_steps' status when it returns after its step budget, to be called again."""
STEP_BUDGET = 2_000_000
"""Steps per call of the compiled loop times the state's size squared (a dense right-hand side's cost): a few tens of
ms per call at small states, so Ctrl-C is seen within ~0.1 s while the calls cost nothing measurable."""
NODES = np.ascontiguousarray(coef.C, dtype=float)
"""The stages' times c_s as fractions of the step (a compile-time constant of the loop)."""
TABLEAU = tuple(np.ascontiguousarray(x, dtype=float) for x in (coef.A, coef.B, coef.E3, coef.E5, coef.D))
"""(A, B, E3, E5, D): the arguments dop853_steps takes after atol."""


@njit(cache=True)
def _rms(x):
    s = 0.0
    for v in x:
        s += v * v
    return math.sqrt(s / x.size)


@njit(cache=True, inline="always")
def sum_scaled_rows(y, h, w, K, count, z):
    """z = y + h sum_{j < count} w[j] K[j] taken row by row, h folded into each weight: z = y, then z += (h w[j]) K[j]
    for every j with w[j] != 0 (K's rows are contiguous)."""
    for i in range(y.size):
        z[i] = y[i]
    for j in range(count):
        a = h * w[j]
        if a != 0.0:
            for i in range(y.size):
                z[i] += a * K[j, i]


@njit(cache=True, inline="always")
def sum_columns(y, h, w, K, count, z):
    """z = y + h sum_{j < count} w[j] K[j] taken entry by entry, h applied last: z_i = y_i + h (sum_j w[j] K[j, i])
    (the dense output's, from y = 0: 0 + x is x exactly, the sum never being -0)."""
    for i in range(y.size):
        acc = 0.0
        for j in range(count):
            acc += w[j] * K[j, i]
        z[i] = y[i] + h * acc


@njit(cache=True, inline="always")
def _stages(rate, args, weighted_sum, first, last, t, y, h, A, K, ytmp):
    """K[s] = rate(t + c_s h, y + h sum_{j<s} A[s, j] K[j]) for s = first .. last - 1."""
    for s in range(first, last):
        weighted_sum(y, h, A[s], K, s, ytmp)
        rate(t + NODES[s] * h, ytmp, K[s], args)


@njit(cache=True, inline="always")
def dop853_steps(rate, args, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps):
    """scipy's DOP853 around rate(t, y, out, args), from y at ts[0], the solution at the sample times ts into out.

    Resumable: y and f (the state and its rate), clock = [t, h_abs] and counts = [next sample, nfev, naccept, nreject]
    carry the integration from one call to the next (counts[0] == 0: start). Takes at most max_steps steps per call;
    returns 0 (done), PAUSED (call again) or -1 (the step size fell below the round-off limit; a rate that is not
    finite rejects the step, as scipy's does, so a model that left its domain ends so)."""
    rows = sum_scaled_rows
    return dop853_sums(rate, args, rows, rows, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps)


@njit(cache=True, inline="always")
def dop853_sums(
    rate, args, stage_sum, dense_sum, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps
):
    """dop853_steps with the order of its weighted sums chosen (sum_scaled_rows or sum_columns, passed as functions,
    as the rate is, so that only the chosen one is compiled): stage_sum for the stages' states and the step's new
    state, dense_sum for the dense output's coefficients."""
    ns = N_STAGES
    nse = N_STAGES_EXTENDED
    na = y.size
    K = np.zeros((nse, na))
    F = np.zeros((INTERPOLATOR_POWER, na))
    ytmp = np.empty(na)
    y_new = np.empty(na)
    f_new = np.empty(na)
    scale = np.empty(na)
    e3 = np.empty(na)
    e5 = np.empty(na)
    zero = np.zeros(na)  # the dense output's coefficients are sums from 0
    t0 = ts[0]
    T = ts[-1]
    nsamp = ts.size
    if counts[0] == 0:  # the start: the rate at y, scipy's initial step (error order 7), the first sample
        t = t0
        rate(t, y, f, args)
        nfev = 1
        for i in range(na):
            if not math.isfinite(f[i]):  # a start outside the model's domain: no step can be taken
                clock[0] = t
                counts[1] = nfev
                return -1
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
        h0 = min(h0, T - t0)
        for i in range(na):
            ytmp[i] = y[i] + h0 * f[i]
        rate(t + h0, ytmp, f_new, args)
        nfev += 1
        for i in range(na):
            e3[i] = (f_new[i] - f[i]) / scale[i]
        d2 = _rms(e3) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h_abs = min(100 * h0, h1, T - t0)
        out[0, :] = y
        isamp = 1
        naccept = 0
        nreject = 0
    else:
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
            status = PAUSED
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
            if not h_abs >= min_step:  # (NaN too)
                status = -1
                break
            h = h_abs
            t_new = t + h
            if t_new > T:
                t_new = T
            h = t_new - t
            h_abs = abs(h)
            K[0, :] = f
            _stages(rate, args, stage_sum, 1, ns, t, y, h, A, K, ytmp)
            stage_sum(y, h, B, K, ns, y_new)
            rate(t + h, y_new, f_new, args)
            K[ns, :] = f_new
            nfev += ns
            for i in range(na):
                e5[i] = 0.0
                e3[i] = 0.0
            for j in range(ns + 1):
                w5, w3 = E5[j], E3[j]
                for i in range(na):
                    e5[i] += K[j, i] * w5
                    e3[i] += K[j, i] * w3
            n5 = 0.0
            n3 = 0.0
            for i in range(na):
                sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
                a5 = e5[i] / sc
                a3 = e3[i] / sc
                n5 += a5 * a5
                n3 += a3 * a3
            if not math.isfinite(n5 + n3):  # scipy's: a NaN error rejects the step at the smallest factor
                err = math.inf
            elif n5 == 0.0 and n3 == 0.0:
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
                h_abs *= max(0.2, 0.9 * err ** (-1.0 / 8.0))  # err inf: 0.2
                rejected = True
                nreject += 1
        if status != 0:
            break
        naccept += 1
        if isamp < nsamp and ts[isamp] < t_new:  # the dense output's extra stages, only when a sample falls here
            _stages(rate, args, stage_sum, ns + 1, nse, t, y, h, A, K, ytmp)
            nfev += nse - ns - 1
            for i in range(na):
                dy = y_new[i] - y[i]
                F[0, i] = dy
                F[1, i] = h * K[0, i] - dy
                F[2, i] = 2.0 * dy - h * (f_new[i] + K[0, i])
            for r in range(INTERPOLATOR_POWER - 3):
                dense_sum(zero, h, DD[r], K, nse, F[3 + r])
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


class Integrated(NamedTuple):
    """What `integrate` returns: the states at the sample times and the loop's end."""

    y: np.ndarray
    """(len(ts), len(y0)) states at the sample times (rows past `reached` unset when status < 0)."""
    status: int
    """0 done; -1 the step size fell below round-off (or the rate stayed not finite)."""
    t: float
    """The time reached."""
    nfev: int
    naccept: int
    nreject: int


def run_loop(call: Callable[[int], int], paused: int, reached: Callable[[], float], steps: int) -> int:
    """Run a resumable compiled loop to its end: call(k) takes at most k steps and returns `paused` while unfinished
    (any other status ends it, and is returned); every call here takes `steps`. A caller that reports progress gives
    a loop of its own (engines.runner.resume, told reached() after each call): a resumable loop takes the same steps,
    bit for bit, however its calls are cut."""
    status = paused
    while status == paused:  # the compiled loop returns every `steps` steps: Ctrl-C is seen in between
        status = call(steps)
    return status


def reporting_loop(on_time: Callable[[float], None] | None) -> Callable:
    """run_loop with on_time(t) told the time reached after every call (a progress bar); run_loop itself when on_time
    is None."""
    if on_time is None:
        return run_loop

    def loop(call: Callable[[int], int], paused: int, reached: Callable[[], float], steps: int) -> int:
        status = paused
        while status == paused:
            status = call(steps)
            on_time(reached())
        return status

    return loop


def integrate(
    driver,
    args: tuple,
    ts: np.ndarray,
    y0: np.ndarray,
    rtol: float,
    atol: float,
    loop=run_loop,
    *,
    steps: int | None = None,
    on_interrupt: Callable[[np.ndarray], KeyboardInterrupt] | None = None,
):
    """Run a driver (the module docstring's) from y0 at ts[0], sampled at ts, through `loop` (run_loop's contract:
    loop(call, PAUSED, reached, steps)).

    steps: the steps per call of the compiled loop (default STEP_BUDGET / the state's size squared, a dense right-hand
    side's cost). on_interrupt: on Ctrl-C, the exception raised instead of the KeyboardInterrupt, made from the
    samples reached (ts[:len(samples)]); None lets the KeyboardInterrupt through."""
    ts = np.ascontiguousarray(ts, dtype=float)
    y = np.array(y0, dtype=float)
    out = np.empty((ts.size, y.size))
    if ts.size < 2:
        out[:] = y
        return Integrated(out, 0, float(ts[0]) if ts.size else 0.0, 0, 0, 0)
    f, clock, counts = np.empty(y.size), np.zeros(2), np.zeros(4, dtype=np.int64)
    if steps is None:
        steps = STEP_BUDGET // max(y.size**2, 1)

    def call(count: int) -> int:
        return driver(y, f, clock, counts, ts, float(rtol), float(atol), *TABLEAU, out, count, args)

    try:
        status = loop(call, PAUSED, lambda: float(clock[0]), max(1, steps))
    except KeyboardInterrupt:
        if on_interrupt is None:
            raise
        raise on_interrupt(out[: int(counts[0])].copy()) from None
    return Integrated(out, int(status), float(clock[0]), int(counts[1]), int(counts[2]), int(counts[3]))

"""The extrapolated interaction (Beds.interaction; by default beyond EXACT_UP_TO links, so a pair or a small row is
exact). The velocities that the other chains' forces on the fluid give chain c's links, u_c = sum_{c' != c} N_cc'
(w_c' - Q_c' lambda_c'), are all that chain c takes from the others: given u_c, chain c alone obeys the same
equations with x_c = N_cc w_c + u_c (D_cc lambda_c = Q_c^T x_c, velocities P_c^T (x_c - N_cc Q_c lambda_c)). So
reduced.fluid.solve_fluid's compiled DOP853 solves the whole system once per step, at the step's start (the loop's
accepted state), and within the step each chain alone with its own block exact at every evaluation and u taken from a
quadratic in time through the whole solves' u at the last three starts; the quadratic starts where the last step's
ended (continuous in time, so the loop's error estimate sees no jump at the starts) and the gap to the whole solve
decays over the step. The time of an evaluation's state from the step's start comes from the rates at the starts
(`_elapsed`). The error is of third order in the step and is not in the loop's error estimate: it is measured
(docs/hydrodynamics.md, "The cost against the number of cilia": period and phase lags of rows of 8 to 24 cilia). Per
step: one whole solve, O(B^2), and about 12 evaluations chain by chain, O(C n^3). reduced.fluid's right-hand side `rhs`,
scipy's method and the budget's Jacobian stay exact.

`alone` and `memory` are a run's own workspace and record; `dop853` is reduced.dop853_loop's driver around the
extrapolated evaluations.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from .dop853_loop import dop853_steps
from .fluid_kernels import Near, Work, motion

__all__ = ["Memory", "alone", "dop853", "memory"]


class Memory(NamedTuple):
    """The extrapolated interaction's record, carried from one evaluation to the next within a run, at the current
    step's start (`_new_step`; (3B,) arrays but spans and steps)."""

    start: np.ndarray
    """The loop's state (NaN before the first step)."""
    rate: np.ndarray
    """The loop's rate (from the second start on)."""
    change: np.ndarray
    """The rate's change per unit time since the start before (from the third start on; zeros before)."""
    flow: np.ndarray
    """(3, 3B): the other chains' flow the step's evaluations take is flow[0] + s flow[1] + s^2 flow[2] at the time s
    since the start (`_elapsed`)."""
    known: np.ndarray
    """(2, 3B): the whole solve's other chains' flow at this start and the one before."""
    spans: np.ndarray
    """(1,): the time between the start before and this one."""
    steps: np.ndarray
    """int64 (1,): the starts recorded."""


def alone(chains: int, n: int) -> tuple:
    """(Near, Work) of each chain with itself only: the extrapolated interaction's evaluations within a step."""
    zero = np.zeros((chains, 1), dtype=np.int64)
    near = Near(np.arange(chains, dtype=np.int64)[:, None], np.ones(chains, dtype=np.int64), zero, zero[:, 0].copy())
    return near, Work(np.empty((chains, 1, 3 * n, 3 * n)), np.empty((chains, 1, 3 * n, n)), np.empty((chains, 1, n, n)))


def memory(size: int) -> Memory:
    """A run's empty Memory for a state of `size` numbers."""
    empty = np.full(size, np.nan)
    return Memory(
        empty, empty.copy(), np.zeros(size), np.zeros((3, size)), np.zeros((2, size)), np.zeros(1),
        np.zeros(1, dtype=np.int64),
    )  # fmt: skip


@njit(cache=True)
def _other_flow(nb, nqb, w, lam, x, n, self_slot, flow):
    """flow <- x less each chain's own part N_cc (w_c - Q_c lambda_c): the links' end-to-end velocities that the other
    chains' forces on the fluid give chain c (x the links' velocities of the whole solve, w and lambda its P r and
    tensions, nb and nqb its blocks)."""
    for c in range(self_slot.size):
        blk = nb[c, self_slot[c]]
        nq = nqb[c, self_slot[c]]
        o = c * n
        for row in range(3 * n):
            acc = x[3 * o + row]
            for j in range(n):
                k = o + j
                acc -= blk[row, 3 * j] * w[k, 0] + blk[row, 3 * j + 1] * w[k, 1] + blk[row, 3 * j + 2] * w[k, 2]
                acc += nq[row, j] * lam[k]
            flow[3 * o + row] = acc


@njit(cache=True)
def _elapsed(y, start, rate, change):
    """The time s from the step's start to the state y along the path y(s) = start + s rate + s^2 / 2 change:
    s0 = <d, rate> / <rate, rate>, d = y - start, then s = <d, g> / <g, g> with g = rate + s0 / 2 change (an error
    of third order in s on the path)."""
    travel = 0.0
    speed = 0.0
    for i in range(y.size):
        travel += (y[i] - start[i]) * rate[i]
        speed += rate[i] * rate[i]
    if not speed > 0.0:
        return 0.0
    s0 = travel / speed
    travel = 0.0
    speed = 0.0
    for i in range(y.size):
        g = rate[i] + 0.5 * s0 * change[i]
        travel += (y[i] - start[i]) * g
        speed += g * g
    return travel / speed if speed > 0.0 else s0


@njit(cache=True)
def _new_step(exact, memory, y, f):
    """Record a step's start y (the loop's state; f its rate there, unless no step was taken yet). The whole solve
    there gives the other chains' flow on each chain's links; the flow the step's evaluations take goes on from where
    the last step's ended (continuous in time: the loop's error estimate sees no jump) as the quadratic through the
    whole solve's flows at the last three starts, less that gap decaying linearly over the last step's time."""
    n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work = exact
    start, rate, change, flow, known, spans, steps = memory
    size = y.size
    x = np.zeros(size)
    scratch = np.empty(size)
    w, lam = motion(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work, x, scratch)
    fresh = np.empty(size)
    _other_flow(work[0], work[1], w, lam, x, n, near[3], fresh)
    if steps[0] == 0:  # the run's start: the whole solve's flow, held over the first step
        for i in range(size):
            flow[0, i] = fresh[i]
            flow[1, i] = 0.0
            flow[2, i] = 0.0
    else:
        if steps[0] == 1:  # no rate known at the first start: the step's time from the rate at its end
            dt = _elapsed(y, start, f, change)
        else:
            dt = _elapsed(y, start, rate, change)
        if not dt > 0.0:
            dt = math.inf  # (a step that went nowhere: the flow held)
        before = spans[0]
        for i in range(size):
            end = flow[0, i] + dt * (flow[1, i] + dt * flow[2, i]) if math.isfinite(dt) else flow[0, i]
            d1 = (fresh[i] - known[0, i]) / dt
            d2 = 0.0
            if steps[0] >= 2 and before > 0.0:
                d2 = (d1 - (known[0, i] - known[1, i]) / before) / (dt + before)
            flow[0, i] = end
            flow[1, i] = d1 + d2 * dt + (fresh[i] - end) / dt
            flow[2, i] = d2
            change[i] = (f[i] - rate[i]) / dt if steps[0] >= 2 else 0.0
        spans[0] = dt if math.isfinite(dt) else 0.0
    for i in range(size):
        start[i] = y[i]
        rate[i] = f[i]
        known[1, i] = known[0, i]
        known[0, i] = fresh[i]
    steps[0] += 1


@njit(cache=True, inline="always")
def _rate_extrapolated(t, y, out, args):
    """t' at y with the other chains' flow extrapolated over the current step (args: the whole solve's arguments,
    each chain alone's (Near, Work), the Memory, the loop's state and rate, which hold the current step's start):
    each chain's own block exact, the others' flow the Memory's quadratic at the time since the start (`_new_step`)."""
    exact, alone, memory, y_step, f_step = args
    fresh = False
    for i in range(y_step.size):
        if y_step[i] != memory.start[i]:  # (NaN before the first step too)
            fresh = True
            break
    if fresh:
        _new_step(exact, memory, y_step, f_step)
    flow = memory.flow
    x = flow[0].copy()
    if memory.steps[0] >= 2:
        s = _elapsed(y, memory.start, memory.rate, memory.change)
        for i in range(y.size):
            x[i] += s * (flow[1, i] + s * flow[2, i])
    n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, near, work = exact
    motion(y, n, chains, sigma, gamma_l, clamped, code, radius, coupling, bases, rot, alone[0], alone[1], x, out)


@njit(cache=True)
def dop853(y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps, args):
    """dop853_loop.dop853_steps around _rate_extrapolated (args: the whole solve's arguments, each chain alone's
    (Near, Work), the Memory), which sees the loop's state and rate: a run's start clears the Memory."""
    exact, alone, memory = args
    if counts[0] == 0:
        memory.start[:] = np.nan
        memory.steps[0] = 0
    seen = (exact, alone, memory, y, f)
    return dop853_steps(_rate_extrapolated, seen, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps)

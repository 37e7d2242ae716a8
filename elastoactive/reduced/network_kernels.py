"""The network model's compiled kernels: the right-hand side, DOP853 around it, and Euler-Maruyama with noise.

All O(N) per evaluation (one pass over the bonds, one over the nodes) and allocation-free: the state y holds the free
nodes' x and y (node order, interleaved) then the units' psi (elastoactive.reduced.network). `Kernel` is the flat
argument tuple every kernel takes after its own arguments.

- `rhs_into(y, out, *kernel)`: dy/dt of the deterministic model, into `out`; the same arithmetic, in the same order,
  as the first compiled kernel (forces summed bond by bond, then the trap, the active force and the turning rate).
- `dop853(...)`: scipy's solve_ivp(method="DOP853") compiled around rhs_into, so a step costs no Python call: a driver
  of reduced.dop853_loop's loop (dop853_loop.integrate runs it; resumable in calls of a bounded number of steps, so
  Ctrl-C is seen between calls). Taking the same steps as scipy's, it agrees with solve_ivp(DOP853) on the same
  right-hand side to round-off.
- `euler_maruyama(...)`: the Ito SDE dy = f(y) dt + amplitude dW (additive noise: translational on the free nodes'
  coordinates, rotational on the polarities), with the counter-based normal xi(seed, k, i) of
  elastoactive.controllers.noise for state entry i over step k, the draw MuJoCo's network run adds after its step k.
- `standard_normal_into(seed, step, out)`: that draw, compiled (splitmix64, Box-Muller), equal to
  controllers.noise.standard_normal to round-off.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .dop853_loop import dop853_sums, sum_columns, sum_scaled_rows

STEP_BUDGET = 20_000_000
"""Steps per call of a compiled loop times the state's size: a few tens of ms per call, so Ctrl-C is seen within
~0.1 s while the calls cost nothing measurable."""
PAUSED = 1
"""A loop's status when it returns after its step budget, to be called again."""

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)


@njit(cache=True, inline="always")
def _splitmix64(x):
    z = x + _GOLDEN
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    return z ^ (z >> np.uint64(31))


@njit(cache=True)
def standard_normal_into(seed, step, out):
    """out[i] = xi(seed, step, i), i = 0 .. out.size - 1: controllers.noise.standard_normal's counter-based draw."""
    key = _splitmix64(_splitmix64(np.uint64(seed)) ^ np.uint64(step))
    scale = 2.0**-53
    for i in range(out.size):
        two = np.uint64(2) * np.uint64(i)
        h1 = _splitmix64(key + two)
        h2 = _splitmix64(key + two + np.uint64(1))
        u1 = float(h1 >> np.uint64(11)) * scale
        u2 = float(h2 >> np.uint64(11)) * scale
        out[i] = math.sqrt(-2.0 * math.log1p(-u1)) * math.cos(2.0 * math.pi * u2)


@njit(cache=True)
def rhs_into(y, out, rest, bonds, rest_lengths, stiffness, anchors, trap, slot, unit, sigma, inv_la, f2):
    """out = dy/dt at y (f2: the free nodes' coordinates, 2F). Forces summed bond by bond into out[:f2], then per
    free node the trap, the active force sigma[u] n and the turning rate (v . n_perp) inv_la[u] (sigma, inv_la: (A,)
    each unit's force and 1 / its alignment length)."""
    for i in range(f2):
        out[i] = 0.0
    for b in range(bonds.shape[0]):
        i, j = bonds[b, 0], bonds[b, 1]
        si, sj = slot[i], slot[j]
        if si >= 0:
            xi, yi = y[2 * si], y[2 * si + 1]
        else:
            xi, yi = rest[i, 0], rest[i, 1]
        if sj >= 0:
            xj, yj = y[2 * sj], y[2 * sj + 1]
        else:
            xj, yj = rest[j, 0], rest[j, 1]
        rx, ry = xj - xi, yj - yi
        d = np.sqrt(rx * rx + ry * ry)
        c = stiffness[b] * (d - rest_lengths[b]) / d
        if si >= 0:
            out[2 * si] += c * rx
            out[2 * si + 1] += c * ry
        if sj >= 0:
            out[2 * sj] -= c * rx
            out[2 * sj + 1] -= c * ry
    for p in range(rest.shape[0]):
        s = slot[p]
        u = unit[p]
        if s < 0:
            if u >= 0:
                out[f2 + u] = 0.0
            continue
        vx = out[2 * s] - trap * (y[2 * s] - anchors[p, 0])
        vy = out[2 * s + 1] - trap * (y[2 * s + 1] - anchors[p, 1])
        if u >= 0:
            c, sn = np.cos(y[f2 + u]), np.sin(y[f2 + u])
            vx += sigma[u] * c
            vy += sigma[u] * sn
            out[f2 + u] = (-sn * vx + c * vy) * inv_la[u]
        out[2 * s] = vx
        out[2 * s + 1] = vy


@njit(cache=True, inline="always")
def _rate(t, y, out, args):
    """rhs_into in dop853_loop's form: args = the Kernel tuple (reduced.network.kernel_args)."""
    rhs_into(y, out, *args)


@njit(cache=True)
def dop853(y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps, args):
    """dop853_loop's driver around rhs_into (args: the Kernel tuple), the stages summed by sum_scaled_rows and the
    dense output by sum_columns."""
    return dop853_sums(
        _rate, args, sum_scaled_rows, sum_columns, y, f, clock, counts, ts, rtol, atol, A, B, E3, E5, DD, out, max_steps
    )


@njit(cache=True)
def euler_maruyama(
    y,
    counts,
    dt,
    every,
    seed,
    amplitude,
    out,
    max_steps,
    rest,
    bonds,
    rest_lengths,
    stiffness,
    anchors,
    trap,
    slot,
    unit,
    sigma,
    inv_la,
    f2,
):
    """Ito Euler-Maruyama steps y <- y + dt f(y) + amplitude * xi(seed, k) (xi: standard_normal_into over the state,
    k the step's index from 0), storing y every `every` steps into out's rows (row 0: the start). counts = [steps
    taken]: resumable; at most max_steps per call; returns 0 (done) or PAUSED."""
    f = np.empty(y.size)
    xi = np.empty(y.size)
    total = (out.shape[0] - 1) * every
    k = counts[0]
    if k == 0:
        out[0, :] = y
    steps = 0
    while k < total:
        if steps == max_steps:
            counts[0] = k
            return PAUSED
        steps += 1
        rhs_into(y, f, rest, bonds, rest_lengths, stiffness, anchors, trap, slot, unit, sigma, inv_la, f2)
        standard_normal_into(seed, k, xi)
        for i in range(y.size):
            y[i] += dt * f[i] + amplitude[i] * xi[i]
        k += 1
        if k % every == 0:
            out[k // every, :] = y
    counts[0] = k
    return 0

"""The network model's compiled kernels: the right-hand side, DOP853 around it, and Euler-Maruyama with noise.

All O(N) per evaluation (one pass over the bonds, one over the nodes) and allocation-free: the state y holds the free
nodes' x and y (node order, interleaved) then the units' psi (elastoactive.reduced.network). `Kernel` is the flat
argument tuple every kernel takes after its own arguments.

- `rhs_into(y, out, *kernel)`: dy/dt of the deterministic model, into `out`; the same arithmetic, in the same order,
  as the first compiled kernel (forces summed bond by bond, then the trap, the active force and the turning rate).
- `dop853(...)`: scipy's solve_ivp(method="DOP853") (the tableau of dop853_coefficients, its error norm, initial step,
  step-size control and 7th-order dense output) compiled around rhs_into, so a step costs no Python call; resumable
  in calls of a bounded number of steps (Ctrl-C is seen between calls). Taking the same steps as scipy's, it agrees
  with solve_ivp(DOP853) on the same right-hand side to round-off.
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

from .dop853_coefficients import INTERPOLATOR_POWER, N_STAGES, N_STAGES_EXTENDED

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


@njit(cache=True)
def _rms(x):
    s = 0.0
    for v in x:
        s += v * v
    return math.sqrt(s / x.size)


@njit(cache=True, inline="always")
def _stages(
    first, last, y, h, A, K, ytmp, rest, bonds, rest_lengths, stiffness, anchors, trap, slot, unit, sigma, inv_la, f2
):
    """The Runge-Kutta stages K[s], s = first .. last - 1, each from y + h sum_j A[s, j] K[j] (j < s)."""
    for s in range(first, last):
        for i in range(y.size):
            ytmp[i] = y[i]
        for j in range(s):  # row by row: K's rows are contiguous (the sum's order is not scipy's: round-off apart)
            a = h * A[s, j]
            if a != 0.0:
                for i in range(y.size):
                    ytmp[i] += a * K[j, i]
        rhs_into(ytmp, K[s], rest, bonds, rest_lengths, stiffness, anchors, trap, slot, unit, sigma, inv_la, f2)


@njit(cache=True)
def dop853(
    y,
    f,
    clock,
    counts,
    ts,
    rtol,
    atol,
    A,
    B,
    E3,
    E5,
    DD,
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
    """scipy's DOP853 compiled around rhs_into, from y at ts[0], writing the solution at the sample times ts into out.

    Resumable: y and f (the state and its rate), clock = [t, h_abs] and counts = [next sample, nfev, naccept, nreject]
    carry the integration from one call to the next (counts[0] == 0: start). Takes at most max_steps steps per call;
    returns 0 (done), PAUSED (call again) or -1 (the step size fell below the round-off limit)."""
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
    t0 = ts[0]
    T = ts[-1]
    nsamp = ts.size
    if counts[0] == 0:  # the start: the rate at y, scipy's initial step (error order 7), the first sample
        t = t0
        rhs_into(y, f, rest, bonds, rest_lengths, stiffness, anchors, trap, slot, unit, sigma, inv_la, f2)
        nfev = 1
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
        rhs_into(ytmp, f_new, rest, bonds, rest_lengths, stiffness, anchors, trap, slot, unit, sigma, inv_la, f2)
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
            _stages(
                1,
                ns,
                y,
                h,
                A,
                K,
                ytmp,
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
            )
            for i in range(na):
                y_new[i] = y[i]
            for j in range(ns):
                a = h * B[j]
                if a != 0.0:
                    for i in range(na):
                        y_new[i] += a * K[j, i]
            rhs_into(y_new, f_new, rest, bonds, rest_lengths, stiffness, anchors, trap, slot, unit, sigma, inv_la, f2)
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
        if isamp < nsamp and ts[isamp] < t_new:  # the dense output's extra stages, only when a sample falls here
            _stages(
                ns + 1,
                nse,
                y,
                h,
                A,
                K,
                ytmp,
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
            )
            nfev += nse - ns - 1
            for i in range(na):
                dy = y_new[i] - y[i]
                F[0, i] = dy
                F[1, i] = h * K[0, i] - dy
                F[2, i] = 2.0 * dy - h * (f_new[i] + K[0, i])
            for r in range(INTERPOLATOR_POWER - 3):
                for i in range(na):
                    F[3 + r, i] = 0.0
                for j in range(nse):
                    a = DD[r, j]
                    if a != 0.0:
                        for i in range(na):
                            F[3 + r, i] += a * K[j, i]
                for i in range(na):
                    F[3 + r, i] *= h
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

"""The reduced model's compiled kernels for the extended terms: a free head, a harmonic trap, self-contact
(ChainSystem.head_free, trap, contact_radius). With any of them on, the overdamped right-hand side is
eval_rhs_general (dense over all coordinates), the inertial one eval_rhs_inertial_general.

Part of elastoactive.reduced.kernels, which documents the whole and is where the rest of the package
imports these from.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .contact import CROSSING_DISTANCE as _CROSSING_DISTANCE
from .kernels_chain import _chain_forces, _pin_correction, chol_solve, chol_solve_cols, cholesky
from .system import CONTACT_LENGTH as _CONTACT_LENGTH

# ----------------------------------------------------------------------------------------------
# the extended terms: a free head, a harmonic trap, self-contact (equations.py, contact.py)
# ----------------------------------------------------------------------------------------------
CONTACT_LENGTH = _CONTACT_LENGTH
CROSSING_DISTANCE = _CROSSING_DISTANCE


@njit(cache=True)
def is_extended(system):
    """Whether any extended term is on (ChainSystem.extended): head_free, trap > 0, contact_radius > 0 or hub_free."""
    return system.head_free or system.trap > 0.0 or system.contact_radius > 0.0 or system.hub_free


@njit(cache=True)
def _n_after(system):
    """Coordinates after the angles (ChainSystem.n_head): 2 for a free head, 1 for a star's turning hub, else 0."""
    return 2 if system.head_free else (1 if system.hub_free else 0)


@njit(cache=True)
def make_general_workspace(nch, n, nq):
    """Scratch arrays (L, D, X, lam) of eval_rhs_general for nch chains of n particles and nq coordinates (n nch,
    plus 2 with a free head): L (2, nq, nq) (L[0] the Cholesky factor, L[1] the drag matrix D), D (nch n, 8)
    per-link records (cos, sin, pivot x, y, node force x, y, scratch), X (nq, 2) D^-1 G^T (pinned), lam (2)."""
    return np.zeros((2, nq, nq)), np.zeros((nch * n, 8)), np.zeros((nq, 2)), np.zeros(2)


@njit(cache=True)
def _general_geometry(y, system, C):
    """C[i, 0:4] = (cos th_i, sin th_i, pivot P_{i-1} x, y) of every link (the pivot of link 0: the head when
    head_free, else the origin); C[i, 4:6] = the trap's force -trap P_i on particle i."""
    n = system.n
    na = n * system.n_chains
    k = system.trap
    for ch in range(system.n_chains):
        off = ch * n
        px = 0.0
        py = 0.0
        if system.head_free and ch == 0:
            px = y[na]
            py = y[na + 1]
        for i in range(n):
            c = math.cos(y[off + i])
            s = math.sin(y[off + i])
            C[off + i, 0] = c
            C[off + i, 1] = s
            C[off + i, 2] = px
            C[off + i, 3] = py
            px += c
            py += s
            C[off + i, 4] = -k * px
            C[off + i, 5] = -k * py


@njit(cache=True)
def _end_contact(C, off, own, other, s_end, s_a, s_b, radius, stiffness):
    """The penalty of the core end at fraction s_end of link `own` against the core of link `other` (contact.py):
    adds the force on the end and the opposite on its closest point to the node forces C[., 4:6] (a force F at
    fraction s of link i: (1 - s) F to its pivot P_{i-1}, s F to particle i). Returns (force on the chain's pivot
    x, y, energy)."""
    span = s_b - s_a
    co = C[off + own, 0]
    so = C[off + own, 1]
    px = C[off + own, 2] + s_end * co
    py = C[off + own, 3] + s_end * so
    ct = C[off + other, 0]
    st = C[off + other, 1]
    ax = C[off + other, 2] + s_a * ct
    ay = C[off + other, 3] + s_a * st
    dx = span * ct
    dy = span * st
    t = min(max(((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
    cx = ax + t * dx
    cy = ay + t * dy
    sx = px - cx
    sy = py - cy
    dist = math.hypot(sx, sy)
    two_r = 2.0 * radius
    if dist >= two_r:
        return 0.0, 0.0, 0.0
    if dist > CROSSING_DISTANCE:
        ux = sx / dist
        uy = sy / dist
    else:  # the end on the other core: along its normal, away on the side of the end's own core midpoint
        mx = C[off + own, 2] + 0.5 * (s_a + s_b) * co
        my = C[off + own, 3] + 0.5 * (s_a + s_b) * so
        if (mx - cx) * (-st) + (my - cy) * ct >= 0.0:
            ux = -st
            uy = ct
        else:
            ux = st
            uy = -ct
        dist = 0.0
    overlap = two_r - dist
    fx = stiffness * overlap * ux
    fy = stiffness * overlap * uy
    hx = 0.0
    hy = 0.0
    # +F on link own at s_end, -F on link other at s_a + t span
    C[off + own, 4] += s_end * fx
    C[off + own, 5] += s_end * fy
    if own == 0:
        hx += (1.0 - s_end) * fx
        hy += (1.0 - s_end) * fy
    else:
        C[off + own - 1, 4] += (1.0 - s_end) * fx
        C[off + own - 1, 5] += (1.0 - s_end) * fy
    s_o = s_a + t * span
    C[off + other, 4] -= s_o * fx
    C[off + other, 5] -= s_o * fy
    if other == 0:
        hx -= (1.0 - s_o) * fx
        hy -= (1.0 - s_o) * fy
    else:
        C[off + other - 1, 4] -= (1.0 - s_o) * fx
        C[off + other - 1, 5] -= (1.0 - s_o) * fy
    return hx, hy, 0.5 * stiffness * overlap * overlap


@njit(cache=True)
def _chain_contact(C, off, n, radius, stiffness):
    """Add the contact penalty's forces of one chain (links off .. off + n - 1 of C, _general_geometry) to the node
    forces C[., 4:6]: for every pair of non-adjacent links, each of the four core ends against the other core
    (_end_contact, contact.py). Returns (force on the chain's pivot x, y, U_contact). Pairs whose cores' midpoints
    are farther apart than the core length plus 2R cannot touch and are skipped."""
    s_a = (1.0 - CONTACT_LENGTH) / 2.0 + radius
    s_b = (1.0 + CONTACT_LENGTH) / 2.0 - radius
    reach = (s_b - s_a) + 2.0 * radius
    reach2 = reach * reach
    hx = 0.0
    hy = 0.0
    energy = 0.0
    for i in range(n):
        mix = C[off + i, 2] + 0.5 * C[off + i, 0]
        miy = C[off + i, 3] + 0.5 * C[off + i, 1]
        for j in range(i + 2, n):
            dx = mix - (C[off + j, 2] + 0.5 * C[off + j, 0])
            dy = miy - (C[off + j, 3] + 0.5 * C[off + j, 1])
            if dx * dx + dy * dy > reach2:
                continue
            for own, other in ((i, j), (j, i)):
                for s_end in (s_a, s_b):
                    fx, fy, u = _end_contact(C, off, own, other, s_end, s_a, s_b, radius, stiffness)
                    hx += fx
                    hy += fy
                    energy += u
    return hx, hy, energy


@njit(cache=True)
def _node_forces(y, system, C):
    """The geometry (_general_geometry) and the node forces of the trap and the contact penalty: C[i, 4:6] on
    particle i, C[off, 6:8] on the pivot of the chain starting at row off. Returns U_contact."""
    n = system.n
    _general_geometry(y, system, C)
    energy = 0.0
    for ch in range(system.n_chains):
        off = ch * n
        # the trap's force on the pivot (zero for a pivot fixed at the origin)
        C[off, 6] = -system.trap * C[off, 2]
        C[off, 7] = -system.trap * C[off, 3]
        if system.contact_radius > 0.0:
            cx, cy, u = _chain_contact(C, off, n, system.contact_radius, system.contact_stiffness)
            C[off, 6] += cx
            C[off, 7] += cy
            energy += u
    return energy


@njit(cache=True)
def _project_node_forces(fac, system, C, out):
    """Add the generalised forces of the node forces C[:, 4:6] (particles) to the angles' entries of out,
    n_k . sum_{i >= k} F_i, and set the head's: all node forces, the pivot's C[0, 6:8] and the follower forces."""
    n = system.n
    na = n * system.n_chains
    for ch in range(system.n_chains):
        off = ch * n
        fx = 0.0
        fy = 0.0
        ax = 0.0
        ay = 0.0
        for k in range(n - 1, -1, -1):
            c = C[off + k, 0]
            s = C[off + k, 1]
            fx += C[off + k, 4]
            fy += C[off + k, 5]
            out[off + k] += -s * fx + c * fy
            ax -= system.sigma * fac[off + k] * c
            ay -= system.sigma * fac[off + k] * s
        if system.head_free and ch == 0:
            out[na] = fx + C[off, 6] + ax
            out[na + 1] = fy + C[off, 7] + ay


@njit(cache=True)
def general_forces(y, fac, system, C, out):
    """out[:nq] = f(q): the generalised forces of the state y (angles, then the free head) with every term:
    springs, follower forces, the pair's coupling, the trap on the particles and the head, the contact penalty
    (the pinned chain's constraint forces are not in it). C: the (n_angles, 8) records of make_general_workspace;
    on return C[:, 0:4] hold the geometry (_general_geometry). Returns U_contact."""
    _chain_forces(y, fac, system, out)  # springs, follower forces, coupling (angles only)
    energy = _node_forces(y, system, C)
    _project_node_forces(fac, system, C, out)
    return energy


@njit(cache=True)
def general_mass(system, C, A):
    """A[:nq, :nq] = M(q) of the inertial model over the angles and the free head, from the geometry C: the angle
    blocks as mass_block, M_{k,h} = m (N - k) n_k (0-based k: the particles k .. N-1 move with both), and the head's
    bead (one particle's mass m at the pivot, turning with the first pendulum, as MuJoCo's paraboloid scene
    builds it): M_hh = m (N + 1) 1, and m inertia_factor more on th_0."""
    n = system.n
    na = n * system.n_chains
    m = system.mass_ratio
    ifac = system.inertia_factor
    A[:, :] = 0.0
    for ch in range(system.n_chains):
        off = ch * n
        for j in range(n):
            cj = C[off + j, 0]
            sj = C[off + j, 1]
            for k in range(j, n):
                v = m * (n - k) * (cj * C[off + k, 0] + sj * C[off + k, 1])
                A[off + j, off + k] = v
                A[off + k, off + j] = v
            A[off + j, off + j] += m * ifac
        if system.head_free and ch == 0:
            for k in range(n):
                vx = -m * (n - k) * C[off + k, 1]
                vy = m * (n - k) * C[off + k, 0]
                A[off + k, na] = vx
                A[na, off + k] = vx
                A[off + k, na + 1] = vy
                A[na + 1, off + k] = vy
            A[na, na] = m * (n + 1)
            A[na + 1, na + 1] = m * (n + 1)
            A[off, off] += m * ifac
    if system.hub_free:  # a star's hub: a bead's rotational inertia at the origin (MuJoCo's hub body)
        A[na, na] = m * ifac


@njit(cache=True, inline="always")
def _particle_forces(CS, off, cc, sc, y, woff, n, vx, vy, gl, gt, m, P, pc, add):
    """The particles' drag and centripetal forces P_i = -W_i v_i - m a_i of the inertial model along one chain
    (eval_rhs_inertial, eval_rhs_inertial_general), v_i and a_i (centripetal) as prefix sums from the pivot's
    velocity (vx, vy): cos th_i, sin th_i read from CS[off + i, cc], CS[off + i, sc], the rates om_i = y[woff + i];
    P_i written into P[off + i, pc], P[off + i, pc + 1] (add: added to what is there). Inlined into its callers
    (inline="always", as _pin_acceleration): the same arithmetic in the same order as the loops it replaced."""
    ax = 0.0
    ay = 0.0
    for i in range(n):
        c = CS[off + i, cc]
        s = CS[off + i, sc]
        w = y[woff + i]
        vx -= s * w
        vy += c * w
        ax -= c * w * w
        ay -= s * w * w
        el = c * vx + s * vy
        et = -s * vx + c * vy
        fx = -(gl * el * c - gt * et * s) - m * ax
        fy = -(gl * el * s + gt * et * c) - m * ay
        if add:
            P[off + i, pc] += fx
            P[off + i, pc + 1] += fy
        else:
            P[off + i, pc] = fx
            P[off + i, pc + 1] = fy


@njit(cache=True, inline="always")
def _pin_acceleration(CS, cc, sc, y, woff, n, beta, delta, L0, X, acc, lam):
    """The pinned chain's Baumgarte-stabilised acceleration constraint G om' = -G' om - 2 beta G om - beta^2 g of
    the inertial model (eval_rhs_inertial, eval_rhs_inertial_general), through the 2 x 2 Schur complement: given
    the unconstrained accelerations a0 = M^-1 (f - D om - c) in acc[:n] and the Cholesky factor L0 of M, sets
    acc[:n] = a0 - X lam with X = M^-1 G^T (left in X) and the multipliers lam. cos th_i, sin th_i are read from
    CS[i, cc], CS[i, sc]; the rates om_0 .. om_{n-1} of chain 1 from y[woff:]. Inlined into its callers
    (inline="always"): a plain call measured ~15 % slower per pinned inertial evaluation (N = 7)."""
    # g, G om and G' om (G' om = -(sum cos th_i om_i^2, sum sin th_i om_i^2)); X = M^-1 G^T
    g0 = -n * (1.0 - delta)
    g1 = 0.0
    v0 = 0.0
    v1 = 0.0
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        c = CS[i, cc]
        s = CS[i, sc]
        w = y[woff + i]
        g0 += c
        g1 += s
        v0 -= s * w
        v1 += c * w
        d0 -= c * w * w
        d1 -= s * w * w
        X[i, 0] = -s
        X[i, 1] = c
    chol_solve_cols(L0, X, 0)
    # (G X) lam = G a0 + G' om + 2 beta G om + beta^2 g;  om' = a0 - X lam
    s00 = 0.0
    s01 = 0.0
    s10 = 0.0
    s11 = 0.0
    r0 = d0 + 2.0 * beta * v0 + beta * beta * g0
    r1 = d1 + 2.0 * beta * v1 + beta * beta * g1
    for i in range(n):
        c = CS[i, cc]
        s = CS[i, sc]
        s00 -= s * X[i, 0]
        s01 -= s * X[i, 1]
        s10 += c * X[i, 0]
        s11 += c * X[i, 1]
        r0 -= s * acc[i]
        r1 += c * acc[i]
    det = s00 * s11 - s01 * s10
    l0 = (s11 * r0 - s01 * r1) / det
    l1 = (s00 * r1 - s10 * r0) / det
    lam[0] = l0
    lam[1] = l1
    for i in range(n):
        acc[i] -= X[i, 0] * l0 + X[i, 1] * l1


@njit(cache=True)
def eval_rhs_inertial_general(y, fac, system, beta, out, L, C, X, lam):
    """out = (q', q'') at y = (q, q') of the inertial model with the extended terms (a free head, the trap,
    self-contact): M q'' = f(q) - D q' - c(q, q') with every force taken as node forces (the particles' drag and
    centripetal terms as in eval_rhs_inertial; the head's bead: one particle's mass and drag), M by general_mass,
    dense Cholesky; the pinned chain's acceleration constraint as in eval_rhs_inertial. L, C, X, lam:
    make_general_workspace with nq position coordinates."""
    n = system.n
    nch = system.n_chains
    na = n * nch
    nq = na + _n_after(system)
    m = system.mass_ratio
    gl = system.gamma_l
    gt = system.gamma_t
    if L.shape[0] < 2 or L.shape[1] != nq or L.shape[2] != nq or C.shape[0] < na or C.shape[1] < 8 or X.shape[0] < nq:
        raise ValueError(
            "eval_rhs_inertial_general needs make_general_workspace's arrays: L (2, nq, nq), C (n_angles, 8), X (nq, 2)"
        )
    if y.size < 2 * nq or out.size < 2 * nq:
        raise ValueError("eval_rhs_inertial_general: the state holds 2 nq numbers (positions, then rates)")
    for i in range(nq):
        out[i] = y[nq + i]
    acc = out[nq:]
    _chain_forces(y, fac, system, acc)  # springs, follower forces, coupling (angles)
    _node_forces(y, system, C)  # geometry, trap, contact
    for ch in range(nch):
        off = ch * n
        vx = 0.0
        vy = 0.0
        if system.head_free and ch == 0:  # the head's drag on its velocity
            vx = y[nq + na]
            vy = y[nq + na + 1]
            c = C[off, 0]
            s = C[off, 1]
            el = c * vx + s * vy
            et = -s * vx + c * vy
            C[off, 6] -= gl * el * c - gt * et * s
            C[off, 7] -= gl * el * s + gt * et * c
        _particle_forces(C, off, 0, 1, y, nq + off, n, vx, vy, gl, gt, m, C, 4, True)
    _project_node_forces(fac, system, C, acc)
    if system.hub_free:  # the hub's drag on its rate
        acc[na] -= system.hub_drag * y[nq + na]
    general_mass(system, C, L[1])
    cholesky(L[1], L[0])
    chol_solve(L[0], out, nq)
    if system.pinned:  # as eval_rhs_inertial (no head: nq = n)
        _pin_acceleration(C, 0, 1, y, nq, n, beta, system.delta, L[0], X, acc, lam)


@njit(cache=True)
def general_drag(system, C, A):
    """A[:nq, :nq] = D(q) over the angles and the free head, from the geometry C (_general_geometry): the angle
    blocks as drag_block (suffix sums S_m of W_i), D_{k,h} = S_k n_k, D_hh = S_0 + W(th_0) (the head's drag);
    zero between the chains of a pair."""
    n = system.n
    na = n * system.n_chains
    gl = system.gamma_l
    gt = system.gamma_t
    A[:, :] = 0.0
    for ch in range(system.n_chains):
        off = ch * n
        head = system.head_free and ch == 0
        sxx = 0.0
        sxy = 0.0
        syy = 0.0
        for m in range(n - 1, -1, -1):
            cm = C[off + m, 0]
            sm = C[off + m, 1]
            sxx += gl * cm * cm + gt * sm * sm
            sxy += (gl - gt) * cm * sm
            syy += gl * sm * sm + gt * cm * cm
            for j in range(m + 1):
                cj = C[off + j, 0]
                sj = C[off + j, 1]
                v = sj * sm * sxx - (sj * cm + cj * sm) * sxy + cj * cm * syy
                A[off + j, off + m] = v
                A[off + m, off + j] = v
            if head:
                vx = -sm * sxx + cm * sxy
                vy = -sm * sxy + cm * syy
                A[off + m, na] = vx
                A[na, off + m] = vx
                A[off + m, na + 1] = vy
                A[na + 1, off + m] = vy
        if head:
            c0 = C[off, 0]
            s0 = C[off, 1]
            A[na, na] = sxx + gl * c0 * c0 + gt * s0 * s0
            v = sxy + (gl - gt) * c0 * s0
            A[na, na + 1] = v
            A[na + 1, na] = v
            A[na + 1, na + 1] = syy + gl * s0 * s0 + gt * c0 * c0
    if system.hub_free:  # a star's hub: its own rotational drag, no particle (the arms' drag does not move it)
        A[na, na] = system.hub_drag


@njit(cache=True)
def eval_rhs_general(y, fac, system, beta, out, L, C, X, lam):
    """out = q' at the state q = y (the angles, then the free head) with every term on (equations.py: a free
    head, a harmonic trap and self-contact): f by general_forces, D by general_drag (O(N^2) each), dense
    Cholesky (L[0]; L[1] holds D); the pinned chain's Baumgarte saddle point as in eval_rhs_dense (X = D^-1 G^T,
    multipliers in lam; with a free head, the free ring, G's head columns are zero and X's head rows carry the
    constraint's pull on the head). L, C, X, lam: make_general_workspace."""
    n = system.n
    na = n * system.n_chains
    nq = na + _n_after(system)
    if L.shape[0] < 2 or L.shape[1] != nq or L.shape[2] != nq or C.shape[0] < na or C.shape[1] < 8 or X.shape[0] < nq:
        raise ValueError(
            "eval_rhs_general needs make_general_workspace's arrays: L (2, nq, nq), C (n_angles, 8), X (nq, 2)"
        )
    if y.size < nq or out.size < nq:
        raise ValueError("eval_rhs_general: the state holds n_angles numbers, plus 2 with a free head (1 with a hub)")
    general_forces(y, fac, system, C, out)
    general_drag(system, C, L[1])
    cholesky(L[1], L[0])
    chol_solve(L[0], out, 0)
    if system.pinned:  # G: the last particle relative to the pivot, (sum cos th_i, sum sin th_i); no head columns
        for i in range(nq):
            if i < n:
                X[i, 0] = -C[i, 1]
                X[i, 1] = C[i, 0]
            else:
                X[i, 0] = 0.0
                X[i, 1] = 0.0
        chol_solve_cols(L[0], X, 0)
        _pin_correction(y, n, beta, system.delta, out, X, lam, C, False)
        for i in range(n, nq):  # the free ring: the constraint forces move the head too
            out[i] -= X[i, 0] * lam[0] + X[i, 1] * lam[1]

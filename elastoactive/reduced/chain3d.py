r"""The reduced overdamped model of a chain in three dimensions: unit tangents, their right-hand side, its solver.

The derivation is docs/model3d.md; in short (units l = C1 = gamma_T = 1):

  coordinates   the N unit tangents t_k of the links (3N numbers, |t_k| = 1), particle i at r_i = sum_{k<=i} t_k;
                no angles, so no pole: every direction of every link is a regular point. Each link has two degrees of
                freedom, dt_k = E_k dq_k with E_k = [a_k, b_k] any orthonormal basis of the plane normal to t_k
                (basis_of: a_k = e_z x t_k / |.|, b_k = t_k x a_k; for a planar chain in the xy plane b_k = e_z
                exactly, so the out-of-plane rows are exact zeros and a planar start stays planar bit for bit)
  bending       U = C/2 sum_k phi_k^2, phi_k = angle(t_{k-1}, t_k) (t_0 = e_x, the clamp; absent on a free pin),
                dU/dt_k projected on the normal plane: -C phi / sin(phi) (t_{k-1} - cos(phi) t_k) from the bend
                before link k, and likewise from the bend after it; in the plane this is exactly the planar
                C/2 (theta_k - theta_{k-1})^2
  twist         none: the particles are points on the links' axes, the follower force and the drag act along or
                across the link through its axis and the bending energy is isotropic, so nothing twists a link and
                the relaxed twist (the minimum of the bending-and-twist spring over the twist, which is zero twist
                for every shape) is all the model needs: the material frames are the discrete parallel transport
                of the clamp's frame and carry no dynamics (docs/model3d.md, section 3)
  follower      F_i = -sigma w_i t_i on particle i (w_i = Chain3D.load's weight, 1 on every particle by default)
  drag          F^d_i = -W_i v_i, W_i = gamma_T (1 - t_i t_i^T) + gamma_L t_i t_i^T (axisymmetric about the link)
  overdamped    D(t) q' = f(t), D_kj = E_k^T (sum_{i >= max(k, j)} W_i) E_j (2 x 2 blocks, symmetric positive
                definite), f_k = E_k^T (sum_{i >= k} F_i - dU/dt_k); t_k' = E_k q'_k

The right-hand side normalises each tangent before use and adds -(|t_k|^2 - 1) / 2 t_k, which keeps |t_k| = 1
against the integrator's round-off (the exact flow conserves it: t_k . t_k' = 0).

Solving D q' = f in O(N) (the articulated-drag recursion, the planar kernels' in three dimensions): the links k..N
seen from particle k-1 moving at velocity V are one body whose drag-minus-load force is R_k(V) = K_k V + c_k (K_k a
3 x 3 articulated drag). From the tip (K_{N+1} = 0, c_{N+1} = 0): W^_k = W_k + K_{k+1}, c^_k = c_{k+1} - F_k,
H_k = E_k^T W^_k E_k (2 x 2), r_k = E_k^T (c^_k + dU/dt_k); link k's equation E_k^T (R_k + dU/dt_k) = 0 gives
q'_k = -H_k^-1 (E_k^T W^_k V + r_k), hence K_k = W^_k - W^_k E_k H_k^-1 E_k^T W^_k, c_k = c^_k - W^_k E_k H_k^-1 r_k.
Then from the anchor (V = 0) each q'_k, and V += E_k q'_k. Its Jacobian d t'/d t (eval_jacobian3d) is analytic:
moving y_j (one component of tangent j) turns u_j and the basis E_j, which puts a point force on particle j (its drag
tensor and load turned), shifts the velocity of particles j.. by dE_j q'_j, changes the bending gradients of links
j-1, j, j+1 (their 3 x 3 second derivatives, _bend_hessian) and turns link j's projection of the force
Lam_j = sum_{i >= j} (W_i v_i - F_i) + dU/dt_j; that perturbation is solved by the same recursion with the unperturbed
K's: O(N) a column.

Plain-numpy twin (rhs_reference, dense solve) and compiled kernel (eval_rhs3d) give the same numbers; solve3d
integrates with scipy's solve_ivp on the compiled kernel: DOP853, or, for the long chain near its onset (stiff: its
fastest relaxation stays ~16 / tau while its period grows like N^4), LSODA with the analytic Jacobian (choose_method;
it imports scipy.integrate when called: ~0.4 s of start-up the rest of the package does not pay).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import ParameterError
from .blas import one_blas_thread

__all__ = [
    "METHODS3D",
    "Chain3D",
    "basis_of",
    "choose_method",
    "eval_jacobian3d",
    "eval_rhs3d",
    "jacobian",
    "planar_angles",
    "positions",
    "rhs",
    "rhs_reference",
    "solve3d",
    "tangents_of_angles",
]


class Chain3D(NamedTuple):
    """A chain of n links in three dimensions (units l = C1 = gamma_T = 1).

    n        particles (links) N >= 1
    sigma    follower force F_a l / C1 on a loaded particle, along its link toward the anchor
    gamma_l  drag along each link (gamma_T = 1 across it, the same in both transverse directions)
    clamped  a bending spring holds link 1 along e_x (False: a free ball pivot)
    load     the follower force's weight on each particle, N numbers >= 0 (1.0 loaded, 0.0 not; particle i carries
             -load[i] sigma t_i); empty: every particle carries it (weight 1). (0.0, ..., 0.0, 1.0) is the chain
             loaded at its tip only
    """

    n: int
    sigma: float
    gamma_l: float = 1.0
    clamped: bool = True
    load: tuple[float, ...] = ()

    def checked(self) -> Chain3D:
        """The record, or ParameterError naming the first parameter out of range."""
        if int(self.n) < 1:
            raise ParameterError(f"n (number of particles N) must be >= 1, got {self.n}")
        if not (np.isfinite(self.sigma) and self.sigma >= 0):
            raise ParameterError(f"sigma must be finite and >= 0, got {self.sigma}")
        if not (np.isfinite(self.gamma_l) and self.gamma_l > 0):
            raise ParameterError(f"gamma_l (drag ratio) must be finite and > 0, got {self.gamma_l}")
        if len(self.load) not in (0, int(self.n)):
            raise ParameterError(
                f"load must hold {int(self.n)} weights (one per particle) or none, got {len(self.load)}"
            )
        if not all(np.isfinite(w) and w >= 0 for w in self.load):
            raise ParameterError(f"load (the particles' weights) must be finite and >= 0, got {self.load}")
        return self

    def weights(self) -> np.ndarray:
        """The load's weight on each particle, N numbers (ones when load is empty)."""
        if len(self.load) == 0:
            return np.ones(int(self.n))
        return np.asarray(self.load, dtype=float)


def tangents_of_angles(theta: np.ndarray) -> np.ndarray:
    """Tangents (N, 3) of a planar chain with absolute angles theta in the xy plane."""
    theta = np.asarray(theta, dtype=float)
    return np.stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)], axis=-1)


def planar_angles(tangents: np.ndarray) -> np.ndarray:
    """Absolute angles in the xy plane of tangents (..., N, 3), unwrapped along the chain (the planar model's theta
    for a planar chain)."""
    return np.unwrap(np.arctan2(tangents[..., 1], tangents[..., 0]), axis=-1)


def positions(tangents: np.ndarray) -> np.ndarray:
    """Particle positions r_i = sum_{k<=i} t_k, shape (..., N, 3) (the anchor at the origin)."""
    return np.cumsum(tangents, axis=-2)


def basis_of(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """An orthonormal basis (a, b) of the plane normal to the unit vector u: a = e_z x u / |.| (e_x x u / |.| when u
    lies within 60 degrees of the z axis), b = u x a."""
    if u[0] * u[0] + u[1] * u[1] > 0.25:
        a = np.array([-u[1], u[0], 0.0])
    else:
        a = np.array([0.0, -u[2], u[1]])
    a /= np.sqrt(a @ a)
    return a, np.cross(u, a)


def _bend(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """d(phi^2 / 2)/dq projected on the plane normal to q, phi = angle(p, q) (unit p, q): -phi w / |w|,
    w = p - (p . q) q."""
    w = p - (p @ q) * q
    s = np.sqrt(w @ w)
    if s == 0.0:
        return np.zeros(3)
    phi = math.atan2(np.linalg.norm(np.cross(p, q)), p @ q)
    return -phi * w / s


def rhs_reference(tangents: np.ndarray, chain: Chain3D) -> np.ndarray:
    """t' (N, 3) of the overdamped chain at tangents (N, 3) (plain numpy: the equations as written above)."""
    n = chain.n
    t = np.asarray(tangents, dtype=float).reshape(n, 3)
    norm2 = np.einsum("ij,ij->i", t, t)
    u = t / np.sqrt(norm2)[:, None]
    E = np.zeros((n, 3, 2))
    for k in range(n):
        E[k, :, 0], E[k, :, 1] = basis_of(u[k])
    grad = np.zeros((n, 3))  # dU/dt_k, projected
    if chain.clamped:
        grad[0] += _bend(np.array([1.0, 0.0, 0.0]), u[0])
    for k in range(1, n):
        grad[k] += _bend(u[k - 1], u[k])
        grad[k - 1] += _bend(u[k], u[k - 1])
    active = -chain.sigma * np.cumsum((chain.weights()[:, None] * u)[::-1], axis=0)[::-1]  # sum_{i>=k} F_i
    W = np.eye(3)[None] + (chain.gamma_l - 1.0) * np.einsum("ia,ib->iab", u, u)
    S = np.cumsum(W[::-1], axis=0)[::-1]  # sum_{i>=m} W_i
    D = np.zeros((2 * n, 2 * n))
    f = np.zeros(2 * n)
    for k in range(n):
        f[2 * k : 2 * k + 2] = E[k].T @ (active[k] - grad[k])
        for j in range(n):
            D[2 * k : 2 * k + 2, 2 * j : 2 * j + 2] = E[k].T @ S[max(k, j)] @ E[j]
    qdot = np.linalg.solve(D, f)
    tdot = np.einsum("kab,kb->ka", E, qdot.reshape(n, 2))
    return tdot - 0.5 * (norm2 - 1.0)[:, None] * u


@njit(cache=True)
def _bend_into(p0, p1, p2, q0, q1, q2, out, k, scale):
    """out[k] += scale * d(phi^2 / 2)/dq (projected), phi = angle(p, q); the compiled _bend."""
    pq = p0 * q0 + p1 * q1 + p2 * q2
    w0, w1, w2 = p0 - pq * q0, p1 - pq * q1, p2 - pq * q2
    s = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    if s == 0.0:
        return
    c0, c1, c2 = p1 * q2 - p2 * q1, p2 * q0 - p0 * q2, p0 * q1 - p1 * q0
    phi = math.atan2(math.sqrt(c0 * c0 + c1 * c1 + c2 * c2), pq)
    g = -scale * phi / s
    out[k, 0] += g * w0
    out[k, 1] += g * w1
    out[k, 2] += g * w2


@njit(cache=True)
def _basis_into(u, E):
    """E[k, 0] = a_k, E[k, 1] = b_k for the unit tangents u (the compiled basis_of)."""
    for k in range(u.shape[0]):
        u0, u1, u2 = u[k, 0], u[k, 1], u[k, 2]
        if u0 * u0 + u1 * u1 > 0.25:
            a0, a1, a2 = -u1, u0, 0.0
        else:
            a0, a1, a2 = 0.0, -u2, u1
        r = 1.0 / math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        a0, a1, a2 = a0 * r, a1 * r, a2 * r
        E[k, 0, 0], E[k, 0, 1], E[k, 0, 2] = a0, a1, a2
        E[k, 1, 0], E[k, 1, 1], E[k, 1, 2] = u1 * a2 - u2 * a1, u2 * a0 - u0 * a2, u0 * a1 - u1 * a0


@njit(cache=True)
def _sweeps(y, n, sigma, gamma_l, clamped, weights, out, u, norm2, E, grad, WE, Hi, rr, What, q, v):
    """eval_rhs3d into out, keeping what the Jacobian reuses: the unit tangents u, |y_k|^2, the bases E, the bending
    gradient, per link the articulated drag W-hat_k (What, the upper triangle 00 01 02 11 12 22) and W-hat_k a_k,
    W-hat_k b_k (WE), H_k^-1 (Hi: 11 12 22), the reduced force rr, and the solution q_k and particle velocities v."""
    for k in range(n):
        x0, x1, x2 = y[3 * k], y[3 * k + 1], y[3 * k + 2]
        norm2[k] = x0 * x0 + x1 * x1 + x2 * x2
        r = 1.0 / math.sqrt(norm2[k])
        u[k, 0], u[k, 1], u[k, 2] = x0 * r, x1 * r, x2 * r
    _basis_into(u, E)
    grad[:] = 0.0
    if clamped:
        _bend_into(1.0, 0.0, 0.0, u[0, 0], u[0, 1], u[0, 2], grad, 0, 1.0)
    for k in range(1, n):
        _bend_into(u[k - 1, 0], u[k - 1, 1], u[k - 1, 2], u[k, 0], u[k, 1], u[k, 2], grad, k, 1.0)
        _bend_into(u[k, 0], u[k, 1], u[k, 2], u[k - 1, 0], u[k - 1, 1], u[k - 1, 2], grad, k - 1, 1.0)
    # backward sweep: links k..N as one body seen from particle k-1 moving at V, R_k(V) = K V + c
    K = np.zeros((3, 3))
    c = np.zeros(3)
    dg = gamma_l - 1.0
    for k in range(n - 1, -1, -1):
        u0, u1, u2 = u[k, 0], u[k, 1], u[k, 2]
        ld = sigma * weights[k]
        K[0, 0] += 1.0 + dg * u0 * u0
        K[1, 1] += 1.0 + dg * u1 * u1
        K[2, 2] += 1.0 + dg * u2 * u2
        K[0, 1] += dg * u0 * u1
        K[0, 2] += dg * u0 * u2
        K[1, 2] += dg * u1 * u2
        K[1, 0], K[2, 0], K[2, 1] = K[0, 1], K[0, 2], K[1, 2]
        What[k, 0], What[k, 1], What[k, 2] = K[0, 0], K[0, 1], K[0, 2]
        What[k, 3], What[k, 4], What[k, 5] = K[1, 1], K[1, 2], K[2, 2]
        c[0] += ld * u0
        c[1] += ld * u1
        c[2] += ld * u2
        for al in range(2):
            for a in range(3):
                WE[k, al, a] = K[a, 0] * E[k, al, 0] + K[a, 1] * E[k, al, 1] + K[a, 2] * E[k, al, 2]
        h11 = E[k, 0, 0] * WE[k, 0, 0] + E[k, 0, 1] * WE[k, 0, 1] + E[k, 0, 2] * WE[k, 0, 2]
        h12 = E[k, 0, 0] * WE[k, 1, 0] + E[k, 0, 1] * WE[k, 1, 1] + E[k, 0, 2] * WE[k, 1, 2]
        h22 = E[k, 1, 0] * WE[k, 1, 0] + E[k, 1, 1] * WE[k, 1, 1] + E[k, 1, 2] * WE[k, 1, 2]
        det = h11 * h22 - h12 * h12
        i11, i12, i22 = h22 / det, -h12 / det, h11 / det
        Hi[k, 0], Hi[k, 1], Hi[k, 2] = i11, i12, i22
        g0, g1, g2 = c[0] + grad[k, 0], c[1] + grad[k, 1], c[2] + grad[k, 2]
        r0 = E[k, 0, 0] * g0 + E[k, 0, 1] * g1 + E[k, 0, 2] * g2
        r1 = E[k, 1, 0] * g0 + E[k, 1, 1] * g1 + E[k, 1, 2] * g2
        rr[k, 0], rr[k, 1] = r0, r1
        s0, s1 = i11 * r0 + i12 * r1, i12 * r0 + i22 * r1
        for a in range(3):
            c[a] -= WE[k, 0, a] * s0 + WE[k, 1, a] * s1
            p0 = i11 * WE[k, 0, a] + i12 * WE[k, 1, a]
            p1 = i12 * WE[k, 0, a] + i22 * WE[k, 1, a]
            for b in range(a, 3):
                K[a, b] -= WE[k, 0, b] * p0 + WE[k, 1, b] * p1
    # forward sweep: from the anchor at rest, q_k = -H_k^-1 (E_k W-hat_k V + rr_k), V += E_k^T q_k
    V0, V1, V2 = 0.0, 0.0, 0.0
    for k in range(n):
        s0 = WE[k, 0, 0] * V0 + WE[k, 0, 1] * V1 + WE[k, 0, 2] * V2 + rr[k, 0]
        s1 = WE[k, 1, 0] * V0 + WE[k, 1, 1] * V1 + WE[k, 1, 2] * V2 + rr[k, 1]
        q0 = -(Hi[k, 0] * s0 + Hi[k, 1] * s1)
        q1 = -(Hi[k, 1] * s0 + Hi[k, 2] * s1)
        q[k, 0], q[k, 1] = q0, q1
        d0 = E[k, 0, 0] * q0 + E[k, 1, 0] * q1
        d1 = E[k, 0, 1] * q0 + E[k, 1, 1] * q1
        d2 = E[k, 0, 2] * q0 + E[k, 1, 2] * q1
        V0 += d0
        V1 += d1
        V2 += d2
        v[k, 0], v[k, 1], v[k, 2] = V0, V1, V2
        h = 0.5 * (norm2[k] - 1.0)
        out[3 * k] = d0 - h * u[k, 0]
        out[3 * k + 1] = d1 - h * u[k, 1]
        out[3 * k + 2] = d2 - h * u[k, 2]
    return out


@njit(cache=True)
def eval_rhs3d(y, n, sigma, gamma_l, clamped, weights, out):
    """t' of the overdamped chain into out (3n), at the tangents y (3n, link by link), particle i loaded by
    weights[i] x sigma: the compiled rhs_reference (the same basis, forces and drag), with D q = f solved in O(N) by
    the articulated-drag recursion (module docstring) instead of a dense factorisation. In a plane every
    out-of-plane entry it forms is a product with an exact zero, so the out-of-plane rows stay exact zeros."""
    return _sweeps(
        y, n, sigma, gamma_l, clamped, weights, out, np.empty((n, 3)), np.empty(n), np.empty((n, 2, 3)),
        np.empty((n, 3)), np.empty((n, 2, 3)), np.empty((n, 3)), np.empty((n, 2)), np.empty((n, 6)),
        np.empty((n, 2)), np.empty((n, 3)),
    )  # fmt: skip


@njit(cache=True)
def _bend_hessian(p0, p1, p2, q0, q1, q2, dp, dq):
    """The derivatives (3 x 3) of the bending gradient _bend_into adds, B(p, q) = -rho(phi) w with w = p - c q,
    c = p . q, rho = phi / sin(phi), by p added into dp and by q into dq, for unit p, q moved along their spheres
    (dphi = -dc / sin(phi)): dB/dp = rho'/sin w q^T - rho (1 - q q^T), dB/dq = rho'/sin w p^T + rho (c + q p^T);
    rho'/sin = (sin - phi c) / sin^3 tends to 1/3 + 2 phi^2 / 15 at small phi (used below phi = 1e-3)."""
    c = p0 * q0 + p1 * q1 + p2 * q2
    w = np.array([p0 - c * q0, p1 - c * q1, p2 - c * q2])
    s = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    phi = math.atan2(s, c)
    if phi < 1e-3:
        rho = 1.0 + phi * phi / 6.0
        slope = 1.0 / 3.0 + 2.0 / 15.0 * phi * phi
    else:
        rho = phi / s
        slope = (s - phi * c) / (s * s * s)  # rho'(phi) / sin(phi)
    p = (p0, p1, p2)
    q = (q0, q1, q2)
    for a in range(3):
        for b in range(3):
            eye = 1.0 if a == b else 0.0
            dp[a, b] += slope * w[a] * q[b] - rho * (eye - q[a] * q[b])
            dq[a, b] += slope * w[a] * p[b] + rho * (c * eye + q[a] * p[b])


@njit(cache=True)
def eval_jacobian3d(y, n, sigma, gamma_l, clamped, weights, J):
    """d t' / d t (3n x 3n) into J at the tangents y, analytic: the right-hand side's derivative by each y_j,a, the
    perturbed forces (a point force on particle j, a velocity shift of the particles beyond it, the bending
    gradients of links j-1, j, j+1, the turn of the basis E_j) solved by the same recursion with the articulated
    drag of the unperturbed chain: O(N) a column, O(N^2) in all (the drag couples every link to every other, so J is
    dense)."""
    out = np.empty(3 * n)
    u, norm2, E = np.empty((n, 3)), np.empty(n), np.empty((n, 2, 3))
    grad, WE, Hi = np.empty((n, 3)), np.empty((n, 2, 3)), np.empty((n, 3))
    rr, What, q, v = np.empty((n, 2)), np.empty((n, 6)), np.empty((n, 2)), np.empty((n, 3))
    _sweeps(y, n, sigma, gamma_l, clamped, weights, out, u, norm2, E, grad, WE, Hi, rr, What, q, v)
    dg = gamma_l - 1.0
    # Lam_k = sum_{i >= k} (W_i v_i - F_i) + grad_k: the force whose part across link k vanishes (its tension is left)
    lam = np.empty((n, 3))
    acc = np.zeros(3)
    for k in range(n - 1, -1, -1):
        uv = u[k, 0] * v[k, 0] + u[k, 1] * v[k, 1] + u[k, 2] * v[k, 2]
        for a in range(3):
            acc[a] += v[k, a] + dg * u[k, a] * uv + sigma * weights[k] * u[k, a]
            lam[k, a] = acc[a] + grad[k, a]
    # the bending gradients' derivatives: G[k, 0] = d grad_{k-1} / d u_k, G[k, 1] = d grad_k / d u_k,
    # G[k, 2] = d grad_{k+1} / d u_k
    G = np.zeros((n, 3, 3, 3))
    scratch = np.zeros((3, 3))
    if clamped:
        _bend_hessian(1.0, 0.0, 0.0, u[0, 0], u[0, 1], u[0, 2], scratch, G[0, 1])
    for k in range(1, n):
        _bend_hessian(u[k - 1, 0], u[k - 1, 1], u[k - 1, 2], u[k, 0], u[k, 1], u[k, 2], G[k - 1, 2], G[k, 1])
        _bend_hessian(u[k, 0], u[k, 1], u[k, 2], u[k - 1, 0], u[k - 1, 1], u[k - 1, 2], G[k, 0], G[k - 1, 1])
    du = np.empty(3)
    da = np.empty(3)
    db = np.empty(3)
    w = np.empty(3)
    force = np.empty(3)
    ell = np.zeros((n, 2))
    c = np.empty(3)
    for j in range(n):
        rn = 1.0 / math.sqrt(norm2[j])
        u0, u1, u2 = u[j, 0], u[j, 1], u[j, 2]
        first, last = max(j - 1, 0), min(j + 1, n - 1)
        for col in range(3):
            # the tangent's turn du, and the basis's: a = A / |A|, b = u x a
            for a in range(3):
                du[a] = ((1.0 if a == col else 0.0) - u[j, a] * u[j, col]) * rn
            if u0 * u0 + u1 * u1 > 0.25:
                A0, A1, A2, dA0, dA1, dA2 = -u1, u0, 0.0, -du[1], du[0], 0.0
            else:
                A0, A1, A2, dA0, dA1, dA2 = 0.0, -u2, u1, 0.0, -du[2], du[1]
            rA = 1.0 / math.sqrt(A0 * A0 + A1 * A1 + A2 * A2)
            ea0, ea1, ea2 = E[j, 0, 0], E[j, 0, 1], E[j, 0, 2]
            proj = ea0 * dA0 + ea1 * dA1 + ea2 * dA2
            da[0], da[1], da[2] = (dA0 - ea0 * proj) * rA, (dA1 - ea1 * proj) * rA, (dA2 - ea2 * proj) * rA
            db[0] = du[1] * ea2 - du[2] * ea1 + u1 * da[2] - u2 * da[1]
            db[1] = du[2] * ea0 - du[0] * ea2 + u2 * da[0] - u0 * da[2]
            db[2] = du[0] * ea1 - du[1] * ea0 + u0 * da[1] - u1 * da[0]
            # the velocity shift of particles j.. (w = dE_j^T q_j) and the point force on particle j
            uv = u0 * v[j, 0] + u1 * v[j, 1] + u2 * v[j, 2]
            duv = du[0] * v[j, 0] + du[1] * v[j, 1] + du[2] * v[j, 2]
            for a in range(3):
                w[a] = q[j, 0] * da[a] + q[j, 1] * db[a]
                force[a] = dg * (du[a] * uv + u[j, a] * duv) + sigma * weights[j] * du[a]
            # the reduced generalised forces of links j-1, j, j+1: E_m d grad_m, and dE_j Lam_j
            for m in range(first, last + 1):
                slot = m - j + 1
                g0, g1, g2 = 0.0, 0.0, 0.0
                for a in range(3):
                    g0 += G[j, slot, 0, a] * du[a]
                    g1 += G[j, slot, 1, a] * du[a]
                    g2 += G[j, slot, 2, a] * du[a]
                ell[m, 0] = E[m, 0, 0] * g0 + E[m, 0, 1] * g1 + E[m, 0, 2] * g2
                ell[m, 1] = E[m, 1, 0] * g0 + E[m, 1, 1] * g1 + E[m, 1, 2] * g2
            ell[j, 0] += da[0] * lam[j, 0] + da[1] * lam[j, 1] + da[2] * lam[j, 2]
            ell[j, 1] += db[0] * lam[j, 0] + db[1] * lam[j, 1] + db[2] * lam[j, 2]
            # backward sweep from link j+1 (nothing beyond it changes)
            c[0], c[1], c[2] = 0.0, 0.0, 0.0
            for k in range(last, -1, -1):
                if k == j:
                    c[0] += force[0]
                    c[1] += force[1]
                    c[2] += force[2]
                r0 = E[k, 0, 0] * c[0] + E[k, 0, 1] * c[1] + E[k, 0, 2] * c[2] + ell[k, 0]
                r1 = E[k, 1, 0] * c[0] + E[k, 1, 1] * c[1] + E[k, 1, 2] * c[2] + ell[k, 1]
                if k == j:
                    r0 += WE[k, 0, 0] * w[0] + WE[k, 0, 1] * w[1] + WE[k, 0, 2] * w[2]
                    r1 += WE[k, 1, 0] * w[0] + WE[k, 1, 1] * w[1] + WE[k, 1, 2] * w[2]
                ell[k, 0], ell[k, 1] = r0, r1  # ell now holds the perturbed rr
                s0, s1 = Hi[k, 0] * r0 + Hi[k, 1] * r1, Hi[k, 1] * r0 + Hi[k, 2] * r1
                for a in range(3):
                    c[a] -= WE[k, 0, a] * s0 + WE[k, 1, a] * s1
                if k == j:
                    W = What[k]
                    c[0] += W[0] * w[0] + W[1] * w[1] + W[2] * w[2]
                    c[1] += W[1] * w[0] + W[3] * w[1] + W[4] * w[2]
                    c[2] += W[2] * w[0] + W[4] * w[1] + W[5] * w[2]
            # forward sweep over the whole chain
            V0, V1, V2 = 0.0, 0.0, 0.0
            column = 3 * j + col
            for k in range(n):
                s0 = WE[k, 0, 0] * V0 + WE[k, 0, 1] * V1 + WE[k, 0, 2] * V2
                s1 = WE[k, 1, 0] * V0 + WE[k, 1, 1] * V1 + WE[k, 1, 2] * V2
                if k <= last:
                    s0 += ell[k, 0]
                    s1 += ell[k, 1]
                    ell[k, 0], ell[k, 1] = 0.0, 0.0
                q0 = -(Hi[k, 0] * s0 + Hi[k, 1] * s1)
                q1 = -(Hi[k, 1] * s0 + Hi[k, 2] * s1)
                d0 = E[k, 0, 0] * q0 + E[k, 1, 0] * q1
                d1 = E[k, 0, 1] * q0 + E[k, 1, 1] * q1
                d2 = E[k, 0, 2] * q0 + E[k, 1, 2] * q1
                V0 += d0
                V1 += d1
                V2 += d2
                if k == j:
                    V0 += w[0]
                    V1 += w[1]
                    V2 += w[2]
                    h = 0.5 * (norm2[j] - 1.0)
                    yd = y[column]  # (y . dy) with dy the unit vector of this column
                    d0 += w[0] - yd * u0 - h * du[0]
                    d1 += w[1] - yd * u1 - h * du[1]
                    d2 += w[2] - yd * u2 - h * du[2]
                J[3 * k, column] = d0
                J[3 * k + 1, column] = d1
                J[3 * k + 2, column] = d2
    return J


def rhs(tangents: np.ndarray, chain: Chain3D) -> np.ndarray:
    """t' (N, 3) by the compiled kernel."""
    y = np.ascontiguousarray(tangents, dtype=float).ravel()
    out = np.empty(y.size)
    n, sigma, gamma_l, clamped, weights = _arguments(chain)
    eval_rhs3d(y, n, sigma, gamma_l, clamped, weights, out)
    return out.reshape(chain.n, 3)


def jacobian(tangents: np.ndarray, chain: Chain3D) -> np.ndarray:
    """d t' / d t, (3N, 3N) over the tangents (N, 3) flattened link by link (eval_jacobian3d)."""
    y = np.ascontiguousarray(tangents, dtype=float).ravel()
    n, sigma, gamma_l, clamped, weights = _arguments(chain)
    return eval_jacobian3d(y, n, sigma, gamma_l, clamped, weights, np.empty((3 * n, 3 * n)))


def _arguments(chain: Chain3D) -> tuple[int, float, float, bool, np.ndarray]:
    """The kernels' arguments of the chain, typed (one compiled signature)."""
    chain.checked()
    return int(chain.n), float(chain.sigma), float(chain.gamma_l), bool(chain.clamped), chain.weights()


METHODS3D = ("DOP853", "LSODA", "Radau", "BDF")
"""solve3d's methods (scipy.integrate.solve_ivp's names; the implicit ones are given eval_jacobian3d)."""


IMPLICIT_RATIO3D = 5.0
"""Stiffness ratio (reduced.solve.stiffness_ratio of the Jacobian's eigenvalues at the start) above which a long run
(IMPLICIT_WORK3D) takes LSODA: below it the motion is as fast as the fastest relaxation (a chain far above onset)
and DOP853 is cheaper (N = 100, sigma = 0.8, ratio 0.08, 300 tau: DOP853 0.7 s against LSODA 1.9 s of CPU)."""

IMPLICIT_WORK3D = 5.0e3
"""Duration x fastest decay rate at the start (about 3 x DOP853's steps) above which a stiff run (IMPLICIT_RATIO3D)
takes LSODA. solve3d's DOP853 is scipy's (~20 us of Python a right-hand side, against the planar engine's compiled
numba-DOP853), so the crossover is lower than the planar IMPLICIT_WORK: one whirl period at S = 100 costs DOP853
0.13, 0.97, 2.6 s of CPU at N = 10, 16, 20 (work 3e3, 2.2e4, 5.6e4) against LSODA 0.04, 0.05, 0.06 s."""


def choose_method(eig: np.ndarray, duration: float) -> str:
    """method=None of solve3d: "LSODA" (its stiff branch BDF with the analytic Jacobian) when the stiffness ratio
    (reduced.solve.stiffness_ratio: the fastest decay rate over the slow dynamics, from the Jacobian's eigenvalues eig
    at the start) is above IMPLICIT_RATIO3D and the run long enough for explicit steps to add up (duration x fastest
    decay above IMPLICIT_WORK3D): the long chain near its onset, its ratio ~ N^4 at a whirl; else "DOP853"."""
    from .solve import stiffness_ratio  # the planar engine's measure (numba kernels: loaded only when choosing)

    eig = np.asarray(eig, dtype=complex)
    decay = float(max(0.0, np.max(-eig.real))) if eig.size else 0.0
    if stiffness_ratio(eig) > IMPLICIT_RATIO3D and duration * decay > IMPLICIT_WORK3D:
        return "LSODA"
    return "DOP853"


def solve3d(
    chain: Chain3D,
    ts: np.ndarray,
    tangents0: np.ndarray,
    *,
    rtol: float = 1e-9,
    atol: float = 1e-9,
    method: str | None = None,
    on_time=None,
    budget=None,
):
    """Tangents (len(ts), N, 3) of the chain from tangents0 (N, 3) at t = 0, sampled at ts (scipy's solve_ivp on the
    compiled right-hand side). Raises RuntimeError naming the solver's message when it fails.

    method: a name of METHODS3D, or None: choose_method at the Jacobian's eigenvalues at the start (DOP853 for short
    chains, short runs and chains well above onset; LSODA with the Jacobian for the long, stiff chain). on_time(t):
    told the time of every right-hand side evaluation (a progress bar; it changes nothing computed, what it raises
    stops the run). budget(method, eig): given the method that will run and the eigenvalues of the right-hand side's
    Jacobian at the start, before the first step: it may refuse the run."""
    # start-up time: scipy.integrate costs ~0.4 s to import; only the integration needs it
    from scipy.integrate import solve_ivp

    if method is not None and method not in METHODS3D:
        raise ParameterError(f"method must be one of {', '.join(METHODS3D)} (or None: automatic), got {method!r}")
    n, sigma, gamma_l, clamped, weights = _arguments(chain)
    ts = np.asarray(ts, dtype=float)
    out = np.empty(3 * n)
    J = np.empty((3 * n, 3 * n))

    def rate(_t, y):
        return eval_rhs3d(y, n, sigma, gamma_l, clamped, weights, out).copy()

    def jac(_t, y):
        return eval_jacobian3d(y, n, sigma, gamma_l, clamped, weights, J).copy()

    y0 = np.ascontiguousarray(tangents0, dtype=float).ravel()
    if y0.size != 3 * n:
        raise ParameterError(f"tangents0 must hold {n} tangents (shape ({n}, 3)), got {np.shape(tangents0)}")
    eig = None
    if method is None or budget is not None:
        eig = np.linalg.eigvals(jac(0.0, y0))
    if method is None:
        method = choose_method(eig, float(ts[-1] - ts[0]))
    if budget is not None:
        budget(method, eig)
    if on_time is None:
        fun = rate
    else:

        def fun(t, y):
            on_time(t)
            return rate(t, y)

    kw = {} if method == "DOP853" else {"jac": jac}
    with one_blas_thread():  # the implicit methods' LU factorisations (blas.py)
        sol = solve_ivp(fun, (ts[0], ts[-1]), y0, method=method, t_eval=ts, rtol=rtol, atol=atol, **kw)
    if not sol.success:
        raise RuntimeError(f"3D chain: the {method} solver failed ({sol.message})")
    return sol.y.T.reshape(ts.size, n, 3)

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
  follower      F_i = -sigma t_i on particle i
  drag          F^d_i = -W_i v_i, W_i = gamma_T (1 - t_i t_i^T) + gamma_L t_i t_i^T (axisymmetric about the link)
  overdamped    D(t) q' = f(t), D_kj = E_k^T (sum_{i >= max(k, j)} W_i) E_j (2 x 2 blocks, symmetric positive
                definite), f_k = E_k^T (sum_{i >= k} F_i - dU/dt_k); t_k' = E_k q'_k

The right-hand side normalises each tangent before use and adds -(|t_k|^2 - 1) / 2 t_k, which keeps |t_k| = 1
against the integrator's round-off (the exact flow conserves it: t_k . t_k' = 0).

Plain-numpy twin (rhs_reference) and compiled kernel (eval_rhs3d) give the same numbers; solve3d integrates with
scipy's DOP853 on the compiled kernel (it imports scipy.integrate when called: ~0.4 s of start-up the rest of the
package does not pay).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import ParameterError

__all__ = [
    "Chain3D",
    "basis_of",
    "eval_rhs3d",
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
    sigma    follower force F_a l / C1 on every particle, along its link toward the anchor
    gamma_l  drag along each link (gamma_T = 1 across it, the same in both transverse directions)
    clamped  a bending spring holds link 1 along e_x (False: a free ball pivot)
    """

    n: int
    sigma: float
    gamma_l: float = 1.0
    clamped: bool = True

    def checked(self) -> Chain3D:
        """The record, or ParameterError naming the first parameter out of range."""
        if int(self.n) < 1:
            raise ParameterError(f"n (number of particles N) must be >= 1, got {self.n}")
        if not (np.isfinite(self.sigma) and self.sigma >= 0):
            raise ParameterError(f"sigma must be finite and >= 0, got {self.sigma}")
        if not (np.isfinite(self.gamma_l) and self.gamma_l > 0):
            raise ParameterError(f"gamma_l (drag ratio) must be finite and > 0, got {self.gamma_l}")
        return self


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
    active = -chain.sigma * np.cumsum(u[::-1], axis=0)[::-1]  # sum_{i>=k} F_i
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
def eval_rhs3d(y, n, sigma, gamma_l, clamped, out):
    """t' of the overdamped chain into out (3n), at the tangents y (3n, link by link): the compiled rhs_reference
    (the same basis, forces and drag blocks; the 2n x 2n drag matrix solved by Cholesky, no pivoting, so the
    out-of-plane rows of a planar chain stay exact zeros)."""
    u = np.empty((n, 3))
    norm2 = np.empty(n)
    for k in range(n):
        x0, x1, x2 = y[3 * k], y[3 * k + 1], y[3 * k + 2]
        norm2[k] = x0 * x0 + x1 * x1 + x2 * x2
        r = 1.0 / math.sqrt(norm2[k])
        u[k, 0], u[k, 1], u[k, 2] = x0 * r, x1 * r, x2 * r
    E = np.empty((n, 2, 3))  # E[k, 0] = a_k, E[k, 1] = b_k
    for k in range(n):
        u0, u1, u2 = u[k, 0], u[k, 1], u[k, 2]
        if u0 * u0 + u1 * u1 > 0.25:
            a0, a1, a2 = -u1, u0, 0.0
        else:
            a0, a1, a2 = 0.0, -u2, u1
        r = 1.0 / math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        a0, a1, a2 = a0 * r, a1 * r, a2 * r
        E[k, 0, 0], E[k, 0, 1], E[k, 0, 2] = a0, a1, a2
        E[k, 1, 0], E[k, 1, 1], E[k, 1, 2] = u1 * a2 - u2 * a1, u2 * a0 - u0 * a2, u0 * a1 - u1 * a0
    grad = np.zeros((n, 3))
    if clamped:
        _bend_into(1.0, 0.0, 0.0, u[0, 0], u[0, 1], u[0, 2], grad, 0, 1.0)
    for k in range(1, n):
        _bend_into(u[k - 1, 0], u[k - 1, 1], u[k - 1, 2], u[k, 0], u[k, 1], u[k, 2], grad, k, 1.0)
        _bend_into(u[k, 0], u[k, 1], u[k, 2], u[k - 1, 0], u[k - 1, 1], u[k - 1, 2], grad, k - 1, 1.0)
    # suffix sums: follower forces and drag tensors of particles m..n
    force = np.zeros((n, 3))
    S = np.zeros((n, 3, 3))
    acc = np.zeros(3)
    accS = np.zeros((3, 3))
    dg = gamma_l - 1.0
    for m in range(n - 1, -1, -1):
        for a in range(3):
            acc[a] -= sigma * u[m, a]
            force[m, a] = acc[a]
            for b in range(3):
                accS[a, b] += dg * u[m, a] * u[m, b] + (1.0 if a == b else 0.0)
                S[m, a, b] = accS[a, b]
    size = 2 * n
    D = np.zeros((size, size))
    f = np.zeros(size)
    tmp = np.empty(3)
    for k in range(n):
        for al in range(2):
            row = 2 * k + al
            f[row] = (
                E[k, al, 0] * (force[k, 0] - grad[k, 0])
                + E[k, al, 1] * (force[k, 1] - grad[k, 1])
                + E[k, al, 2] * (force[k, 2] - grad[k, 2])
            )
            for j in range(k + 1):  # lower triangle: max(k, j) = k
                Sk = S[k]
                for a in range(3):
                    tmp[a] = E[k, al, 0] * Sk[0, a] + E[k, al, 1] * Sk[1, a] + E[k, al, 2] * Sk[2, a]
                for be in range(2):
                    col = 2 * j + be
                    if col > row:
                        continue
                    D[row, col] = tmp[0] * E[j, be, 0] + tmp[1] * E[j, be, 1] + tmp[2] * E[j, be, 2]
    # Cholesky D = L L^T in place (lower triangle), then the two triangular solves
    for j in range(size):
        s = D[j, j]
        for p in range(j):
            s -= D[j, p] * D[j, p]
        d = math.sqrt(s)
        D[j, j] = d
        for i in range(j + 1, size):
            s = D[i, j]
            for p in range(j):
                s -= D[i, p] * D[j, p]
            D[i, j] = s / d
    for i in range(size):
        s = f[i]
        for p in range(i):
            s -= D[i, p] * f[p]
        f[i] = s / D[i, i]
    for i in range(size - 1, -1, -1):
        s = f[i]
        for p in range(i + 1, size):
            s -= D[p, i] * f[p]
        f[i] = s / D[i, i]
    for k in range(n):
        h = 0.5 * (norm2[k] - 1.0)
        for a in range(3):
            out[3 * k + a] = E[k, 0, a] * f[2 * k] + E[k, 1, a] * f[2 * k + 1] - h * u[k, a]
    return out


def rhs(tangents: np.ndarray, chain: Chain3D) -> np.ndarray:
    """t' (N, 3) by the compiled kernel."""
    y = np.ascontiguousarray(tangents, dtype=float).ravel()
    out = np.empty(y.size)
    eval_rhs3d(y, int(chain.n), float(chain.sigma), float(chain.gamma_l), bool(chain.clamped), out)
    return out.reshape(chain.n, 3)


def solve3d(
    chain: Chain3D,
    ts: np.ndarray,
    tangents0: np.ndarray,
    *,
    rtol: float = 1e-9,
    atol: float = 1e-9,
    on_time=None,
    budget=None,
):
    """Tangents (len(ts), N, 3) of the chain from tangents0 (N, 3) at t = 0, sampled at ts (scipy's DOP853 on the
    compiled right-hand side). Raises RuntimeError naming the solver's message when it fails.

    on_time(t): told the time of every right-hand side evaluation (a progress bar; it changes nothing computed, what
    it raises stops the run). budget(method, eig): given "DOP853" and the eigenvalues of the right-hand side's
    Jacobian at the start (central differences over the tangents), before the first step: it may refuse the run."""
    # start-up time: scipy.integrate costs ~0.4 s to import; only the integration needs it
    from scipy.integrate import solve_ivp

    chain.checked()
    ts = np.asarray(ts, dtype=float)
    n, sigma, gamma_l, clamped = int(chain.n), float(chain.sigma), float(chain.gamma_l), bool(chain.clamped)
    out = np.empty(3 * n)

    def rate(_t, y):
        return eval_rhs3d(y, n, sigma, gamma_l, clamped, out).copy()

    y0 = np.ascontiguousarray(tangents0, dtype=float).ravel()
    if y0.size != 3 * n:
        raise ParameterError(f"tangents0 must hold {n} tangents (shape ({n}, 3)), got {np.shape(tangents0)}")
    if budget is not None:
        budget("DOP853", np.linalg.eigvals(_jacobian(rate, y0)))
    if on_time is None:
        fun = rate
    else:

        def fun(t, y):
            on_time(t)
            return rate(t, y)

    sol = solve_ivp(fun, (ts[0], ts[-1]), y0, method="DOP853", t_eval=ts, rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"3D chain: the DOP853 solver failed ({sol.message})")
    return sol.y.T.reshape(ts.size, n, 3)


def _jacobian(f, y: np.ndarray) -> np.ndarray:
    """d f(0, y) / dy by central differences (relative step 1e-7): what bounds an explicit solver's steps."""
    J = np.empty((y.size, y.size))
    for k in range(y.size):
        h = 1e-7 * max(1.0, abs(y[k]))
        up, down = y.copy(), y.copy()
        up[k] += h
        down[k] -= h
        J[:, k] = (f(0.0, up) - f(0.0, down)) / (2.0 * h)
    return J

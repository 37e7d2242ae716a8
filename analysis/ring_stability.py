r"""Linear stability of the pinned ring's rigid rotation (the ring scene): a relative equilibrium of the reduced model.

The ring (ChainSystem.closed, pinned with delta = 1: N links, the first pivot and the last particle on one free pin at
the origin, a spring at every joint including the closing one) obeys the two-pinned chain's overdamped saddle point

    [[D, G^T], [G, 0]] [theta'; lam] = [f; -beta g],   g = (sum cos theta_i, sum sin theta_i),  G = dg/dtheta,

theta' = F(theta; sigma) (elastoactive/reduced/equations.py). F is affine in sigma (f = -dU/dtheta + sigma Q1(theta)).

Symmetry. Shifting every angle, theta -> theta + c 1 (turning the ring about the pin; the follower forces turn with
the links), leaves D, f and the springs alone and turns g and G by the rotation R(c), so the saddle point's solution
is unchanged: F(theta + c 1) = F(theta) exactly, hence J 1 = 0 for the Jacobian J = dF/dtheta at every theta. A
steady rigid rotation is a relative equilibrium theta(t) = theta* + Omega t 1 with

    F(theta*; sigma) = Omega 1                                                      (N + 1 unknowns with theta*_1 = 0)

(then g(theta*) = 0 follows: G F = -beta g and G 1 = (-g_2, g_1) give beta g = Omega (g_2, -g_1), so g = 0).

The regular N-gon is not theta* for sigma > 0: the follower forces bend the ring unevenly (at the polygon the links
of the N = 7 ring turn at rates between -0.06 sigma and -0.67 sigma), so theta* is a deformed polygon, found here by
Newton's method from the polygon and followed in sigma by pseudo-arclength continuation. Torque balance about the pin
(1^T of the first row: 1^T G^T = (G 1)^T = 0 on g = 0 and 1^T dU/dtheta = 0) gives the rate exactly,

    Omega = 1^T f(theta*) / (1^T D(theta*) 1),

and as sigma -> 0 (theta* -> the polygon, isotropic drag): the follower forces' torque -sigma sum_i r_{i-1} x r_i =
-2 sigma (the polygon's area) over the rotational drag sum_i |r_i|^2 = 2 N R^2 (R = 1 / (2 sin(pi/N))), i.e.

    Omega / sigma -> -sin(2 pi / N) / 2         (-0.390916 at N = 7; the study's rate / sigma at sigma = 0.2: -0.39174,
                                                  which Omega(0.2) / 0.2 = -0.3917394 reproduces).

Linearisation. With theta = theta* + Omega t 1 + u, the shift invariance makes u' = J(theta*) u autonomous: the
stability of the rigid rotation is that of a fixed point of the shape dynamics. The constraint's tangent space
T = ker G(theta*) (N - 2 dimensions, containing 1) is invariant under J: differentiating g' = -beta g along the
rotating solution gives G J u = -(beta + Omega R(pi/2)) G u, so the two normal directions decay at -beta +- i Omega
(the Baumgarte drift, seen from the turning frame) and do not mix with T. J restricted to T (V^T J V, V an orthonormal
basis of T; independent of beta) has the eigenvalue 0 of the uniform rotation (J 1 = 0) and N - 3 shape eigenvalues:
those of the quotient W^T J W, W an orthonormal basis of T orthogonal to 1 (exact, since 1 is a right eigenvector).
J is the reduced model's own analytic Jacobian (analysis.reduced.jacobian: the saddle point's derivative, springs,
follower forces, the drag's own derivative at theta' = Omega 1, the multipliers), so the operator is that of the very
equations the reduced engine integrates; central differences of its right-hand side agree (tests).

What it shows (docs/outlook.md, section 3): the rigid rotation followed from the polygon stays stable at every sigma
up to 100 for N <= 14; from N = 15 on it loses stability in a subcritical Hopf bifurcation (N^3 sigma_H = 5900..6900,
N = 24: sigma_H = 0.4377, omega = 0.1063 rad/tau) and does not regain it. The rigid rotations a long ring reaches at
large sigma lie on other branches (restabilisation follows one from a run's settled shape): the one the N = 24 ring
reaches at sigma = 8 is born in a fold at sigma = 1.687, so between 0.4377 and 1.687 no rigid rotation of either
branch is stable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from scipy.linalg import null_space
from scipy.optimize import brentq

from ..reduced import DEFAULT_BETA, ChainSystem, drag_and_forces_reference, jacobian, rhs

__all__ = [
    "Branch",
    "central_jacobian",
    "Crossing",
    "follow",
    "linearise",
    "onset",
    "polygon",
    "relative_equilibrium",
    "restabilisation",
    "RigidRotation",
    "ring_jacobian",
    "ring_system",
    "rotation_rate_per_sigma",
    "shape_basis",
    "shape_spectrum",
    "tangent_basis",
    "tangent_spectrum",
    "unstable_intervals",
]

SCAN_MAX = 100.0
"""sigma up to which follow and onset trace the branch by default (the study's rings go to 80)."""
START = 1.0
"""The continuation starts at sigma = START / N^3 (Newton from the polygon): the ring's shape responds to sigma on the
scale 1 / N^3 (N^3 sigma_H = 5900..6900 for N = 15..40), so the first point is a small deformation at any N."""
STEP_MAX = 0.15
"""Largest pseudo-arclength step, measured in (rms change of the angles, change of log sigma)."""
STEP_MIN = 1e-7
DRIFT = 0.3
"""A step is taken again, halved, when its corrector moves the point more than DRIFT times the step from the
predictor, or when the tangent turns by more than arccos(TURN): large corrections are how a continuation jumps from
one branch to another."""
TURN = 0.9
NEWTON_TOL = 1e-10
"""Newton's method stops when its step (in the angles) is below this, or when the residual it corrected was already
at round-off, below RESIDUAL_TOL (1 + sigma) (the rates scale with sigma; at sigma ~ 100 the steps' round-off
plateau is ~3e-11)."""
RESIDUAL_TOL = 1e-12
NEWTON_MAX = 12
MAX_POINTS = 20000
HOPF_FREQUENCY = 1e-6
"""A crossing whose eigenvalue has |Im lambda| above this (times 1 + |Omega|) is a Hopf crossing, else a real one."""


def polygon(n: int) -> np.ndarray:
    """Absolute angles of the regular N-gon, first link along +x, turning counterclockwise (the ring's rest state)."""
    return 2.0 * math.pi * np.arange(int(n)) / int(n)


def ring_system(n: int, sigma: float, gamma_l: float = 1.0) -> ChainSystem:
    """The pinned ring's reduced model (overdamped, gamma_T = 1; gamma_l: the longitudinal drag)."""
    return ChainSystem(
        n=int(n),
        n_chains=1,
        clamped=False,
        pinned=True,
        sigma=float(sigma),
        gamma_l=float(gamma_l),
        gamma_t=1.0,
        delta=1.0,
        closed=True,
    ).typed()


@lru_cache(maxsize=8)
def _model(n: int, gamma_l: float):
    """(F, J): the compiled right-hand side and analytic Jacobian as functions of (theta, sigma), each affine in sigma
    (the force, and so the saddle point's solution, is affine in sigma; the Baumgarte term does not depend on it)."""
    f0, f1 = (rhs(ring_system(n, s, gamma_l), beta=DEFAULT_BETA) for s in (0.0, 1.0))
    j0, j1 = (jacobian(ring_system(n, s, gamma_l), beta=DEFAULT_BETA) for s in (0.0, 1.0))

    def rates(theta, sigma):
        a, b = f0(0.0, theta), f1(0.0, theta)
        return a + sigma * (b - a), b - a

    def jac(theta, sigma):
        a, b = j0(0.0, theta), j1(0.0, theta)
        return a + sigma * (b - a)

    return rates, jac


def ring_jacobian(n: int, sigma: float, theta, gamma_l: float = 1.0) -> np.ndarray:
    """J = dF/dtheta at theta: the reduced model's analytic Jacobian (analysis.reduced.jacobian) of the pinned ring."""
    return _model(int(n), float(gamma_l))[1](np.asarray(theta, dtype=float), float(sigma))


def rotation_rate_per_sigma(n: int, gamma_l: float = 1.0) -> float:
    """lim_{sigma -> 0} Omega / sigma: the follower forces' torque about the pin over the rotational drag, at the
    polygon, 1^T Q1 / (1^T D 1) (isotropic drag: -sin(2 pi / N) / 2)."""
    system = ring_system(n, 1.0, gamma_l)
    theta = polygon(n)
    D, force = drag_and_forces_reference(system, theta)
    elastic = drag_and_forces_reference(system._replace(sigma=0.0), theta)[1]
    one = np.ones(int(n))
    return float(one @ (force - elastic) / (one @ D @ one))


def relative_equilibrium(n: int, sigma: float, guess=None, gamma_l: float = 1.0) -> tuple[np.ndarray, float]:
    """(theta*, Omega): the rigidly turning ring's shape (theta*_1 = 0) and rate at sigma, by Newton's method on
    F(theta; sigma) = Omega 1 from guess (default: the polygon; for sigma beyond a small deformation use follow, or
    a nearby solution). Raises ArithmeticError when Newton's method does not converge."""
    rates, jac = _model(int(n), float(gamma_l))
    theta = polygon(n) if guess is None else np.array(guess, dtype=float).reshape(-1)
    theta = theta - theta[0]
    omega = float(np.mean(rates(theta, sigma)[0]))
    x = _newton(n, rates, jac, np.r_[theta, omega], sigma)
    if x is None:
        raise ArithmeticError(f"no rigid rotation found near the guess at N = {n}, sigma = {sigma:g}")
    return x[:n], float(x[n])


def _newton(n, rates, jac, x, sigma):
    """Newton on (F - Omega 1, theta_1) = 0 at fixed sigma; None when it does not converge."""
    x = x.copy()
    A = np.zeros((n + 1, n + 1))
    A[:n, n] = -1.0
    A[n, 0] = 1.0
    for _ in range(NEWTON_MAX):
        A[:n, :n] = jac(x[:n], sigma)
        r = np.r_[rates(x[:n], sigma)[0] - x[n], x[0]]
        d = np.linalg.solve(A, -r)
        x += d
        if not np.all(np.isfinite(d)) or np.max(np.abs(d[:n])) > 1.0:
            return None
        if _converged(d, r, sigma):
            return x
    return None


def _converged(d, r, sigma) -> bool:
    return bool(np.max(np.abs(d)) < NEWTON_TOL or np.max(np.abs(r)) < RESIDUAL_TOL * (1.0 + sigma))


def tangent_basis(theta) -> np.ndarray:
    """Orthonormal basis (N x (N - 2)) of the closure constraint's tangent space ker G(theta)."""
    theta = np.asarray(theta, dtype=float)
    return null_space(np.vstack([-np.sin(theta), np.cos(theta)]))


def shape_basis(theta) -> np.ndarray:
    """Orthonormal basis (N x (N - 3)) of the shape changes: ker G(theta) orthogonal to the uniform rotation 1."""
    theta = np.asarray(theta, dtype=float)
    return null_space(np.vstack([-np.sin(theta), np.cos(theta), np.ones(theta.size)]))


def _sorted(lam: np.ndarray) -> np.ndarray:
    return lam[np.lexsort((-lam.imag, -lam.real))]


def tangent_spectrum(n: int, sigma: float, theta, gamma_l: float = 1.0, jacobian_matrix=None) -> np.ndarray:
    """Eigenvalues of the Jacobian restricted to the constraint's tangent space at theta (V^T J V, N - 2 of them; at
    a relative equilibrium one is 0, the uniform rotation), by decreasing real part."""
    J = (
        _model(int(n), float(gamma_l))[1](np.asarray(theta, dtype=float), sigma)
        if jacobian_matrix is None
        else jacobian_matrix
    )
    V = tangent_basis(theta)
    return _sorted(np.linalg.eigvals(V.T @ J @ V))


def shape_spectrum(n: int, sigma: float, theta, gamma_l: float = 1.0, jacobian_matrix=None) -> np.ndarray:
    """The shape eigenvalues at a relative equilibrium theta (the tangent spectrum without the rotation's 0: W^T J W,
    N - 3 of them), by decreasing real part. jacobian_matrix: J at theta if already known (e.g. by differences)."""
    J = (
        _model(int(n), float(gamma_l))[1](np.asarray(theta, dtype=float), sigma)
        if jacobian_matrix is None
        else jacobian_matrix
    )
    W = shape_basis(theta)
    return _sorted(np.linalg.eigvals(W.T @ J @ W))


@dataclass(frozen=True)
class RigidRotation:
    """The rigidly turning ring at sigma and its linear stability."""

    sigma: float
    theta: np.ndarray
    """theta* (theta*_1 = 0): the shape that turns."""
    omega: float
    """Omega (rad / tau; negative: clockwise, the polygon running counterclockwise)."""
    spectrum: np.ndarray
    """The N - 3 shape eigenvalues (the rotation's 0 removed), by decreasing real part."""
    zero: float
    """|lambda| of the tangent spectrum's eigenvalue nearest 0 (the rotation's; round-off)."""

    @property
    def leading(self) -> complex:
        """The least stable shape eigenvalue (Im >= 0 of a pair)."""
        lam = self.spectrum[0]
        return complex(lam.real, abs(lam.imag))


def linearise(n: int, sigma: float, theta=None, gamma_l: float = 1.0) -> RigidRotation:
    """The rigid rotation at sigma and its spectrum: theta None takes the branch followed from the polygon (the first
    point at sigma along it, follow: where the branch folds back, N = 15..20 and 32..37, the first of the shapes at
    that sigma it reaches), else Newton's method from theta (a shape near the wanted relative equilibrium, e.g. the
    end of a run that settled). N >= 4."""
    n = int(n)
    if theta is None:
        theta = polygon(n) if sigma <= START / n**3 else follow(n, sigma, gamma_l=gamma_l).theta[-1]
    theta, omega = relative_equilibrium(n, sigma, theta, gamma_l)
    J = _model(n, float(gamma_l))[1](theta, sigma)
    tangent = tangent_spectrum(n, sigma, theta, gamma_l, J)
    return RigidRotation(
        float(sigma), theta, omega, shape_spectrum(n, sigma, theta, gamma_l, J), float(np.min(np.abs(tangent)))
    )


@dataclass(frozen=True)
class Crossing:
    """Where the leading shape eigenvalue crosses Re lambda = 0 along a branch."""

    sigma: float
    omega: float
    """|Im lambda| there (rad / tau): the shape's beat frequency at the crossing (0: a real eigenvalue)."""
    loses: bool
    """True: this branch's rigid rotation is stable just below sigma and unstable just above (as sigma increases
    through the crossing, locally along the branch); False: the reverse. At a fold: along the branch as followed."""
    fold: bool = False
    """Whether the crossing is a saddle-node turning point of the branch (a real eigenvalue through 0 where the branch
    turns back in sigma: beyond it, this rigid rotation does not exist)."""

    @property
    def kind(self) -> str:
        return "fold" if self.fold else "Hopf" if self.omega > 0 else "real"


@dataclass(frozen=True)
class Branch:
    """A branch of rigid rotations followed by pseudo-arclength continuation (points in the order followed)."""

    n: int
    sigma: np.ndarray
    omega: np.ndarray
    """The rotation rate Omega at each point."""
    growth: np.ndarray
    """Re of the leading shape eigenvalue at each point."""
    frequency: np.ndarray
    """|Im| of the leading shape eigenvalue at each point."""
    theta: np.ndarray
    """theta* at each point, (points, N)."""
    crossings: tuple[Crossing, ...]
    """In the order followed."""
    folds: tuple[float, ...]
    """sigma at the branch's saddle-node turning points (where it turns back in sigma), in the order followed."""
    closed: bool
    """Whether the branch closed on itself (an isola) before leaving the sigma range."""

    def unstable_arcs(self) -> list[tuple[float, float]]:
        """The stretches of the branch where its rigid rotation is unstable, in the order followed, each as (sigma
        where it starts, sigma where it ends): at a crossing, or at the branch's first or last point (still unstable
        there). Without a fold between them, the interval between the two sigmas."""
        arcs, start = [], (float(self.sigma[0]) if self.growth[0] > 0 else None)
        for c in self.crossings:
            if start is None:
                start = c.sigma
            else:
                arcs.append((start, c.sigma))
                start = None
        if start is not None:
            arcs.append((start, float(self.sigma[-1])))
        return arcs


class _Continuation:
    """Pseudo-arclength continuation of (theta, Omega, u = log sigma) on F(theta; e^u) = Omega 1, theta_1 = 0, with
    the arclength measured in (theta / sqrt(N), u) (Omega, a function of the others, is not weighted)."""

    def __init__(self, n: int, gamma_l: float):
        self.n = n
        self.rates, self.jac = _model(n, gamma_l)
        self.weight = np.r_[np.full(n, 1.0 / n), 0.0, 1.0]

    def system(self, x):
        n = self.n
        sigma = math.exp(x[n + 1])
        f, f1 = self.rates(x[:n], sigma)
        A = np.zeros((n + 1, n + 2))
        A[:n, :n] = self.jac(x[:n], sigma)
        A[:n, n] = -1.0
        A[:n, n + 1] = sigma * f1  # dF / du, F affine in sigma
        A[n, 0] = 1.0
        return np.r_[f - x[n], x[0]], A

    def tangent(self, x, previous=None):
        """The unit tangent (in the weighted metric) at x, oriented along `previous`."""
        t = null_space(self.system(x)[1])[:, 0]
        t /= math.sqrt(t @ (self.weight * t))
        if previous is not None and t @ (self.weight * previous) < 0:
            t = -t
        return t

    def correct(self, x, t, ds):
        """The point at arclength ds from x along t (Newton on the system plus the arclength condition) and the
        iterations it took; (None, 0) when it does not converge."""
        y = x + ds * t
        wt = self.weight * t
        for k in range(NEWTON_MAX):
            r, A = self.system(y)
            d = np.linalg.solve(np.vstack([A, wt]), -np.r_[r, (y - x) @ wt - ds])
            y += d
            if not np.all(np.isfinite(d)) or np.max(np.abs(d)) > 1.0:
                return None, 0
            if _converged(d, r, math.exp(y[self.n + 1])):
                return y, k + 1
        return None, 0

    def at(self, x, t, ds):
        """The corrected point at arclength ds (x itself at 0); raises ArithmeticError if the corrector fails."""
        if ds == 0:
            return x
        y = self.correct(x, t, ds)[0]
        if y is None:
            raise ArithmeticError("the continuation's corrector failed while refining a crossing or a fold")
        return y

    def leading(self, y) -> complex:
        """The leading shape eigenvalue at the point y (Im >= 0)."""
        n = self.n
        sigma = math.exp(y[n + 1])
        lam = shape_spectrum(n, sigma, y[:n], jacobian_matrix=self.jac(y[:n], sigma))[0]
        return complex(lam.real, abs(lam.imag))

    def distance(self, x, y) -> float:
        d = x - y
        return math.sqrt(d @ (self.weight * d))


def follow(
    n: int,
    sigma_max: float = SCAN_MAX,
    start=None,
    gamma_l: float = 1.0,
    downward: bool = False,
    sigma_min: float | None = None,
) -> Branch:
    """Follow a branch of rigid rotations by pseudo-arclength continuation in (theta, log sigma), through folds.

    start None: the branch through the polygon, from sigma = START / N^3 upward; start (theta, sigma): the branch
    through the relative equilibrium near theta at sigma (e.g. a run's settled shape), upward, or downward (towards
    smaller sigma first). Stops where sigma first leaves [sigma_min, sigma_max] along the branch (sigma_min default:
    START / N^3; the last point is then exactly at that bound), or when the branch closes on itself. Sign changes of
    the leading shape eigenvalue's real part and turning points between the continuation's points are refined by
    brentq along the arclength. N >= 4 (a triangle has no shape modes)."""
    n = int(n)
    if n < 4:
        raise ValueError(f"N = {n}: a ring of fewer than 4 links has no shape modes (N - 3 = {n - 3})")
    low = START / n**3 if sigma_min is None else float(sigma_min)
    cont = _Continuation(n, float(gamma_l))
    sigma0, guess = (low, polygon(n)) if start is None else (float(start[1]), np.asarray(start[0], dtype=float))
    theta, omega = relative_equilibrium(n, sigma0, guess, gamma_l)
    x = np.r_[theta, omega, math.log(sigma0)]
    t = cont.tangent(x)
    if (t[n + 1] < 0) != downward:
        t = -t
    bounds = {math.log(sigma_max): float(sigma_max), math.log(low): float(low)}
    points, lead, crossings, folds = [x], [cont.leading(x)], [], []
    ds, closed, edge = 0.02, False, None
    while len(points) < MAX_POINTS:
        y, its = cont.correct(x, t, ds)
        if y is None:
            ds /= 2.0
            if ds < STEP_MIN:
                break
            continue
        ty = cont.tangent(y, t)
        if cont.distance(y, x + ds * t) > DRIFT * ds or ty @ (cont.weight * t) < TURN:  # too far: may jump branches
            ds /= 2.0
            if ds < STEP_MIN:
                break
            continue
        ly = cont.leading(y)
        u = (x[n + 1], y[n + 1])
        edge = next((b for b in bounds if (u[0] - b) * (u[1] - b) <= 0 and u[0] != b), None)
        span = ds
        if edge is not None:  # the last point, exactly at the bound: along the arclength, where u reaches it
            if y[n + 1] != edge:
                span = brentq(lambda s: cont.at(x, t, s)[n + 1] - edge, 0.0, ds, xtol=1e-14)
                y = cont.at(x, t, span)
                ly = cont.leading(y)
        if (lead[-1].real < 0) != (ly.real < 0):
            crossings.append(_crossing(cont, x, t, span, lead[-1], ly))
        if edge is None and (t[n + 1] > 0) != (ty[n + 1] > 0):
            h = brentq(lambda s: cont.tangent(cont.at(x, t, s), t)[n + 1], 0.0, ds, xtol=1e-12)
            folds.append(math.exp(cont.at(x, t, h)[n + 1]))
            if crossings and crossings[-1].omega == 0 and abs(crossings[-1].sigma / folds[-1] - 1.0) < 1e-6:
                crossings[-1] = replace(crossings[-1], fold=True, loses=lead[-1].real < 0)
        points.append(y)
        lead.append(ly)
        if edge is not None:
            break
        if len(points) > 20 and cont.distance(y, points[0]) < ds:  # back where it started: an isola
            closed = True
            break
        x, t = y, ty
        ds = min(STEP_MAX, ds * (1.5 if its <= 3 else 1.0 if its <= 5 else 0.5))
    X = np.array(points)
    sigma = np.exp(X[:, n + 1])
    if edge is not None:
        sigma[-1] = bounds[edge]  # exactly the bound (its log round-trips to within an ulp)
    lam = np.array(lead)
    return Branch(n, sigma, X[:, n], lam.real, np.abs(lam.imag), X[:, :n], tuple(crossings), tuple(folds), closed)


def _crossing(cont: _Continuation, x, t, span, before: complex, after: complex) -> Crossing:
    """Refine a sign change of the leading real part between x and the point at arclength span from x (brentq)."""
    n = cont.n
    h = brentq(
        lambda s: cont.leading(cont.at(x, t, s)).real if 0 < s < span else (before.real if s == 0 else after.real),
        0.0,
        span,
        xtol=1e-13,
        rtol=1e-12,
    )
    z = cont.at(x, t, h)
    lam = cont.leading(z)
    omega = abs(lam.imag) if abs(lam.imag) > HOPF_FREQUENCY * (1.0 + abs(z[n])) else 0.0
    grows = after.real > before.real  # along the path
    rising = cont.tangent(z, t)[n + 1] > 0  # sigma increases along the path here
    return Crossing(float(math.exp(z[n + 1])), float(omega), bool(grows == rising))


def unstable_intervals(n: int, sigma_max: float = SCAN_MAX, gamma_l: float = 1.0) -> list[tuple[float, float]]:
    """The sigma intervals where the rigid rotation on the branch through the polygon is unstable, up to sigma_max
    (an interval ending at sigma_max is still unstable there: the scan's end, not a restabilisation); [] when it is
    stable throughout (and for N < 4, which has no shape modes)."""
    if int(n) < 4:
        return []
    return follow(n, sigma_max, gamma_l=gamma_l).unstable_arcs()


def onset(n: int, sigma_max: float = SCAN_MAX, gamma_l: float = 1.0) -> tuple[float, float, Branch | None]:
    """(sigma_c, omega_c, branch): where the rigid rotation through the polygon first loses stability along its
    branch (stable at small sigma: its first crossing; branch.crossings[0].kind says how), omega_c the shape's angular
    frequency there (0 for a real eigenvalue); (inf, nan, branch) when it is stable up to sigma_max; (inf, nan, None)
    for N < 4 (no shape modes: the triangle turns rigidly at every sigma)."""
    if int(n) < 4:
        return math.inf, math.nan, None
    branch = follow(n, sigma_max, gamma_l=gamma_l)
    if not branch.crossings:
        return math.inf, math.nan, branch
    return branch.crossings[0].sigma, branch.crossings[0].omega, branch


def restabilisation(n: int, theta, sigma: float, gamma_l: float = 1.0) -> tuple[float, str, Branch]:
    """Where the rigid rotation near theta at sigma (stable there: e.g. a run's settled shape) stops being stable as
    sigma is lowered: (sigma, how, branch), following its branch downward to the first crossing (how: "Hopf", "real",
    or "fold", where the branch turns back and this rigid rotation ceases to exist), or (the branch's last sigma,
    "none", branch) if it stays stable down to START / N^3."""
    branch = follow(n, sigma * (1.0 + 1e-4), start=(theta, sigma), gamma_l=gamma_l, downward=True)
    if not branch.crossings:
        return float(branch.sigma[-1]), "none", branch
    return branch.crossings[0].sigma, branch.crossings[0].kind, branch


def central_jacobian(n: int, sigma: float, theta, step: float = 1e-6, gamma_l: float = 1.0) -> np.ndarray:
    """dF/dtheta at theta by central differences of the reduced model's compiled right-hand side (step in rad): the
    check of the analytic Jacobian (error ~ step^2 until round-off ~ 1e-16 / step)."""
    rates = _model(int(n), float(gamma_l))[0]
    theta = np.asarray(theta, dtype=float)
    J = np.empty((theta.size, theta.size))
    for k in range(theta.size):
        e = np.zeros(theta.size)
        e[k] = step
        J[:, k] = (rates(theta + e, sigma)[0] - rates(theta - e, sigma)[0]) / (2.0 * step)
    return J

r"""The whirl as a relative equilibrium: a shape that turns rigidly about the clamp axis, found by Newton's method
rather than by waiting for a simulation to settle; its stability, and its continuum limit. And the planar beat's
stability out of its plane.

A whirl of the reduced 3D chain (elastoactive.reduced.chain3d) is a solution t_k(t) = R_x(Omega t) t_k(0): every
tangent turns about e_x at one rate Omega. So its shape solves

    t_k' = rhs(t)_k = Omega e_x x t_k        for every link k,

2N equations (the components of each residual across its own link, in the basis E_k of the shape) for 2N + 1 unknowns
(a small move E_k dq_k of each tangent, and Omega). The rotation about e_x is a symmetry (every shape turned about the
axis whirls as well), fixed by a phase condition that never degenerates: the guess is first turned about e_x so that its
tip lies on +y, the tip's z is then held at 0 (its derivative along the symmetry is the tip's y, the tip's whole
distance from the axis), and the whirl found is turned back: 2N + 1 equations (`find_whirl`, scipy's hybrid Powell root,
residual ~1e-15), whatever the guess's azimuth. (Holding the tip's z at the guess's own value degenerates when the tip
lies near the z axis: the turn then hardly moves z, and Newton stalls.) Its stability: the Jacobian of rhs(t) - Omega
e_x x t at the whirl, in the rotating frame, has the symmetry's eigenvalue 0 (the shape turned) and the others; the
whirl is linearly stable when every other eigenvalue has a negative real part (`WhirlState.growth`: the largest of
their real parts).

The continuum limit (`ladder`): at a fixed load S = N^3 sigma the chain of N links tends to the clamped filament under
a distributed follower load (analysis.filament, docs/filament.md), whose time unit is N^4 tau. The whirl's angular
rate N^4 Omega, its tip's distance from the axis over the length, R / N, and the angle between the first and last link
are extrapolated in 1/N by analysis.filament.richardson, each rung started from the previous rung's shape carried to
its N (`resample_tangents`).

The planar beat (`beat_out_of_plane`): a beat in the xy plane is an exact solution of the 3D model (its plane is an
invariant subspace), and at linear order a small out-of-plane shape z evolves on its own, by the b rows of the model
(the reflection z -> -z is a symmetry, so in-plane and out-of-plane perturbations do not mix). Its Floquet multipliers
are those of the N x N monodromy matrix of z over one period, the product of the monodromies of PIECES pieces of it:
column k of a piece's is the out-of-plane shape at its end after starting it with z_k = EPSILON (a linear response).
Turning the beat's plane about e_x gives another beat, so one multiplier is 1 (that turn's shape, z = y). The beat is
stable out of its plane when every other multiplier lies inside the unit circle; the exponent log|mu| / T is its
growth rate per tau. Pure functions (numbers and arrays in, records out).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from ..core.errors import ParameterError
from ..reduced.chain3d import Chain3D, basis_of, planar_angles, rhs, solve3d, tangents_of_angles
from .filament import Extrapolation, beat, richardson
from .motion3d import measure3d

__all__ = [
    "BeatStability",
    "NoWhirl",
    "WhirlLadder",
    "WhirlState",
    "beat_out_of_plane",
    "continuum_whirl",
    "find_whirl",
    "ladder",
    "resample_tangents",
    "rotating_jacobian",
    "settled_whirl",
    "turn_about_axis",
]

EX = np.array([1.0, 0.0, 0.0])
STEP = 1e-7
"""Central-difference step of rotating_jacobian."""
TOLERANCE = 1e-10
"""Largest residual (per tau) a whirl is accepted at."""
STRAIGHT_TIP = 1e-6
"""A converged shape whose tip lies within this distance (l) of the clamp axis is the straight chain, not a whirl."""
EPSILON = 1e-8
"""Out-of-plane push of beat_out_of_plane's monodromy columns (l)."""
SAMPLES_PER_PERIOD = 200
"""Samples per period of the settling run beat_out_of_plane measures the period on."""
SETTLE_TIME = 6.0
"""Length of settled_whirl's run in units of N^4 tau / S, the load's natural time (several turns)."""
SETTLE_SAMPLES = 6000
"""Sample intervals of settled_whirl's run."""
HELIX = 0.3
"""settled_whirl's start: link k of N turned by HELIX s_k across the axis in y and HELIX s_k^2 in z (s_k = k / N)."""
PIECES = 8
"""Pieces of the period whose monodromies beat_out_of_plane multiplies (each piece's growth stays small enough for
the push EPSILON to respond linearly: a beat may grow out of its plane by e^16 in one period)."""


class NoWhirl(ParameterError):
    """Newton's method found no whirl: `straight` when it converged to the straight chain (its tip on the clamp
    axis, a solution of every load), else it did not converge."""

    def __init__(self, message: str, straight: bool) -> None:
        super().__init__(message)
        self.straight = straight


@dataclass(frozen=True)
class WhirlState:
    """A whirl of the reduced 3D chain (module docstring)."""

    n: int
    sigma: float
    gamma_l: float
    omega: float
    """Angular rate about e_x (rad / tau), signed: > 0 turning from +y to +z."""
    tangents: np.ndarray
    """The shape (N, 3) at t = 0."""
    residual: float
    """Largest |t' - Omega e_x x t| at the shape (per tau)."""
    growth: float
    """Largest real part of the rotating-frame Jacobian's eigenvalues but the symmetry's 0: < 0 when stable."""

    @property
    def rate(self) -> float:
        """Cycles per tau, signed (omega / 2 pi)."""
        return self.omega / (2 * np.pi)

    @property
    def tip_radius(self) -> float:
        """The tip's distance from the clamp axis (l)."""
        tip = self.tangents.sum(axis=0)
        return float(np.hypot(tip[1], tip[2]))

    @property
    def bend(self) -> float:
        """Angle between the first and last link (rad)."""
        return float(np.arccos(np.clip(self.tangents[0] @ self.tangents[-1], -1.0, 1.0)))


def turn_about_axis(angle: float) -> np.ndarray:
    """The 3 x 3 rotation by `angle` (rad) about the clamp axis e_x (from +y towards +z); shapes (N, 3) turn as
    shape @ R.T."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _moved(base: np.ndarray, frames: np.ndarray, q: np.ndarray) -> np.ndarray:
    t = base + np.einsum("kab,kb->ka", frames, q.reshape(-1, 2))
    return t / np.linalg.norm(t, axis=1)[:, None]


def _frames(tangents: np.ndarray) -> np.ndarray:
    return np.stack([np.column_stack(basis_of(u)) for u in tangents])  # (N, 3, 2): columns a_k, b_k


def rotating_jacobian(chain: Chain3D, tangents: np.ndarray, omega: float) -> np.ndarray:
    """The 2N x 2N Jacobian of rhs(t) - omega e_x x t in the shape's basis (central differences, step STEP)."""
    frames = _frames(tangents)
    size = 2 * chain.n
    jac = np.empty((size, size))

    def field(q):
        t = _moved(tangents, frames, q)
        return np.einsum("kab,ka->kb", frames, rhs(t, chain) - omega * np.cross(EX, t)).ravel()

    for j in range(size):
        dq = np.zeros(size)
        dq[j] = STEP
        jac[:, j] = (field(dq) - field(-dq)) / (2 * STEP)
    return jac


def find_whirl(chain: Chain3D, guess: np.ndarray, omega_guess: float) -> WhirlState:
    """The whirl nearest the shape guess (N, 3) and rate omega_guess (rad / tau). Raises NoWhirl (a ParameterError)
    when Newton's method converges to the straight chain (its tip within STRAIGHT_TIP of the axis) or does not
    converge (a guess too far, or no whirl at this load)."""
    chain = chain.checked()
    guess = np.asarray(guess, dtype=float)
    if guess.shape != (chain.n, 3):
        raise ParameterError(f"guess must have shape ({chain.n}, 3), got {guess.shape}")
    unit = guess / np.linalg.norm(guess, axis=1)[:, None]
    tip = unit.sum(axis=0)
    azimuth = float(np.arctan2(tip[2], tip[1]))
    base = unit @ turn_about_axis(-azimuth).T  # the tip on +y: holding its z fixes the phase, never degenerately
    frames = _frames(base)

    def equations(x):
        t = _moved(base, frames, x[:-1])
        v = rhs(t, chain) - x[-1] * np.cross(EX, t)
        return np.concatenate([np.einsum("kab,ka->kb", frames, v).ravel(), [t.sum(axis=0)[2]]])

    x0 = np.zeros(2 * chain.n + 1)
    x0[-1] = omega_guess
    solution = root(equations, x0, method="hybr", options={"xtol": 1e-14})
    tangents = _moved(base, frames, solution.x[:-1]) @ turn_about_axis(azimuth).T  # back to the guess's azimuth
    omega = float(solution.x[-1])
    residual = float(np.abs(rhs(tangents, chain) - omega * np.cross(EX, tangents)).max())
    tip = tangents.sum(axis=0)
    where = f"N = {chain.n}, sigma = {chain.sigma:g}, drag ratio {chain.gamma_l:g}"
    if residual > TOLERANCE:
        raise NoWhirl(
            f"Newton's method did not converge to a whirl at {where} (residual {residual:.1e} per tau)", straight=False
        )
    if np.hypot(tip[1], tip[2]) < STRAIGHT_TIP:
        raise NoWhirl(
            f"Newton's method converged to the straight chain (its tip on the clamp axis), not a whirl, at {where}",
            straight=True,
        )
    lam = np.linalg.eigvals(rotating_jacobian(chain, tangents, omega))
    others = np.delete(lam, np.argmin(np.abs(lam)))  # the symmetry's 0
    return WhirlState(chain.n, chain.sigma, chain.gamma_l, omega, tangents, residual, float(others.real.max()))


def resample_tangents(tangents: np.ndarray, n: int) -> np.ndarray:
    """A shape (N, 3) carried to n links: the tangent of link k sits at s = (k - 1/2) / N of the length, and each
    component is interpolated linearly in s (held at the ends), then normalised."""
    tangents = np.asarray(tangents, dtype=float)
    old = (np.arange(tangents.shape[0]) + 0.5) / tangents.shape[0]
    new = (np.arange(int(n)) + 0.5) / int(n)
    t = np.column_stack([np.interp(new, old, tangents[:, a]) for a in range(3)])
    return t / np.linalg.norm(t, axis=1)[:, None]


@dataclass(frozen=True)
class WhirlLadder:
    """The whirl at one load S = N^3 sigma along a ladder of N, and its continuum limit."""

    load: float
    states: tuple[WhirlState, ...]
    omega: Extrapolation
    """N^4 Omega (rad per filament time zeta L^4 / B), extrapolated."""
    radius: Extrapolation
    """The tip's distance from the axis over the length, R / N, extrapolated."""
    bend: Extrapolation
    """The angle between the first and last link (rad), extrapolated."""


def ladder(load: float, ns, guess: np.ndarray, omega_guess: float, gamma_l: float = 1.0, on_rung=None) -> WhirlLadder:
    """Whirls at S = load for each N of ns (increasing), the first from the shape guess (any number of links) and the
    rate omega_guess (rad / tau at ns[0]), each next from the previous carried to its N with the rate scaled by
    N^-4; their continuum limits (analysis.filament.richardson). on_rung(n, seconds): told each rung's N and wall
    time as it is found (a caller's cost estimate of the rungs left)."""
    ns = [int(n) for n in ns]
    states = []
    shape, omega, previous = np.asarray(guess, dtype=float), float(omega_guess), ns[0]
    for n in ns:
        omega *= (previous / n) ** 4  # the rate scales as N^-4 at a fixed load: the next rung's first guess
        start = time.perf_counter()
        state = find_whirl(Chain3D(n=n, sigma=load / n**3, gamma_l=gamma_l), resample_tangents(shape, n), omega)
        if on_rung is not None:
            on_rung(n, time.perf_counter() - start)
        states.append(state)
        shape, omega, previous = state.tangents, state.omega, n
    n_arr = np.array(ns, dtype=float)
    return WhirlLadder(
        float(load),
        tuple(states),
        richardson(ns, [s.omega * n**4 for s, n in zip(states, n_arr)]),
        richardson(ns, [s.tip_radius / n for s, n in zip(states, n_arr)]),
        richardson(ns, [s.bend for s in states]),
    )


def settled_whirl(n: int, sigma: float, gamma_l: float = 1.0) -> WhirlState:
    """The whirl of N links at sigma, from a helix (HELIX) run SETTLE_TIME natural times N^4 / (N^3 sigma) until it
    settles (its rate measured over the second half, analysis.motion3d), then refined by Newton (find_whirl; its
    NoWhirl, saying what the run ended in, when the run did not reach a whirl)."""
    chain = Chain3D(n=int(n), sigma=float(sigma), gamma_l=float(gamma_l)).checked()
    ts = np.linspace(0.0, SETTLE_TIME * chain.n / chain.sigma if chain.sigma > 0 else 1.0, SETTLE_SAMPLES + 1)
    s = np.arange(1, chain.n + 1) / chain.n
    t0 = np.column_stack([np.ones(chain.n), HELIX * s, HELIX * s * s])
    path = solve3d(chain, ts, t0 / np.linalg.norm(t0, axis=1)[:, None], rtol=1e-10, atol=1e-10)
    motion = measure3d(ts, path)
    try:
        return find_whirl(chain, path[-1], 2 * np.pi * motion.whirl_rate)
    except NoWhirl as missed:
        raise NoWhirl(
            f"{missed}: the run from a helix over {ts[-1]:.4g} tau had not settled into a whirl (its tip "
            f"{motion.tip_radius:.3g} l from the axis, turning at {motion.whirl_rate:.2g} cycles per tau)",
            missed.straight,
        ) from None


def continuum_whirl(load: float, ns, gamma_l: float = 1.0, on_rung=None) -> WhirlLadder:
    """The whirl's continuum limit at S = load: the first rung (ns[0]) settled from a helix (settled_whirl), the ladder
    of ns from it (ladder; on_rung as there)."""
    ns = [int(n) for n in ns]
    first = settled_whirl(ns[0], load / ns[0] ** 3, gamma_l)
    return ladder(load, ns, first.tangents, first.omega, gamma_l, on_rung)


@dataclass(frozen=True)
class BeatStability:
    """The planar beat's Floquet multipliers out of its plane (module docstring)."""

    period: float
    """The beat's period (tau)."""
    multipliers: np.ndarray
    """The out-of-plane Floquet multipliers, by decreasing modulus."""

    @property
    def growth(self) -> float:
        """log|mu_max| / period (per tau): > 0 when the beat is unstable out of its plane."""
        return float(np.log(np.abs(self.multipliers[0])) / self.period)


def beat_out_of_plane(chain: Chain3D, settle: float, periods: int = 20) -> BeatStability:
    """The out-of-plane Floquet multipliers of the planar beat the chain reaches from a small planar push after
    `settle` tau (its period measured over the last `periods` periods of the settling run, analysis.filament.beat)."""
    chain = chain.checked()
    n = chain.n
    theta0 = 0.01 * np.sin(0.3 * np.arange(1, n + 1))
    ts = np.linspace(0.0, settle, int(settle * 20) + 1)
    path = solve3d(chain, ts, tangents_of_angles(theta0), rtol=1e-11, atol=1e-12)
    theta = planar_angles(path)
    curvature = theta[:, -1] - theta[:, 0]
    rough = beat(ts[ts.size // 2 :], curvature[ts.size // 2 :]).period
    fine = np.linspace(0.0, periods * rough, periods * SAMPLES_PER_PERIOD + 1)
    start = path[-1]
    cycle = planar_angles(solve3d(chain, fine, start, rtol=1e-11, atol=1e-12))
    period = beat(fine, cycle[:, -1] - cycle[:, 0]).period
    piece = period / PIECES
    orbit = solve3d(chain, np.linspace(0.0, period, PIECES + 1), start, rtol=1e-11, atol=1e-12)
    monodromy = np.eye(n)
    for base in orbit[:-1]:  # the product of the pieces' monodromies, each a linear response
        step = np.empty((n, n))
        for k in range(n):
            pushed = base.copy()
            pushed[k, 2] = EPSILON
            pushed[k] /= np.linalg.norm(pushed[k])
            end = solve3d(chain, np.array([0.0, piece]), pushed, rtol=1e-11, atol=1e-14)[-1]
            step[:, k] = end[:, 2] / EPSILON
        monodromy = step @ monodromy
    mu = np.linalg.eigvals(monodromy)
    return BeatStability(float(period), mu[np.argsort(-np.abs(mu))])

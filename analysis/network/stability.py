"""Linear stability of a network's fixed points: where collective actuation must set in.

At rest every node velocity vanishes, so any polarities psi* are a fixed point with the nodes where the springs
balance the active forces (H(x*) the passive forces' Jacobian there). Linearised about it, on the state (x, psi) of
the free nodes and the units (lengths in units a, drag 1, N_perp the (2F x A) matrix of the units' n_perp):

    J = [[ H,               sigma N_perp      ],
         [ N_perp^T H / l_a, (sigma / l_a) I  ]]   (model.jacobian at the fixed point)

non-symmetric, of rank <= 2F: J = [I; N_perp^T / l_a] [H, sigma N_perp], so its non-zero eigenvalues are those of
H + Pi Q with Pi = sigma / l_a (the elasto-active coupling l_e / l_a) and Q = N_perp N_perp^T (the projector on each
unit's perpendicular), and it has A zero eigenvalues along the family of fixed points. In the linear-elastic limit
H = -D (the dynamical matrix; x* - rest = O(sigma)), the fixed point of polarities psi is stable while
Pi < Pi_c(psi) = 1 / mu_max(psi), mu_max the largest generalised eigenvalue of Q v = mu D v, equivalently the largest
eigenvalue of the A x A matrix M(psi) = N_perp^T D^-1 N_perp. What is proved and what is found, for Pi* = max over
psi of Pi_c(psi) (where the last fixed point loses stability):

- every fixed point is stable below the softest mode's eigenvalue lambda_1 (Q <= I, so Pi_c >= lambda_1);
- some fixed point is stable up to at least the best Pi_c found (`threshold`: a search over the polarities, whose
  best local maximum bounds Pi* from below);
- none is stable above `coupling_ceiling`, an upper bound on Pi* proved for every psi (two bounds, the smaller kept):
  by interlacing, Pi_c(psi) <= lambda_{2F-A+1}, and from one unit, Pi_c(psi) <= 1 / max_u lambda_min((D^-1)_uu).

A floppy network (D singular on its free nodes: a honeycomb lattice, a diluted network, a node or cluster held by
nothing) has a fixed point unstable at every Pi > 0 for almost every psi (Q meets D's null space); `threshold` reports
its bracket as [0, interlacing_ceiling] without searching.

Large networks (more than reduced.network.DENSE_MODES free coordinates) run sparse, never building an N x N array:
lambda_1 and the softest modes by shift-invert Lanczos, the one-unit ceiling from UNIT_CANDIDATES units (the most
compliant by the softest modes: a bound from any set of units is proved, the max over all of them only the
tightest), the interlacing ceiling where its index lies among the softest LOWEST_CEILING modes (else Gershgorin's
bound on lambda_max, weaker, still proved); no search (`threshold` reports the best found as lambda_1, from 0 starts).

A single unit in a trap of stiffness k_t: D = k_t I, Pi_c = k_t for every psi, and both bounds are exact (Pi = l_e /
l_a = 1 in the trap's own units).

Units of their own (unit u pushing with f_u sigma, turning over l_u: networks.geometry.unit_forces,
unit_alignment_lengths): the linearisation is J = [I; L^-1 N_perp^T] [H, sigma N_perp F] (F = diag f_u,
L = diag l_u), whose non-zero eigenvalues are those of H + sigma N_perp F L^-1 N_perp^T = H + Pi Q_w, with Pi = sigma /
l_a (l_a the run's alignment length, the reference) and Q_w = N_perp W N_perp^T, W = diag w_u, w_u = f_u l_a / l_u
(`unit_weights`; every w_u = 1 without the fields, and every result is then today's to the bit: the weights multiply
by 1.0). The fixed point psi is stable while Pi < 1 / mu_max(psi), mu_max the largest eigenvalue of
M_w = W^(1/2) N_perp^T D^-1 N_perp W^(1/2); a unit of force 0 is passive (w_u = 0: its row of M_w vanishes, its
polarity is free) and drops out of everything, as if removed. The bounds with the weights (w_max = max_u w_u, w_+ the
least weight of the A_+ units with w_u > 0):

- every fixed point is stable below lambda_1 / w_max (Q_w <= w_max Q <= w_max I);
- one unit: M_w,uu = w_u n_perp_u^T (D^-1)_uu n_perp_u, so Pi_c <= 1 / max_u (w_u lambda_min((D^-1)_uu));
- interlacing: Q_w >= w_+ Q_+ (Q_+ the projector on the A_+ active units' n_perp), so D - Pi Q_w <= D - Pi w_+ Q_+,
  which is not positive definite for Pi w_+ > lambda_{2F-A_+ +1}: Pi_c <= lambda_{2F-A_+ +1} / w_+.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...core.errors import ParameterError
from ...networks.geometry import Network, unit_alignment_lengths, unit_forces
from ...reduced.network import (
    LOWEST_MODES,
    dynamical_matrix,
    dynamical_matrix_sparse,
    factorized,
    is_large,
    lowest_eigenvalues,
)


def perpendiculars(psi: np.ndarray, units: np.ndarray, n_free: int) -> np.ndarray:
    """(2F, A) N_perp: column u holds unit u's n_perp on its node's two coordinates (units[u]: the node's index
    among the free nodes)."""
    out = np.zeros((2 * n_free, len(psi)))
    for u, (p, s) in enumerate(zip(psi, units)):
        out[2 * s : 2 * s + 2, u] = (-np.sin(p), np.cos(p))
    return out


def unit_slots(network: Network) -> np.ndarray:
    """(A,) the index among the free nodes of each active unit's node (active units on free nodes only)."""
    slot = np.cumsum(~network.pinned) - 1
    active = np.flatnonzero(network.active & ~network.pinned)
    return slot[active]


def unit_weights(network: Network, alignment_length: float | None = None) -> np.ndarray:
    """(A,) w_u = f_u l_a / l_u in node order: unit u's weight in Q_w = N_perp W N_perp^T (Pi = sigma / l_a, l_a the
    run's `alignment_length`, needed only when the network gives the units their own alignment lengths). Exactly 1
    for every unit without the fields; 0 for a passive unit (force 0). At least one unit must push."""
    count = int(np.count_nonzero(network.active & ~network.pinned))
    if network.unit_force is None and network.unit_alignment_length is None:
        return np.ones(count)
    if network.unit_alignment_length is not None and alignment_length is None:
        raise ParameterError(
            "stability: the network's units have their own alignment lengths (unit_alignment_length); the bracket "
            "needs the run's alignment_length, the reference of Pi = sigma / l_a"
        )
    reference = 1.0 if alignment_length is None else float(alignment_length)
    weights = unit_forces(network, 1.0) * reference / unit_alignment_lengths(network, reference)
    if count and not np.any(weights > 0):
        raise ParameterError("stability: every unit has force 0 (unit_force): nothing drives the network")
    return weights


def _pushing(weights: np.ndarray) -> np.ndarray:
    """Indices among the units of those that push (w_u > 0): the passive ones drop out of the analysis."""
    return np.flatnonzero(weights > 0)


def weighted_perpendiculars(
    network: Network, psi: np.ndarray, n_free: int, alignment_length: float | None = None
) -> np.ndarray:
    """(2F, A) N_perp W^(1/2): Q_w = N_perp W N_perp^T is its product with its transpose."""
    weights = unit_weights(network, alignment_length)
    return perpendiculars(np.asarray(psi, dtype=float), unit_slots(network), n_free) * np.sqrt(weights)


def coupling_operator(
    network: Network, psi: np.ndarray, coupling: float, alignment_length: float | None = None
) -> np.ndarray:
    """-D + Pi Q_w (2F x 2F): its eigenvalues are the linear-elastic fixed point's non-zero growth rates."""
    d = dynamical_matrix(network)
    n = weighted_perpendiculars(network, psi, d.shape[0] // 2, alignment_length)
    return -d + coupling * n @ n.T


def critical_coupling(network: Network, psi: np.ndarray, alignment_length: float | None = None) -> float:
    """Pi_c(psi) = 1 / mu_max: the coupling at which the fixed point of polarities psi loses stability (D must be
    positive definite: a pinned patch or a trap)."""
    from scipy.linalg import eigh  # start-up time: scipy.linalg only for the stability analysis

    d = dynamical_matrix(network)
    n = weighted_perpendiculars(network, psi, d.shape[0] // 2, alignment_length)
    return float(1.0 / eigh(n @ n.T, d, eigvals_only=True)[-1])


SMOOTHING = (0.1, 0.03, 0.01, 0.003, 0.001)
"""Temperatures (relative to mu_max) of the smoothed searches `threshold` runs after each plain one: mu_max is not
differentiable where its top eigenvalues cross, which is where Pi_c peaks, and a plain descent stalls there (R = 3:
Pi_c 0.968 from 6 plain starts, 0.9914 once smoothed)."""
REACHED = 1e-4
"""Relative distance within which a search's Pi_c counts as having reached the best found."""
SEARCH_UNITS = 120
"""`threshold` searches from about SEARCH_UNITS / A starts (A units), at least MIN_STARTS and at most MAX_STARTS: more
where a search is cheap."""
MIN_STARTS, MAX_STARTS = 4, 16


def search_starts(units: int) -> int:
    """How many seeded starts `threshold` searches from by default for `units` active units."""
    return int(np.clip(round(SEARCH_UNITS / max(units, 1)), MIN_STARTS, MAX_STARTS))


def _critical_coupling_objective(network: Network, weights: np.ndarray):
    """mu_max(psi) and its gradient over the pushing units' polarities (weights > 0), for minimising (Pi_c =
    1 / mu_max), or at temperature t > 0 its smooth upper bound t log sum_i exp(mu_i / t) over the eigenvalues mu_i
    of M_w. With D = L L^T and B = L^-1 N_perp W^(1/2), the mu_i are the eigenvalues of B^T B;
    w_i = L^-T B c_i / sqrt(mu_i) (c_i their eigenvectors) is the generalised eigenvector with w^T D w = 1, and
    d mu_i / d psi_u = w_i^T (dQ_w / dpsi_u) w_i = -2 w_u (w_iu . n_perp_u)(w_iu . n_u)."""
    from scipy.linalg import cholesky, solve_triangular  # start-up time: scipy.linalg only for the stability analysis

    d = dynamical_matrix(network)
    pushing = _pushing(weights)
    slots = unit_slots(network)[pushing]
    weights = weights[pushing]
    scale = np.sqrt(weights)
    free = d.shape[0] // 2
    inverse = solve_triangular(cholesky(d, lower=True), np.eye(2 * free), lower=True)

    def objective(psi: np.ndarray, temperature: float = 0.0) -> tuple[float, np.ndarray]:
        b = inverse @ (perpendiculars(psi, slots, free) * scale)
        values, vectors = np.linalg.eigh(b.T @ b)
        top = float(values[-1])
        if temperature > 0:
            weight = np.exp((values - top) / temperature)
            total = float(weight.sum())
            weight /= total
            top += temperature * np.log(total)
        else:
            weight = np.zeros_like(values)
            weight[-1] = 1.0
        keep = np.flatnonzero(weight > 1e-12)
        w = (inverse.T @ (b @ vectors[:, keep]) / np.sqrt(values[keep])).T.reshape(keep.size, -1, 2)[:, slots]
        along = w[..., 0] * np.cos(psi) + w[..., 1] * np.sin(psi)
        across = -w[..., 0] * np.sin(psi) + w[..., 1] * np.cos(psi)
        return top, -2.0 * weights * (weight[keep, None] * across * along).sum(axis=0)

    return objective


def interlacing_ceiling(network: Network, alignment_length: float | None = None) -> float:
    """lambda_{2F-A+1} of the dynamical matrix, above which no fixed point is stable. The units sit on distinct nodes,
    so the n_perp columns of N_perp are orthonormal and Q projects on their span S(psi), of dimension A; the span E of
    D's 2F - A + 1 softest modes meets S(psi) in some v != 0 (the dimensions add to more than 2F), where
    v^T D v <= lambda_{2F-A+1} |v|^2 and v^T Q v = |v|^2, so D - Pi Q is not positive definite for
    Pi > lambda_{2F-A+1}, whatever psi. Units of their own: Q_w >= w_+ Q_+ over the A_+ pushing units (w_+ their
    least weight), so the ceiling is lambda_{2F-A_+ +1} / w_+. A large network: that eigenvalue when it is among the
    LOWEST_CEILING softest, else Gershgorin's bound on lambda_max (>= it: a weaker bound, still proved)."""
    weights = unit_weights(network, alignment_length)
    pushing = weights[_pushing(weights)]
    least = float(pushing.min()) if pushing.size else 1.0
    index = 2 * int(np.count_nonzero(~network.pinned)) - pushing.size
    if not is_large(network):
        values = np.linalg.eigvalsh(dynamical_matrix(network))
        return float(values[index]) / least
    values, _ = _softest(network)
    if index < values.size:
        return float(values[index]) / least
    if index < LOWEST_CEILING:
        return float(lowest_eigenvalues(network, index + 1)[index]) / least
    return gershgorin(network) / least


def gershgorin(network: Network) -> float:
    """max_i sum_j |D_ij|: Gershgorin's bound on lambda_max of the dynamical matrix (>= every eigenvalue), O(B)."""
    d = dynamical_matrix_sparse(network)
    return float(abs(d).sum(axis=1).max()) if d.shape[0] else 0.0


def unit_ceiling(network: Network, alignment_length: float | None = None) -> float:
    """1 / max_u lambda_min((D^-1)_uu), above which no fixed point is stable: Pi_c(psi) = 1 / lambda_max(M) with
    M = N_perp^T D^-1 N_perp, and lambda_max(M) >= M_uu = n_perp_u^T (D^-1)_uu n_perp_u >= lambda_min((D^-1)_uu)
    for every unit u ((D^-1)_uu: the 2 x 2 block of unit u's node); with units of their own, M_w,uu = w_u M_uu and the
    ceiling is 1 / max_u (w_u lambda_min((D^-1)_uu)). Dense over every unit for a small network; a large one:
    unit_ceiling_sparse over UNIT_CANDIDATES units."""
    if is_large(network):
        return unit_ceiling_sparse(network, alignment_length=alignment_length)
    weights = unit_weights(network, alignment_length)
    inverse = np.linalg.inv(dynamical_matrix(network))
    floor = max(
        w * float(np.linalg.eigvalsh(inverse[2 * s : 2 * s + 2, 2 * s : 2 * s + 2])[0])
        for s, w in zip(unit_slots(network), weights)
    )
    return float(1.0 / floor)


def _softest(network: Network) -> tuple[np.ndarray, np.ndarray]:
    """The LOWEST_MODES + 2 lowest eigenpairs of a large network's dynamical matrix (reduced.network keeps the last
    network's, so a run's observables and its stability analysis factorise it once)."""
    return lowest_eigenvalues(network, LOWEST_MODES + 2, vectors=True, sparse=True)


UNIT_CANDIDATES = 32
"""Units whose 2 x 2 compliance blocks (D^-1)_uu a large network's one-unit ceiling solves for (two sparse solves
each): the most compliant by the softest modes' estimate sum_m |v_m,u|^2 / lambda_m."""
LOWEST_CEILING = 64
"""A large network's interlacing ceiling is computed when its index lies among this many softest modes."""


def unit_ceiling_sparse(
    network: Network, units: np.ndarray | None = None, alignment_length: float | None = None
) -> float:
    """unit_ceiling from sparse solves D x = e (D factorised once): over the units given (indices among the units),
    by default every pushing unit of a network with at most UNIT_CANDIDATES of them, else the UNIT_CANDIDATES most
    compliant by the softest modes (times their weights). Each unit's bound holds on its own, so the result is a
    proved ceiling whichever units are used (the max over every unit, unit_ceiling's, is the tightest)."""
    slots = unit_slots(network)
    weights = unit_weights(network, alignment_length)
    if units is None:
        units = _pushing(weights)
        if units.size > UNIT_CANDIDATES:
            values, vectors = _softest(network)
            weight = (vectors**2 / values).reshape(-1, 2, values.size).sum(axis=(1, 2))  # per free node
            units = units[np.argsort(weight[slots[units]] * weights[units])[::-1][:UNIT_CANDIDATES]]
    units = np.asarray(units, dtype=int)
    chosen = slots[units]
    d = dynamical_matrix_sparse(network)
    solve = factorized(d)
    x = np.empty((d.shape[0], 2 * chosen.size))
    for k, dof in enumerate(np.column_stack([2 * chosen, 2 * chosen + 1]).ravel()):  # one column at a time: SuperLU
        unit = np.zeros(d.shape[0])  # solves many columns at once ~3x slower per column
        unit[dof] = 1.0
        x[:, k] = solve(unit)
    columns = np.arange(chosen.size)
    a = x[2 * chosen, 2 * columns]  # each unit's symmetric 2 x 2 block [[a, b], [b, c]] of D^-1
    b = 0.5 * (x[2 * chosen, 2 * columns + 1] + x[2 * chosen + 1, 2 * columns])
    c = x[2 * chosen + 1, 2 * columns + 1]
    lowest = 0.5 * (a + c) - np.sqrt(0.25 * (a - c) ** 2 + b**2)
    return float(1.0 / (weights[units] * lowest).max())


def softest(network: Network) -> float:
    """lambda_1, the dynamical matrix's lowest eigenvalue (dense or sparse by the network's size)."""
    if is_large(network):
        return float(_softest(network)[0][0])
    return float(lowest_eigenvalues(network, 1)[0])


def stable_below(network: Network, alignment_length: float | None = None) -> float:
    """lambda_1 / max_u w_u: every fixed point is stable below this coupling (Q_w <= max_u w_u I); lambda_1 itself
    when every unit has the run's force and alignment length."""
    return softest(network) / float(unit_weights(network, alignment_length).max())


def least_stable_growth(network: Network, coupling: float, alignment_length: float | None = None) -> float:
    """The least stable fixed point's largest growth rate at coupling Pi: max over psi of lambda_max(-D + Pi Q_w) =
    lambda_max(-D + Pi P_w), P_w diagonal with w_u on both coordinates of unit u's node (for any v,
    sum_u w_u (v_u . n_perp_u)^2 <= sum_u w_u |v_u|^2, equal for each n_perp_u along v_u). Every free node carrying a
    unit of weight 1 (P_w = I): Pi - lambda_1. A large network otherwise: Pi max_u w_u - lambda_1, an upper bound."""
    weights = unit_weights(network, alignment_length)
    slots = unit_slots(network)
    if np.all(weights == 1.0) and slots.size == np.count_nonzero(~network.pinned):
        return coupling - softest(network)
    if is_large(network):
        return coupling * float(weights.max()) - softest(network)
    d = dynamical_matrix(network)
    diagonal = np.zeros(d.shape[0])
    diagonal[2 * slots] = diagonal[2 * slots + 1] = weights
    return float(np.linalg.eigvalsh(-d + coupling * np.diag(diagonal))[-1])


FLOPPY = 1e-10
"""Eigenvalues of the dynamical matrix at most FLOPPY times its largest (or 1) are zero modes: the network is floppy."""


def floppy_modes(network: Network) -> int:
    """How many zero modes the dynamical matrix of the free nodes has (0: D is positive definite). A large network:
    counted among its softest eigenvalues (more asked for while every one is zero), below FLOPPY times Gershgorin's
    bound on lambda_max."""
    if not is_large(network):
        values = np.linalg.eigvalsh(dynamical_matrix(network))
        return int(np.count_nonzero(values <= FLOPPY * max(1.0, float(values[-1]) if values.size else 1.0)))
    limit = FLOPPY * max(1.0, gershgorin(network))
    values = _softest(network)[0]
    if np.count_nonzero(values <= limit) < values.size:
        return int(np.count_nonzero(values <= limit))
    count = 2 * values.size
    while True:
        values = lowest_eigenvalues(network, count)
        zero = int(np.count_nonzero(values <= limit))
        if zero < values.size:
            return zero
        count *= 2


def coupling_ceiling(network: Network, alignment_length: float | None = None) -> float:
    """A proved upper bound on Pi* (no fixed point is stable above it, whatever the polarities): the smaller of
    interlacing_ceiling and unit_ceiling (interlacing_ceiling alone for a floppy network, whose D has no inverse)."""
    if floppy_modes(network):
        return interlacing_ceiling(network, alignment_length)
    return min(interlacing_ceiling(network, alignment_length), unit_ceiling(network, alignment_length))


class Threshold(NamedTuple):
    softest: float  # stable_below, lambda_1 / max_u w_u (lambda_1 for equal units): every fixed point stable below
    coupling: float  # the best Pi_c found: some fixed point is stable up to at least this (Pi* >= coupling)
    polarities: np.ndarray  # that fixed point's psi
    typical: float  # median of Pi_c over uniformly random polarities
    ceiling: float  # coupling_ceiling: no fixed point is stable above it (proved, Pi* <= ceiling)
    starts: int  # searches run
    reached: int  # searches that ended within REACHED of the best
    floppy: int = 0  # zero modes of D (floppy_modes): then softest = coupling = typical = 0, no search run


def threshold(
    network: Network,
    starts: int | None = None,
    seed: int = 0,
    samples: int = 400,
    iterations: int = 3000,
    alignment_length: float | None = None,
) -> Threshold:
    """stable_below (lambda_1 for equal units); the best Pi_c found by searches over the polarities from `starts`
    seeded random polarities (default search_starts): from each, L-BFGS on the analytic gradient of mu_max (at most
    `iterations` steps), then the same through the SMOOTHING temperatures and again plain, keeping the better end; the
    median Pi_c of `samples` random polarities; and coupling_ceiling. Units of their own weigh Q by w_u = f_u l_a / l_u
    (unit_weights; `alignment_length`, the run's l_a, when they have their own lengths); the search runs over the
    pushing units' polarities only (a passive unit's is reported as 0: any value is the same fixed point's stability).
    A floppy network (floppy_modes > 0): softest, coupling and typical 0 (almost every fixed point is unstable at any
    Pi > 0), no search. A large network (reduced.network.is_large): the sparse bracket, stable_below and
    coupling_ceiling, with no search (coupling = stable_below, typical NaN, starts 0)."""
    from scipy.optimize import minimize  # start-up time: scipy.optimize only for the stability analysis

    rng = np.random.default_rng(seed)
    weights = unit_weights(network, alignment_length)
    pushing = _pushing(weights)
    count = pushing.size
    floppy = floppy_modes(network)
    if floppy:
        return Threshold(
            0.0, 0.0, np.zeros(weights.size), 0.0, interlacing_ceiling(network, alignment_length), 0, 0, floppy
        )
    if is_large(network):  # the search's A x A eigenproblems are dense: none; stable_below is a proved lower bound
        lowest = stable_below(network, alignment_length)
        return Threshold(
            lowest, lowest, np.zeros(weights.size), float("nan"), coupling_ceiling(network, alignment_length), 0, 0
        )
    starts = search_starts(count) if starts is None else int(starts)
    objective = _critical_coupling_objective(network, weights)
    options = {"maxiter": iterations}
    ends = []
    for _ in range(starts):
        plain = minimize(objective, rng.uniform(0, 2 * np.pi, count), jac=True, method="L-BFGS-B", options=options)
        x = plain.x
        for temperature in SMOOTHING:
            scale = temperature * objective(x)[0]
            x = minimize(objective, x, args=(scale,), jac=True, method="L-BFGS-B", options=options).x
        smoothed = minimize(objective, x, jac=True, method="L-BFGS-B", options=options)
        ends.append(
            min(
                (float(objective(plain.x)[0]), plain.x),
                (float(objective(smoothed.x)[0]), smoothed.x),
                key=lambda end: end[0],
            )
        )
    best, polarities = min(ends, key=lambda end: end[0])
    reached = sum(mu <= best * (1.0 + REACHED) for mu, _ in ends)
    typical = float(np.median([1.0 / objective(rng.uniform(0, 2 * np.pi, count))[0] for _ in range(samples)]))
    every = np.zeros(weights.size)
    every[pushing] = np.mod(polarities, 2 * np.pi)
    return Threshold(
        stable_below(network, alignment_length),
        1.0 / best,
        every,
        typical,
        coupling_ceiling(network, alignment_length),
        starts,
        reached,
    )

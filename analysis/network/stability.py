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
Pi < Pi_c(psi) = 1 / mu_max(psi), mu_max the largest generalised eigenvalue of Q v = mu D v. Since Q <= I, every
fixed point is stable below the softest mode's eigenvalue lambda_1, and none is stable above
Pi* = max over psi of Pi_c(psi): `threshold` bounds it from below by optimising the polarities (L-BFGS on the
analytic gradient of mu_max from seeded starts: a lower bound, the best local maximum found), `coupling_ceiling` from
above (a trace bound, no optimisation). A single unit in a trap of
stiffness k_t: D = k_t I, Pi_c = k_t for every psi (Pi = l_e / l_a = 1 in the trap's own units).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .geometry import Network
from .model import dynamical_matrix


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


def coupling_operator(network: Network, psi: np.ndarray, coupling: float) -> np.ndarray:
    """-D + Pi Q (2F x 2F): its eigenvalues are the linear-elastic fixed point's non-zero growth rates."""
    d = dynamical_matrix(network)
    n = perpendiculars(np.asarray(psi, dtype=float), unit_slots(network), d.shape[0] // 2)
    return -d + coupling * n @ n.T


def critical_coupling(network: Network, psi: np.ndarray) -> float:
    """Pi_c(psi) = 1 / mu_max: the coupling at which the fixed point of polarities psi loses stability (D must be
    positive definite: a pinned patch or a trap)."""
    from scipy.linalg import eigh  # start-up time: scipy.linalg only for the stability analysis

    d = dynamical_matrix(network)
    n = perpendiculars(np.asarray(psi, dtype=float), unit_slots(network), d.shape[0] // 2)
    return float(1.0 / eigh(n @ n.T, d, eigvals_only=True)[-1])


def _critical_coupling_objective(network: Network):
    """mu_max(psi) and its gradient, for minimising (Pi_c = 1 / mu_max): with D = L L^T and B = L^-1 N_perp, mu_max
    is the top eigenvalue of B^T B; w = L^-T B c / sqrt(mu) (c its eigenvector) is the generalised eigenvector with
    w^T D w = 1, and d mu / d psi_u = w^T (dQ / dpsi_u) w = -2 (w_u . n_perp_u)(w_u . n_u)."""
    from scipy.linalg import cholesky, solve_triangular  # start-up time: scipy.linalg only for the stability analysis

    d = dynamical_matrix(network)
    slots = unit_slots(network)
    free = d.shape[0] // 2
    inverse = solve_triangular(cholesky(d, lower=True), np.eye(2 * free), lower=True)

    def objective(psi: np.ndarray) -> tuple[float, np.ndarray]:
        b = inverse @ perpendiculars(psi, slots, free)
        values, vectors = np.linalg.eigh(b.T @ b)
        mu = float(values[-1])
        w = (inverse.T @ (b @ vectors[:, -1]) / np.sqrt(mu)).reshape(-1, 2)[slots]
        along = w[:, 0] * np.cos(psi) + w[:, 1] * np.sin(psi)
        across = -w[:, 0] * np.sin(psi) + w[:, 1] * np.cos(psi)
        return mu, -2.0 * across * along

    return objective


def coupling_ceiling(network: Network) -> float:
    """An upper bound on Pi*, no optimisation: D^-1/2 Q D^-1/2 has rank <= A, so mu_max >= tr(D^-1 Q) / A, and
    tr(D^-1 Q) = sum_u n_perp_u^T (D^-1)_uu n_perp_u >= sum_u (smallest eigenvalue of unit u's 2 x 2 block of D^-1):
    Pi_c(psi) <= A / that sum for every psi."""
    inverse = np.linalg.inv(dynamical_matrix(network))
    slots = unit_slots(network)
    floor = sum(float(np.linalg.eigvalsh(inverse[2 * s : 2 * s + 2, 2 * s : 2 * s + 2])[0]) for s in slots)
    return len(slots) / floor


class Threshold(NamedTuple):
    softest: float        # lambda_1: below it every fixed point is stable
    coupling: float       # Pi* (a lower bound: the best local maximum found): above it no fixed point is stable
    polarities: np.ndarray  # the most stable fixed point's psi (the last to lose stability)
    typical: float        # median of Pi_c over uniformly random polarities
    ceiling: float        # coupling_ceiling: an upper bound on Pi*


def threshold(network: Network, starts: int = 12, seed: int = 0, samples: int = 400,
              iterations: int = 3000) -> Threshold:
    """lambda_1, Pi* >= max over `starts` seeded random polarities of the local maximum of Pi_c (L-BFGS on the
    analytic gradient, at most `iterations` steps each), the median Pi_c of `samples` random polarities, and
    coupling_ceiling."""
    from scipy.optimize import minimize  # start-up time: scipy.optimize only for the stability analysis

    rng = np.random.default_rng(seed)
    count = len(unit_slots(network))
    objective = _critical_coupling_objective(network)
    best = None
    for _ in range(starts):
        result = minimize(objective, rng.uniform(0, 2 * np.pi, count), jac=True, method="L-BFGS-B",
                          options={"maxiter": iterations})
        if best is None or result.fun < best.fun:
            best = result
    typical = float(np.median([1.0 / objective(rng.uniform(0, 2 * np.pi, count))[0] for _ in range(samples)]))
    softest = float(np.linalg.eigvalsh(dynamical_matrix(network))[0])
    return Threshold(softest, float(1.0 / best.fun), np.mod(best.x, 2 * np.pi), typical, coupling_ceiling(network))

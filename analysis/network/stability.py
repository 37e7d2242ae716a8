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
Pi* = max over psi of Pi_c(psi): `threshold` finds it by optimising the polarities. A single unit in a trap of
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


class Threshold(NamedTuple):
    softest: float        # lambda_1: below it every fixed point is stable
    coupling: float       # Pi*: above it no fixed point is stable
    polarities: np.ndarray  # the most stable fixed point's psi (the last to lose stability)
    typical: float        # median of Pi_c over uniformly random polarities


def threshold(network: Network, starts: int = 12, seed: int = 0, samples: int = 400) -> Threshold:
    """lambda_1, Pi* = max_psi Pi_c(psi) (Nelder-Mead from `starts` seeded random polarities, the best kept) and the
    median Pi_c of `samples` random polarities."""
    from scipy.optimize import minimize  # start-up time: scipy.optimize only for the stability analysis

    rng = np.random.default_rng(seed)
    count = len(unit_slots(network))
    best = None
    for _ in range(starts):
        result = minimize(lambda p: -critical_coupling(network, p), rng.uniform(0, 2 * np.pi, count),
                          method="Nelder-Mead", options={"maxiter": 400 * count, "xatol": 1e-9, "fatol": 1e-12})
        if best is None or result.fun < best.fun:
            best = result
    typical = float(np.median([critical_coupling(network, rng.uniform(0, 2 * np.pi, count)) for _ in range(samples)]))
    softest = float(np.linalg.eigvalsh(dynamical_matrix(network))[0])
    return Threshold(softest, float(-best.fun), np.mod(best.x, 2 * np.pi), typical)

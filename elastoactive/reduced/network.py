"""The reduced (overdamped) model of an elastic network of self-aligning active units, as pure functions.

Nodes i at x_i joined by linear springs (stiffness k_b, rest length L_b: force k_b (|r| - L_b) along the bond), an
optional isotropic trap (stiffness `trap`, pulling each free node to its anchor); each active node carries a unit of
polarity n_i = (cos psi_i, sin psi_i) pushing with force sigma n_i (Baconnier et al., Nature Physics 18, 1234 (2022)):

    dx_i/dt   = sigma n_i + F_i(x)                    (drag 1; pinned nodes stay at rest)
    dpsi_i/dt = (1 / l_a) (dx_i/dt) . n_perp_i,       n_perp = (-sin psi, cos psi)

Units: k = 1, drag gamma = 1, rest length a = 1; time in gamma / k. sigma = F_a / (k a), l_a = alignment_length
(units a). The state y holds the free nodes' x and y (node order, interleaved: x_0, y_0, x_1, ...) then the active
units' psi (node order); pinned nodes are not in it.

The right-hand side is a numba kernel (`rhs`), checked against the plain numpy `rhs_reference`; the analytic
Jacobian (`jacobian`) is what the linear stability (analysis.network.stability) and the implicit solver use.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from ..networks.geometry import Network
from ..networks.state import NetworkState


class NetworkSystem(NamedTuple):
    """Everything the kernels read: the network as flat arrays, the activity and the alignment length."""

    rest: np.ndarray  # (P, 2) rest positions (the pinned nodes' fixed positions)
    bonds: np.ndarray  # (B, 2) int
    rest_lengths: np.ndarray  # (B,)
    stiffness: np.ndarray  # (B,)
    anchors: np.ndarray  # (P, 2)
    trap: float
    slot: np.ndarray  # (P,) int: index of the node among the free nodes (-1: pinned)
    unit: np.ndarray  # (P,) int: index of the node's active unit (-1: none)
    sigma: float  # active force F_a / (k a)
    alignment_length: float  # l_a / a

    @property
    def n_free(self) -> int:
        return int(np.count_nonzero(self.slot >= 0))

    @property
    def n_units(self) -> int:
        return int(np.count_nonzero(self.unit >= 0))

    @property
    def state_size(self) -> int:
        return 2 * self.n_free + self.n_units


def network_system(network: Network, sigma: float, alignment_length: float) -> NetworkSystem:
    """The reduced model of `network` with active force sigma and alignment length l_a."""
    free = ~np.asarray(network.pinned, dtype=bool)
    slot = np.full(network.n_nodes, -1, dtype=np.int64)
    slot[free] = np.arange(int(free.sum()))
    unit = np.full(network.n_nodes, -1, dtype=np.int64)
    active = np.asarray(network.active, dtype=bool)
    unit[active] = np.arange(int(active.sum()))
    return NetworkSystem(
        rest=np.ascontiguousarray(network.positions, dtype=float),
        bonds=np.ascontiguousarray(network.bonds, dtype=np.int64).reshape(-1, 2),
        rest_lengths=np.ascontiguousarray(network.rest_lengths, dtype=float),
        stiffness=np.ascontiguousarray(network.stiffness, dtype=float),
        anchors=np.ascontiguousarray(network.anchors, dtype=float),
        trap=float(network.trap),
        slot=slot,
        unit=unit,
        sigma=float(sigma),
        alignment_length=float(alignment_length),
    )


# ------------------------------------------------------------------------------------------------ state
def pack(system: NetworkSystem, state: NetworkState) -> np.ndarray:
    """The solver's state vector of a NetworkState (free nodes' positions, then polarities)."""
    free = system.slot >= 0
    return np.concatenate(
        [np.asarray(state.positions, dtype=float)[free].reshape(-1), np.asarray(state.polarity, dtype=float)]
    )


def unpack(system: NetworkSystem, y: np.ndarray) -> NetworkState:
    """Positions of every node (T, P, 2) or (P, 2), and polarities, from state vectors (T, S) or (S,)."""
    y = np.asarray(y, dtype=float)
    lead = y.shape[:-1]
    free = system.slot >= 0
    f2 = 2 * system.n_free
    positions = np.broadcast_to(system.rest, lead + system.rest.shape).copy()
    positions[..., free, :] = y[..., :f2].reshape(lead + (system.n_free, 2))
    return NetworkState(positions, y[..., f2:].copy())


# ------------------------------------------------------------------------------------------------ forces
def passive_forces(system: NetworkSystem, positions: np.ndarray) -> np.ndarray:
    """(P, 2) spring and trap forces on every node at `positions` (plain numpy)."""
    i, j = system.bonds[:, 0], system.bonds[:, 1]
    r = positions[j] - positions[i]
    d = np.linalg.norm(r, axis=1)
    f = (system.stiffness * (d - system.rest_lengths) / d)[:, None] * r
    out = np.zeros_like(positions)
    np.add.at(out, i, f)
    np.add.at(out, j, -f)
    out -= system.trap * (positions - system.anchors)
    return out


def velocities(system: NetworkSystem, positions: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """(P, 2) node velocities dx/dt (0 for pinned nodes) at positions and polarities."""
    v = passive_forces(system, positions)
    has = system.unit >= 0
    p = psi[system.unit[has]]
    v[has] += system.sigma * np.column_stack([np.cos(p), np.sin(p)])
    v[system.slot < 0] = 0.0
    return v


def rhs_reference(system: NetworkSystem):
    """Plain numpy f(t, y) -> dy/dt, written straight from the equations (for tests)."""

    def f(t, y):
        positions, psi = unpack(system, y)
        v = velocities(system, positions, psi)
        has = system.unit >= 0
        p = psi[system.unit[has]]
        dpsi = np.zeros_like(psi)
        dpsi[system.unit[has]] = (-np.sin(p) * v[has, 0] + np.cos(p) * v[has, 1]) / system.alignment_length
        return np.concatenate([v[system.slot >= 0].reshape(-1), dpsi])

    return f


@njit(cache=True)
def _rhs(y, out, rest, bonds, rest_lengths, stiffness, anchors, trap, slot, unit, sigma, inv_la):
    count = rest.shape[0]
    f2 = y.size - np.count_nonzero(unit >= 0)  # the free nodes' coordinates come first
    pos = rest.copy()
    for p in range(count):
        s = slot[p]
        if s >= 0:
            pos[p, 0] = y[2 * s]
            pos[p, 1] = y[2 * s + 1]
    force = np.zeros((count, 2))
    for b in range(bonds.shape[0]):
        i, j = bonds[b, 0], bonds[b, 1]
        rx, ry = pos[j, 0] - pos[i, 0], pos[j, 1] - pos[i, 1]
        d = np.sqrt(rx * rx + ry * ry)
        c = stiffness[b] * (d - rest_lengths[b]) / d
        force[i, 0] += c * rx
        force[i, 1] += c * ry
        force[j, 0] -= c * rx
        force[j, 1] -= c * ry
    for p in range(count):
        s = slot[p]
        if s < 0:
            if unit[p] >= 0:
                out[f2 + unit[p]] = 0.0
            continue
        vx = force[p, 0] - trap * (pos[p, 0] - anchors[p, 0])
        vy = force[p, 1] - trap * (pos[p, 1] - anchors[p, 1])
        u = unit[p]
        if u >= 0:
            c, sn = np.cos(y[f2 + u]), np.sin(y[f2 + u])
            vx += sigma * c
            vy += sigma * sn
            out[f2 + u] = (-sn * vx + c * vy) * inv_la
        out[2 * s] = vx
        out[2 * s + 1] = vy


def rhs(system: NetworkSystem):
    """Compiled f(t, y) -> dy/dt of the model (numba kernel)."""
    args = (
        system.rest,
        system.bonds,
        system.rest_lengths,
        system.stiffness,
        system.anchors,
        float(system.trap),
        system.slot,
        system.unit,
        float(system.sigma),
        1.0 / float(system.alignment_length),
    )

    def f(t, y):
        out = np.empty(y.size)
        _rhs(np.asarray(y, dtype=float), out, *args)
        return out

    return f


# ------------------------------------------------------------------------------------------------ Jacobians
def force_jacobian(system: NetworkSystem, positions: np.ndarray) -> np.ndarray:
    """H = dF/dx (2P x 2P, node-interleaved) of the passive forces at `positions`: symmetric, -(the stiffness
    matrix); at rest -H is the dynamical matrix (drag 1)."""
    count = len(positions)
    h = np.zeros((2 * count, 2 * count))
    for (i, j), k, length in zip(system.bonds, system.stiffness, system.rest_lengths):
        r = positions[j] - positions[i]
        d = np.linalg.norm(r)
        e = r / d
        block = k * (np.outer(e, e) + (1.0 - length / d) * (np.eye(2) - np.outer(e, e)))
        si, sj = slice(2 * i, 2 * i + 2), slice(2 * j, 2 * j + 2)
        h[si, si] -= block
        h[sj, sj] -= block
        h[si, sj] += block
        h[sj, si] += block
    h -= system.trap * np.eye(2 * count)
    return h


def free_dofs(system: NetworkSystem) -> np.ndarray:
    """Indices of the free nodes' coordinates among all 2P (node-interleaved), in state order."""
    nodes = np.flatnonzero(system.slot >= 0)
    return np.column_stack([2 * nodes, 2 * nodes + 1]).reshape(-1)


def jacobian(system: NetworkSystem, y: np.ndarray) -> np.ndarray:
    """Analytic d(dy/dt)/dy (S x S) at state y.

    dv_i/dx_j = H_ij, dv_i/dpsi_i = sigma n_perp_i; dpsi_i'/dx_j = n_perp_i . H_ij / l_a,
    dpsi_i'/dpsi_i = (sigma - v_i . n_i) / l_a."""
    positions, psi = unpack(system, y)
    v = velocities(system, positions, psi)
    dofs = free_dofs(system)
    f2 = dofs.size
    size = system.state_size
    jac = np.zeros((size, size))
    h = force_jacobian(system, positions)[np.ix_(dofs, dofs)]
    jac[:f2, :f2] = h
    inv = 1.0 / system.alignment_length
    for p in np.flatnonzero(system.unit >= 0):
        u, s = system.unit[p], system.slot[p]
        if s < 0:
            continue
        n = np.array([np.cos(psi[u]), np.sin(psi[u])])
        perp = np.array([-n[1], n[0]])
        row = f2 + u
        jac[2 * s : 2 * s + 2, row] = system.sigma * perp
        jac[row, :f2] = inv * (perp @ h[2 * s : 2 * s + 2, :])
        jac[row, row] = inv * (system.sigma - v[p] @ n)
    return jac


def dynamical_matrix(network: Network) -> np.ndarray:
    """The dynamical matrix D of the free nodes at rest (2F x 2F, drag 1): -dF/dx, symmetric, positive
    semi-definite (zero modes where the patch can move rigidly)."""
    system = network_system(network, 0.0, 1.0)
    dofs = free_dofs(system)
    return -force_jacobian(system, system.rest)[np.ix_(dofs, dofs)]


def normal_modes(network: Network) -> tuple[np.ndarray, np.ndarray]:
    """(eigenvalues ascending (2F,), eigenvectors as columns (2F, 2F), orthonormal) of the dynamical matrix."""
    values, vectors = np.linalg.eigh(dynamical_matrix(network))
    return values, vectors


# ------------------------------------------------------------------------------------------------ integration
METHODS = ("DOP853", "LSODA", "Radau")
"""The ODE methods of scipy's solve_ivp the network model runs with (the implicit ones take the analytic Jacobian)."""


class Solution(NamedTuple):
    y: np.ndarray  # (T, S) states at the sample times
    nfev: int
    method: str


def solve(
    system: NetworkSystem,
    t: np.ndarray,
    y0: np.ndarray,
    *,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    method: str = "DOP853",
) -> Solution:
    """Integrate from y0 at t[0] and sample at t (scipy's solve_ivp with the compiled right-hand side)."""
    from scipy.integrate import solve_ivp  # start-up time: scipy.integrate costs ~0.4 s to import

    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    options = {} if method == "DOP853" else {"jac": lambda t, y: jacobian(system, y)}
    sol = solve_ivp(
        rhs(system),
        (float(t[0]), float(t[-1])),
        np.asarray(y0, dtype=float),
        method=method,
        t_eval=t,
        rtol=rtol,
        atol=atol,
        **options,
    )
    if not sol.success:
        raise RuntimeError(f"solve_ivp ({method}) failed on the network model: {sol.message}")
    return Solution(sol.y.T, int(sol.nfev), method)

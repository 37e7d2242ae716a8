"""The reduced (overdamped) model of an elastic network of self-aligning active units, as pure functions.

Nodes i at x_i joined by linear springs (stiffness k_b, rest length L_b: force k_b (|r| - L_b) along the bond), an
optional isotropic trap (stiffness `trap`, pulling each free node to its anchor); each active node carries a unit of
polarity n_i = (cos psi_i, sin psi_i) pushing with force sigma n_i (Baconnier et al., Nature Physics 18, 1234 (2022)):

    dx_i/dt   = sigma n_i + F_i(x)                    (drag 1; pinned nodes stay at rest)
    dpsi_i/dt = (1 / l_a) (dx_i/dt) . n_perp_i,       n_perp = (-sin psi, cos psi)

Units: k = 1, drag gamma = 1, rest length a = 1; time in gamma / k. sigma = F_a / (k a), l_a = alignment_length
(units a). The state y holds the free nodes' x and y (node order, interleaved: x_0, y_0, x_1, ...) then the active
units' psi (node order); pinned nodes are not in it.

The right-hand side is a numba kernel (`rhs`, network_kernels.rhs_into: O(bonds + nodes)), checked against the plain
numpy `rhs_reference`; `solve` runs DOP853 compiled around it (no Python per step), `solve_noisy` the Ito SDE of
noise on the units (Euler-Maruyama with the counter-based draws MuJoCo's run adds). The analytic Jacobian
(`jacobian`, dense or sparse) is what the linear stability (analysis.network.stability) and the implicit solvers use.
Above DENSE_MODES free coordinates the linear algebra is sparse (`is_large`): the dynamical matrix and the Jacobian
as scipy.sparse matrices built in O(bonds), the softest modes by shift-invert Lanczos, the largest rate by Lanczos;
no N x N array is built.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from ..networks.geometry import Network, unit_alignment_lengths, unit_forces
from ..networks.state import NetworkState
from .blas import one_blas_thread
from .dop853_loop import integrate, run_loop
from .network_kernels import PAUSED, STEP_BUDGET, dop853, euler_maruyama, rhs_into


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
    sigma: float  # the run's active force F_a / (k a)
    alignment_length: float  # the run's l_a / a
    unit_force: np.ndarray  # (A,) each unit's force (sigma unless the network gives it a factor)
    unit_length: np.ndarray  # (A,) each unit's alignment length (the run's unless the network gives its own)

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
    """The reduced model of `network` with active force sigma and alignment length l_a (each unit's own where the
    network gives them: networks.geometry.unit_forces, unit_alignment_lengths)."""
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
        unit_force=np.ascontiguousarray(unit_forces(network, sigma)),
        unit_length=np.ascontiguousarray(unit_alignment_lengths(network, alignment_length)),
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
    v[has] += system.unit_force[system.unit[has], None] * np.column_stack([np.cos(p), np.sin(p)])
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
        dpsi[system.unit[has]] = (-np.sin(p) * v[has, 0] + np.cos(p) * v[has, 1]) / system.unit_length[system.unit[has]]
        return np.concatenate([v[system.slot >= 0].reshape(-1), dpsi])

    return f


def kernel_args(system: NetworkSystem) -> tuple:
    """The flat arguments every compiled kernel of network_kernels takes after its own."""
    return (
        system.rest,
        system.bonds,
        system.rest_lengths,
        system.stiffness,
        system.anchors,
        float(system.trap),
        system.slot,
        system.unit,
        system.unit_force,
        1.0 / system.unit_length,
        2 * system.n_free,
    )


def rhs(system: NetworkSystem):
    """Compiled f(t, y) -> dy/dt of the model (numba kernel: network_kernels.rhs_into)."""
    args = kernel_args(system)

    def f(t, y):
        out = np.empty(y.size)
        rhs_into(np.asarray(y, dtype=float), out, *args)
        return out

    return f


# ------------------------------------------------------------------------------------------------ Jacobians
def force_jacobian(system: NetworkSystem, positions: np.ndarray) -> np.ndarray:
    """H = dF/dx (2P x 2P, node-interleaved) of the passive forces at `positions`: symmetric, -(the stiffness
    matrix); at rest -H is the dynamical matrix (drag 1). Dense: for small networks (force_jacobian_sparse scales)."""
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


def force_jacobian_sparse(system: NetworkSystem, positions: np.ndarray):
    """H = dF/dx on the free nodes' coordinates only (2F x 2F, state order) as a scipy.sparse CSR matrix: O(B) to
    build and to store (16 entries per bond at most), equal to force_jacobian's free block to round-off."""
    from scipy import sparse  # start-up time: scipy.sparse only for the network's linear algebra

    positions = np.asarray(positions, dtype=float)
    size = 2 * system.n_free
    i, j = system.bonds[:, 0], system.bonds[:, 1]
    r = positions[j] - positions[i]
    d = np.linalg.norm(r, axis=1)
    e = r / d[:, None]
    tension = 1.0 - system.rest_lengths / d
    eye = np.eye(2)
    block = system.stiffness[:, None, None] * (
        e[:, :, None] * e[:, None, :] + tension[:, None, None] * (eye - e[:, :, None] * e[:, None, :])
    )  # (B, 2, 2)
    rows, cols, values = [], [], []
    for a, b, sign in ((i, i, -1.0), (j, j, -1.0), (i, j, 1.0), (j, i, 1.0)):
        sa, sb = system.slot[a], system.slot[b]
        keep = (sa >= 0) & (sb >= 0)
        for p in range(2):
            for q in range(2):
                rows.append(2 * sa[keep] + p)
                cols.append(2 * sb[keep] + q)
                values.append(sign * block[keep, p, q])
    diagonal = np.arange(size)
    rows.append(diagonal)
    cols.append(diagonal)
    values.append(np.full(size, -system.trap))
    return sparse.coo_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=(size, size)
    ).tocsr()


def jacobian(system: NetworkSystem, y: np.ndarray, sparse: bool = False):
    """Analytic d(dy/dt)/dy (S x S) at state y: dense, or (sparse=True) a scipy.sparse CSR matrix of O(B) entries.

    dv_i/dx_j = H_ij, dv_i/dpsi_i = sigma_i n_perp_i; dpsi_i'/dx_j = n_perp_i . H_ij / l_i,
    dpsi_i'/dpsi_i = (sigma_i - v_i . n_i) / l_i (sigma_i, l_i: unit i's force and alignment length)."""
    positions, psi = unpack(system, y)
    v = velocities(system, positions, psi)
    if sparse:
        return _sparse_jacobian(system, positions, psi, v)
    dofs = free_dofs(system)
    f2 = dofs.size
    size = system.state_size
    jac = np.zeros((size, size))
    h = force_jacobian(system, positions)[np.ix_(dofs, dofs)]
    jac[:f2, :f2] = h
    for p in np.flatnonzero(system.unit >= 0):
        u, s = system.unit[p], system.slot[p]
        if s < 0:
            continue
        n = np.array([np.cos(psi[u]), np.sin(psi[u])])
        perp = np.array([-n[1], n[0]])
        row = f2 + u
        inv, force = 1.0 / system.unit_length[u], system.unit_force[u]
        jac[2 * s : 2 * s + 2, row] = force * perp
        jac[row, :f2] = inv * (perp @ h[2 * s : 2 * s + 2, :])
        jac[row, row] = inv * (force - v[p] @ n)
    return jac


def _sparse_jacobian(system: NetworkSystem, positions: np.ndarray, psi: np.ndarray, v: np.ndarray):
    """jacobian's matrix as [[H, N_perp S], [L^-1 N_perp^T H, L^-1 diag(sigma_u - v . n)]] in sparse blocks (S, L:
    the units' forces sigma_u and alignment lengths l_u on the diagonal)."""
    from scipy import sparse  # start-up time: scipy.sparse only for the network's linear algebra

    h = force_jacobian_sparse(system, positions)
    f2 = h.shape[0]
    nodes = np.flatnonzero((system.unit >= 0) & (system.slot >= 0))
    units, slots = system.unit[nodes], system.slot[nodes]
    count = len(psi)
    n = np.column_stack([np.cos(psi[units]), np.sin(psi[units])])
    rows = np.concatenate([2 * slots, 2 * slots + 1])
    cols = np.concatenate([units, units])
    perp = sparse.csr_matrix((np.concatenate([-n[:, 1], n[:, 0]]), (rows, cols)), shape=(f2, count))
    inv = sparse.diags(1.0 / system.unit_length)
    turn = np.zeros(count)
    turn[units] = (1.0 / system.unit_length[units]) * (system.unit_force[units] - np.einsum("ij,ij->i", v[nodes], n))
    force = perp @ sparse.diags(system.unit_force)
    return sparse.bmat([[h, force], [inv @ (perp.T @ h), sparse.diags(turn)]], format="csr")


def dynamical_matrix(network: Network) -> np.ndarray:
    """The dynamical matrix D of the free nodes at rest (2F x 2F, drag 1): -dF/dx, symmetric, positive
    semi-definite (zero modes where the patch can move rigidly). Dense: dynamical_matrix_sparse for large networks."""
    system = network_system(network, 0.0, 1.0)
    dofs = free_dofs(system)
    return -force_jacobian(system, system.rest)[np.ix_(dofs, dofs)]


def dynamical_matrix_sparse(network: Network):
    """dynamical_matrix as a scipy.sparse CSR matrix, built in O(B) (never an N x N array)."""
    system = network_system(network, 0.0, 1.0)
    return -force_jacobian_sparse(system, system.rest)


DENSE_MODES = 1500
"""Free coordinates (2F) up to which the normal modes are all computed densely (numpy's eigh: ~1 s at 1500);
above, only the softest ones, by sparse shift-invert Lanczos (scipy's eigsh)."""
LOWEST_MODES = 16
"""How many of the softest normal modes a large network's analyses ask for by default (~2 s at 10 000 nodes)."""


def is_large(network: Network) -> bool:
    """Whether the network's linear algebra runs sparse (more than DENSE_MODES free coordinates)."""
    return 2 * int(np.count_nonzero(~np.asarray(network.pinned, dtype=bool))) > DENSE_MODES


def factorized(matrix):
    """A solver x = matrix^-1 b (b: vector or columns) of a sparse symmetric matrix: SuperLU with the ordering of
    matrix + matrix^T (MMD), about half the fill and half the cost per solve of its default COLAMD on a lattice."""
    from scipy.sparse.linalg import splu  # start-up time: scipy.sparse only for the network's linear algebra

    return splu(matrix.tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True}).solve


def _shift(d) -> float:
    """A shift just below 0 for shift-invert: D - shift I is positive definite, also for a floppy network."""
    return -1e-6 * float(abs(d.diagonal()).max() or 1.0)


def lowest_eigenvalues(network: Network, count: int, vectors: bool = False, sparse: bool | None = None):
    """The `count` lowest eigenvalues (ascending) of the dynamical matrix, with their eigenvectors as columns when
    `vectors`: numpy's eigh for a network of at most DENSE_MODES free coordinates, else shift-invert Lanczos on the
    sparse matrix (scipy's eigsh about a shift just below 0, never an N x N array); `sparse` forces either."""
    from scipy.sparse import identity  # start-up time: scipy.sparse only for the network's linear algebra
    from scipy.sparse.linalg import LinearOperator, eigsh

    count = int(count)
    if not (is_large(network) if sparse is None else sparse):
        if vectors:
            values, modes = np.linalg.eigh(dynamical_matrix(network))
            return values[:count], modes[:, :count]
        return np.linalg.eigvalsh(dynamical_matrix(network))[:count]
    if _LAST and _LAST[0] is network and _LAST[1] >= count:  # the same network's softest modes, just computed
        return (_LAST[2][:count], _LAST[3][:, :count]) if vectors else _LAST[2][:count]
    d = dynamical_matrix_sparse(network)
    shift = _shift(d)
    solve = factorized(d - shift * identity(d.shape[0], format="csr"))
    inverse = LinearOperator(d.shape, matvec=solve, dtype=float)
    with one_blas_thread():  # Lanczos' small BLAS calls: 0.6 s of CPU at 10 000 nodes, 3.3 s threaded (blas.py)
        values, modes = eigsh(inverse, k=min(count, d.shape[0] - 1), which="LM")
    values = shift + 1.0 / values
    order = np.argsort(values)
    values, modes = values[order], modes[:, order]
    _LAST[:] = [network, count, values, modes]
    return (values, modes) if vectors else values


_LAST: list = []
"""(network, count, eigenvalues, eigenvectors) of the last sparse lowest_eigenvalues: a run's observables and a
stability analysis of the same network object ask for its softest modes once."""


def softest_modes(network: Network, count: int, sparse: bool | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The softest normal modes, at most `count` (eigenvalues ascending, orthonormal eigenvectors as columns), whole
    eigenspaces only: an eigenspace that `count` would cut is left out (its basis would be arbitrary)."""
    values, vectors = lowest_eigenvalues(network, int(count) + 2, vectors=True, sparse=sparse)
    gap = 1e-8 * max(float(abs(values).max()), 1e-300)
    keep = np.flatnonzero(values < values[-1] - gap)[: int(count)]  # the last eigenspace may be cut: drop it
    while keep.size and keep[-1] + 1 < values.size and values[keep[-1] + 1] - values[keep[-1]] <= gap:
        keep = keep[:-1]  # `count` itself cut an eigenspace
    return values[keep], vectors[:, keep]


def normal_modes(network: Network, count: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(eigenvalues ascending, eigenvectors as columns, orthonormal) of the dynamical matrix: all 2F (numpy's eigh)
    for a network of at most DENSE_MODES free coordinates when `count` is None; else the softest `count` (default
    LOWEST_MODES) by softest_modes (whole eigenspaces only)."""
    if count is None and not is_large(network):
        values, vectors = np.linalg.eigh(dynamical_matrix(network))
        return values, vectors
    return softest_modes(network, LOWEST_MODES if count is None else count)


def stiffest_rate(network: Network) -> float:
    """The largest eigenvalue of the dynamical matrix (0 with no free node): dense for small networks, by Lanczos on
    the sparse matrix for large ones."""
    if not is_large(network):
        matrix = dynamical_matrix(network)
        return float(np.linalg.eigvalsh(matrix).max()) if matrix.size else 0.0
    from scipy.sparse.linalg import eigsh  # start-up time: scipy.sparse only for the network's linear algebra

    with one_blas_thread():  # Lanczos' small BLAS calls (blas.py)
        return float(eigsh(dynamical_matrix_sparse(network), k=1, which="LA", return_eigenvectors=False)[0])


def elastic_energy(network: Network, displacements: np.ndarray) -> np.ndarray:
    """(T,) the linear-elastic energy u^T D u / 2 of the free nodes' displacements ((T, 2F), node-interleaved), with
    the sparse dynamical matrix."""
    u = np.atleast_2d(np.asarray(displacements, dtype=float))
    return 0.5 * np.einsum("ti,ti->t", u, (dynamical_matrix_sparse(network) @ u.T).T)


# ------------------------------------------------------------------------------------------------ integration
METHODS = ("DOP853", "LSODA", "Radau", "BDF")
"""The ODE methods the network model runs with: DOP853 compiled with the right-hand side (network_kernels.dop853,
scipy's algorithm), scipy's LSODA (dense analytic Jacobian), Radau and BDF (the analytic Jacobian, sparse for a large
network)."""


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
    on_time: Callable[[float], None] | None = None,
    loop=run_loop,
) -> Solution:
    """Integrate from y0 at t[0] and sample at t: DOP853 compiled (O(N) per step, no Python per step), or scipy's
    solve_ivp with the compiled right-hand side. on_time(t) is told the time of every scipy evaluation; `loop` runs
    the compiled loop (run_loop's contract)."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if method == "DOP853":
        return _solve_compiled(system, t, y0, rtol, atol, loop)
    from scipy.integrate import solve_ivp  # start-up time: scipy.integrate costs ~0.4 s to import

    sparse = method != "LSODA" and system.state_size > DENSE_MODES
    options = {"jac": lambda t, y: jacobian(system, y, sparse=sparse)}
    fun = rhs(system)
    if on_time is not None:
        compiled = fun

        def fun(time, y):
            on_time(time)
            return compiled(time, y)

    sol = solve_ivp(
        fun,
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


def _solve_compiled(system: NetworkSystem, t: np.ndarray, y0: np.ndarray, rtol: float, atol: float, loop) -> Solution:
    y0 = np.asarray(y0, dtype=float)
    steps = STEP_BUDGET // max(y0.size, 1)  # rhs_into costs O(N)
    run = integrate(dop853, kernel_args(system), t, y0, rtol, atol, loop, steps=steps)
    if run.status < 0:
        raise RuntimeError(f"DOP853 failed on the network model: the step size fell below round-off at t = {run.t}")
    return Solution(run.y, run.nfev, "DOP853")


def noise_amplitudes(system: NetworkSystem, dt: float, translational: float, rotational: float) -> np.ndarray:
    """(S,) the Ito increments' scales over a step dt: sqrt(2 D_t dt) on each free coordinate, sqrt(2 D_r dt) on each
    polarity (D_t in a^2 per gamma / k, D_r in rad^2 per gamma / k)."""
    return np.concatenate(
        [
            np.full(2 * system.n_free, np.sqrt(2.0 * translational * dt)),
            np.full(system.n_units, np.sqrt(2.0 * rotational * dt)),
        ]
    )


def solve_noisy(
    system: NetworkSystem,
    t: np.ndarray,
    y0: np.ndarray,
    *,
    dt: float,
    seed: int,
    translational: float,
    rotational: float,
    loop=run_loop,
) -> Solution:
    """The Ito SDE dx = v dt + sqrt(2 D_t) dW (free nodes), dpsi = psi' dt + sqrt(2 D_r) dW' (units) by
    Euler-Maruyama at step dt with the counter-based draws xi(seed, k, i) (network_kernels.euler_maruyama); the
    polarity turns toward the node's deterministic velocity v (the drift), not its noise. Samples at t, evenly spaced
    by a whole number of steps; `loop` runs the compiled loop (run_loop's contract)."""
    ts = np.asarray(t, dtype=float)
    every = 1 if ts.size < 2 else int(round((ts[1] - ts[0]) / dt))
    if ts.size > 1 and (every < 1 or abs(every * dt - (ts[1] - ts[0])) > 1e-9 * max(1.0, ts[1] - ts[0])):
        raise ValueError(f"the sample spacing {ts[1] - ts[0]:g} must be a whole number of steps dt = {dt:g}")
    y = np.array(y0, dtype=float)
    out = np.empty((ts.size, y.size))
    amplitude = noise_amplitudes(system, dt, translational, rotational)
    counts = np.zeros(1, dtype=np.int64)
    args = kernel_args(system)

    def call(steps: int) -> int:
        return euler_maruyama(y, counts, float(dt), every, int(seed), amplitude, out, steps, *args)

    loop(call, PAUSED, lambda: float(counts[0]) * dt, max(1, STEP_BUDGET // max(y.size, 1)))
    return Solution(out, int(counts[0]), "Euler-Maruyama")

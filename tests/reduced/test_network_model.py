"""The network's reduced model (analysis.network.model): the compiled right-hand side against the numpy one, the
analytic Jacobian against finite differences, the normal modes of the passive lattice (sigma = 0) against a direct
computation, and a single mode's relaxation at its eigenvalue."""

from __future__ import annotations

import time

import numpy as np
import pytest

from elastoactive.analysis.network import NetworkState, hexagonal_patch, initial_state, trap_unit
from elastoactive.reduced import network as m

CASES = [
    (hexagonal_patch(2, "pinned"), 0.3, 0.5),
    (hexagonal_patch(2, "centre"), 0.2, 0.1),
    (hexagonal_patch(1, "free"), 0.4, 2.0),
    (trap_unit(0.7), 0.8, 1.3),
]


@pytest.mark.parametrize("network, sigma, la", CASES)
def test_rhs_and_jacobian(network, sigma, la):
    system = m.network_system(network, sigma, la)
    y = m.pack(system, initial_state(network, 0.2, 5))
    assert y.size == system.state_size == 2 * int((~network.pinned).sum()) + int(network.active.sum())
    f, reference = m.rhs(system), m.rhs_reference(system)
    np.testing.assert_allclose(f(0.0, y), reference(0.0, y), rtol=0, atol=1e-13)
    eps = 1e-6
    numeric = np.column_stack(
        [(reference(0, y + eps * e) - reference(0, y - eps * e)) / (2 * eps) for e in np.eye(y.size)]
    )
    np.testing.assert_allclose(m.jacobian(system, y), numeric, rtol=0, atol=1e-7)


def test_rhs_by_hand_for_the_trapped_unit():
    """dx/dt = sigma n - trap x, dpsi/dt = (dx/dt . n_perp) / l_a, written out."""
    system = m.network_system(trap_unit(0.5), 0.8, 2.0)
    x, y, psi = 0.3, -0.2, 1.1
    n, perp = np.array([np.cos(psi), np.sin(psi)]), np.array([-np.sin(psi), np.cos(psi)])
    v = 0.8 * n - 0.5 * np.array([x, y])
    np.testing.assert_allclose(m.rhs(system)(0, np.array([x, y, psi])), [*v, v @ perp / 2.0], atol=1e-15)


def _energy_hessian(network) -> np.ndarray:
    """The elastic energy sum_b k_b (|r_b| - L_b)^2 / 2 of the free nodes, differentiated twice by central
    differences at rest: the dynamical matrix computed directly from the energy."""
    free = np.flatnonzero(~network.pinned)

    def energy(q):
        pos = network.positions.copy()
        pos[free] = q.reshape(-1, 2)
        r = pos[network.bonds[:, 1]] - pos[network.bonds[:, 0]]
        return 0.5 * np.sum(network.stiffness * (np.linalg.norm(r, axis=1) - network.rest_lengths) ** 2)

    q0, h, size = network.positions[free].reshape(-1), 1e-4, 2 * free.size
    out = np.empty((size, size))
    for a in range(size):
        for b in range(size):
            ea, eb = np.eye(size)[a] * h, np.eye(size)[b] * h
            out[a, b] = (energy(q0 + ea + eb) - energy(q0 + ea - eb) - energy(q0 - ea + eb) + energy(q0 - ea - eb)) / (
                4 * h * h
            )
    return out


@pytest.mark.parametrize("rings, boundary", [(1, "pinned"), (2, "pinned"), (2, "free"), (2, "centre")])
def test_dynamical_matrix_is_the_energy_hessian(rings, boundary):
    network = hexagonal_patch(rings, boundary)
    values, vectors = m.normal_modes(network)
    np.testing.assert_allclose(values, np.linalg.eigvalsh(_energy_hessian(network)), atol=1e-6)
    np.testing.assert_allclose(vectors.T @ vectors, np.eye(values.size), atol=1e-12)


def test_textbook_modes():
    """The single free node of the pinned R = 1 patch: six unit springs give D = 3 I. A free patch has exactly three
    zero modes (two translations, one rotation); the centre-pinned one a single one (the rotation); the pinned one
    none. The pinned R = 2 patch's two softest modes are degenerate (the hexagon's symmetry)."""
    np.testing.assert_allclose(m.normal_modes(hexagonal_patch(1))[0], [3.0, 3.0], atol=1e-12)
    for rings in (1, 2, 3):
        assert np.sum(np.abs(m.normal_modes(hexagonal_patch(rings, "free"))[0]) < 1e-9) == 3
        assert np.sum(np.abs(m.normal_modes(hexagonal_patch(rings, "centre"))[0]) < 1e-9) == 1
        assert m.normal_modes(hexagonal_patch(rings, "pinned"))[0][0] > 0.1
    values = m.normal_modes(hexagonal_patch(2))[0]
    assert values[0] == pytest.approx(values[1], abs=1e-12) and values[2] > values[1] + 0.1


def test_passive_mode_relaxes_at_its_eigenvalue():
    """sigma = 0: a small displacement along normal mode m decays as exp(-lambda_m t) (overdamped, drag 1)."""
    network = hexagonal_patch(2)
    values, vectors = m.normal_modes(network)
    system = m.network_system(network, 0.0, 1.0)
    for mode in (0, 2, 13):
        start = network.positions.copy()
        start[~network.pinned] += 1e-4 * vectors[:, mode].reshape(-1, 2)
        y0 = m.pack(system, NetworkState(start, np.zeros(int(network.active.sum()))))
        t = np.linspace(0, 2.0, 5)
        y = m.solve(system, t, y0, rtol=1e-11, atol=1e-16).y
        amplitude = (m.unpack(system, y).positions[:, ~network.pinned] - network.positions[~network.pinned]).reshape(
            t.size, -1
        ) @ vectors[:, mode]
        np.testing.assert_allclose(amplitude, 1e-4 * np.exp(-values[mode] * t), rtol=1e-5)


@pytest.mark.slow
def test_largest_patch_runs_1000_relaxation_times_within_a_minute():
    network = hexagonal_patch(6)
    system = m.network_system(network, 0.2, 0.1)
    y0 = m.pack(system, initial_state(network, 0.01, 0))
    m.solve(system, np.linspace(0, 1, 3), y0)  # compile
    start = time.perf_counter()
    m.solve(system, np.arange(0, 1000.0001, 0.5), y0)
    assert time.perf_counter() - start < 60.0


def test_compiled_dop853_is_scipys_to_round_off():
    """The compiled DOP853 (network_kernels.dop853) takes scipy's steps: the same samples to round-off, the same
    number of evaluations within the few a different rounding of the step control can change."""
    from scipy.integrate import solve_ivp

    network = hexagonal_patch(2)
    system = m.network_system(network, 0.2, 0.1)
    y0 = m.pack(system, initial_state(network, 0.2, 1))
    t = np.arange(0.0, 20.0001, 0.25)
    compiled = m.solve(system, t, y0)
    reference = solve_ivp(m.rhs(system), (0.0, 20.0), y0, method="DOP853", t_eval=t, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(compiled.y, reference.y.T, rtol=0, atol=1e-10)
    assert abs(compiled.nfev - reference.nfev) <= 0.01 * reference.nfev


@pytest.mark.parametrize("network, sigma, la", CASES)
def test_sparse_jacobian_is_the_dense_one(network, sigma, la):
    system = m.network_system(network, sigma, la)
    y = m.pack(system, initial_state(network, 0.2, 4))
    np.testing.assert_allclose(m.jacobian(system, y, sparse=True).toarray(), m.jacobian(system, y), atol=1e-13)
    d = m.dynamical_matrix(network)
    np.testing.assert_allclose(m.dynamical_matrix_sparse(network).toarray(), d, atol=1e-13)


def test_sparse_softest_modes_are_the_dense_ones():
    """Shift-invert Lanczos on the sparse matrix gives numpy's softest eigenvalues and the same eigenspaces (whole:
    a degenerate pair is kept or left out together)."""
    network = hexagonal_patch(4)
    values, vectors = np.linalg.eigh(m.dynamical_matrix(network))
    sparse_values, sparse_vectors = m.softest_modes(network, 5, sparse=True)
    assert sparse_values.size == 5  # 1-2, 3, 4-5: whole eigenspaces
    np.testing.assert_allclose(sparse_values, values[:5], rtol=1e-10)
    projector = vectors[:, :5] @ vectors[:, :5].T
    np.testing.assert_allclose(projector @ sparse_vectors, sparse_vectors, atol=1e-8)
    cut, _ = m.softest_modes(network, 2, sparse=True)  # 2 modes would split nothing: the softest pair
    np.testing.assert_allclose(cut, values[:2], rtol=1e-10)
    one, _ = m.softest_modes(network, 1, sparse=True)  # 1 would cut the degenerate pair: left out
    assert one.size == 0


def test_a_large_network_never_builds_a_dense_matrix(monkeypatch):
    """Above DENSE_MODES free coordinates the modes, the rate, the stability bracket and the elastic energy use only
    sparse matrices: the dense builders raise here, and the bracket still comes out."""
    from elastoactive.analysis.network import stability as st
    from elastoactive.networks.lattices import generate

    network = generate("triangular", "hexagonal", 17, "pinned", 0.0, 0)
    assert m.is_large(network) and not m.is_large(hexagonal_patch(6))

    def refuse(*args, **kwargs):
        raise AssertionError("a dense N x N matrix was built for a large network")

    monkeypatch.setattr(m, "force_jacobian", refuse)
    monkeypatch.setattr(st, "dynamical_matrix", refuse)
    values, vectors = m.normal_modes(network)
    assert 0 < values.size <= m.LOWEST_MODES and vectors.shape == (2 * int((~network.pinned).sum()), values.size)
    assert m.stiffest_rate(network) < st.gershgorin(network)
    bracket = st.threshold(network)
    assert 0 < bracket.softest == values[0] == bracket.coupling < bracket.ceiling and bracket.starts == 0
    system = m.network_system(network, 0.2, 0.1)
    y = m.pack(system, initial_state(network, 0.1, 0))
    assert m.jacobian(system, y, sparse=True).nnz < 40 * y.size


def test_noise_draw_is_the_counter_based_stream():
    from elastoactive.controllers.noise import standard_normal
    from elastoactive.reduced.network_kernels import standard_normal_into

    for seed, step in ((0, 0), (7, 123), (2**40, 10**9)):
        out = np.empty(257)
        standard_normal_into(seed, step, out)
        np.testing.assert_allclose(out, standard_normal(seed, step, 257)[0], rtol=1e-14, atol=1e-14)


def test_noisy_solve_is_euler_maruyama_with_the_seeded_draws():
    """solve_noisy steps y + dt f(y) + amplitude xi(seed, k): replayed in numpy, step by step."""
    from elastoactive.controllers.noise import standard_normal

    network = hexagonal_patch(1)
    system = m.network_system(network, 0.3, 0.5)
    y0 = m.pack(system, initial_state(network, 0.1, 2))
    dt, seed = 0.01, 11
    t = np.arange(0, 0.2001, 0.05)
    out = m.solve_noisy(system, t, y0, dt=dt, seed=seed, translational=0.02, rotational=0.3).y
    amplitude = m.noise_amplitudes(system, dt, 0.02, 0.3)
    f, y = m.rhs_reference(system), y0.copy()
    for k in range(20):
        y = y + dt * f(0.0, y) + amplitude * standard_normal(seed, k, y.size)[0]
    np.testing.assert_allclose(out[-1], y, atol=1e-13)
    again = m.solve_noisy(system, t, y0, dt=dt, seed=seed, translational=0.02, rotational=0.3).y
    other = m.solve_noisy(system, t, y0, dt=dt, seed=seed + 1, translational=0.02, rotational=0.3).y
    assert np.array_equal(out, again) and not np.allclose(out[-1], other[-1])

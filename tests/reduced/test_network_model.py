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

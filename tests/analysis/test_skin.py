"""The chain's non-Hermitian linear algebra (analysis.skin) and the skin-effect study."""

import math

import numpy as np
import pytest

from elastoactive.analysis import skin
from elastoactive.analysis import stability as stab
from elastoactive.core.errors import ParameterError


def _b(n):
    return np.tril(np.ones((n, n)))


def test_displacement_operator_is_the_engines_linearisation_in_particle_displacements():
    import elastoactive as ea
    from elastoactive.engines.reduced import base_state, jacobian  # the engine loads numba: only this test needs it

    n, sigma = 8, 0.07
    m = skin.displacement_operator(n, sigma)
    b = _b(n)
    assert np.allclose(m, b @ stab.linear_operator(n, sigma) @ np.linalg.inv(b), atol=1e-12)
    physics = ea.Physics(n=n, sigma=sigma)
    jac = jacobian(physics)(0.0, base_state(physics))
    assert np.allclose(m, b @ jac @ np.linalg.inv(b), atol=1e-9)


def test_bulk_rows_are_bending_link_compression_and_the_own_follower_force():
    """Row k: -(4th difference) - [C_{k+1/2} (y_{k+1} - y_k) - C_{k-1/2} (y_k - y_{k-1})] - sigma (y_k - y_{k-1}),
    C_{k+1/2} = sigma (N - k); the non-conservative part is the same in every row and equals the ring's."""
    n, sigma = 15, 0.02
    m = skin.displacement_operator(n, sigma)
    for k in range(3, n - 1):  # 1-based rows with both neighbours' neighbours present
        row = np.zeros(n + 2)
        for j, c in {-2: -1.0, -1: 4.0, 0: -6.0, 1: 4.0, 2: -1.0}.items():
            row[k + j] += c
        c_out, c_in = sigma * (n - k), sigma * (n - k + 1)
        row[k + 1] -= c_out
        row[k] += c_out + c_in
        row[k - 1] -= c_in
        row[k] -= sigma
        row[k - 1] += sigma
        assert np.allclose(m[k - 1], row[1 : n + 1], atol=1e-13), k
    ring = skin.ring_operator(n, sigma, 0.3)
    anti, ring_anti = 0.5 * (m - m.T), 0.5 * (ring - ring.T)
    assert np.allclose(anti[4:-4, :], ring_anti[4:-4, :], atol=1e-14)
    assert anti[5, 4] == pytest.approx(sigma / 2) and anti[5, 6] == pytest.approx(-sigma / 2)


def test_ring_spectrum_is_the_symbol_and_its_modes_are_extended():
    n, sigma, t = 24, 0.05, 0.2
    lam = np.linalg.eigvals(skin.ring_operator(n, sigma, t))
    symbol = skin.bulk_symbol(2 * np.pi * np.arange(n) / n, sigma, t)
    assert np.abs(lam[:, None] - symbol[None, :]).min(axis=1).max() < 1e-10
    assert np.abs(lam[:, None] - symbol[None, :]).min(axis=0).max() < 1e-10
    loc = skin.localisation(skin.ring_operator(n, sigma, t))
    assert np.allclose(loc.participation, 1.0) and np.allclose(loc.condition, 1.0)


def test_winding_is_nonzero_only_with_the_non_conservative_force():
    assert skin.winding_number(0.01, 0.0) == -1
    assert skin.winding_number(1e-5, 0.002) == -1
    z0 = skin.loop_reference(0.01, 0.0)
    assert skin.winding_number(0.0, 0.0, z0 + 0.5j) == 0
    assert skin.winding_number(0.01, 0.0, 5.0) == 0  # a point outside the loop
    with pytest.raises(ParameterError, match="z0"):
        skin.winding_number(0.0, 0.0, -8.0)


def test_open_stencil_localises_at_the_tip_and_the_chain_below_onset_does_not():
    short, long_ = (skin.localisation(skin.segment_operator(n, 0.1, 0.0)) for n in (30, 120))
    assert long_.participation[0] < 0.5 * short.participation[0]
    assert long_.centre[0] > 0.9 > short.centre[0]
    lam, vec = np.linalg.eig(skin.segment_operator(200, 0.1, 0.0))
    xi = skin.decay_length(vec[:, np.argmax(lam.real)])
    assert 2.5 < xi * 0.1 ** (1 / 3) < 3.5  # xi ~ 3 sigma^(-1/3)
    a, b = (skin.localisation(skin.displacement_operator(n, 0.9 * stab.onset(n)[0])) for n in (20, 80))
    assert abs(a.participation[0] - b.participation[0]) < 0.03 and abs(a.centre[0] - b.centre[0]) < 0.02
    assert b.centre[0] > 0.7 and b.condition.max() < 2


def test_transient_growth_needs_non_normality():
    n = 20
    sc = stab.onset(n)[0]
    below, near = (skin.displacement_operator(n, r * sc) for r in (0.5, 0.99))
    times = np.linspace(0, 0.02 * n**4, 41)[1:]
    assert skin.numerical_abscissa(below) < 0 and skin.worst_gain(below, times).max() <= 1 + 1e-12
    assert skin.numerical_abscissa(near) > 0 and skin.worst_gain(near, times).max() > 1.5
    herm = skin.hermitian_part(near)
    assert skin.worst_gain(herm - (np.linalg.eigvalsh(herm).max() + 1e-9) * np.eye(n), times).max() <= 1 + 1e-12
    y0 = skin.kick(n, 0.5, 0.08, 1e-4)
    tr = skin.transient(times, skin.propagate(near, y0, np.r_[0.0, times])[1:])
    assert tr.peak_centre > 0.7


def test_kick_angles_round_trip_and_bad_inputs():
    y = skin.kick(12, 0.4, 0.1, 0.05)
    assert np.allclose(skin.displacements(skin.angles_from_displacements(y)), y, atol=1e-14)
    for bad in (dict(position=0.0, width=0.1), dict(position=0.5, width=0.0)):
        with pytest.raises(ParameterError):
            skin.kick(12, amplitude=1e-3, **bad)
    with pytest.raises(ParameterError, match="sigma"):
        skin.displacement_operator(10, -1.0)
    with pytest.raises(ParameterError, match="n must"):
        skin.ring_operator(4, 0.1, 0.0)
    m = np.diag([-1.0, -2.0])
    assert skin.nonnormality_ratio(m, np.linspace(-3, 1, 5), np.linspace(-1, 1, 3)) == pytest.approx(1.0)
    assert math.isfinite(
        skin.nonnormality_ratio(skin.segment_operator(10, 0.5, 0.0), np.linspace(-3, 1, 5), np.linspace(-1, 1, 3))
    )


@pytest.fixture(scope="module")
def runs(tiny_studies):
    return tiny_studies("skin")


def test_skin_study_tiny(runs, round_trip):
    s = runs[1]["skin"].summary
    assert s.winding == -1 and s.winding_hermitian == 0
    assert s.kick_max_deviation < 1e-6 and min(s.kick_peak_sim) > 1.1 and s.kick_mujoco_deviation < 1e-3
    assert all(c.condition_max < 3 for c in s.chains)
    table = round_trip(runs, "skin")
    assert "Skin effect" in table and "| **partly** |" in table

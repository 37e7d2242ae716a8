"""Linear stability of the straight chain in 3D (elastoactive.analysis.stability3d): the spectrum is the planar one
twice (in-plane and out-of-plane branches, degenerate for the isotropic chain), whatever the drag ratio, and the onset
is the planar onset. The numerical operator (central differences of the reduced 3D right-hand side) is the independent
check of the analytic one the scenes use."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis import stability
from elastoactive.analysis.stability3d import (
    branches,
    fastest_rate3d,
    linear_operator3d,
    numerical_operator3d,
    onset3d,
    planar_operator,
    searched_onset3d,
)


@pytest.mark.parametrize("gamma_l", [1.0, 0.3, 3.0])
def test_numerical_operator_is_the_planar_one_twice(gamma_l):
    n, sigma = 6, 0.5
    a3 = linear_operator3d(n, sigma, gamma_l)
    np.testing.assert_allclose(a3[:n, :n], stability.linear_operator(n, sigma), atol=1e-14)
    np.testing.assert_allclose(numerical_operator3d(n, sigma, gamma_l), a3, atol=1e-8)


@pytest.mark.parametrize("gamma_l", [1.0, 2.0])
def test_free_pivot_operator_is_the_numerical_one(gamma_l):
    """Without the clamp spring each block gains (e_1 - e_2) e_1^T."""
    n, sigma = 5, 0.05
    np.testing.assert_allclose(
        numerical_operator3d(n, sigma, gamma_l, clamped=False), linear_operator3d(n, sigma, gamma_l, False), atol=1e-8
    )
    assert not np.allclose(planar_operator(n, sigma, clamped=False), planar_operator(n, sigma))


def test_branches_are_degenerate_and_independent():
    n, sigma = 7, 0.3  # above the onset 0.1575: one unstable pair in each branch
    b = branches(n, sigma, gamma_l=2.0)
    assert b.coupling < 1e-9
    assert b.splitting < 1e-8
    np.testing.assert_allclose(b.in_plane, stability.eigenvalues(n, sigma), atol=1e-8)
    assert np.sum(b.in_plane.real > 0) == np.sum(b.out_of_plane.real > 0) == 2


@pytest.mark.parametrize("gamma_l", [1.0, 0.5])
def test_onset_is_the_planar_onset(gamma_l):
    """N = 7: sigma_c = 0.157470, f_c tau = 0.006828 in the plane; found again from the whole numerical 3D operator."""
    searched, searched_omega = searched_onset3d(7, gamma_l)
    sigma_c, omega_c = onset3d(7, gamma_l)
    planar, planar_omega = stability.critical_sigma(7)
    assert searched == pytest.approx(planar, rel=1e-7)
    assert searched_omega == pytest.approx(planar_omega, rel=1e-6)
    assert sigma_c == pytest.approx(searched, rel=1e-7)
    assert omega_c == pytest.approx(searched_omega, rel=1e-6)
    assert sigma_c == pytest.approx(0.157470, abs=1e-6)


def test_onset_of_a_long_chain_is_the_planar_ones_continuum_limit():
    """N = 1000 (O(N) per sigma): N^3 sigma_c near the continuum filament's 76.10."""
    sigma_c, omega_c = onset3d(1000)
    assert 1000**3 * sigma_c == pytest.approx(76.1, rel=0.01)
    assert omega_c > 0


def test_fastest_rate_is_the_whole_operators():
    for clamped in (True, False):
        whole = np.abs(np.linalg.eigvals(numerical_operator3d(6, 0.4, 1.5, clamped))).max()
        assert fastest_rate3d(6, 0.4, clamped) == pytest.approx(whole, rel=1e-7)


def test_free_pivot_branches_are_degenerate_too():
    """On a free ball pivot (no clamp spring) each branch is the rotating pin's spectrum plus the rigid turn (0)."""
    b = branches(5, 0.05, clamped=False)
    assert b.splitting < 1e-8
    assert abs(b.in_plane[0]) < 1e-9
    planar = np.linalg.eigvals(stability.rotating_operator(5, 0.05))
    np.testing.assert_allclose(b.in_plane[1:], planar[np.lexsort((-planar.imag, -planar.real))], atol=1e-7)
    lam = np.linalg.eigvals(planar_operator(5, 0.05, clamped=False))
    np.testing.assert_allclose(np.sort_complex(lam), np.sort_complex(b.in_plane), atol=1e-7)

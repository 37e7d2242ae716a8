"""Linear stability of the straight chain in 3D (elastoactive.analysis.stability3d): the spectrum is the planar one
twice (in-plane and out-of-plane branches, degenerate for the isotropic chain), whatever the drag ratio, and the onset
is the planar onset."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis import stability
from elastoactive.analysis.stability3d import branches, exact_operator3d, linear_operator3d, onset3d


@pytest.mark.parametrize("gamma_l", [1.0, 0.3, 3.0])
def test_numerical_operator_is_the_planar_one_twice(gamma_l):
    n, sigma = 6, 0.5
    np.testing.assert_allclose(linear_operator3d(n, sigma, gamma_l), exact_operator3d(n, sigma), atol=1e-8)


def test_branches_are_degenerate_and_independent():
    n, sigma = 7, 0.3  # above the onset 0.1575: one unstable pair in each branch
    b = branches(n, sigma, gamma_l=2.0)
    assert b.coupling < 1e-9
    assert b.splitting < 1e-8
    np.testing.assert_allclose(b.in_plane, stability.eigenvalues(n, sigma), atol=1e-8)
    assert np.sum(b.in_plane.real > 0) == np.sum(b.out_of_plane.real > 0) == 2


def test_onset_is_the_planar_onset():
    """N = 7: sigma_c = 0.157470, f_c tau = 0.006828 in the plane; found again from the whole 3D operator."""
    sigma_c, omega_c = onset3d(7)
    planar, planar_omega = stability.critical_sigma(7)
    assert sigma_c == pytest.approx(planar, rel=1e-7)
    assert omega_c == pytest.approx(planar_omega, rel=1e-6)
    assert sigma_c == pytest.approx(0.157470, abs=1e-6)


def test_free_pivot_branches_are_degenerate_too():
    """On a free ball pivot (no clamp spring) each branch is the rotating pin's spectrum plus the rigid turn (0)."""
    b = branches(5, 0.05, clamped=False)
    assert b.splitting < 1e-8
    assert abs(b.in_plane[0]) < 1e-9
    planar = np.linalg.eigvals(stability.rotating_operator(5, 0.05))
    np.testing.assert_allclose(b.in_plane[1:], planar[np.lexsort((-planar.imag, -planar.real))], atol=1e-7)

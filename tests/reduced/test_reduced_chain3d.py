"""The reduced 3D chain (elastoactive.reduced.chain3d): its compiled right-hand side against the plain-numpy one, the
symmetries it must have, and a planar start against the planar reduced model."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis import observables as obs
from elastoactive.core.errors import ParameterError
from elastoactive.reduced import ChainSystem, rhs_reference, solve_ode
from elastoactive.reduced.chain3d import (
    Chain3D,
    planar_angles,
    rhs,
    solve3d,
    tangents_of_angles,
)
from elastoactive.reduced.chain3d import (
    rhs_reference as rhs3d_reference,
)


def _random_tangents(n: int, seed: int = 0) -> np.ndarray:
    t = np.random.default_rng(seed).standard_normal((n, 3))
    return t / np.linalg.norm(t, axis=1)[:, None]


def _planar_system(n: int, sigma: float, gamma_l: float = 1.0, clamped: bool = True) -> ChainSystem:
    return ChainSystem(
        n=n, n_chains=1, clamped=clamped, pinned=False, sigma=sigma, gamma_l=gamma_l, gamma_t=1.0, kappa=0.0, rho=1.0,
        delta=0.0, mass_ratio=0.0, inertia_factor=0.0,
    )  # fmt: skip


def _rotation_about_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


@pytest.mark.parametrize("clamped", [True, False])
def test_compiled_rhs_equals_reference(clamped):
    chain = Chain3D(n=6, sigma=0.9, gamma_l=1.7, clamped=clamped)
    t = _random_tangents(6)
    np.testing.assert_allclose(rhs(t, chain), rhs3d_reference(t, chain), atol=1e-12)


def test_velocities_are_tangent_and_the_norm_is_held():
    chain = Chain3D(n=5, sigma=0.5, gamma_l=0.6)
    t = _random_tangents(5, seed=1)
    v = rhs(t, chain)
    assert np.abs(np.einsum("ka,ka->k", v, t)).max() < 1e-13
    stretched = 1.01 * t  # off the unit sphere: pulled back along the tangent, at rate 1
    radial = np.einsum("ka,ka->k", rhs(stretched, chain), t)
    np.testing.assert_allclose(radial, -0.5 * (1.01**2 - 1.0), rtol=1e-12)


@pytest.mark.parametrize("clamped", [True, False])
def test_planar_rhs_is_the_planar_model(clamped):
    """In the plane, the clamped chain and the free pivot are the planar one-pinned and rotating-pin models."""
    n, sigma, gamma_l = 7, 0.8, 1.7
    theta = np.random.default_rng(2).standard_normal(n) * 0.7
    planar = rhs_reference(_planar_system(n, sigma, gamma_l, clamped), beta=10.0)(0.0, theta)
    v = rhs(tangents_of_angles(theta), Chain3D(n=n, sigma=sigma, gamma_l=gamma_l, clamped=clamped))
    normals = np.stack([-np.sin(theta), np.cos(theta), np.zeros(n)], axis=1)
    np.testing.assert_allclose(np.einsum("ka,ka->k", v, normals), planar, atol=1e-13)
    assert np.all(v[:, 2] == 0.0)  # the out-of-plane rows are exact zeros


@pytest.mark.parametrize("gamma_l", [1.0, 0.4])
def test_isotropic_about_the_clamp_axis(gamma_l):
    """Turning the chain about e_x (the clamp's axis) turns its velocities with it: no direction across the chain is
    special, the ground of the degenerate in-plane and out-of-plane modes."""
    chain = Chain3D(n=5, sigma=0.7, gamma_l=gamma_l)
    t = _random_tangents(5, seed=3)
    R = _rotation_about_x(0.83)
    np.testing.assert_allclose(rhs(t @ R.T, chain), rhs(t, chain) @ R.T, atol=1e-12)


def test_a_link_along_the_pole_is_a_regular_point():
    """Tangents through and around e_z (where two angles per link would be singular, and where the basis switches)
    give a continuous velocity."""
    chain = Chain3D(n=3, sigma=0.6)
    base = np.array([[1.0, 0.0, 0.0], [0.3, 0.2, 1.0], [0.0, 0.0, 1.0]])
    base /= np.linalg.norm(base, axis=1)[:, None]
    v0 = rhs(base, chain)
    assert np.all(np.isfinite(v0))
    for eps in (1e-9, -1e-9):
        tilted = base.copy()
        tilted[2] = [eps, 0.0, 1.0]
        tilted[1, :2] *= 1 + eps  # across the basis switch of link 2 (|(x, y)| = 1/2)
        assert np.abs(rhs(tilted, chain) - v0).max() < 1e-7


def test_bending_energy_decreases_without_activity():
    chain = Chain3D(n=5, sigma=0.0, gamma_l=2.0)
    t = _random_tangents(5, seed=4)
    ts = np.linspace(0.0, 2.0, 21)
    path = solve3d(chain, ts, t, rtol=1e-10, atol=1e-10)
    ex = np.array([1.0, 0.0, 0.0])
    before = np.concatenate([np.broadcast_to(ex, (ts.size, 1, 3)), path[:, :-1]], axis=1)
    cosines = np.clip(np.einsum("tka,tka->tk", before, path), -1.0, 1.0)
    energy = 0.5 * (np.arccos(cosines) ** 2).sum(axis=1)
    assert np.all(np.diff(energy) < 0)


def test_planar_start_reproduces_the_planar_engine():
    """N = 7, sigma = 0.8 from the same planar start, both at rtol 1e-12: the chain stays in its plane exactly, and
    the tip angle, Theta and the beat frequency agree with the planar reduced model to 1e-9."""
    n, sigma = 7, 0.8
    ts = np.linspace(0.0, 150.0, 3001)
    theta0 = 0.01 * np.sin(0.3 * np.arange(1, n + 1))
    planar, _ = solve_ode(_planar_system(n, sigma), ts, theta0, rtol=1e-12, atol=1e-12, beta=10.0)
    path = solve3d(Chain3D(n=n, sigma=sigma), ts, tangents_of_angles(theta0), rtol=1e-12, atol=1e-12)
    assert np.all(path[..., 2] == 0.0)
    theta = planar_angles(path)
    assert np.abs(theta[:, -1] - planar[:, -1]).max() < 1e-9
    assert np.abs(obs.curvature(theta) - obs.curvature(planar)).max() < 1e-9
    f2, f3 = obs.frequency(ts, obs.curvature(planar)), obs.frequency(ts, obs.curvature(theta))
    assert f2 > 0.04 and abs(f3 - f2) < 1e-9


def test_bad_input_names_the_parameter():
    with pytest.raises(ParameterError, match="gamma_l"):
        solve3d(Chain3D(n=3, sigma=0.5, gamma_l=0.0), np.linspace(0, 1, 3), _random_tangents(3))
    with pytest.raises(ParameterError, match="tangents0"):
        solve3d(Chain3D(n=3, sigma=0.5), np.linspace(0, 1, 3), _random_tangents(4))

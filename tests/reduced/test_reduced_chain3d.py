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
    choose_method,
    jacobian,
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
@pytest.mark.parametrize("load", [(), (0.0, 0.0, 0.5, 0.0, 0.0, 1.0)])
def test_compiled_rhs_equals_reference(clamped, load):
    """The O(N) recursion against the dense solve, off the unit sphere too; and a long chain."""
    chain = Chain3D(n=6, sigma=0.9, gamma_l=1.7, clamped=clamped, load=load)
    t = _random_tangents(6) * np.linspace(0.99, 1.01, 6)[:, None]
    np.testing.assert_allclose(rhs(t, chain), rhs3d_reference(t, chain), atol=1e-12)
    long = Chain3D(n=60, sigma=0.002, gamma_l=0.5, clamped=clamped)
    t = _random_tangents(60, seed=5)
    np.testing.assert_allclose(rhs(t, long), rhs3d_reference(t, long), atol=1e-11)


def _central_differences(t: np.ndarray, chain: Chain3D, step: float = 1e-6) -> np.ndarray:
    y = t.ravel()
    columns = []
    for j in range(y.size):
        dy = np.zeros(y.size)
        dy[j] = step
        columns.append((rhs((y + dy).reshape(t.shape), chain) - rhs((y - dy).reshape(t.shape), chain)).ravel())
    return np.array(columns).T / (2 * step)


@pytest.mark.parametrize(
    "shape", ["random", "stretched", "straight", "planar", "near the pole"]
)  # fmt: skip
def test_analytic_jacobian_equals_central_differences(shape):
    """The analytic Jacobian against central differences of the right-hand side (error ~1e-10 of step 1e-6), at a
    general shape with anisotropic drag and uneven loads, off the unit sphere, and where the bending gradient's
    second derivative takes its small-angle limit (straight, nearly straight)."""
    n = 7
    chain = Chain3D(n=n, sigma=0.8, gamma_l=1.6, load=tuple(np.linspace(0.2, 1.0, n)))
    t = {
        "random": _random_tangents(n, seed=6),
        "stretched": _random_tangents(n, seed=7) * np.linspace(0.98, 1.02, n)[:, None],
        "straight": np.tile([1.0, 0.0, 0.0], (n, 1)),
        "planar": tangents_of_angles(1e-4 * np.arange(n)),
        "near the pole": _random_tangents(n, seed=8) * 0.2 + [0.0, 0.0, 1.0],
    }[shape]
    J = jacobian(t, chain)
    assert np.abs(J - _central_differences(t, chain)).max() < 1e-8 * max(1.0, np.abs(J).max())


def test_tip_loaded_planar_rhs_is_the_planar_loaded_model():
    """Loaded at its tip only (load = (0, ..., 0, 1)), the chain in a plane is the planar model with the same
    per-particle force factors."""
    n, sigma = 6, 3.0
    load = (0.0,) * (n - 1) + (1.0,)
    theta = np.random.default_rng(9).standard_normal(n) * 0.5
    planar = rhs_reference(_planar_system(n, sigma), beta=10.0, factor=np.array(load))(0.0, theta)
    v = rhs(tangents_of_angles(theta), Chain3D(n=n, sigma=sigma, load=load))
    normals = np.stack([-np.sin(theta), np.cos(theta), np.zeros(n)], axis=1)
    np.testing.assert_allclose(np.einsum("ka,ka->k", v, normals), planar, atol=1e-13)
    unloaded = rhs(tangents_of_angles(theta), Chain3D(n=n, sigma=sigma, load=(0.0,) * n))
    np.testing.assert_allclose(unloaded, rhs(tangents_of_angles(theta), Chain3D(n=n, sigma=0.0)), atol=1e-15)


def test_the_long_chain_near_onset_runs_implicit_and_agrees():
    """N = 16 at S = N^3 sigma = 100: over a whirl period the stiffness picks LSODA with the analytic Jacobian, whose
    path agrees with DOP853's to the tolerance (over a quarter period); a short chain keeps DOP853."""
    n = 16
    chain = Chain3D(n=n, sigma=100.0 / n**3)
    s = (np.arange(n) + 0.5) / n
    t0 = np.column_stack([np.ones(n), 0.3 * s, 0.3 * s * s])
    t0 /= np.linalg.norm(t0, axis=1)[:, None]
    period = 2 * np.pi / 278.0 * n**4
    assert choose_method(np.linalg.eigvals(jacobian(t0, chain)), period) == "LSODA"
    ts = np.linspace(0.0, 0.25 * period, 11)
    implicit = solve3d(chain, ts, t0, rtol=1e-10, atol=1e-12, method="LSODA")
    explicit = solve3d(chain, ts, t0, rtol=1e-10, atol=1e-12, method="DOP853")
    assert np.abs(implicit - explicit).max() < 1e-7
    short = Chain3D(n=5, sigma=0.8)
    assert choose_method(np.linalg.eigvals(jacobian(_random_tangents(5), short)), 100.0) == "DOP853"


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
    with pytest.raises(ParameterError, match="load"):
        rhs(_random_tangents(3), Chain3D(n=3, sigma=0.5, load=(1.0, 1.0)))
    with pytest.raises(ParameterError, match="load"):
        rhs(_random_tangents(3), Chain3D(n=3, sigma=0.5, load=(1.0, -1.0, 1.0)))
    with pytest.raises(ParameterError, match="method"):
        solve3d(Chain3D(n=3, sigma=0.5), np.linspace(0, 1, 3), _random_tangents(3), method="Euler")

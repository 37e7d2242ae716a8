"""Linear stability with inertia (analysis/flutter.py): the quadratic eigenvalue problem, its overdamped limit,
Ziegler's double pendulum and the nonlinear pieces it linearises."""

from __future__ import annotations

import math

import numpy as np
import pytest

from elastoactive.analysis import flutter as F
from elastoactive.analysis import stability as St
from elastoactive.core.errors import ParameterError

RNG = np.random.default_rng(20230605)


# ------------------------------------------------------------------------ independent geometry for the checks


def _positions(theta):
    """Particle positions r_i = sum_{j<=i} (cos th_j, sin th_j), shape (n, 2)."""
    return np.cumsum(np.stack([np.cos(theta), np.sin(theta)], axis=1), axis=0)


def _jacobian_positions(theta, h=1e-6):
    """d r_i / d theta_k by central differences, shape (n, 2, n)."""
    n = len(theta)
    J = np.zeros((n, 2, n))
    for k in range(n):
        d = np.zeros(n)
        d[k] = h
        J[:, :, k] = (_positions(theta + d) - _positions(theta - d)) / (2 * h)
    return J


def _kinetic_energy(theta, dtheta, masses, inertia, h=1e-6):
    """1/2 sum m_i |v_i|^2 + 1/2 sum I_i th_i'^2 with v_i from differencing the positions along theta'."""
    v = (_positions(theta + h * dtheta) - _positions(theta - h * dtheta)) / (2 * h)
    return 0.5 * np.sum(masses * np.sum(v**2, axis=1)) + 0.5 * np.sum(inertia * dtheta**2)


def _generalised(theta, forces):
    """Q_k = sum_i F_i . d r_i / d theta_k (virtual work)."""
    return np.einsum("ia,iak->k", forces, _jacobian_positions(theta))


def _follower_particle_forces(theta, sigma, active):
    e = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    return -sigma * e * np.asarray(active, dtype=float)[:, None]


# ---------------------------------------------------------------------------------------- overdamped limit


@pytest.mark.parametrize("n", [2, 7])
@pytest.mark.parametrize("mass", [0.0, 1e-10])
def test_vanishing_mass_recovers_overdamped_threshold(n, mass):
    s0, w0 = St.critical_sigma(n)
    s, w = F.critical_sigma(n, mass)
    assert abs(s - s0) < 1e-6
    assert abs(w - w0) < 1e-6
    if n == 2:
        assert abs(s - 3.0) < 1e-6 and abs(w - 1.0) < 1e-6
    else:
        assert abs(s - 0.1575) < 5e-4


def test_massless_spectrum_is_the_overdamped_spectrum():
    for n, sigma in [(2, 2.5), (7, 0.3)]:
        lam = F.eigenvalues(n, sigma, 0.0)
        assert len(lam) == n
        np.testing.assert_allclose(lam, St.eigenvalues(n, sigma), atol=1e-10)
        assert lam[0].imag > 0 and abs(lam[1] - np.conj(lam[0])) < 1e-12  # conjugate pairs come + then -
    # small mass: the n slow eigenvalues move by O(m), n more relax fast at ~ -1/m
    lam = F.eigenvalues(7, 0.3, 1e-6)
    assert len(lam) == 14
    np.testing.assert_allclose(lam[:7], St.eigenvalues(7, 0.3), rtol=1e-4)
    assert np.all(lam[7:].real < -1e4)


def test_operators_at_default_inertia():
    M, C, K, S = F.linear_operators(7, 0.5)
    D0, K0, S0 = St._matrices(7)
    np.testing.assert_allclose(M, 0.5 * D0 + 0.5 * 0.4 * 0.14**2 * np.eye(7))
    np.testing.assert_allclose(C, D0)
    np.testing.assert_allclose(K, K0)
    np.testing.assert_allclose(S, S0)
    _, C2, _, _ = F.linear_operators(7, 0.5, drag=0.0, joint_damping=0.3)
    np.testing.assert_allclose(C2, 0.3 * K0)


def test_free_pin_divergence_threshold_is_independent_of_mass():
    s_rot = St.rotation_threshold(7)
    for m in (0.0, 0.3, 5.0):
        s, w = F.critical_sigma(7, m, clamped=False)
        assert abs(s - s_rot) < 1e-8
        assert w == 0.0


# ----------------------------------------------------------------------------------------- Ziegler's column


def test_ziegler_undamped_flutter_load():
    P, w = F.ziegler_critical_load()
    assert abs(P - (3.5 - math.sqrt(2.0))) < 1e-6
    assert abs(P - F.ZIEGLER_UNDAMPED) < 1e-9
    assert abs(w - 2.0**-0.25) < 1e-6  # lambda^2 = -1/sqrt 2 at the merging
    # below the load the undamped spectrum is exactly imaginary, above it a pair grows
    assert F.growth_rate(2, P - 1e-3, [2.0, 1.0], inertia=0.0, drag=0.0, active=[1]) == 0.0
    assert F.growth_rate(2, P + 1e-3, [2.0, 1.0], inertia=0.0, drag=0.0, active=[1]) > 1e-3
    # mass only sets the time scale
    P3, w3 = F.ziegler_critical_load(mass=3.0)
    assert abs(P3 - P) < 1e-9 and abs(w3 - w / math.sqrt(3.0)) < 1e-9


def test_ziegler_vanishing_joint_damping_destabilisation_paradox():
    P, w = F.ziegler_critical_load(damping=1e-4)
    assert abs(P - 41.0 / 28.0) < 1e-3
    assert abs(P - F.ZIEGLER_DAMPED_LIMIT) < 1e-7
    assert abs(w - math.sqrt(2.0 / 7.0)) < 1e-6
    assert P < F.ZIEGLER_UNDAMPED - 0.6  # the paradox: far below 2.086
    for c, m in [(0.3, 1.0), (0.05, 1.0), (0.2, 2.0)]:
        assert abs(F.ziegler_critical_load(mass=m, damping=c)[0] - F.ziegler_damped_load(c, m)) < 1e-9


def test_ziegler_vanishing_lab_drag():
    for g in (1.0, 0.1, 1e-3):
        assert abs(F.ziegler_critical_load(drag=g)[0] - F.ziegler_drag_load(g)) < 1e-9
    P, w = F.ziegler_critical_load(drag=1e-5)
    assert abs(P - F.ZIEGLER_DRAG_LIMIT) < 1e-8
    assert abs(w**2 - (math.sqrt(5.0) - 1.0) / 2.0) < 1e-6
    assert 0.01 < F.ZIEGLER_UNDAMPED - P < 0.02  # a small paradox, not the undamped load


def test_ziegler_operators():
    M, C, K, S = F.ziegler_operators(mass=1.0, damping=0.1)
    np.testing.assert_allclose(M, [[3.0, 1.0], [1.0, 1.0]])
    np.testing.assert_allclose(C, 0.1 * np.array([[2.0, -1.0], [-1.0, 1.0]]))
    np.testing.assert_allclose(K - 2.0 * S, [[0.0, 1.0], [-1.0, 1.0]])  # [[2 - P, P - 1], [-1, 1]]


# ------------------------------------------------------------------------------------- the mass-ratio curve


@pytest.mark.parametrize("n", [2, 7])
def test_mass_ratio_curve_continuous_and_decreasing(n):
    ms = np.geomspace(1e-4, 1e3, 57)  # factor 1.33 per step
    s, w = F.critical_sigma_curve(n, ms)
    assert np.all(np.isfinite(s)) and np.all(w > 0)
    assert np.all(np.diff(s) < 0)  # inertia lowers the threshold monotonically
    assert np.all(np.diff(w) < 0)
    # continuous: around the largest step, halving the step (in log m) halves the jump
    i = int(np.argmax(np.abs(np.diff(s))))
    jump = abs(s[i + 1] - s[i])
    assert jump / s[i] < 0.06
    m_mid = math.sqrt(ms[i] * ms[i + 1])
    s_mid = F.critical_sigma(n, m_mid)[0]
    assert s[i + 1] < s_mid < s[i]
    assert max(abs(s_mid - s[i]), abs(s[i + 1] - s_mid)) < 0.7 * jump
    assert abs(s[0] / St.critical_sigma(n)[0] - 1) < 1e-3
    # heavy end: the drag-free limit (sigma_c depends on gamma / sqrt(m) only)
    s_inf, w_inf = F.critical_sigma(n, 1.0, drag=1e-6)
    assert 0 < s[-1] / s_inf - 1 < 0.015  # gamma / sqrt(m) = 0.03 at m = 1e3
    assert abs(w[-1] * math.sqrt(ms[-1]) / w_inf - 1) < 0.015


def test_drag_and_mass_enter_through_gamma_over_sqrt_mass():
    for n in (2, 7):
        a = F.critical_sigma(n, 100.0)
        b = F.critical_sigma(n, 1.0, drag=0.1)
        assert abs(a[0] - b[0]) < 1e-9
        assert abs(a[1] * 10.0 - b[1]) < 1e-8


def test_paper_model_drag_free_limit():
    # point masses: the drag D0 is proportional to M0, no destabilisation paradox
    for n, undamped in [(2, 2.0), (7, None)]:
        s_u = F.critical_sigma(n, 1.0, drag=0.0, inertia=0.0)[0]
        if undamped is not None:
            assert abs(s_u - undamped) < 1e-9
        assert abs(F.critical_sigma(n, 1.0, drag=1e-5, inertia=0.0)[0] - s_u) < 1e-8
    # with the bead's rotational inertia it no longer is: a tiny paradox for N = 2
    s_u = F.critical_sigma(2, 1.0, drag=0.0)[0]
    s_0 = F.critical_sigma(2, 1.0, drag=1e-5)[0]
    assert 1e-5 < s_u - s_0 < 1e-4


def test_one_percent_shift_for_seven():
    m, s, s0 = F.onset_shift_mass_ratio(7, 0.01, m_min=1e-2)
    assert 0.3 < m < 0.45
    assert abs(s / s0 - 0.99) < 1e-6


# ------------------------------------------------------------------------------------- nonlinear pieces


@pytest.mark.parametrize("n, active", [(2, [False, True]), (5, [True, False, True, True, False]), (4, None)])
def test_follower_matrix_is_the_linearised_follower_force(n, active):
    mask = np.ones(n, bool) if active is None else np.array(active)
    sigma = 0.7
    # the formula Q_k = sigma sum_{i>=k, active} sin(th_k - th_i) is the virtual work of -sigma e_i
    th = RNG.normal(size=n)
    np.testing.assert_allclose(
        F.follower_forces(th, sigma, active), _generalised(th, _follower_particle_forces(th, sigma, mask)), atol=1e-8
    )
    # and its Jacobian at the straight chain is sigma S
    h = 1e-6
    J = np.zeros((n, n))
    for k in range(n):
        d = np.zeros(n)
        d[k] = h
        J[:, k] = (F.follower_forces(d, sigma, active) - F.follower_forces(-d, sigma, active)) / (2 * h)
    np.testing.assert_allclose(J, sigma * F.follower_matrix(n, active), atol=1e-8)
    if n == 2 and active == [False, True]:
        np.testing.assert_allclose(F.follower_matrix(2, active), [[1.0, -1.0], [0.0, 0.0]])


def test_follower_matrix_by_indices_and_rigid_rotation():
    np.testing.assert_array_equal(F.follower_matrix(5, [1, 3]), F.follower_matrix(5, [0, 1, 0, 1, 0] == np.ones(5)))
    S = F.follower_matrix(6, [0, 2, 5])
    np.testing.assert_allclose(S @ np.ones(6), 0.0)
    # a load on the first particle only passes through the pin: never unstable
    assert F.critical_sigma(3, 1.0, active=[0])[0] == math.inf


@pytest.mark.parametrize("n", [2, 3, 6])
def test_mass_matrix_is_the_hessian_of_the_kinetic_energy(n):
    masses = RNG.uniform(0.5, 2.0, n)
    inertia = RNG.uniform(0.0, 0.1, n)
    th = RNG.normal(size=n)
    step = 0.5  # T is quadratic in theta': the central second difference is exact up to rounding
    H = np.zeros((n, n))
    T = lambda dth: _kinetic_energy(th, dth, masses, inertia)  # noqa: E731
    for j in range(n):
        for k in range(n):
            ej, ek = np.eye(n)[j] * step, np.eye(n)[k] * step
            H[j, k] = (T(ej + ek) - T(ej - ek) - T(-ej + ek) + T(-ej - ek)) / (4 * step**2)
    np.testing.assert_allclose(F.mass_matrix_at(th, masses, inertia), H, atol=1e-7)
    np.testing.assert_allclose(F.mass_matrix_at(np.zeros(n), masses, inertia), F.mass_matrix(n, masses, inertia))
    # default inertia: MuJoCo's bead
    np.testing.assert_allclose(
        np.diag(F.mass_matrix(n, masses) - F.mass_matrix(n, masses, 0.0)), 0.4 * 0.14**2 * masses
    )


def test_drag_matrix_is_the_lab_frame_drag():
    n, ratio = 4, 3.0
    gt = RNG.uniform(0.5, 1.5, n)
    th, dth = RNG.normal(size=n), RNG.normal(size=n)
    h = 1e-6
    v = (_positions(th + h * dth) - _positions(th - h * dth)) / (2 * h)
    e = np.stack([np.cos(th), np.sin(th)], axis=1)
    nn = np.stack([-np.sin(th), np.cos(th)], axis=1)
    force = -(ratio * gt[:, None] * np.sum(e * v, 1)[:, None] * e + gt[:, None] * np.sum(nn * v, 1)[:, None] * nn)
    np.testing.assert_allclose(-F.drag_matrix_at(th, gt, ratio) @ dth, _generalised(th, force), atol=1e-7)
    np.testing.assert_allclose(F.drag_matrix_at(np.zeros(n), gt, ratio), F.drag_matrix(n, gt))


def test_bad_parameters():
    with pytest.raises(ParameterError):
        F.linear_operators(3, -1.0)
    with pytest.raises(ParameterError):
        F.linear_operators(3, [1.0, 2.0])
    with pytest.raises(ParameterError):
        F.linear_operators(0)
    with pytest.raises(ParameterError):
        F.critical_sigma(3, 1.0, drag=0.0, clamped=False)
    with pytest.raises(ParameterError):
        F.eigenvalues(3, 0.1, 0.0, inertia=0.0, drag=0.0)

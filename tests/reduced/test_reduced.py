"""The reduced overdamped model: equations, compiled kernels, integrators and the four scenes' physics."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis import stability
from elastoactive.controllers.noise import force_factor
from elastoactive.core import registry
from elastoactive.core.params import Numerics, ParameterError, Physics, scene_parameters
from elastoactive.core.registry import initial_angles
from elastoactive.engines import reduced as R
from elastoactive.reduced.initial import pin_residual

SCENES = ("one-pinned", "two-pinned", "rotating-pin", "coupled-pair")
DRAG_RATIOS = (1.0, 2.5, 0.4)


def _physics(scene, drag_ratio=1.0, n=5, **kw):
    base = dict(n=n, sigma=0.7, drag_ratio=drag_ratio, kappa=1.3, rho=1.4, delta=0.1)
    base.update(kw)
    own = scene_parameters(registry.get(scene))  # the values the scene has (kappa and rho on the pair, ...)
    return Physics(scene=scene, **{k: v for k, v in base.items() if k in own})


def _state(physics, rng, spread=0.8):
    return spread * rng.standard_normal(physics.n_angles)


def _theta(traj):
    return traj.theta[:, -1] - traj.theta[:, 0]


# ------------------------------------------------------------------------------------------------
# equations
# ------------------------------------------------------------------------------------------------
def test_n2_equals_paper_equations_1_2():
    """Main text Eqs. (1)-(2), solved for the rates, at random states and sigma."""
    rng = np.random.default_rng(0)
    for _ in range(20):
        sigma = rng.uniform(0, 5)
        th = rng.uniform(-2, 2, 2)
        c, s = np.cos(th[0] - th[1]), np.sin(th[0] - th[1])
        M = np.array([[2.0, c], [c, 1.0]])
        b = np.array([th[1] - 2 * th[0] + sigma * s, th[0] - th[1]])
        expected = np.linalg.solve(M, b)
        got = R.rhs(Physics(scene="one-pinned", n=2, sigma=sigma))(0.0, th)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-13)


@pytest.mark.parametrize("scene", SCENES)
@pytest.mark.parametrize("drag_ratio", DRAG_RATIOS)
def test_numba_rhs_equals_numpy_reference(scene, drag_ratio):
    rng = np.random.default_rng(1)
    for n in (2, 5, 9):
        ph = _physics(scene, drag_ratio, n=n)
        for _ in range(3):
            th = _state(ph, rng)
            fac = 1.0 + 0.5 * rng.standard_normal(ph.n_angles)
            for factor in (None, fac):
                fast = R.rhs(ph, factor=factor)(0.0, th)
                ref = R.rhs_reference(ph, factor=factor)(0.0, th)
                assert np.max(np.abs(fast - ref)) <= 1e-12 * max(1.0, np.max(np.abs(ref)))


def test_single_pendulum():
    """N = 1, one pinned end: the follower force exerts no torque, th' = -th (drag 1, spring 1)."""
    ph = Physics(scene="one-pinned", n=1, sigma=2.0)
    assert R.rhs(ph)(0.0, np.array([0.3]))[0] == pytest.approx(-0.3, abs=1e-15)
    assert R.rhs(Physics(scene="rotating-pin", n=1, sigma=2.0))(0.0, np.array([0.3]))[0] == 0.0


@pytest.mark.parametrize("scene", SCENES)
@pytest.mark.parametrize("drag_ratio", DRAG_RATIOS)
def test_analytic_jacobian_equals_finite_differences(scene, drag_ratio):
    rng = np.random.default_rng(2)
    ph = _physics(scene, drag_ratio, n=6)
    f, jac = R.rhs(ph), R.jacobian(ph)
    for _ in range(2):
        th = _state(ph, rng)
        J = jac(0.0, th)
        h = 1e-6
        fd = np.column_stack([(f(0.0, th + h * e) - f(0.0, th - h * e)) / (2 * h) for e in np.eye(th.size)])
        assert np.max(np.abs(J - fd)) < 1e-7 * max(1.0, np.max(np.abs(J)))


@pytest.mark.parametrize("drag_ratio", DRAG_RATIOS)
def test_drag_matrix_symmetric_positive_rotation_invariant(drag_ratio):
    rng = np.random.default_rng(3)
    ph = _physics("one-pinned", drag_ratio, n=7)
    th = _state(ph, rng, 1.5)
    D = R.drag_matrix(ph, th)
    np.testing.assert_allclose(D, D.T, atol=1e-14)
    assert np.linalg.eigvalsh(D).min() > 0
    np.testing.assert_allclose(R.drag_matrix(ph, th + 0.7), D, atol=1e-13)
    if drag_ratio == 1.0:
        i = np.arange(1, ph.n + 1)
        iso = (ph.n - np.maximum(i[:, None], i[None, :]) + 1) * np.cos(th[:, None] - th[None, :])
        np.testing.assert_allclose(D, iso, atol=1e-13)


def test_paper_general_n_rows_misprinted():
    """Appendix C's printed drag rows: rows 2..N-1 agree with D; row 1 lacks (N-j+1), row N sums from j=i."""
    rng = np.random.default_rng(4)
    n = 5
    th = rng.uniform(-1, 1, n)
    D = R.drag_matrix(Physics(n=n), th)
    C = np.cos(th[:, None] - th[None, :])
    printed = np.zeros((n, n))
    for i in range(1, n + 1):  # 1-based as printed
        for j in range(1, n + 1):
            if i == 1:
                printed[0, j - 1] = n if j == 1 else C[0, j - 1]
            elif i == n:
                printed[n - 1, j - 1] = C[n - 1, j - 1] if j >= i else 0.0
            else:
                printed[i - 1, j - 1] = ((n - i + 1) if j <= i else (n - j + 1)) * C[i - 1, j - 1]
    np.testing.assert_allclose(printed[1:-1], D[1:-1], atol=1e-14)
    assert np.max(np.abs(printed[0] - D[0])) > 0.5
    assert np.max(np.abs(printed[-1] - D[-1])) > 0.5
    corrected_first = np.array([(n - j + 1) * C[0, j - 1] for j in range(1, n + 1)])
    np.testing.assert_allclose(corrected_first, D[0], atol=1e-14)
    np.testing.assert_allclose(C[-1], D[-1], atol=1e-14)


def _paper_anisotropic_n2(t1, t2, tau_l, tau_t=1.0):
    """The supplement's printed drag matrix of the anisotropic N = 2 equations."""
    return np.array(
        [
            [
                tau_l * np.sin(t1 - t2) ** 2 + tau_t / 4 * (np.cos(4 * t1) + 2 * np.cos(2 * t1) * np.cos(2 * t2) + 5),
                tau_t / 2 * (2 * np.sin(t1) * np.sin(t2) + np.cos(t1) * (np.cos(t2) + np.cos(3 * t2))),
            ],
            [
                tau_t / 2 * (np.sin(t1) * (np.sin(t2) - np.sin(3 * t2)) + 2 * np.cos(t1) * np.cos(t2)),
                tau_t / 4 * (np.cos(4 * t2) + 3),
            ],
        ]
    )


def test_paper_anisotropic_n2_is_wrong():
    """Equal to the first-principles D at th = 0 (so the onset is unaffected), wrong elsewhere."""
    for tau_l in (1.0, 3.0):
        ph = Physics(n=2, drag_ratio=tau_l)
        np.testing.assert_allclose(_paper_anisotropic_n2(0.0, 0.0, tau_l), R.drag_matrix(ph, np.zeros(2)), atol=1e-14)
        q = np.pi / 4
        np.testing.assert_allclose(_paper_anisotropic_n2(q, q, tau_l), 0.5 * R.drag_matrix(ph, [q, q]), atol=1e-14)
        P = _paper_anisotropic_n2(0.3, -0.2, tau_l)
        assert abs(P[0, 1] - P[1, 0]) > 0.1  # not symmetric
        d = 0.5
        ours = np.array([[1 + np.cos(d) ** 2 + tau_l * np.sin(d) ** 2, np.cos(d)], [np.cos(d), 1.0]])
        np.testing.assert_allclose(R.drag_matrix(ph, [0.3, -0.2]), ours, atol=1e-14)
    iso = Physics(n=2)
    assert np.max(np.abs(_paper_anisotropic_n2(0.8, 0.6, 1.0) - R.drag_matrix(iso, [0.8, 0.6]))) > 0.5


# ------------------------------------------------------------------------------------------------
# integrators
# ------------------------------------------------------------------------------------------------
def test_trajectory_metadata_and_default_theta0():
    ph, nu = Physics(n=4, sigma=0.5), Numerics(sample_dt=0.05, seed=3)
    tr = R.simulate_reduced(ph, nu, 2.0)
    np.testing.assert_allclose(tr.t, 0.05 * np.arange(41), rtol=0, atol=1e-15)
    assert tr.theta.shape == (41, 4)
    np.testing.assert_array_equal(tr.theta[0], initial_angles(ph, nu))
    assert tr.engine == "reduced" and tr.wall_time_s > 0
    assert tr.info["method"] == "numba-DOP853" and tr.info["rtol"] == 1e-9 and tr.info["nfev"] > 0
    with pytest.raises(ParameterError):
        R.simulate_reduced(ph, nu, 1.0, theta0=np.zeros(3))


def test_compiled_dop853_equals_scipy_and_reference():
    ph, nu = Physics(n=7, sigma=0.8), Numerics()
    fast = R.simulate_reduced(ph, nu, 40.0)
    scipy_numba = R.simulate_reduced(ph, nu, 40.0, method="DOP853")
    ref = R.simulate_reference(ph, nu, 40.0)
    assert np.max(np.abs(fast.theta - scipy_numba.theta)) < 1e-9
    assert np.max(np.abs(fast.theta - ref.theta)) < 1e-9
    radau = R.simulate_reduced(ph, nu, 40.0, method="Radau", rtol=1e-10, atol=1e-12)
    assert radau.info["njev"] > 0
    assert np.max(np.abs(fast.theta - radau.theta)) < 1e-6


def test_stiff_pair_switches_to_implicit():
    ph = Physics(scene="coupled-pair", n=3, sigma=0.8, kappa=5000.0)
    tr = R.simulate_reduced(ph, Numerics(), 1.0, rtol=1e-7, atol=1e-9)
    assert tr.info["method"] == "Radau" and tr.info["spectral_radius"] > R.STIFF_RADIUS
    ex = R.simulate_reduced(ph, Numerics(), 1.0, rtol=1e-7, atol=1e-9, method="numba-DOP853")
    assert np.max(np.abs(tr.theta - ex.theta)) < 1e-5


# ------------------------------------------------------------------------------------------------
# physics of the scenes
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("sigma, grows", [(2.9, False), (3.1, True)])
def test_n2_hopf_bracketed(sigma, grows):
    tr = R.simulate_reduced(Physics(n=2, sigma=sigma), Numerics(), 60.0)
    Th = np.abs(_theta(tr))
    early, late = Th[tr.t <= 10].max(), Th[tr.t >= 50].max()
    if grows:
        assert late > 10 * early
    else:
        assert late < 0.1 * early


def test_n2_onset_angular_frequency_is_one():
    lam = stability.eigenvalues(2, 3.0)
    assert abs(lam[0].real) < 1e-12 and abs(abs(lam[0].imag) - 1.0) < 1e-12
    # simulated small oscillation just below onset: omega = sqrt(1 - 0.02^2)
    tr = R.simulate_reduced(Physics(n=2, sigma=2.98), Numerics(sample_dt=0.01), 120.0, theta0=[1e-3, 0.0])
    x = tr.theta[:, 0]
    i = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    tc = tr.t[i] - x[i] * (tr.t[i + 1] - tr.t[i]) / (x[i + 1] - x[i])
    omega = 2 * np.pi * (len(tc) - 1) / (tc[-1] - tc[0])
    assert len(tc) > 15
    assert omega == pytest.approx(np.sqrt(1 - 0.02**2), abs=2e-3)


def test_n7_below_onset_stays_straight():
    ph, nu = Physics(n=7, sigma=0.1), Numerics(perturbation=1e-2)
    tr = R.simulate_reduced(ph, nu, 300.0)  # slowest decay rate 0.024 (sigma_c = 0.157)
    assert np.abs(tr.theta[0]).max() > 5e-3
    assert np.abs(tr.theta[tr.t >= 250]).max() < 0.05 * np.abs(tr.theta[0]).max()


def test_n7_above_onset_oscillates():
    tr = R.simulate_reduced(Physics(n=7, sigma=0.8), Numerics(), 200.0)
    assert np.ptp(_theta(tr)[tr.t >= 150]) > 1.0


def test_two_pinned_straight_does_not_oscillate_compressed_snaps():
    nu = Numerics()
    flat = R.simulate_reduced(Physics(scene="two-pinned", n=7, sigma=0.8, delta=0.0), nu, 150.0)
    late = flat.t >= 100
    assert np.std(flat.theta[late, 2]) < 1e-6 and np.abs(flat.theta[late]).max() < 1e-5
    snap = R.simulate_reduced(Physics(scene="two-pinned", n=7, sigma=0.8, delta=0.1), nu, 150.0)
    assert np.std(snap.theta[snap.t >= 100, 2]) > 0.1
    for tr in (flat, snap):
        assert tr.info["constraint_violation"] < 1e-6
        assert np.abs(np.array([pin_residual(th, tr.physics.delta) for th in tr.theta])).max() < 1e-6


def test_rotating_pin_turns_at_constant_rate():
    tr = R.simulate_reduced(Physics(scene="rotating-pin", n=7, sigma=0.8), Numerics(), 400.0)
    w = np.gradient(tr.theta[:, 0], tr.t)[tr.t >= 300]
    assert abs(w.mean()) > 0.05
    assert np.ptp(w) < 0.01 * abs(w.mean())
    bends = np.diff(tr.theta[tr.t >= 300], axis=1)  # steady shape in the rotating frame
    assert np.ptp(bends, axis=0).max() < 1e-3


def test_pair_uncoupled_second_chain_is_rescaled_single_chain():
    """kappa = 0: phi obeys the single chain with sigma / rho in time rho t."""
    rho, sigma = 2.0, 0.8
    rng = np.random.default_rng(5)
    th0 = 0.1 * rng.standard_normal(10)
    pair = R.simulate_reduced(
        Physics(scene="coupled-pair", n=5, sigma=sigma, rho=rho, kappa=0.0), Numerics(sample_dt=0.05), 30.0, theta0=th0
    )
    one = R.simulate_reduced(Physics(n=5, sigma=sigma), Numerics(sample_dt=0.05), 30.0, theta0=th0[:5])
    two = R.simulate_reduced(Physics(n=5, sigma=sigma / rho), Numerics(sample_dt=0.1), 60.0, theta0=th0[5:])
    assert np.max(np.abs(pair.chain(0) - one.theta)) < 1e-6  # integration error of the growing oscillation
    assert np.max(np.abs(pair.chain(1) - two.theta)) < 1e-6


def test_pair_identical_chains_stay_identical_and_coupling_pulls_together():
    th0 = np.tile(0.05 * np.arange(1, 6), 2)
    tr = R.simulate_reduced(
        Physics(scene="coupled-pair", n=5, sigma=0.8, rho=1.0, kappa=2.0), Numerics(), 30.0, theta0=th0
    )
    assert np.max(np.abs(tr.chain(0) - tr.chain(1))) < 1e-10
    f = R.rhs(Physics(scene="coupled-pair", n=3, sigma=0.0, rho=1.0, kappa=1.0))
    rate = f(0.0, np.array([0.1, 0.1, 0.1, -0.1, -0.1, -0.1]))
    assert rate[0] < 0 < rate[3]


# ------------------------------------------------------------------------------------------------
# noise
# ------------------------------------------------------------------------------------------------
def test_noise_reproducible_by_seed():
    ph = Physics(n=2, sigma=3.5, noise=0.3)
    nu = Numerics(seed=1, dt=0.01)
    a = R.simulate_reduced(ph, nu, 20.0)
    b = R.simulate_reduced(ph, nu, 20.0)
    c = R.simulate_reduced(ph, Numerics(seed=2, dt=0.01), 20.0, theta0=a.theta[0])
    assert a.info["method"] == "Euler-Maruyama" and a.info["nsteps"] == 2000
    np.testing.assert_array_equal(a.theta, b.theta)
    assert np.max(np.abs(a.theta - c.theta)) > 1e-2
    np.testing.assert_allclose(a.t, 0.05 * np.arange(401), atol=1e-12)


def test_noise_euler_maruyama_step_by_step():
    ph, nu = Physics(scene="coupled-pair", n=3, sigma=0.8, noise=0.2, kappa=1.0), Numerics(seed=7)
    tr = R.simulate_reduced(ph, nu, 1.0)
    th = tr.theta[0].copy()
    for k in range(100):
        fac = force_factor(nu.seed, k, ph.n_angles, ph.noise, nu.dt)[0]
        th = th + nu.dt * R.rhs_reference(ph, factor=fac)(0.0, th)
        if (k + 1) % nu.steps_per_sample == 0:
            np.testing.assert_allclose(tr.theta[(k + 1) // nu.steps_per_sample], th, rtol=0, atol=1e-13)


def test_zero_noise_uses_the_ode_path():
    tr = R.simulate_reduced(Physics(n=2, sigma=3.5, noise=0.0), Numerics(seed=1), 5.0)
    assert tr.info["method"] != "Euler-Maruyama"
    tr2 = R.simulate_reduced(Physics(n=2, sigma=3.5, noise=0.0), Numerics(seed=1), 5.0, method="numba-DOP853")
    np.testing.assert_array_equal(tr.theta, tr2.theta)


def test_noisy_two_pinned_keeps_constraint():
    tr = R.simulate_reduced(Physics(scene="two-pinned", n=7, sigma=0.8, noise=0.3), Numerics(seed=3), 20.0)
    assert tr.info["constraint_violation"] < 1e-10

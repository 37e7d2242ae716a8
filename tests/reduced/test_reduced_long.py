"""Long chains in the reduced model: the O(N) articulated-drag solve of D(theta) theta' = f against the
dense Cholesky solve, and which of the two the solvers take (no timings here: the costs are measured
outside the tests)."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive import reduced as M
from elastoactive.reduced import kernels as K

BETA = 3.0
NS = (2, 3, 7, 30, 100)
SYSTEMS = {  # the kinds of chain the scenes build, at sigma = 0.7
    "one-pinned": dict(),
    "anisotropic": dict(gamma_l=2.5),
    "anisotropic-low": dict(gamma_l=0.4),
    "rotating-pin": dict(clamped=False, gamma_l=1.6),
    "two-pinned": dict(clamped=False, pinned=True, delta=0.1, gamma_l=1.7),
    "coupled-pair": dict(n_chains=2, kappa=1.3, rho=1.4, gamma_l=0.6),
}


def _system(kind, n):
    return M.ChainSystem(n=n, sigma=0.7, **SYSTEMS[kind]).typed()


def _states(system, rng, count=3):
    """Random states (large angles) and force factors; pinned states near the pins, as in a run."""
    for _ in range(count):
        th = 0.8 * rng.standard_normal(system.n_angles)
        if system.pinned:
            th = M.project_on_pins(0.3 * rng.standard_normal(system.n_angles), system.delta)
            th += 1e-3 * rng.standard_normal(system.n_angles)  # a little off the pins: beta g matters
        yield th, 1.0 + 0.3 * rng.standard_normal(system.n_angles)


def _eval(system, th, fac, dense):
    L, D, X, lam = K.workspace(system, dense=dense)
    out = np.empty(system.n_angles)
    K.eval_rhs(th, fac, system, BETA, out, L, D, X, lam)
    return out, X, lam


# ------------------------------------------------------------------------------------------------
# the O(N) solve equals the dense solve
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("n", NS)
@pytest.mark.parametrize("kind", list(SYSTEMS))
def test_recursive_rhs_equals_dense(kind, n):
    system = _system(kind, n)
    rng = np.random.default_rng(n)
    for th, fac in _states(system, rng):
        dense, Xd, lamd = _eval(system, th, fac, dense=True)
        fast, Xr, lamr = _eval(system, th, fac, dense=False)
        scale = np.max(np.abs(dense))
        assert np.max(np.abs(fast - dense)) <= 1e-10 * scale, kind
        if system.pinned:  # D^-1 G^T and the multipliers too
            np.testing.assert_allclose(Xr, Xd, rtol=0, atol=1e-10 * np.max(np.abs(Xd)))
            np.testing.assert_allclose(lamr, lamd, rtol=0, atol=1e-10 * np.max(np.abs(lamd)))
        # and both equal the plain-numpy formulas (np.linalg.solve of the saddle point)
        ref = M.rhs_reference(system, beta=BETA, factor=fac)(0.0, th)
        assert np.max(np.abs(fast - ref)) <= 1e-10 * scale, kind


@pytest.mark.parametrize("n", (1,) + NS)
@pytest.mark.parametrize("gamma_l", (1.0, 2.5, 0.4))
def test_articulated_solve_inverts_the_drag_matrix(n, gamma_l):
    """D w = b for arbitrary b, and D X = G^T (the pinned chain's two extra right-hand sides)."""
    rng = np.random.default_rng(7 + n)
    system = M.ChainSystem(n=n, gamma_l=gamma_l).typed()
    for _ in range(3):
        th = 1.2 * rng.standard_normal(n)
        b = rng.standard_normal(n)
        U = np.zeros((n, 4))
        U[:, 2], U[:, 3] = np.cos(th), np.sin(th)
        X = np.zeros((n, 2))
        w = b.copy()
        K.articulated_solve(0, n, system.gamma_l, system.gamma_t, w, U, X, 2)
        D = M.drag_matrix(system, th)
        np.testing.assert_allclose(w, np.linalg.solve(D, b), rtol=0, atol=1e-10 * np.max(np.abs(w)))
        GT = np.stack([-np.sin(th), np.cos(th)], axis=1)
        np.testing.assert_allclose(X, np.linalg.solve(D, GT), rtol=0, atol=1e-10 * np.max(np.abs(X)))


def test_recursive_pinned_rates_keep_the_baumgarte_law():
    """G th' = -beta g on the recursive path (N = 100, off the pins)."""
    system = _system("two-pinned", 100)
    rng = np.random.default_rng(3)
    for th, fac in _states(system, rng):
        rate, _, _ = _eval(system, th, fac, dense=False)
        G = M.pin_jacobian(th)
        np.testing.assert_allclose(G @ rate, -BETA * M.pin_residual(th, system.delta), rtol=0, atol=1e-11)


def test_straight_isotropic_chain_closed_form():
    """Straight chain, isotropic drag: D_jk = N - max(j, k) + 1, D^-1 = B^-1 B^-T with B the lower-triangular
    ones (the reduced model's linear limit); solved by the recursion at N = 400."""
    n = 400
    b = np.random.default_rng(0).standard_normal(n)
    U = np.zeros((n, 4))
    U[:, 2] = 1.0
    w = b.copy()
    K.articulated_solve(0, n, 1.0, 1.0, w, U, np.zeros((n, 2)), 0)
    # D = B^T B (B[i, j] = [j <= i]): D^-1 b = B^-1 B^-T b; B^-1 is the difference operator
    y = np.append(b[:-1] - b[1:], b[-1])  # B^-T b
    expected = np.diff(np.concatenate([[0.0], y]))  # B^-1 y
    np.testing.assert_allclose(w, expected, rtol=0, atol=1e-12 * np.max(np.abs(expected)))


# ------------------------------------------------------------------------------------------------
# which path the solvers take
# ------------------------------------------------------------------------------------------------
def _workspace_size(ws):
    return sum(a.size for a in ws)


def test_workspace_picks_the_path_by_n():
    lo, hi = K.RECURSIVE_MIN_N - 1, K.RECURSIVE_MIN_N
    assert 2 <= K.RECURSIVE_MIN_N <= 16
    for nch in (1, 2):
        dense = K.workspace(M.ChainSystem(n=lo, n_chains=nch))
        assert dense[0].shape == (nch, lo, lo) and not K.uses_recursive(lo)
        rec = K.workspace(M.ChainSystem(n=hi, n_chains=nch))
        assert rec[0].shape == (nch, 0, 0) and K.uses_recursive(hi)
    # the O(N) path holds no N x N array: its scratch grows linearly with N (the dense one, as N^2)
    sizes = {n: _workspace_size(K.workspace(M.ChainSystem(n=n, n_chains=2))) for n in (100, 200, 300)}
    assert sizes[300] - sizes[200] == sizes[200] - sizes[100] and sizes[300] < 20 * 300
    assert _workspace_size(K.workspace(M.ChainSystem(n=400), dense=True)) >= 400**2
    # the Jacobian reuses the Cholesky factors: solve.jacobian asks for the dense workspace at every N


@pytest.mark.parametrize("kind", ["one-pinned", "two-pinned", "coupled-pair"])
def test_public_rhs_takes_the_recursive_path_for_long_chains(kind):
    """rhs() is, bit for bit, the recursive evaluation from RECURSIVE_MIN_N particles on and the dense one below."""
    rng = np.random.default_rng(11)
    for n in sorted({max(K.RECURSIVE_MIN_N - 1, 2), K.RECURSIVE_MIN_N, 7, 100}):
        dense = not K.uses_recursive(n)
        system = _system(kind, n)
        f = M.rhs(system, beta=BETA)
        for th, _ in _states(system, rng, count=2):
            ones = np.ones(system.n_angles)
            np.testing.assert_array_equal(f(0.0, th), _eval(system, th, ones, dense=dense)[0])


def test_euler_maruyama_takes_the_path_of_rhs():
    """One Euler-Maruyama step from the compiled loop equals theta0 + dt f(theta0) bit for bit (N = 30)."""
    system = _system("coupled-pair", 30)
    th0 = 0.5 * np.random.default_rng(5).standard_normal(system.n_angles)
    dt = 0.01
    em, _ = M.solve_sde(system, np.array([0.0, dt]), th0, dt=dt, factors=lambda s: np.ones((s.size, 60)), beta=BETA)
    np.testing.assert_array_equal(em[1], th0 + dt * M.rhs(system, beta=BETA)(0.0, th0))


def test_jacobian_of_a_long_chain_matches_finite_differences_of_the_recursive_rhs():
    """The analytic Jacobian (dense, O(N^3)) against central differences of the O(N) right-hand side."""
    for kind in ("anisotropic", "two-pinned", "coupled-pair"):
        system = _system(kind, 30)
        th, _ = next(_states(system, np.random.default_rng(2)))
        f, jac = M.rhs(system, beta=BETA), M.jacobian(system, beta=BETA)
        J = jac(0.0, th)
        h = 1e-6
        fd = np.empty_like(J)
        for m in range(th.size):
            e = np.zeros(th.size)
            e[m] = h
            fd[:, m] = (f(0.0, th + e) - f(0.0, th - e)) / (2 * h)
        np.testing.assert_allclose(J, fd, rtol=0, atol=1e-6 * np.max(np.abs(J)), err_msg=kind)


def test_long_pinned_chain_integrates_on_its_pins():
    n, delta = 40, 0.1
    system = M.ChainSystem(n=n, pinned=True, clamped=False, sigma=0.05, delta=delta)
    arch = M.project_on_pins(0.3 * np.cos(np.pi * (np.arange(1, n + 1) - 0.5) / n), delta)
    t = 0.5 * np.arange(11)
    theta, info = M.solve_ode(system, t, arch, rtol=1e-9, atol=1e-11, method="numba-DOP853", beta=M.DEFAULT_BETA)
    assert info["status"] == 0 and M.constraint_violation(system, theta) < 1e-8
    # and the compiled DOP853 (recursive RHS inside) follows scipy's DOP853 on the public rhs
    from scipy.integrate import solve_ivp

    sol = solve_ivp(
        M.rhs(system, beta=M.DEFAULT_BETA), (0.0, t[-1]), arch, method="DOP853", t_eval=t, rtol=1e-9, atol=1e-11
    )
    np.testing.assert_allclose(theta, sol.y.T, rtol=0, atol=1e-10)

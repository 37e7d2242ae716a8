"""Linear stability of the straight chain."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis import stability as S
from elastoactive.core.params import Physics
from elastoactive.engines import reduced as R


def test_n2_critical_sigma_is_three_with_unit_frequency():
    sigma_c, omega_c = S.critical_sigma(2)
    assert abs(sigma_c - 3.0) < 1e-8
    assert abs(omega_c - 1.0) < 1e-8


@pytest.mark.parametrize("sigma", [0.0, 2.5, 2.9, 3.0, 3.3, 3.9])
def test_n2_eigenvalues_closed_form(sigma):
    mu = sigma - 3.0
    root = np.sqrt(complex(mu**2 - 1))  # i sqrt(1 - mu^2) in the oscillatory range |mu| < 1
    np.testing.assert_allclose(S.eigenvalues(2, sigma), [mu + root, mu - root], atol=1e-12)


def test_n7_critical_sigma_matches_paper():
    sigma_c, omega_c = S.critical_sigma(7)
    assert 0.14 <= sigma_c <= 0.16
    assert omega_c > 0
    assert S.growth_rate(7, sigma_c - 1e-3) < 0 < S.growth_rate(7, sigma_c + 1e-3)


def test_critical_sigmas_vectorised_and_scaling():
    ns = np.arange(2, 11)
    sig, om = S.critical_sigmas(ns)
    for n, s, w in zip(ns, sig, om):
        assert (s, w) == S.critical_sigma(int(n))
    assert np.all(np.diff(sig) < 0)
    scaled = ns**3 * sig
    assert np.all(np.diff(scaled) > 0)  # N^3 sigma_c rises towards the continuum value
    s40, _ = S.critical_sigma(40)
    assert 65 < 40**3 * s40 < 80


def test_single_pendulum_never_unstable():
    assert S.critical_sigma(1) == (np.inf, pytest.approx(np.nan, nan_ok=True))


@pytest.mark.parametrize("drag_ratio", [1.0, 3.0])
def test_linear_operator_equals_reduced_jacobian_at_rest(drag_ratio):
    for n, sigma in [(2, 3.2), (7, 0.8)]:
        J = R.jacobian(Physics(n=n, sigma=sigma, drag_ratio=drag_ratio))(0.0, np.zeros(n))
        np.testing.assert_allclose(J, S.linear_operator(n, sigma), atol=1e-12)


def test_pair_linearisation():
    n, sigma, kappa, rho = 4, 0.8, 1.7, 1.4
    J = R.jacobian(Physics(scene="coupled-pair", n=n, sigma=sigma, kappa=kappa, rho=rho))(0.0, np.zeros(2 * n))
    np.testing.assert_allclose(J, S.pair_linear_operator(n, sigma, kappa, rho), atol=1e-12)
    # uncoupled: union of chain 1 (sigma) and chain 2 (rho * A(sigma / rho))
    lam = np.sort_complex(S.pair_eigenvalues(n, sigma, 0.0, rho))
    expected = np.sort_complex(np.concatenate([S.eigenvalues(n, sigma), rho * S.eigenvalues(n, sigma / rho)]))
    np.testing.assert_allclose(lam, expected, atol=1e-10)


@pytest.mark.parametrize("n", [2, 3, 7, 20, 35, 36, 37, 60, 120, 200])
def test_rotation_threshold_is_the_first_crossing_for_every_n(n):
    """The free-pin threshold is bracketed from below: the straight chain is stable on the whole way up to it
    and unstable just above it, from N = 2 to 200 (N^3 sigma_r lies between 20 and ~31)."""
    s_r = S.rotation_threshold(n)
    growth = lambda s: np.max(np.linalg.eigvals(S.rotating_operator(n, s)).real)  # noqa: E731
    assert 19.9 < n**3 * s_r < 31.0
    assert all(growth(f * s_r) < 0 for f in (0.0, 0.3, 0.7, 0.99))
    assert growth(1.01 * s_r) > 0


@pytest.mark.parametrize("n", [2, 5, 6, 7, 12, 30, 60])
def test_onset_agrees_with_the_dense_critical_sigma(n):
    sigma_c, omega_c = S.onset(n)
    ref_sigma, ref_omega = S.critical_sigma(n, tol=1e-14)
    assert sigma_c == pytest.approx(ref_sigma, rel=1e-8)
    assert omega_c == pytest.approx(ref_omega, rel=1e-7)


def test_onset_of_long_chains_tends_to_the_continuum():
    """The banded O(N) path at N = 1000: N^3 sigma_c and N^4 omega_c between N = 200 and the continuum
    (76.10, 196.59), approached like 1/N."""
    s200, w200 = S.onset(200)
    s1000, w1000 = S.onset(1000)
    assert 75.3 < 200**3 * s200 < 1000**3 * s1000 < 76.102
    assert 192.7 < 200**4 * w200 < 1000**4 * w1000 < 196.591
    gap = (76.102 - 200**3 * s200) / (76.102 - 1000**3 * s1000)
    assert 4.0 < gap < 6.0  # 1/N convergence: the gap shrinks 5x from N = 200 to 1000
    lam = S.slow_eigenvalues(1000, s1000)
    assert abs(lam[0].real) < 1e-9 * abs(lam[0])


def test_stability_command(capsys):
    from elastoactive.cli import main

    assert main(["stability", "one-pinned", "--n", "7", "--sigma", "0.8"]) == 0
    out = capsys.readouterr().out
    assert "sigma_c = 0.15746950" in out and "S_c = f L^3 / B = 76.10" in out and "growth rate +" in out
    assert main(["stability", "rotating-pin", "--n", "40"]) == 0
    assert f"sigma_c = {S.rotation_threshold(40):.10g}" in capsys.readouterr().out
    assert main(["stability", "coupled-pair", "--n", "7", "--kappa", "0", "--rho", "1"]) == 0
    assert "sigma_c = 0.15746950" in capsys.readouterr().out  # two uncoupled equal chains: one chain's onset
    assert main(["stability", "two-pinned"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "two-pinned has no linear operator" in err[0]

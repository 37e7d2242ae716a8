"""The observables and fits the studies add (analysis.measures, analysis.fits, analysis.continuum),
each on a case with a known answer."""

from __future__ import annotations

import math

import numpy as np
import pytest

from elastoactive.analysis import fits
from elastoactive.analysis import measures as ms
from elastoactive.analysis import stability as stab
from elastoactive.analysis.continuum import continuum_critical, continuum_eigenvalues

T = np.arange(0.0, 400.0, 0.05)


# ------------------------------------------------------------------------------------------- measures
def test_landau_variable():
    theta = np.array([[0.1, 0.2], [-0.3, 0.05]])
    mu = 0.2
    b = math.sqrt(1.2 / 0.8)
    np.testing.assert_allclose(ms.landau_variable(theta, mu), theta[:, 0] + 1j * b * theta[:, 1])
    with pytest.raises(ValueError):
        ms.landau_variable(np.zeros((3, 3)), 0.1)
    with pytest.raises(ValueError):
        ms.landau_variable(theta, 1.5)


@pytest.mark.parametrize("g", [0.02, -0.03, 0.0])
def test_growth_rate_of_exponential_oscillation(g):
    t = T[T <= 150]  # growth or decay by e^3 at most over the record
    x = np.exp(g * t) * np.cos(0.7 * t + 0.4)
    assert ms.growth_rate(t, x) == pytest.approx(g, abs=3e-4)
    _, env = ms.envelope(t, x, center=False)
    mid = slice(t.size // 4, 3 * t.size // 4)
    ratio = env[mid] / np.exp(g * t[mid])  # FFT Hilbert: ripples of a few % off whole periods
    assert np.median(ratio) == pytest.approx(1.0, abs=0.02) and np.all(np.abs(ratio - 1) < 0.1)
    _, env = ms.envelope(t, 3.0 + 0.5 * np.cos(0.7 * t))  # centred: the offset is removed
    assert np.median(env[mid]) == pytest.approx(0.5, rel=0.02)


def test_phase_difference_drifts_at_the_mismatch_and_stays_put_when_locked():
    x1 = np.cos(2 * np.pi * 0.10 * T)
    x2 = np.cos(2 * np.pi * 0.11 * T + 1.0)
    t, psi = ms.phase_difference(T, x1, x2, 0.0)
    assert np.polyfit(t, psi, 1)[0] / (2 * np.pi) == pytest.approx(0.01, rel=1e-2)
    assert ms.phase_slips(T, x1, x2, 0.0) == pytest.approx(0.01 * (t[-1] - t[0]) * 0.9, rel=0.05)
    assert not ms.is_locked(T, x1, x2, 0.0)
    x3 = np.cos(2 * np.pi * 0.10 * T + 0.7)  # same frequency, constant lag
    t, psi = ms.phase_difference(T, x1, x3, 0.0)
    assert np.median(psi) == pytest.approx(0.7, abs=0.02)
    assert ms.is_locked(T, x1, x3, 0.0)


def test_steady_shape_and_rotation_uniformity_of_rigid_rotation():
    phi = np.array([0.0, -0.3, -0.7, -1.0])
    theta = 0.2 * T[:, None] + phi[None, :]
    mean, spread = ms.steady_shape(theta, T, 100.0)
    np.testing.assert_allclose(mean, phi - phi[0], atol=1e-12)
    np.testing.assert_allclose(spread, 0.0, atol=1e-12)
    assert ms.rotation_uniformity(T, theta, 100.0) < 1e-9
    wobbly = theta + 0.05 * np.sin(T)[:, None]  # rate 0.2 + 0.05 cos t: std/mean = 0.05/sqrt2/0.2
    assert ms.rotation_uniformity(T, wobbly, 100.0) == pytest.approx(0.05 / math.sqrt(2) / 0.2, rel=0.02)


def test_period_and_amplitude_variability():
    x = np.sin(2 * np.pi * 0.1 * T)
    assert ms.period_variability(T, x, 0.0) < 1e-3
    assert ms.amplitude_variability(T, x, 0.0) < 1e-2
    # alternate cycles of amplitude 1 and 2: CV of the per-cycle amplitudes = 1/3
    phase = 2 * np.pi * 0.1 * T
    amp = np.where(np.floor(phase / (2 * np.pi)) % 2 == 0, 1.0, 2.0)
    assert ms.amplitude_variability(T, amp * np.sin(phase), 0.0) == pytest.approx(1 / 3, rel=0.05)
    # periods alternating 8 and 12: CV = 2/10
    t = np.arange(0, 2000, 0.01)
    edges = np.cumsum(np.tile([8.0, 12.0], 200))
    k = np.searchsorted(edges, t, side="right")
    start = np.r_[0.0, edges][k]
    length = np.tile([8.0, 12.0], 201)[k]
    y = np.sin(2 * np.pi * (t - start) / length)
    assert ms.period_variability(t, y, 0.0) == pytest.approx(0.2, rel=0.02)


def test_chain_positions():
    x, y = ms.chain_positions(np.zeros(5))
    np.testing.assert_allclose(x, [1, 2, 3, 4, 5])
    np.testing.assert_allclose(y, 0)
    x, y = ms.chain_positions(np.full((2, 3), np.pi / 2))
    np.testing.assert_allclose(y, [[1, 2, 3], [1, 2, 3]], atol=1e-12)


# ----------------------------------------------------------------------------------------------- fits
def test_linear_fit_exact_and_noisy():
    x = np.linspace(0, 1, 20)
    f = fits.linear_fit(x, 2 + 3 * x)
    assert f["intercept"] == pytest.approx(2) and f["slope"] == pytest.approx(3) and f.r2 == pytest.approx(1)
    rng = np.random.default_rng(1)
    hits = 0
    for _ in range(200):
        g = fits.linear_fit(x, 2 + 3 * x + 0.1 * rng.standard_normal(x.size))
        hits += abs(g["slope"] - 3) < g.err("slope")
    assert 0.55 < hits / 200 < 0.8  # one-sigma errors cover ~68%


def test_power_law_and_finite_size_fits():
    n = np.arange(10, 60)
    f = fits.power_law_fit(n, 76.0 * n**-3.0)
    assert f["exponent"] == pytest.approx(-3.0) and f["prefactor"] == pytest.approx(76.0)
    g = fits.finite_size_fit(n, 76.0 - 150.0 / n + 20.0 / n**2)
    assert g["limit"] == pytest.approx(76.0, abs=1e-9)
    assert g["b1"] == pytest.approx(-150.0, abs=1e-6)


def test_onset_fits_recover_a_square_root_onset():
    x = np.linspace(0.21, 0.3, 12)
    y = 1.5 * np.sqrt(x - 0.2)
    f = fits.onset_power_law_fit(x, y)
    assert f["onset"] == pytest.approx(0.2, abs=1e-6)
    assert f["beta"] == pytest.approx(0.5, abs=1e-4)
    assert f["prefactor"] == pytest.approx(1.5, rel=1e-4)
    g = fits.square_root_onset_fit(x, y)
    assert g["onset"] == pytest.approx(0.2, abs=1e-9)
    # a linear onset is told apart
    h = fits.onset_power_law_fit(x, 2.0 * (x - 0.19))
    assert h["beta"] == pytest.approx(1.0, abs=1e-3)
    rng = np.random.default_rng(3)
    noisy = fits.onset_power_law_fit(x, y * (1 + 0.01 * rng.standard_normal(x.size)))
    assert abs(noisy["beta"] - 0.5) < 4 * noisy.err("beta")


@pytest.mark.parametrize("rate", [-0.1, 0.05])
def test_exp_oscillation_fit(rate):
    t = np.arange(0, 20, 0.05)
    x = np.exp(rate * t) * np.cos(0.8 * t + 0.3) + 0.2
    f = fits.exp_oscillation_fit(t, x)
    assert f["rate"] == pytest.approx(rate, abs=1e-6)
    assert f["omega"] == pytest.approx(0.8, abs=1e-6)


def test_richardson_and_crossing():
    assert fits.richardson(1 + 2 * 0.1, 1 + 2 * 0.05) == pytest.approx(1.0)
    assert fits.richardson(1 + 0.1**2, 1 + 0.05**2, order=2) == pytest.approx(1.0)
    assert fits.crossing([0, 1, 2], [-1, 1, 3]) == pytest.approx(0.5)
    assert math.isnan(fits.crossing([0, 1], [1, 2]))


# ------------------------------------------------------------------------------------------ continuum
def test_continuum_passive_rod_and_onset():
    # clamped-free beam without forcing: slowest decay rate (1.8751)^4
    assert continuum_eigenvalues(0.0)[0].real == pytest.approx(-((1.8751040687) ** 4), rel=1e-6)
    S_c, w_c = continuum_critical()
    assert 75.5 < S_c < 76.5
    # the discrete chain tends to it: N^3 sigma_c(N) extrapolated from N = 20..40
    n = np.arange(20, 41)
    sc, _ = stab.critical_sigmas(n)
    lim = fits.finite_size_fit(n, n**3 * sc)["limit"]
    assert lim == pytest.approx(S_c, abs=0.1)

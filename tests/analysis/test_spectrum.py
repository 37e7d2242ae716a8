"""Harmonic amplitudes on signals with known answers (elastoactive.analysis.spectrum)."""

import math

import numpy as np
import pytest

from elastoactive.analysis import observables as ob
from elastoactive.analysis import spectrum as sp

F = 0.2371  # cycles per tau: 1 / (F * dt) = 84.35... samples a period, never a whole number of periods
DT = 0.05
AMPS = np.array([1.3, 0.4, 0.1, 0.03, 0.007])
PHASES = np.array([0.3, -1.2, 2.5, 0.1, -2.9])


def series(t, amps=AMPS, phases=PHASES, f=F, offset=0.7):
    return offset + sum(a * np.cos(2 * np.pi * (k + 1) * f * t + p) for k, (a, p) in enumerate(zip(amps, phases)))


def test_known_harmonics_recovered_with_a_non_integer_number_of_periods():
    t = np.arange(0.0, 403.7, DT)
    x = series(t)
    steady = t[t >= 0.5 * t[-1]]
    assert abs(F * (steady[-1] - steady[0]) % 1.0 - 0.5) < 0.45  # the steady part is not a whole number of periods
    fit = sp.harmonic_fit(t, x)
    np.testing.assert_allclose(fit.relative, AMPS / AMPS[0], rtol=1e-6)
    np.testing.assert_allclose(sp.harmonics(t, x), AMPS / AMPS[0], rtol=1e-6)
    np.testing.assert_allclose(fit.amplitudes, AMPS, rtol=1e-6)
    np.testing.assert_allclose(np.angle(np.exp(1j * (fit.phases - PHASES))), 0.0, atol=1e-4)
    assert fit.frequency == pytest.approx(F, rel=1e-7)
    assert fit.offset == pytest.approx(0.7, abs=1e-7)
    assert fit.explained > 1 - 1e-9
    assert fit.periods == pytest.approx(round(fit.periods), abs=1e-3)


def test_recovered_with_mild_noise_a_transient_and_a_large_offset():
    rng = np.random.default_rng(7)
    t = np.arange(0.0, 600.0, DT)
    x = series(t, offset=-40.0) + 1e-3 * rng.standard_normal(t.size)
    x[t < 100] += 3.0 * np.exp(-t[t < 100] / 10.0)  # a decaying transient, discarded
    rel = sp.harmonics(t, x, transient=100.0)
    assert np.max(np.abs(rel - AMPS / AMPS[0])) < 1e-3 * 0.2  # relative to the fundamental: < 2e-4
    # each harmonic to < 1e-3 of its own size where it stands well above the noise
    np.testing.assert_allclose(rel[:3], AMPS[:3] / AMPS[0], rtol=1e-3)


def test_irregular_sampling_and_a_mid_chain_column():
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.03, 0.07, 8000))
    theta = np.column_stack([0.1 * t, series(t), np.zeros_like(t)])  # the caller passes the column
    rel = sp.harmonics(t, theta[:, 1], count=4)
    np.testing.assert_allclose(rel, AMPS[:4] / AMPS[0], rtol=1e-5)


def test_square_wave_odd_harmonics_fall_as_one_over_k():
    t = np.arange(0.0, 400.0, 0.002)
    x = np.sign(np.sin(2 * np.pi * F * t + 0.2))
    rel = sp.harmonics(t, x, count=9)
    k = np.arange(1, 10)
    odd = k % 2 == 1
    np.testing.assert_allclose(rel[odd], 1.0 / k[odd], rtol=3e-4)
    assert np.all(rel[~odd] < 1e-4)  # even harmonics vanish (up to the sampling of the jumps)


def test_truncated_square_wave_exactly():
    t = np.arange(0.0, 300.0, DT)
    k = np.arange(1, 10)
    amps = np.where(k % 2 == 1, 4 / (np.pi * k), 0.0)
    x = series(t, amps=amps, phases=np.zeros(9), offset=0.0)
    rel = sp.harmonics(t, x, count=9)
    np.testing.assert_allclose(rel, np.where(k % 2 == 1, 1.0 / k, 0.0), atol=1e-9)


def test_no_fundamental_gives_nan():
    t = np.arange(0.0, 200.0, DT)
    for x in (np.full(t.size, 2.5), 2.5 + 1e-12 * np.sin(2 * np.pi * F * t), 0.01 * t):
        assert np.all(np.isnan(sp.harmonics(t, x)))
    fit = sp.harmonic_fit(t, np.full(t.size, 2.5), count=3)
    assert fit.amplitudes.shape == (3,) and math.isnan(fit.frequency) and np.all(np.isnan(fit.phases))
    # an oscillation of half peak-to-peak 5e-4 is below the default threshold (1e-3), above a smaller one
    small = 5e-4 * np.sin(2 * np.pi * F * t)
    assert np.all(np.isnan(sp.harmonics(t, small)))
    np.testing.assert_allclose(sp.harmonics(t, small, threshold=1e-4)[:2], [1.0, 0.0], atol=1e-9)


def test_fewer_than_two_periods_gives_nan():
    t = np.arange(0.0, 3.5 / F, DT)  # 3.5 periods in the record, 1.75 in the steady half
    x = np.sin(2 * np.pi * F * t)
    assert np.all(np.isnan(sp.harmonics(t, x)))
    assert np.all(np.isfinite(sp.harmonics(t, x, transient=0.0)))


def test_noise_is_not_a_beat():
    rng = np.random.default_rng(11)
    t = np.arange(0.0, 400.0, DT)
    x = rng.standard_normal(t.size)
    assert ob.frequency(t, x) > 0  # it crosses its mean: the crossings alone would call it a beat
    assert np.all(np.isnan(sp.harmonics(t, x)))


def test_two_incommensurate_frequencies_are_not_one_beat():
    t = np.arange(0.0, 400.0, DT)
    x = np.sin(2 * np.pi * F * t) + 0.8 * np.sin(2 * np.pi * F * math.sqrt(2) * t)
    fit = sp.harmonic_fit(t, x)
    assert math.isnan(fit.frequency) and np.all(np.isnan(fit.amplitudes))
    assert sp.harmonic_fit(t, x, min_explained=0.0).explained < 0.9  # the best single-beat fit explains too little


def test_harmonics_above_nyquist_are_nan():
    dt = 1.0 / (F * 7.3)  # 7.3 samples a period: harmonics 1 .. 3 below the Nyquist frequency
    t = np.arange(0.0, 400.0, dt)
    x = series(t, amps=AMPS[:3], phases=PHASES[:3])
    rel = sp.harmonics(t, x, count=5)
    np.testing.assert_allclose(rel[:3], AMPS[:3] / AMPS[0], rtol=1e-6)
    assert np.all(np.isnan(rel[3:]))


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda t, x: sp.harmonics(t[:, None], x), "t"),
        (lambda t, x: sp.harmonics(t[::-1], x), "t"),
        (lambda t, x: sp.harmonics(t, x[:-1]), "x"),
        (lambda t, x: sp.harmonics(t, np.column_stack([x, x])), "x"),
        (lambda t, x: sp.harmonics(t, np.where(t > 50, np.nan, x)), "x"),
        (lambda t, x: sp.harmonics(t, x, count=0), "count"),
        (lambda t, x: sp.harmonics(t, x, count=2.0), "count"),
        (lambda t, x: sp.harmonics(t, x, transient=-1.0), "transient"),
        (lambda t, x: sp.harmonics(t, x, transient=1e6), "transient"),
        (lambda t, x: sp.harmonics(t, x, threshold=-1.0), "threshold"),
        (lambda t, x: sp.harmonics(t, x, min_explained=1.5), "min_explained"),
        (lambda t, x: sp.harmonic_fit(t, x, hysteresis=-0.1), "hysteresis"),
    ],
)
def test_invalid_inputs_name_the_argument(call, name):
    t = np.arange(0.0, 100.0, DT)
    x = np.sin(2 * np.pi * F * t)
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        call(t, x)

"""Observables on signals with known answers (elastoactive.analysis.observables)."""

import math

import numpy as np
import pytest
from scipy.signal import sawtooth

from elastoactive.analysis import observables as ob


def sinusoid(f=0.37, periods=20, per_period=20, amp=1.0, offset=0.0, phase=0.3, stretch=1.013):
    """A*sin(2 pi f t + phase) + offset, ~per_period samples per period (stretch: not an exact
    divisor, so the window never holds a whole number of periods)."""
    dt = stretch / (per_period * f)
    t = np.arange(int(periods * per_period) + 1) * dt
    return t, amp * np.sin(2 * np.pi * f * t + phase) + offset


# ----------------------------------------------------------------------------- chain shape


def test_curvature_polarisation_limit_cycle_by_hand():
    theta = np.array([[0.0, 0.1, 0.3], [0.2, -0.1, -0.4], [1.0, 1.0, 1.0]])
    np.testing.assert_allclose(ob.curvature(theta), [0.3, -0.6, 0.0])
    np.testing.assert_allclose(ob.polarisation(theta), [0.4 / 3, -0.1, 1.0])
    omega, big_theta = ob.limit_cycle(theta)
    np.testing.assert_allclose(omega, [0.4 / 3, -0.1, 1.0])
    np.testing.assert_allclose(big_theta, [0.3, -0.6, 0.0])


# ----------------------------------------------------------------------------- transients


def test_steady_part_default_is_last_half_and_transient_in_tau():
    t = np.arange(11.0)  # 0..10 tau
    x = 2 * t
    ts, xs = ob.steady_part(t, x)
    np.testing.assert_array_equal(ts, np.arange(5.0, 11.0))
    np.testing.assert_array_equal(xs, 2 * ts)
    ts, _ = ob.steady_part(t, x, transient=8.0)
    np.testing.assert_array_equal(ts, [8.0, 9.0, 10.0])
    ts, xs2 = ob.steady_part(t, np.c_[x, -x], fraction=0.8)
    np.testing.assert_array_equal(ts, [8.0, 9.0, 10.0])
    assert xs2.shape == (3, 2)


def test_transient_excludes_a_different_early_regime():
    # a big slow transient for t < 50, then a clean oscillation at f = 0.5
    t = np.arange(0, 100, 0.05)
    x = np.where(t < 50, 10 * np.sin(2 * np.pi * 0.05 * t), 0.2 * np.sin(2 * np.pi * 0.5 * t))
    assert ob.frequency(t, x, transient=50.0) == pytest.approx(0.5, rel=1e-4)
    assert ob.amplitude(t, x, transient=50.0) == pytest.approx(0.2, rel=1e-3)
    assert ob.amplitude(t, x, transient=0.0) == pytest.approx(10.0, rel=1e-3)


# ----------------------------------------------------------------------------- amplitude


def test_amplitude_of_offset_sinusoid():
    # 40 samples per period: the peaks are sampled exactly
    f, amp = 0.25, 0.7
    t = np.arange(0, 80, 0.1)
    x = amp * np.sin(2 * np.pi * f * t) + 3.0
    assert ob.amplitude(t, x) == pytest.approx(amp, rel=1e-9)
    # coarse, unaligned sampling reads low by at most 1 - cos(pi/20)
    t, x = sinusoid(amp=amp, offset=-2.0)
    a = ob.amplitude(t, x)
    assert amp * math.cos(math.pi / 20) - 1e-12 <= a <= amp + 1e-12


# ----------------------------------------------------------------------------- frequency


@pytest.mark.parametrize("phase", [0.0, 0.3, 1.7, 4.0])
@pytest.mark.parametrize("stretch", [1.0, 1.013, 1.04])
def test_sinusoid_frequency_zero_crossings_and_hilbert(phase, stretch):
    f = 0.37
    t, x = sinusoid(f=f, phase=phase, stretch=stretch, amp=0.8, offset=0.4)
    assert ob.frequency(t, x) == pytest.approx(f, rel=1e-4)
    assert ob.phase_frequency(t, x) == pytest.approx(f, rel=1e-4)


def test_frequency_does_not_depend_on_units_of_time():
    # f*tau scales as 1/time: the same samples on a time axis twice as long give half
    t, x = sinusoid(f=1.0)
    assert ob.frequency(2 * t, x) == pytest.approx(0.5, rel=1e-4)


@pytest.mark.parametrize("width", [0.8, 0.95])
def test_non_sinusoidal_frequency(width):
    # asymmetric sawtooth (slow rise, fast fall) with a nonzero mean
    f = 0.21
    t = np.arange(0, 30 / f, 1 / (25 * f) * 1.007)
    x = 1.5 * sawtooth(2 * np.pi * f * t + 0.4, width=width) + 0.8
    assert ob.frequency(t, x) == pytest.approx(f, rel=1e-4)
    assert ob.phase_frequency(t, x) == pytest.approx(f, rel=2e-3)


def test_harmonic_rich_frequency_and_hysteresis():
    f = 0.6
    t = np.arange(0, 40 / f, 1 / (30 * f))
    w = 2 * np.pi * f * t
    x = np.sin(w) + 0.35 * np.sin(2 * w + 1.0) + 0.2 * np.cos(3 * w) + 0.3
    assert ob.frequency(t, x) == pytest.approx(f, rel=1e-4)
    assert ob.phase_frequency(t, x) == pytest.approx(f, rel=1e-3)
    # small fast noise on top: hysteresis keeps the count at one crossing per period
    rng = np.random.default_rng(0)
    t = np.arange(0, 40 / f, 1 / (200 * f))
    w = 2 * np.pi * f * t
    x = np.sin(w) + 0.35 * np.sin(2 * w + 1.0) + 0.2 * np.cos(3 * w) + 0.3
    noisy = x + 0.02 * rng.standard_normal(t.size)
    assert ob.frequency(t, noisy) == pytest.approx(f, rel=2e-3)
    assert ob.frequency(t, noisy, hysteresis=0.0) > 1.1 * f  # without it, extra crossings


def test_no_oscillation_gives_zero_frequency():
    t = np.linspace(0, 50, 1001)
    assert ob.frequency(t, np.full_like(t, 0.3)) == 0.0
    assert ob.frequency(t, 1.0 - np.exp(-t)) == 0.0  # monotone relaxation
    assert not ob.is_oscillating(t, np.full_like(t, 0.3))
    assert not ob.is_oscillating(t, 1e-5 * np.sin(2 * np.pi * t))  # below threshold
    assert ob.is_oscillating(t, 0.1 * np.sin(2 * np.pi * t))
    decaying = np.exp(-t / 10) * np.sin(2 * np.pi * t)
    assert ob.is_oscillating(t, decaying)
    assert not ob.is_oscillating(t, decaying, max_decay=0.2)


def test_hilbert_phase_alignment_and_slope():
    t, x = sinusoid(f=0.5, stretch=1.0)
    ts, _ = ob.steady_part(t, x)
    phi = ob.hilbert_phase(t, x)
    assert phi.shape == ts.shape
    # sin(w t + p) has analytic phase w t + p - pi/2 (mod 2 pi), away from the edges
    mid = slice(ts.size // 4, 3 * ts.size // 4)
    err = np.angle(np.exp(1j * (phi[mid] - (2 * np.pi * 0.5 * ts[mid] + 0.3 - np.pi / 2))))
    assert np.max(np.abs(err)) < 0.05
    tw, phw = ob.hilbert_phase(t, x, whole_periods=True, return_time=True)
    assert tw.shape == phw.shape and tw.size < ts.size
    assert np.all(np.diff(phw) > 0)


# ----------------------------------------------------------------------------- pairs


@pytest.mark.parametrize("f2", [1.05, 0.8])
def test_frequency_mismatch_of_two_sinusoids(f2):
    f1 = 1.0
    t = np.arange(0, 20, 1 / 20) * 1.013
    x1 = np.sin(2 * np.pi * f1 * t) + 0.2
    x2 = 0.6 * np.sin(2 * np.pi * f2 * t + 2.0) - 0.1
    assert ob.frequency_mismatch(t, x1, x2) == pytest.approx(f2 - f1, abs=1e-4)
    assert ob.frequency_mismatch(t, x2, x1) == pytest.approx(f1 - f2, abs=1e-4)
    assert ob.frequency_mismatch(t, x2, x1, absolute=True) == pytest.approx(abs(f2 - f1), abs=1e-4)


@pytest.mark.parametrize("lag", [0.0, 0.7, 2.5])
def test_frequency_mismatch_zero_when_locked_with_phase_lag(lag):
    t = np.arange(0, 20, 1 / 20) * 1.04
    x1 = np.sin(2 * np.pi * t)
    x2 = 0.5 * np.sin(2 * np.pi * t - lag) + 1.0
    assert abs(ob.frequency_mismatch(t, x1, x2)) < 1e-4


# ----------------------------------------------------------------------------- scenes


def test_snap_amplitude_of_sinusoid_is_amp_over_sqrt2():
    amp, f = 0.4, 0.5
    t = np.arange(0, 40, 0.05)  # last half: exactly 10 periods
    theta = np.zeros((t.size, 5))
    theta[:, 2] = amp * np.sin(2 * np.pi * f * t) + 0.1  # particle 3 (1-based)
    theta[:, 0] = 5 * np.sin(2 * np.pi * f * t)  # other columns must not matter
    expected = amp / math.sqrt(2)
    assert ob.snap_amplitude(theta) == pytest.approx(expected, rel=1e-9)
    assert ob.snap_amplitude(theta, t=t) == pytest.approx(expected, rel=1e-9)
    assert ob.snap_amplitude(theta, t=t, transient=10.0) == pytest.approx(expected, rel=1e-9)
    assert ob.snap_amplitude(theta, particle=1) == pytest.approx(5 / math.sqrt(2), rel=1e-9)
    assert ob.snap_amplitude(theta, particle=2) == 0.0


def test_rotation_rate_of_linear_ramp():
    t = np.linspace(0, 100, 2001)
    theta = np.c_[-0.37 * t + 1.0 + 0.01 * np.sin(2 * np.pi * t), 2 * t, np.zeros_like(t)]
    assert ob.rotation_rate(t, theta) == pytest.approx(-0.37, rel=1e-4)
    assert ob.rotation_rate(t, theta[:, 0]) == pytest.approx(-0.37, rel=1e-4)
    wrapped = np.angle(np.exp(1j * theta[:, 0]))
    assert ob.rotation_rate(t, wrapped, unwrap=True) == pytest.approx(-0.37, rel=1e-4)


# ----------------------------------------------------------------------------- bad input


def test_bad_input_raises():
    t = np.linspace(0, 10, 101)
    x = np.sin(t)
    theta = np.zeros((101, 4))
    with pytest.raises(ValueError, match="2-D"):
        ob.curvature(np.zeros(5))
    with pytest.raises(ValueError, match="non-finite"):
        ob.polarisation(np.array([[0.0, np.nan]]))
    with pytest.raises(ValueError, match="lengths must match"):
        ob.frequency(t, x[:-1])
    with pytest.raises(ValueError, match="strictly increasing"):
        ob.amplitude(t[::-1], x)
    with pytest.raises(ValueError, match="non-finite"):
        ob.amplitude(t, np.where(t > 5, np.inf, x))
    with pytest.raises(ValueError, match="1-D"):
        ob.frequency(t, theta)
    with pytest.raises(ValueError, match="shorter than the record"):
        ob.amplitude(t, x, transient=20.0)
    with pytest.raises(ValueError, match="transient"):
        ob.amplitude(t, x, transient=-1.0)
    with pytest.raises(ValueError, match="particle"):
        ob.snap_amplitude(theta, particle=5)
    with pytest.raises(ValueError, match="particle"):
        ob.snap_amplitude(theta, particle=0)
    with pytest.raises(ValueError, match="pass t"):
        ob.snap_amplitude(theta, transient=1.0)
    with pytest.raises(ValueError, match="uniformly"):
        ob.phase_frequency(np.r_[t[:60], t[60:] + np.linspace(0, 0.5, 41)], x)
    with pytest.raises(ValueError, match="trim"):
        ob.phase_frequency(t, x, trim=0.6)
    with pytest.raises(ValueError, match="x2"):
        ob.frequency_mismatch(t, x, x[:50])


def test_whole_period_mean_is_unbiased_by_a_ragged_window():
    """A sine of amplitude 1 about 0.01 over 3.4 periods: the plain mean is off by the 0.4 period's swing (~0.05),
    the whole-period mean by the sampling alone."""
    t = np.linspace(0.0, 3.4, 3401)
    x = 0.01 + np.sin(2 * np.pi * t)
    assert abs(np.mean(x) - 0.01) > 0.02
    assert ob.whole_period_mean(t, x, transient=0.0) == pytest.approx(0.01, abs=2e-3)
    assert ob.whole_period_mean(t[:50], x[:50], transient=0.0) == pytest.approx(np.mean(x[:50]))

"""What cilia do together (elastoactive.analysis.cilia): phases, locking, waves, and Blake's flux against the flow the
wall's mobility itself carries through a half-plane."""

import math

import numpy as np
import pytest

from elastoactive.analysis import cilia
from elastoactive.hydro.blake import rpb_kernel

T = np.arange(0.0, 400.0, 0.05)
OMEGA = 2 * math.pi * 0.05


def beats(lags):
    """Signals (M, T) of beats at one frequency, each behind the first by its lag."""
    return np.array([np.sin(OMEGA * T - lag) for lag in lags])


@pytest.mark.parametrize(
    ("lag", "state"),
    [(0.05, "in-phase"), (math.pi - 0.1, "anti-phase"), (-math.pi + 0.1, "anti-phase"), (1.2, "lag"), (-0.9, "lag")],
)
def test_a_pair_s_lag_and_state(lag, state):
    x1, x2 = beats([0.0, lag])
    locking = cilia.pair_locking(T, x1, x2, transient=100.0)
    assert locking.state == state
    assert math.isclose(math.remainder(locking.lag + lag, 2 * math.pi), 0.0, abs_tol=0.01)  # Phi_2 - Phi_1 = -lag


def test_a_pair_at_two_frequencies_is_not_locked():
    x1 = np.sin(OMEGA * T)
    x2 = np.sin(1.1 * OMEGA * T)
    assert cilia.pair_locking(T, x1, x2, transient=100.0).state == "none"


def test_a_pair_at_rest_is_not_locked_and_has_no_lag():
    locking = cilia.pair_locking(T, np.zeros_like(T), np.zeros_like(T), transient=100.0)
    assert locking.state == "none"


@pytest.mark.parametrize(("step", "direction"), [(0.5, "+x"), (-0.5, "-x"), (0.0, "synchronous")])
def test_a_row_s_wave_number_and_direction(step, direction):
    """Phi_m = omega t - k x_m at x_m = m d: each cilium behind the last by k d, a wave toward +x for k > 0."""
    d = 2.0
    wave = cilia.metachronal_wave(T, beats([m * step for m in range(5)]), d, transient=100.0)
    assert wave.direction == direction
    assert math.isclose(wave.wave_number, step / d, abs_tol=0.005)


def test_tip_signals_project_every_tip_on_the_first_s_axis():
    """Two tips beating along the same diagonal of the wall's plane, the second twice as far: one axis for both."""
    s = np.sin(OMEGA * T)
    positions = np.zeros((T.size, 2, 3, 3))
    direction = np.array([1.0, 1.0, 0.0]) / math.sqrt(2)
    positions[:, 0, -1] = s[:, None] * direction
    positions[:, 1, -1] = 2 * s[:, None] * direction + [5.0, 0.0, 2.0]
    signals = cilia.tip_signals(positions)
    np.testing.assert_allclose(np.abs(signals[1]), 2 * np.abs(signals[0]), atol=1e-12)
    np.testing.assert_allclose(np.abs(signals[0]), np.abs(s - s.mean()), atol=1e-12)


def flux_through_half_plane(x_plane, height, radius):
    """The flux through the half-plane x = x_plane (all y, z > 0) of the Rotne-Prager-Blake flow of a unit force
    along x on a bead at (0, 0, height): probe beads' velocities on a polar Gauss grid about the foot."""
    s, ws = np.polynomial.legendre.leggauss(64)
    s, ws = (s + 1) * np.pi / 4, ws * np.pi / 4
    phi, wp = np.polynomial.legendre.leggauss(24)
    phi, wp = (phi + 1) * np.pi / 2, wp * np.pi / 2
    rho, drho = x_plane * np.tan(s), x_plane / np.cos(s) ** 2
    r, p = np.meshgrid(rho, phi, indexing="ij")
    weights = ((ws * drho * rho)[:, None] * wp[None, :]).ravel()
    probes = np.stack([np.full(r.size, x_plane), (r * np.cos(p)).ravel(), (r * np.sin(p)).ravel()], axis=1)
    x = np.vstack([[0.0, 0.0, height], probes])
    m = np.empty((3 * len(x), 3 * len(x)))
    rpb_kernel(x, radius, m)
    return float(m[3::3, 0] @ weights)


@pytest.mark.parametrize(("x_plane", "height"), [(2.0, 1.0), (5.0, 1.0), (10.0, 3.0)])
def test_blake_s_flux_is_what_the_wall_s_mobility_carries(x_plane, height):
    """Q = F h / (pi mu) = 6 a F h through any half-plane across the force, to the probes' finite size (a^2 / X^2)."""
    radius = 0.1
    expected = cilia.blake_flux(np.array([[1.0]]), np.array([[height]]), radius)[0]
    assert expected == pytest.approx(6 * radius * height)
    assert flux_through_half_plane(x_plane, height, radius) == pytest.approx(expected, rel=1e-3)


def test_blake_s_flux_sums_over_the_beads_and_keeps_time():
    f = np.array([[[1.0, -2.0]], [[0.5, 0.5]]])  # (T, C, N)
    h = np.array([[[1.0, 2.0]], [[3.0, 1.0]]])
    np.testing.assert_allclose(cilia.blake_flux(f, h, 0.2), 1.2 * np.array([1 - 4, 1.5 + 0.5]))

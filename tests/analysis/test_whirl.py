"""The whirl as a relative equilibrium (elastoactive.analysis.whirl): Newton's whirl is the simulation's, its symmetries
hold, and a ladder at one load approaches its continuum limit."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis.motion3d import measure3d
from elastoactive.analysis.whirl import (
    NoWhirl,
    beat_out_of_plane,
    find_whirl,
    ladder,
    resample_tangents,
    turn_about_axis,
)
from elastoactive.core.errors import ParameterError
from elastoactive.reduced.chain3d import Chain3D, solve3d


@pytest.fixture(scope="module")
def settled():
    """N = 3, sigma = 2.5 (onset 1.163) run from a helix into its whirl: (chain, last shape, measured rate)."""
    chain = Chain3D(n=3, sigma=2.5)
    ts = np.arange(0.0, 60.0 + 1e-9, 0.01)
    s = np.arange(1, 4) / 3
    t0 = np.column_stack([np.ones(3), 0.3 * s, 0.3 * s * s])
    path = solve3d(chain, ts, t0 / np.linalg.norm(t0, axis=1)[:, None], rtol=1e-10, atol=1e-10)
    return chain, path[-1], measure3d(ts, path, transient=40.0).whirl_rate


def test_newton_whirl_is_the_simulated_one(settled):
    chain, shape, rate = settled
    whirl = find_whirl(chain, shape, 2 * np.pi * rate)
    assert whirl.residual < 1e-12
    assert whirl.rate == pytest.approx(rate, rel=1e-4)
    assert whirl.growth < 0  # the simulation settled into it: stable
    np.testing.assert_allclose(whirl.tangents, shape, atol=1e-3)


def test_whirl_symmetries(settled):
    """A whirl turned about the clamp axis whirls at the same rate; its mirror image (z -> -z) the other way."""
    chain, shape, rate = settled
    whirl = find_whirl(chain, shape, 2 * np.pi * rate)
    c, s = np.cos(1.1), np.sin(1.1)
    turned = whirl.tangents @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]]).T
    assert find_whirl(chain, turned, whirl.omega).omega == pytest.approx(whirl.omega, rel=1e-10)
    mirrored = whirl.tangents * [1.0, 1.0, -1.0]
    assert find_whirl(chain, mirrored, -whirl.omega).omega == pytest.approx(-whirl.omega, rel=1e-10)


def test_whirl_found_from_any_azimuth(settled):
    """Started 1.3 rad round the axis from the settled shape, and with the tip on the z axis (where holding the tip's z
    gives no phase condition), pushed off the whirl and with a rate 10% off: Newton finds the same whirl, at the
    guess's azimuth."""
    chain, shape, rate = settled
    tip = shape.sum(axis=0)
    push = 0.05 * np.array([[0.0, 0.3, -0.2], [0.0, -0.1, 0.4], [0.0, 0.2, 0.1]])
    for angle in (1.3, np.pi / 2 - np.arctan2(tip[2], tip[1])):
        guess = shape @ turn_about_axis(angle).T + push
        whirl = find_whirl(chain, guess, 1.1 * 2 * np.pi * rate)
        assert whirl.residual < 1e-12
        assert whirl.rate == pytest.approx(rate, rel=1e-4)
        found, wanted = whirl.tangents.sum(axis=0), (guess / np.linalg.norm(guess, axis=1)[:, None]).sum(axis=0)
        assert abs(np.angle(complex(found[1], found[2]) / complex(wanted[1], wanted[2]))) < 1e-9


def test_ladder_approaches_a_limit(settled):
    """At S = 67.5 (N = 3's sigma = 2.5) the rungs N = 3..6 change N^4 Omega less and less, and the extrapolation's
    error estimate is a small part of the value."""
    chain, shape, rate = settled
    result = ladder(27 * 2.5, [3, 4, 5, 6], shape, 2 * np.pi * rate)
    steps = np.abs(np.diff(result.omega.values))
    assert np.all(steps[1:] < steps[:-1])
    assert result.omega.error < 0.05 * abs(result.omega.value)
    assert all(state.residual < 1e-10 for state in result.states)


def test_resample_keeps_a_straight_chain_and_bad_guesses_are_refused():
    straight = np.tile([1.0, 0.0, 0.0], (5, 1))
    np.testing.assert_array_equal(resample_tangents(straight, 9), np.tile([1.0, 0.0, 0.0], (9, 1)))
    with pytest.raises(ParameterError, match="converged to the straight chain"):
        find_whirl(Chain3D(n=3, sigma=0.5), np.tile([1.0, 0.0, 0.0], (3, 1)), 0.0)  # below onset: the straight chain
    with pytest.raises(ParameterError, match="guess"):
        find_whirl(Chain3D(n=3, sigma=0.5), straight, 0.0)


def test_planar_beat_is_unstable_out_of_its_plane():
    """N = 3, sigma = 2.5: the planar beat has the neutral multiplier 1 (its plane turned about the axis) and one far
    outside the unit circle (it grows out of its plane into the whirl, which the simulation above settles in)."""
    result = beat_out_of_plane(Chain3D(n=3, sigma=2.5), settle=60.0, periods=4)
    assert abs(result.period * 0.0862 - 1.0) < 0.01  # the planar beat's f tau = 0.0862
    assert np.min(np.abs(result.multipliers - 1.0)) < 1e-6
    assert abs(result.multipliers[0]) > 1e6 and result.growth > 1.0


def test_landing_on_the_straight_chain_is_said():
    """From a guess near the straight chain at zero rate, Newton converges to it: NoWhirl says so (straight)."""
    guess = np.array([[1.0, 0.0, 0.0], [1.0, 1e-3, 0.0], [1.0, 2e-3, 1e-3]])
    with pytest.raises(NoWhirl, match="^Newton's method converged to the straight chain") as missed:
        find_whirl(Chain3D(n=3, sigma=2.5), guess, 0.0)
    assert missed.value.straight and isinstance(missed.value, ParameterError)
    assert "simulation" not in str(missed.value)

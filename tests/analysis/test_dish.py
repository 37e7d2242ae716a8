"""Observables and states of a free chain in a dish, on synthetic trajectories (elastoactive.analysis.dish)."""

import math

import numpy as np
import pytest

from elastoactive.analysis import dish
from elastoactive.analysis import observables as ob

N = 7
T = np.arange(0.0, 400.0, 0.05)
SHAPE = 0.3 + 0.25 * np.arange(N)  # a bent chain: absolute angles in its own frame, bends of 0.25 rad


def body_com(theta):
    """Centre of mass relative to the head, (T, 2): the mean over head (0) and particles."""
    steps = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    return np.cumsum(steps, axis=1).sum(axis=1) / (theta.shape[1] + 1)


def trajectory(body_rate, orbit_rate, radius, t=T, shape=SHAPE, phase=0.4):
    """The chain turns at body_rate while its centre of mass goes round the origin at orbit_rate on a
    circle of the given radius."""
    theta = shape[None, :] + body_rate * t[:, None]
    com = radius * np.stack([np.cos(orbit_rate * t + phase), np.sin(orbit_rate * t + phase)], axis=-1)
    return theta, com - body_com(theta)


def rigid(rate, t=T, shape=SHAPE, head0=(1.2, -0.5)):
    """A rigid chain turning about the origin: every point, the head included, rotates at rate."""
    theta = shape[None, :] + rate * t[:, None]
    c, s = np.cos(rate * t), np.sin(rate * t)
    head = np.stack([c * head0[0] - s * head0[1], s * head0[0] + c * head0[1]], axis=-1)
    return theta, head


# ----------------------------------------------------------------------------- geometry


def assert_dish(theta, head, *, rotation, orbit, radius, state, tol=1e-6):
    """The body rotation rate, orbit rate and radius, and the state of a synthetic trajectory."""
    assert ob.rotation_rate(T, theta) == pytest.approx(rotation, abs=tol)
    assert dish.orbit_rate(T, theta, head) == pytest.approx(orbit, abs=tol)
    assert dish.orbit_radius(T, theta, head) == pytest.approx(radius, abs=tol)
    assert dish.dish_state(T, theta, head) == state


def test_positions_and_centre_of_mass_by_hand():
    theta = np.array([[0.0, math.pi / 2], [math.pi, math.pi]])
    head = np.array([[1.0, 2.0], [0.0, 0.0]])
    p = dish.positions(theta, head)
    np.testing.assert_allclose(p[0], [[1, 2], [2, 2], [2, 3]], atol=1e-15)
    np.testing.assert_allclose(p[1], [[0, 0], [-1, 0], [-2, 0]], atol=1e-15)
    np.testing.assert_allclose(dish.centre_of_mass(theta, head), [[5 / 3, 7 / 3], [-1, 0]], atol=1e-15)


def test_mean_curvature_signed_and_absolute():
    theta = np.tile([0.0, 0.2, 0.1, 0.4], (10, 1))  # bends 0.2, -0.1, 0.3
    assert dish.mean_curvature(theta) == pytest.approx(0.4 / 3)
    assert dish.mean_curvature(theta, absolute=True) == pytest.approx(0.6 / 3)
    assert dish.mean_curvature(theta) == pytest.approx(ob.curvature(theta)[0] / 3)
    t = np.arange(10.0)
    moving = theta * np.where(t < 5, 2.0, 1.0)[:, None]  # twice as bent before t = 5
    assert dish.mean_curvature(moving, t, transient=5.0) == pytest.approx(0.4 / 3)
    assert dish.mean_curvature(moving, t, transient=0.0) == pytest.approx(0.4 / 3 * 1.5)
    assert dish.mean_curvature(-theta, absolute=True) == pytest.approx(0.2)
    assert dish.mean_curvature(-theta) == pytest.approx(-0.4 / 3)


# ----------------------------------------------------------------------------- states and rates


def test_rigid_orbit():
    theta, head = rigid(0.08)
    r = np.hypot(*dish.centre_of_mass(theta, head)[0])
    assert r > dish.SPIN_RADIUS * N  # away from the centre
    assert_dish(theta, head, rotation=0.08, orbit=0.08, radius=r, state="orbit")
    assert dish.mean_curvature(theta, T) == pytest.approx(0.25, abs=1e-12)
    theta, head = rigid(-0.08)  # clockwise
    assert dish.orbit_rate(T, theta, head) == pytest.approx(-0.08, abs=1e-6)
    assert dish.dish_state(T, theta, head) == "orbit"


def test_spin_about_its_own_centre_of_mass_at_the_centre():
    theta, head = trajectory(0.155, 0.0, 0.0)
    np.testing.assert_allclose(dish.centre_of_mass(theta, head), 0.0, atol=1e-14)
    assert ob.rotation_rate(T, theta) == pytest.approx(0.155, abs=1e-6)
    assert math.isnan(dish.orbit_rate(T, theta, head))  # the polar angle of the origin is undefined
    assert np.all(np.isnan(dish.orbit_angle(T, theta, head)))
    assert dish.orbit_radius(T, theta, head) < 1e-12
    assert dish.dish_state(T, theta, head) == "spin"


def test_spin_about_a_point_near_the_centre_of_mass():
    theta, head = trajectory(0.155, 0.155, 0.27)  # the trap 0.3: curled, spinning about radius 0.27
    assert_dish(theta, head, rotation=0.155, orbit=0.155, radius=0.27, state="spin")


def test_rest():
    theta, head = trajectory(0.0, 0.0, 2.0)
    assert_dish(theta, head, rotation=0.0, orbit=0.0, radius=2.0, state="rest", tol=1e-9)
    # a straight chain pointing outward, at rest with mild jitter
    rng = np.random.default_rng(0)
    theta = np.zeros((T.size, N)) + 1e-4 * rng.standard_normal((T.size, N))
    head = np.tile([0.5, 0.0], (T.size, 1)) + 1e-4 * rng.standard_normal((T.size, 2))
    assert dish.dish_state(T, theta, head) == "rest"


def test_a_chain_still_gliding_to_rest_is_at_rest_one_drifting_steadily_is_not():
    """A straight chain pointing outward relaxes to its resting place in a trap 0.01 (time 1/k = 100 tau)."""
    theta = np.zeros((T.size, N))
    x = 26.0 - 20.0 * np.exp(-0.003 * T)  # trap 0.003: slows down by exp(-0.003 * 150) = 0.64 across the steady part
    head = np.stack([x, np.zeros_like(x)], axis=-1)
    _, x_steady = ob.steady_part(T, x)
    assert np.std(x_steady) > 10 * dish.REST_MOTION  # it still moves, but slows down
    assert dish.dish_state(T, theta, head) == "rest"
    head = np.stack([0.01 * T + 5.0, np.zeros_like(x)], axis=-1)  # sliding at a steady speed
    assert dish.dish_state(T, theta, head) == "irregular"


def test_centre_of_mass_with_or_without_the_head():
    theta, head = rigid(0.08)
    p = dish.positions(theta, head)
    np.testing.assert_allclose(dish.centre_of_mass(theta, head, include_head=False), p[:, 1:].mean(axis=1))
    r = np.hypot(*p[0, 1:].mean(axis=0))
    assert dish.orbit_radius(T, theta, head, include_head=False) == pytest.approx(r, abs=1e-9)
    assert r != pytest.approx(dish.orbit_radius(T, theta, head), abs=1e-3)
    assert dish.orbit_rate(T, theta, head, include_head=False) == pytest.approx(0.08, abs=1e-6)
    assert dish.orbit_angle(T, theta, head, include_head=False)[0] == pytest.approx(
        math.atan2(*p[T >= T[-1] / 2][0, 1:].mean(axis=0)[::-1]), abs=1e-12
    )


def test_crawl_body_and_orbit_at_different_rates():
    theta, head = trajectory(0.12, 0.05, 1.5)
    assert_dish(theta, head, rotation=0.12, orbit=0.05, radius=1.5, state="crawl")
    theta, head = trajectory(-0.03, 0.05, 1.5)  # the body turns against its orbit
    assert dish.dish_state(T, theta, head) == "crawl"
    theta, head = trajectory(0.0, 0.05, 1.5)  # the body keeps its heading as it goes round
    assert dish.dish_state(T, theta, head) == "crawl"


def test_orbit_and_crawl_are_told_apart_at_rigid_rtol():
    inside = 0.08 * (1 - 0.5 * dish.RIGID_RTOL)
    outside = 0.08 * (1 - 2.0 * dish.RIGID_RTOL)
    assert dish.dish_state(T, *trajectory(inside, 0.08, 1.5)) == "orbit"
    assert dish.dish_state(T, *trajectory(outside, 0.08, 1.5)) == "crawl"


def test_orbit_with_a_beat_on_top():
    """The body wobbles with a beat as it orbits: the rates are the mean slopes, the state still an orbit."""
    wobble = 0.3 * np.sin(2 * np.pi * 0.25 * T)[:, None] * np.linspace(0, 1, N)[None, :]
    theta, head = trajectory(0.08, 0.08, 1.4)
    theta = theta + wobble
    assert ob.rotation_rate(T, theta) == pytest.approx(0.08, abs=1e-5)  # theta_1 does not wobble
    assert dish.orbit_rate(T, theta, head) == pytest.approx(0.08, rel=0.01)
    assert dish.dish_state(T, theta, head) == "orbit"


def test_irregular_when_the_rates_drift_or_it_beats_irregularly():
    theta = SHAPE[None, :] + (0.02 * T + 0.0004 * T**2)[:, None]  # the body spins up
    head = -body_com(theta)
    assert dish.dish_state(T, theta, head) == "irregular"
    theta, head = trajectory(0.1, 0.0, 3.0)  # turning in place far from the centre, not going round
    assert dish.dish_state(T, theta, head) == "irregular"
    theta, head = trajectory(0.0, 0.0, 2.0)  # beating in place with a period that wanders
    wobble = 0.5 * np.sin(2 * np.pi * (0.2 * T + 0.8 * np.sin(2 * np.pi * T / 97.0)))
    assert dish.dish_state(T, theta + wobble[:, None] * np.linspace(0, 1, N)[None, :], head) == "irregular"


def test_beat_when_it_beats_in_place_without_turning():
    theta, head = trajectory(0.0, 0.0, 2.0)
    theta = theta + 0.5 * np.sin(2 * np.pi * 0.2 * T)[:, None] * np.linspace(0, 1, N)[None, :]
    assert dish.dish_state(T, theta, head) == "beat"


def test_transient_is_discarded():
    theta, head = trajectory(0.12, 0.05, 1.5)
    theta_r, head_r = trajectory(0.0, 0.0, 2.0)
    early = T < 100.0
    theta[early], head[early] = theta_r[early], head_r[early]  # at rest, then crawling
    assert dish.orbit_rate(T, theta, head, transient=100.0) == pytest.approx(0.05, abs=1e-6)
    assert dish.dish_state(T, theta, head, transient=100.0) == "crawl"
    assert dish.dish_state(T, theta, head, transient=0.0) == "irregular"
    assert dish.orbit_angle(T, theta, head, transient=100.0).shape == (np.count_nonzero(~early),)


def test_states_are_the_documented_ones():
    assert set(dish.STATES) == {"rest", "spin", "orbit", "crawl", "beat", "irregular"}


# ----------------------------------------------------------------------------- invalid inputs


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda th, h: dish.positions(th[:, 0], h), "theta"),
        (lambda th, h: dish.positions(th, h[:, :1]), "head"),
        (lambda th, h: dish.positions(th, h[:-1]), "head"),
        (lambda th, h: dish.centre_of_mass(th, np.where(h > 1, np.nan, h)), "head"),
        (lambda th, h: dish.orbit_rate(T[:-1], th, h), "theta"),
        (lambda th, h: dish.orbit_rate(T[::-1], th, h), "t"),
        (lambda th, h: dish.orbit_radius(T, th, h, transient=-1.0), "transient"),
        (lambda th, h: dish.dish_state(T, th, h, transient=1e5), "transient"),
        (lambda th, h: dish.mean_curvature(th[:, :1]), "theta"),
        (lambda th, h: dish.mean_curvature(th, transient=1.0), "transient"),
    ],
)
def test_invalid_inputs_name_the_argument(call, name):
    theta, head = trajectory(0.1, 0.05, 1.5)
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        call(theta, head)

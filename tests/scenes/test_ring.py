"""The ring: a chain closed on itself, one particle on a free pin, in both engines.

The reduced model is the two-pinned chain's constraints with the pin at the pivot plus the closing spring
(ChainSystem.closed); MuJoCo holds the last particle at the pin with a connect equality and closes the springs with a
fixed tendon. Checked: the compiled right-hand side against its numpy twin and the Jacobian against finite
differences (the closing spring in both), the regular N-gon at rest without activity, both engines' turning rate, and
the refusals. The free ring (pin = free: the root slides, the last particle held on it): its compiled right-hand side
against the numpy twin, both engines' turning rate against each other and against the rigid regular polygon's, and a
centre of drag that stays put.
"""

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.engines.reduced import system_of
from elastoactive.reduced import jacobian, rhs, rhs_reference
from elastoactive.reduced.constraints import project_on_pins
from elastoactive.scenes.ring import polygon


@pytest.fixture(scope="module")
def system():
    return system_of(ea.Physics(scene="ring", n=7, sigma=0.8)).typed()


def test_compiled_rhs_and_jacobian_have_the_closing_spring(system):
    theta = polygon(7) + 0.05 * np.random.default_rng(1).standard_normal(7)
    f, reference, jac = rhs(system, beta=1.0), rhs_reference(system, beta=1.0), jacobian(system, beta=1.0)
    np.testing.assert_allclose(f(0.0, theta), reference(0.0, theta), atol=1e-13)
    eps = 1e-6
    numeric = np.array([(f(0.0, theta + eps * e) - f(0.0, theta - eps * e)) / (2 * eps) for e in np.eye(7)]).T
    np.testing.assert_allclose(jac(0.0, theta), numeric, atol=1e-7)


def test_the_regular_polygon_rests_without_activity():
    system = system_of(ea.Physics(scene="ring", n=9, sigma=0.0)).typed()
    np.testing.assert_allclose(rhs(system, beta=1.0)(0.0, polygon(9)), 0.0, atol=1e-12)


def test_both_engines_turn_the_ring_alike():
    physics = ea.Physics(scene="ring", n=7, sigma=0.8)
    rates = {e: ea.measure(ea.simulate(physics, duration=60.0, engine=e)).rotation_rate for e in ("mujoco", "reduced")}
    assert rates["reduced"] < -0.3  # the follower forces point back along the links: the ring turns clockwise
    assert rates["mujoco"] == pytest.approx(rates["reduced"], rel=0.01)


def test_refusals_are_one_line():
    with pytest.raises(ea.ParameterError, match="must be >= 3 for ring"):
        ea.Physics(scene="ring", n=2)
    with pytest.raises(ea.ParameterError, match="self-contact is not built for the ring"):
        ea.Physics(scene="ring", contact=True)
    with pytest.raises(ea.ParameterError, match="reduced model's ring .* without a trap or self-contact"):
        system_of(ea.Physics(scene="ring")).typed()._replace(contact_radius=0.1, contact_stiffness=1e3).typed()


def test_free_ring_compiled_rhs_matches_its_numpy_twin():
    system = system_of(ea.Physics(scene="ring", n=7, sigma=0.8, pin="free")).typed()
    assert system.head_free and system.closed and system.pinned and system.state_size == 9
    assert not system_of(ea.Physics(scene="ring", n=7, sigma=0.8)).head_free  # the default: the pinned ring as before
    rng = np.random.default_rng(2)
    y = np.r_[project_on_pins(polygon(7) + 0.05 * rng.standard_normal(7), 1.0), 0.3, -0.2]
    np.testing.assert_allclose(rhs(system, beta=1.0)(0.0, y), rhs_reference(system, beta=1.0)(0.0, y), atol=1e-13)


def test_free_ring_turns_about_its_centre_in_both_engines():
    """N = 7, sigma = 0.8: the free ring turns steadily at -0.5565 rad/tau, within 2% of the rigid regular polygon's
    sigma N sin(2 pi / N) / (N + 1) about its centre of drag, which does not move (isotropic drag: the total force
    vanishes); the engines agree to 1e-5."""
    physics = ea.Physics(scene="ring", n=7, sigma=0.8, pin="free")
    res = {e: ea.measure(ea.simulate(physics, duration=80.0, engine=e)) for e in ("mujoco", "reduced")}
    rigid = 0.8 * 7 * np.sin(2 * np.pi / 7) / 8
    for r in res.values():
        assert -r.rotation_rate == pytest.approx(rigid, rel=0.03)
        assert r.extra["centre_drift"] < 1e-3
        assert r.amplitude < 1e-2  # a steady shape: no beat
    assert res["mujoco"].rotation_rate == pytest.approx(res["reduced"].rotation_rate, rel=0.01)


def test_free_ring_refusals_are_one_line():
    with pytest.raises(ea.ParameterError, match="must be >= 3 for ring"):
        ea.Physics(scene="ring", n=2, pin="free")
    with pytest.raises(ea.ParameterError, match="self-contact is not built for the ring"):
        ea.Physics(scene="ring", pin="free", contact=True)
    with pytest.raises(ea.ParameterError, match="pin"):
        ea.Physics(scene="ring", pin="loose")
    with pytest.raises(ea.ParameterError, match="pin"):
        ea.Physics(scene="one-pinned", pin="free")  # a ring's parameter only
    with pytest.raises(ea.ParameterError, match="overdamped model only"):
        system_of(ea.Physics(scene="ring", pin="free")).typed()._replace(mass_ratio=0.01).typed()


def test_ring_study_round_trip_and_claims(tiny_studies, round_trip):
    """The study (tiny): N = 7 turns rigidly and both engines agree; N = 24 beats at sigma = 0.5 in both."""
    runs = tiny_studies("rings")
    s = runs[1]["rings"].summary
    assert max(s.rigid_amplitude_mujoco, s.rigid_amplitude_reduced) < 1e-3 and s.rate_difference < 0.01
    assert s.beating_mujoco == s.beating_reduced == [0.5]
    table = round_trip(runs, "rings")
    assert table.count("**yes**") == 3

"""The ring: a chain closed on itself, one particle on a free pin, in both engines.

The reduced model is the two-pinned chain's constraints with the pin at the pivot plus the closing spring
(ChainSystem.closed); MuJoCo holds the last particle at the pin with a connect equality and closes the springs with a
fixed tendon. Checked: the compiled right-hand side against its numpy twin and the Jacobian against finite
differences (the closing spring in both), the regular N-gon at rest without activity, both engines' turning rate, and
the refusals.
"""

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.analysis.reduced import jacobian, rhs, rhs_reference
from elastoactive.engines.reduced import system_of
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


def test_ring_study_round_trip_and_claims(tiny_studies, round_trip):
    """The study (tiny): N = 7 turns rigidly and both engines agree; N = 24 beats at sigma = 0.5 in both."""
    runs = tiny_studies("rings")
    s = runs[1]["rings"].summary
    assert max(s.rigid_amplitude_mujoco, s.rigid_amplitude_reduced) < 1e-3 and s.rate_difference < 0.01
    assert s.beating_mujoco == s.beating_reduced == [0.5]
    table = round_trip(runs, "rings")
    assert table.count("**yes**") == 2

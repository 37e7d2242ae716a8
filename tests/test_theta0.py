"""ea.simulate(..., theta0=...) and a chain's angles given as start=: one-dimensional finite numbers, refused before
any work in one line naming the option otherwise, in either engine."""

import numpy as np
import pytest

import elastoactive as ea

PHYSICS = ea.Physics(scene="one-pinned", n=7)


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
@pytest.mark.parametrize(
    "theta0, words",
    [
        (np.full(7, np.nan), "angle 0 is nan"),
        ([0.1, 0.2, np.inf, 0.0, 0.0, 0.0, 0.0], "angle 2 is inf"),
        (np.nan, "one-dimensional"),
        (np.zeros((7, 2)), r"one-dimensional .*shape \(7, 2\)"),
        (np.zeros((7, 1)), r"shape \(7, 1\)"),
        ("abc", "must be numbers, got str"),
    ],
)
def test_theta0_that_is_no_chains_angles_is_refused_naming_it(engine, theta0, words, no_simulation):
    with pytest.raises(ea.ParameterError, match=f"^theta0: .*{words}") as refused:
        ea.simulate(PHYSICS, duration=1.0, engine=engine, theta0=theta0)
    assert "\n" not in str(refused.value)


def test_a_start_of_non_finite_angles_is_refused_naming_it(no_simulation):
    with pytest.raises(ea.ParameterError, match=r"^start: angle 3 is nan; every angle must be finite$"):
        ea.simulate(PHYSICS, duration=1.0, engine="reduced", start=[0.0, 0.0, 0.0, np.nan, 0.0, 0.0, 0.0])


def test_finite_angles_of_the_right_count_run_as_given():
    theta0 = 0.01 * np.arange(7.0)
    traj = ea.simulate(PHYSICS, duration=0.5, engine="reduced", theta0=list(theta0))
    np.testing.assert_allclose(traj.theta[0], theta0, atol=1e-12)
    with pytest.raises(ea.ParameterError, match="theta0 must have 7 angles, got 3"):
        ea.simulate(PHYSICS, duration=0.5, engine="reduced", theta0=theta0[:3])

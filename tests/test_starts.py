"""A run started from a given or saved state: continuing a run is the run (reduced engine, to its tolerance), MuJoCo
starts where it is told, and a state of another scene is refused in one line."""

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.core.errors import ParameterError
from elastoactive.starts import Start, as_start, last_state

PATCH = ea.Physics(scene="lattice", rings=1, sigma=0.2, alignment_length=0.1)
SAMPLES = ea.Numerics(sample_dt=0.25)


def test_a_continued_network_run_is_the_run():
    whole = ea.simulate(PATCH, SAMPLES, duration=20, engine="reduced")
    half = ea.simulate(PATCH, SAMPLES, duration=10, engine="reduced")
    rest = ea.simulate(PATCH, SAMPLES, duration=10, engine="reduced", start=half)
    assert np.abs(rest.nodes[0] - half.nodes[-1]).max() == 0.0
    tolerance = 0.1 * whole.info["rtol"]  # the adaptive steps restart at the state: apart by the solver's error
    assert np.abs(rest.nodes[-1] - whole.nodes[-1]).max() < tolerance
    assert np.abs(rest.polarity[-1] - whole.polarity[-1]).max() < tolerance


def test_mujoco_starts_from_the_given_state():
    state = last_state(ea.simulate(PATCH, SAMPLES, duration=5, engine="reduced"))
    run = ea.simulate(PATCH, SAMPLES, duration=5, engine="mujoco", start=state)
    assert np.abs(run.nodes[0] - state.positions).max() < 1e-12
    assert np.abs(run.polarity[0] - state.polarity).max() < 1e-12


def test_a_chain_continues_from_its_angles():
    first = ea.simulate("one-pinned", duration=2, engine="reduced")
    then = ea.simulate("one-pinned", duration=2, engine="reduced", start=first)
    assert np.array_equal(then.theta[0], first.theta[-1])


@pytest.mark.parametrize(
    "start, words",
    [
        (Start(positions=np.zeros((19, 2)), polarity=np.zeros(7)), "positions must be 7 nodes"),
        (Start(positions=np.zeros((7, 2)), polarity=np.zeros(3)), "polarity must hold 1 angles"),
        (Start(theta=np.zeros(7)), "theta0"),
    ],
)
def test_a_state_of_another_scene_is_refused(start, words):
    with pytest.raises(ParameterError, match=words):
        ea.simulate(PATCH, SAMPLES, duration=5, engine="reduced", start=start)


def test_a_pinned_node_moved_is_refused():
    network = PATCH.scene_def.network(PATCH)
    positions = network.positions.copy()
    positions[np.flatnonzero(network.pinned)[0]] += 0.1
    with pytest.raises(ParameterError, match="pinned node"):
        ea.simulate(PATCH, SAMPLES, duration=5, engine="reduced", start=(positions, np.zeros(1)))


def test_a_start_is_one_kind_of_state():
    with pytest.raises(ParameterError, match="not both"):
        Start(theta=np.zeros(3), positions=np.zeros((1, 2)), polarity=np.zeros(1))
    with pytest.raises(ParameterError, match="holds no saved run"):
        as_start("/nonexistent/run")

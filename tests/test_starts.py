"""A run started from a given or saved state: continuing a run is the run (reduced engine, to its tolerance), MuJoCo
starts where it is told, and a state of another scene (or shape, kind, size, or off the scene's pin) is refused in one
line naming the option and both scenes."""

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.cli import main
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
        (Start(theta=np.zeros(7)), "start: a chain's angles cannot start lattice"),
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


def _default(scene: str) -> ea.Physics:
    """A scene at its defaults (N = 7 where N sizes it)."""
    return ea.Physics(scene=scene, **({"n": 7} if ea.scenes.get(scene).sized_by_n else {}))


def _run_state(physics: ea.Physics) -> Start:
    """A state of `physics` as a run of it would leave it (its origin that physics), without running it."""
    if physics.n_angles:
        return Start(theta=np.zeros(physics.n_angles), source="a run", origin=physics)
    network = physics.scene_def.network(physics)
    polarity = np.zeros(int(np.count_nonzero(network.active)))
    return Start(positions=network.positions, polarity=polarity, source="a run", origin=physics)


@pytest.mark.parametrize("target", ea.scenes.names())
def test_a_run_of_every_other_scene_is_refused_naming_both(target):
    physics = _default(target)
    for origin in ea.scenes.names():
        if origin == target:
            continue
        with pytest.raises(ParameterError) as refused:
            _run_state(_default(origin)).checked(physics)
        message = str(refused.value)
        assert message.startswith(f"start: the run is of scene {origin} (") and f", not {target} (" in message
        assert "\n" not in message


@pytest.mark.parametrize(
    "target, origin, words",
    [
        (ea.Physics("one-pinned", n=14), ea.Physics("clamped-3d", n=7), "clamped-3d (N = 7), not one-pinned (N = 14)"),
        (ea.Physics("clamped-3d", n=20), ea.Physics("one-pinned", n=40), "(N = 40), not clamped-3d (N = 20)"),
        (ea.Physics("one-pinned", n=14), ea.Physics("coupled-pair", n=7), "coupled-pair (2 chains of N = 7)"),
        (ea.Physics("ring", n=7), ea.Physics("one-pinned", n=7), "one-pinned (N = 7), not ring (N = 7)"),
        (ea.Physics("one-pinned", n=14), ea.Physics("one-pinned", n=7), "start from a run of one-pinned (N = 14)"),
    ],
)
def test_a_trajectory_of_another_scene_is_refused(target, origin, words):
    run = ea.simulate(origin, duration=0.5, engine="reduced")
    with pytest.raises(ParameterError, match=r"^start: the run is of scene") as refused:
        ea.simulate(target, duration=0.5, engine="reduced", start=run)
    assert words in str(refused.value)


def test_given_angles_are_held_to_the_scene():
    ring = ea.Physics("ring", n=7)
    with pytest.raises(ParameterError, match=r"^start: 3 angles given; ring \(N = 7\) takes 7$"):
        ea.simulate(ring, duration=0.5, engine="reduced", start=np.zeros(3))
    with pytest.raises(ParameterError, match=r"^start: its last particle is 7 l from the pin"):
        ea.simulate(ring, duration=0.5, engine="reduced", start=np.zeros(7))  # an open chain, straight
    with pytest.raises(ParameterError, match="^start: a network's nodes and polarities cannot start one-pinned"):
        ea.simulate("one-pinned", duration=0.5, engine="reduced", start=(np.zeros((7, 2)), np.zeros(1)))


def test_a_pinned_run_continues_on_its_pin():
    """MuJoCo's ring ends a hair off its pin (its soft equality): well inside what a start may be."""
    ring = ea.Physics("ring", n=7)
    first = ea.simulate(ring, duration=5, engine="mujoco")
    then = ea.simulate(ring, duration=1, engine="reduced", start=first)
    assert np.array_equal(then.theta[0], first.theta[-1])


def test_the_command_line_names_start_from(tmp_path, capsys):
    assert main(["run", "one-pinned", "--n", "7", "--duration", "1", "--engine", "reduced", "--quiet",
                 "--out", str(tmp_path / "chain")]) == 0  # fmt: skip
    capsys.readouterr()
    assert main(["run", "ring", "--n", "7", "--duration", "1", "--engine", "reduced", "--quiet",
                 "--start-from", str(tmp_path / "chain")]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error: --start-from: the run is of scene one-pinned (N = 7), not ring (N" in err
    ramp = ["ramp", "lattice", "--rings", "1", "--alignment-length", "0.1", "--ramp", "Pi=1,2"]
    assert main([*ramp, "--start-from", str(tmp_path / "chain"), "--out", str(tmp_path / "r.nc")]) == 2
    err = capsys.readouterr().err
    assert "error: --start-from: the run is of scene one-pinned (N = 7), not lattice (7 nodes, 1 unit)" in err

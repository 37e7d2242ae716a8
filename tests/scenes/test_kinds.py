"""Chains and networks are two kinds of scene, and a third kind needs no module outside scenes/.

Every registered scene implements the kind contract (elastoactive.scenes.base); a scene of no kind is refused in one
line; a kind defined in this file alone (one particle on a prescribed circle) runs through ea.simulate in both
engines, ea.measure, Trajectory and `elastoactive run --out`.
"""

import json

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.core.trajectory import Trajectory
from elastoactive.scenes.base import Scene

KIND_HOOKS = (
    "run_mujoco",
    "run_reduced",
    "check_timestep",
    "reduced_methods",
    "positions",
    "tip",
    "centre_of_drag",
    "state_variables",
    "state_difference",
    "beat_signals",
)
"""The hooks a kind must implement (Scene's raise NotImplementedError naming the contract)."""
DRAWING_HOOKS = ("painter", "draw_shape", "stability_report")
"""Hooks of the built-in kinds that a kind without pictures or a stability analysis may leave out."""


@pytest.mark.parametrize("name", ea.scenes.names())
def test_every_scene_is_of_a_kind_that_implements_the_contract(name):
    scene = ea.scenes.get(name)
    assert scene.kind and scene.units.length and scene.state_units and scene.state_name and scene.builder
    missing = [h for h in KIND_HOOKS + DRAWING_HOOKS if getattr(type(scene), h) is getattr(Scene, h)]
    assert not missing, f"{name} leaves the kind hooks {missing} to Scene"
    assert set(scene.reduced_methods())


def test_a_chain_scene_has_no_network_and_a_network_scene_no_chains():
    chain, network = ea.scenes.get("one-pinned"), ea.scenes.get("lattice")
    assert not hasattr(chain, "network") and not hasattr(network, "chain_prefixes")
    assert chain.mujoco_batched and not network.mujoco_batched and network.seeded_start and not chain.seeded_start


class Kindless(Scene):
    name = "toy-kindless"
    summary = "a scene subclassing Scene itself (refused)"


def test_a_scene_of_no_kind_is_refused_in_one_line():
    with pytest.raises(TypeError, match="of no kind: subclass elastoactive.scenes.ChainScene") as err:
        ea.scenes.register(Kindless())
    assert "\n" not in str(err.value) and "toy-kindless" not in ea.scenes.names()
    with pytest.raises(NotImplementedError, match="implements no kind"):
        Kindless().positions(None)


class Orbit(Scene):
    """A third kind, this file's alone: one particle on a circle of radius 1 turning at angular speed sigma (a
    prescribed motion both 'engines' give exactly)."""

    kind = "orbit"
    name = "toy-orbit"
    summary = "one particle on a prescribed circle (a test's third kind of scene)"
    state_units = "l"
    state_name = "position"
    seeded_start = True
    builder = "none: the orbit is prescribed"
    term_parameters = ("sigma",)

    def _run(self, physics, numerics, duration, engine):
        t = numerics.sample_times(duration)
        xy = np.stack([np.cos(physics.sigma * t), np.sin(physics.sigma * t)], axis=-1)[:, None, :]
        return Trajectory(t=t, theta=np.empty((t.size, 0)), physics=physics, engine=engine, nodes=xy)

    def run_mujoco(self, physics, numerics, duration, **options):
        return self._run(physics, numerics, duration, "mujoco")

    def run_reduced(self, physics, numerics, duration, **options):
        return self._run(physics, numerics, duration, "reduced")

    def check_timestep(self, physics, numerics, safety, accuracy, **options):
        return None  # nothing is stepped

    def reduced_methods(self):
        return ("exact",)

    def positions(self, traj):
        return traj.nodes.copy()

    def tip(self, traj):
        return traj.nodes

    def centre_of_drag(self, traj):
        return traj.nodes.mean(axis=-2)

    def state_variables(self, traj):
        return {}, {"position": (("time", "particle", "xy"), traj.nodes, {"units": "l", "long_name": "position"})}

    def state_difference(self, traj, reference, early):
        n = early.size
        return float(np.abs(traj.nodes[:n][early] - reference.nodes[:n][early]).max()), 1.0

    def beat_signals(self, traj):
        return [traj.nodes[:, 0, 0]]


@pytest.fixture
def orbit():
    scene = ea.scenes.register(Orbit())
    yield scene
    ea.scenes.unregister(scene.name)


def test_a_third_kind_runs_through_simulate_measure_and_the_trajectory(orbit):
    physics = ea.Physics(scene=orbit.name, sigma=0.5)
    for engine in ("mujoco", "reduced"):
        traj = ea.simulate(physics, duration=100.0, engine=engine)
        results = ea.measure(traj)
        assert results.amplitude == pytest.approx(1.0, rel=1e-5)
        assert results.frequency == pytest.approx(0.5 / (2 * np.pi), rel=1e-6)
        assert traj.positions().shape == (traj.t.size, 1, 2) and traj.length_units == "l"
        assert list(traj.to_xarray().data_vars) == ["position"]


def test_a_third_kind_runs_from_the_command_line(orbit, tmp_path):
    out = tmp_path / "orbit"
    assert main(["run", orbit.name, "--sigma", "0.5", "--duration", "100", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["results"]["frequency"] == pytest.approx(0.5 / (2 * np.pi), rel=1e-6)

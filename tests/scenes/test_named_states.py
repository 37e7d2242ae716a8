"""Each named state on a tiny real run (reduced engine, the pinned R = 2 hexagon, l_a = 0.1): frozen below lambda_1,
collective at Pi = 2, mixed chirality at Pi = 2.5 (seed 1), and the named state, ring rates and mode space in the
results of every network scene."""

import pytest

import elastoactive as ea
from elastoactive.core import observables

PATCH = dict(scene="lattice", rings=2, alignment_length=0.1)
NAMED = ("network_state", "edge_rate", "bulk_rate", "counter_fraction", "mode_space", "mode_space_size")


@pytest.mark.parametrize(
    "coupling, seed, state",
    [(1.0, 0, "frozen"), (2.0, 0, "collective"), (2.5, 1, "mixed")],
)
def test_states_of_real_runs(coupling, seed, state):
    physics = ea.Physics(**PATCH, sigma=coupling * 0.1)
    run = ea.simulate(physics, ea.Numerics(sample_dt=0.05, seed=seed), duration=300, engine="reduced")
    results = ea.measure(run)
    assert results.network_state == state
    if state == "collective":  # every ring at one rate, the softest degenerate pair holding most of the energy
        assert results.edge_rate == pytest.approx(results.bulk_rate, rel=1e-3) and results.counter_fraction == 0
        assert (results.mode_space, results.mode_space_size) == (1, 2) and results.mode_space_share > 0.9
    if state == "mixed":
        assert 0 < results.counter_fraction <= 0.5 and results.polarity_speed > 0.5


@pytest.mark.parametrize("scene", [s.name for s in ea.scenes.scenes() if "network_state" in s.observable_names()])
def test_every_network_scene_names_its_state(scene):
    physics = ea.Physics(scene=scene)
    results = ea.measure(ea.simulate(physics, ea.Numerics(sample_dt=0.1), duration=10, engine="reduced"))
    assert set(NAMED) <= set(results.extra)
    assert results.network_state in observables.get("network_state").categories

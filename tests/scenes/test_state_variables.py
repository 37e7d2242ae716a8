"""A trajectory's Dataset says what it holds (Scene.state_variables through Trajectory.to_xarray): a network's units
carry the node each sits on and its nodes which are pinned; a chain's self-aligning units the chain and particle they
sit on; a 3D chain's fields all share the chain dimension, and no dataset has a component coordinate nothing uses."""

import numpy as np

import elastoactive as ea
from elastoactive.scenes.clamped3d import angles_of

T = np.linspace(0.0, 1.0, 5)


def test_a_network_s_units_say_which_node_they_sit_on():
    physics = ea.Physics(scene="lattice", rings=2, sigma=0.5)
    network = physics.scene_def.network(physics)
    nodes = np.repeat(network.positions[None], T.size, axis=0)
    polarity = np.zeros((T.size, network.n_units))
    ds = ea.Trajectory(T, np.empty((T.size, 0)), physics, "reduced", polarity=polarity, nodes=nodes).to_xarray()
    assert ds["polarity"].dims == ("time", "unit") and ds["unit_node"].dims == ("unit",)
    np.testing.assert_array_equal(ds["unit_node"].values, np.flatnonzero(network.active))
    np.testing.assert_array_equal(ds["pinned"].values, network.pinned)
    assert ds["pinned"].dims == ("node",) and ds["pinned"].dtype == bool
    # a unit's polarity and the position of its node, by the coordinate
    first = ds["polarity"].isel(unit=0)
    assert int(first["unit_node"]) == np.flatnonzero(network.active)[0]
    assert not ds["pinned"].sel(node=ds["unit_node"].values).any()


def test_a_chain_s_units_say_which_particle_they_sit_on():
    physics = ea.Physics(scene="coupled-pair", n=4, sigma=1.0, active="self-aligning", loaded="tip")
    chains = physics.n_chains
    polarity = np.zeros((T.size, chains))
    ds = ea.Trajectory(T, np.zeros((T.size, 4 * chains)), physics, "reduced", polarity=polarity).to_xarray()
    np.testing.assert_array_equal(ds["unit_chain"].values, np.arange(chains))
    np.testing.assert_array_equal(ds["unit_particle"].values, [3] * chains)


def test_a_3d_chain_s_fields_share_the_chain_dimension_and_no_plane():
    tangents = np.tile([1.0, 0.0, 0.0], (T.size, 3, 1))
    ds = ea.Trajectory(T, angles_of(tangents), ea.Physics(scene="clamped-3d", n=3, sigma=1.0), "reduced").to_xarray()
    assert ds["tangent"].dims == ds["position"].dims == ("time", "chain", "particle", "xyz")
    assert ds["tip"].dims == ("time", "chain", "xyz")
    assert "xy" not in ds.coords and "xy" not in ds.dims
    np.testing.assert_allclose(ds["tangent"].sel(chain=0, xyz="x").values, 1.0)


def test_a_planar_chain_keeps_its_plane():
    physics = ea.Physics(scene="one-pinned", n=3, sigma=1.0)
    ds = ea.Trajectory(T, np.zeros((T.size, 3)), physics, "reduced").to_xarray()
    assert list(ds["xy"].values) == ["x", "y"] and "unit" not in ds.dims

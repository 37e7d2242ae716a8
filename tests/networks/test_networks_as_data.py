"""Networks as data: the checked record (make_network), the JSON network file, the generators (triangular, kagome,
square with and without diagonals, honeycomb, delaunay; hexagonal or rectangular patches; dilution; the boundary
choices), the scene `network` running any of them in both engines, and the normal modes and the linear-stability
bracket on every generator."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import HAND_WRITTEN

import elastoactive as ea
from elastoactive.analysis.network import stability
from elastoactive.core.errors import ParameterError
from elastoactive.networks.files import read_network, write_network
from elastoactive.networks.geometry import hexagonal_patch, make_network
from elastoactive.networks.lattices import LATTICES, MIN_SEPARATION, PATCHES, generate
from elastoactive.reduced.network import normal_modes

BULK = {"triangular": 6, "kagome": 4, "square": 4, "square-diagonals": 8, "honeycomb": 3}
"""Each periodic lattice's coordination in the bulk."""


def _same(a, b) -> bool:
    return all(np.array_equal(x, y) for x, y in zip(a, b)) and len(a) == len(b)


# ------------------------------------------------------------------------------------------------ the record
@pytest.mark.parametrize("rings", [1, 2, 3, 4])
@pytest.mark.parametrize("boundary", ["pinned", "free", "centre"])
def test_the_triangular_generator_is_the_hexagonal_patch_to_the_last_digit(rings, boundary):
    assert _same(generate("triangular", "hexagonal", rings, boundary), hexagonal_patch(rings, boundary))


def test_rest_lengths_default_to_the_initial_distances():
    network = make_network([[0, 0], [3, 0], [0, 4]], [[0, 1], [1, 2]], pinned=[0])
    assert network.rest_lengths.tolist() == [3.0, 5.0]
    assert network.stiffness.tolist() == [1.0, 1.0]
    assert network.active.tolist() == [False, True, True]  # every node not pinned carries a unit by default


@pytest.mark.parametrize(
    "fields, word",
    [
        (dict(nodes=[[0, 0, 0], [1, 0, 0]]), "nodes"),
        (dict(nodes=[[0, 0], [0, 0]]), "nodes"),
        (dict(nodes=[[0, 0], [np.nan, 0]]), "nodes"),
        (dict(bonds=[[0, 2]]), "bonds"),
        (dict(bonds=[[1, 1]]), "bonds"),
        (dict(bonds=[[0, 1], [1, 0]]), "bonds"),
        (dict(bonds=[[0, 1.5]]), "bonds"),
        (dict(stiffness=[1.0, 2.0]), "stiffness"),
        (dict(stiffness=-1.0), "stiffness"),
        (dict(rest_lengths=[0.0]), "rest_lengths"),
        (dict(pinned=[5]), "pinned"),
        (dict(pinned=[0, 0]), "pinned"),
        (dict(units=[0], pinned=[0]), "units"),
        (dict(trap=-1.0), "trap"),
    ],
)
def test_a_bad_field_is_refused_in_one_line_naming_it(fields, word):
    values = dict(nodes=[[0, 0], [1, 0]], bonds=[[0, 1]]) | fields
    with pytest.raises(ParameterError, match=rf"\b{word}\b") as err:
        make_network(values.pop("nodes"), values.pop("bonds"), **values)
    assert "\n" not in str(err.value)


# ------------------------------------------------------------------------------------------------ the file
@pytest.mark.parametrize("lattice", LATTICES)
def test_a_network_file_reads_back_the_same_network(tmp_path, lattice):
    network = generate(lattice, "rectangular", 2, "pinned", dilution=0.1, seed=3)
    assert _same(read_network(write_network(network, tmp_path / "net.json")), network)


@pytest.mark.parametrize(
    "change, word",
    [
        (dict(bond=[[0, 1]]), "bond"),
        (dict(nodes=None), "nodes"),
        (dict(format="other"), "format"),
        (dict(version=2), "version"),
        (dict(units=[0]), "units"),
        (dict(bonds=[[0, 12]]), "bonds"),
        (dict(trap="stiff"), "trap"),
    ],
)
def test_a_bad_network_file_is_refused_in_one_line_naming_the_field(tmp_path, change, word):
    data = dict(HAND_WRITTEN) | {k: v for k, v in change.items() if v is not None}
    data = {k: v for k, v in data.items() if change.get(k, 0) is not None}
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ParameterError, match=rf"bad\.json.*\b{word}\b") as err:
        read_network(path)
    assert "\n" not in str(err.value)


def test_a_file_that_is_not_json_or_not_there_is_refused(tmp_path):
    path = tmp_path / "net.json"
    with pytest.raises(ParameterError, match="cannot be read"):
        read_network(path)
    path.write_text("{nodes")
    with pytest.raises(ParameterError, match="not JSON"):
        read_network(path)
    with pytest.raises(ParameterError, match=r"\.json"):
        read_network(tmp_path / "net.txt")


# ------------------------------------------------------------------------------------------------ the generators
@pytest.mark.parametrize("lattice", sorted(BULK))
@pytest.mark.parametrize("patch", PATCHES)
def test_a_lattice_has_its_coordination_unit_bonds_and_its_boundaries(lattice, patch):
    pinned = generate(lattice, patch, 4, "pinned")
    positions, bonds = pinned.positions, pinned.bonds
    degree = np.bincount(bonds.ravel(), minlength=len(positions))
    assert degree.max() == BULK[lattice]
    length = np.linalg.norm(positions[bonds[:, 1]] - positions[bonds[:, 0]], axis=1)
    assert np.allclose(length, np.where(length > 1.2, np.sqrt(2.0), 1.0), atol=1e-12)
    assert np.allclose(pinned.rest_lengths, length, rtol=0, atol=1e-15)  # no pre-stress
    assert np.array_equal(pinned.pinned, degree < BULK[lattice]) and np.array_equal(pinned.active, ~pinned.pinned)
    assert np.argmin(np.hypot(*positions.T)) == 0  # node 0 is the most central
    assert not generate(lattice, patch, 4, "free").pinned.any()
    assert np.flatnonzero(generate(lattice, patch, 4, "centre").pinned).tolist() == [0]


@pytest.mark.parametrize("patch", PATCHES)
def test_a_delaunay_network_is_seeded_and_keeps_its_points_apart(patch):
    network = generate("delaunay", patch, 3, "pinned", seed=7)
    assert _same(network, generate("delaunay", patch, 3, "pinned", seed=7))
    assert not _same(network, generate("delaunay", patch, 3, "pinned", seed=8))
    from scipy.spatial.distance import pdist

    assert pdist(network.positions).min() >= MIN_SEPARATION - 1e-12
    triangular = generate("triangular", patch, 3, "pinned")
    inner = network.n_nodes - network.pinned.sum()
    assert inner == triangular.n_nodes - triangular.pinned.sum()  # as many points inside as the triangular patch
    assert 2.5 < 2 * network.n_bonds / network.n_nodes < 6  # a triangulation


def test_dilution_removes_its_fraction_of_the_bonds_at_random():
    whole = generate("kagome", "hexagonal", 4, "pinned")
    diluted = generate("kagome", "hexagonal", 4, "pinned", dilution=0.25, seed=1)
    assert diluted.n_bonds == whole.n_bonds - round(0.25 * whole.n_bonds)
    assert set(map(tuple, diluted.bonds.tolist())) < set(map(tuple, whole.bonds.tolist()))
    assert np.array_equal(diluted.pinned, whole.pinned)  # the edge is the undiluted lattice's


@pytest.mark.parametrize(
    "values, name",
    [
        (dict(lattice="hexagon"), "geometry"),
        (dict(patch="circle"), "patch"),
        (dict(size=0), "size"),
        (dict(boundary="clamped"), "boundary"),
        (dict(dilution=1.0), "dilution"),
        (dict(seed=-1), "network_seed"),
    ],
)
def test_a_generator_refuses_a_bad_argument_naming_it(values, name):
    with pytest.raises(ParameterError, match=rf"^{name}\b"):
        generate(**values)


# ------------------------------------------------------------------------------------------------ modes, stability
@pytest.mark.parametrize("lattice", LATTICES)
@pytest.mark.parametrize("patch", PATCHES)
def test_normal_modes_and_the_stability_bracket_on_every_generator(lattice, patch):
    network = generate(lattice, patch, 2, "pinned", seed=2)
    values, vectors = normal_modes(network)
    assert np.all(np.isfinite(values)) and values[0] > 0  # held at its edge: no zero mode
    assert np.allclose(vectors.T @ vectors, np.eye(len(values)), atol=1e-9)
    bracket = stability.threshold(network, starts=1, samples=10, iterations=100)
    assert bracket.floppy == 0 and bracket.softest == pytest.approx(values[0])
    assert bracket.softest <= bracket.coupling * (1 + 1e-9) <= bracket.ceiling * (1 + 1e-6)


@pytest.mark.parametrize(
    "network, floppy",
    [
        (make_network([[0, 0], [1, 0]], [[0, 1]], pinned=[0]), 1),  # a node held by one spring: free sideways
        (generate("honeycomb", "rectangular", 3, "pinned"), 3),  # coordination 3 < 4: floppy though held at its edge
        (generate("triangular", "hexagonal", 3, "pinned", dilution=0.5, seed=1), 6),
    ],
)
def test_a_floppy_network_has_a_bracket_from_zero_to_a_proved_ceiling(network, floppy):
    assert stability.floppy_modes(network) == floppy
    bracket = stability.threshold(network)
    assert (bracket.softest, bracket.coupling, bracket.typical, bracket.starts, bracket.floppy) == (0, 0, 0, 0, floppy)
    assert bracket.ceiling == stability.interlacing_ceiling(network) >= 0
    assert normal_modes(network)[0][floppy - 1] == pytest.approx(0, abs=1e-9)


# ------------------------------------------------------------------------------------------------ the scene
def test_the_network_scene_runs_todays_lattice_to_the_last_digit():
    kw = dict(sigma=0.2, alignment_length=0.1)
    lattice = ea.simulate(ea.Physics(scene="lattice", rings=2, **kw), duration=20, engine="reduced")
    network = ea.simulate(ea.Physics(scene="network", size=2, **kw), duration=20, engine="reduced")
    assert np.abs(network.nodes - lattice.nodes).max() <= 1e-12
    assert np.abs(network.polarity - lattice.polarity).max() <= 1e-12


@pytest.mark.parametrize(
    "values, name",
    [
        (dict(geometry="hexagon"), "geometry"),
        (dict(geometry="square", network_seed=3), "network_seed"),
        (dict(size=0), "size"),
        (dict(patch="circle"), "patch"),
        (dict(dilution=-0.1), "dilution"),
        (dict(geometry="missing.json"), "network file"),
        (dict(rings=3), "rings"),
    ],
)
def test_the_network_scene_refuses_in_one_line_naming_the_parameter(values, name):
    with pytest.raises(ParameterError, match=rf"^{name}\b") as err:
        ea.Physics(scene="network", **values)
    assert "\n" not in str(err.value)


def test_a_network_file_refuses_the_generators_parameters(tmp_path):
    path = tmp_path / "net.json"
    path.write_text(json.dumps(HAND_WRITTEN))
    for name, value in (("size", 3), ("boundary", "free"), ("dilution", 0.1), ("patch", "rectangular")):
        with pytest.raises(ParameterError, match=rf"^{name} has no effect on a network file"):
            ea.Physics(scene="network", geometry=str(path), **{name: value})


def test_a_network_without_units_is_refused(tmp_path):
    path = tmp_path / "passive.json"
    path.write_text(json.dumps(dict(HAND_WRITTEN, units=[])))
    with pytest.raises(ParameterError, match=r"^geometry: .* carries no active unit"):
        ea.Physics(scene="network", geometry=str(path))


def test_a_generated_network_is_the_callers_own():
    first = generate("kagome", "hexagonal", 2)
    first.positions[:] = 0.0
    first.pinned[:] = True
    assert _same(generate("kagome", "hexagonal", 2), generate("kagome", "hexagonal", 2))
    assert not generate("kagome", "hexagonal", 2).pinned.all()


def test_a_network_file_is_held_by_what_it_pins(tmp_path):
    scene = ea.scenes.get("network")
    for pinned, hold in (([], "free"), ([0], "centre"), ([0, 3], "pinned")):
        path = tmp_path / f"held{len(pinned)}.json"
        path.write_text(json.dumps(dict(HAND_WRITTEN, pinned=pinned)))
        assert scene.hold(ea.Physics(scene="network", geometry=str(path))) == hold


OBSERVED = ("polarization", "polarity_speed")
"""The units' observables compared between the engines (with the beat's amplitude and frequency)."""


def _agree(physics, duration):
    reduced, mujoco = (ea.measure(ea.simulate(physics, duration=duration, engine=e)) for e in ("reduced", "mujoco"))
    assert reduced.extra["polarity_speed"] > 0.1 and reduced.frequency > 0  # it beats: not a comparison of two rests
    for name in OBSERVED:
        assert mujoco.extra[name] == pytest.approx(reduced.extra[name], rel=0.01), name
    assert mujoco.amplitude == pytest.approx(reduced.amplitude, rel=0.01)
    assert mujoco.frequency == pytest.approx(reduced.frequency, rel=0.01)


def test_a_hand_written_network_file_agrees_in_both_engines(tmp_path):
    path = tmp_path / "hand.json"
    path.write_text(json.dumps(HAND_WRITTEN))
    physics = ea.Physics(scene="network", geometry=str(path), sigma=0.2, alignment_length=0.1)
    network = physics.scene_def.network(physics)
    assert (network.n_nodes, network.pinned.sum(), network.active.sum()) == (12, 3, 5)
    _agree(physics, 60.0)


@pytest.mark.parametrize("geometry", ["kagome", "delaunay"])
def test_kagome_and_delaunay_networks_agree_in_both_engines(geometry):
    _agree(ea.Physics(scene="network", geometry=geometry, size=2, sigma=0.2, alignment_length=0.1), 60.0)


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
def test_a_network_with_nothing_stiff_runs_and_stays(tmp_path, engine):
    """No bond, no trap and no force: no rate limits the step (the timestep check divides by none), nothing moves."""
    path = tmp_path / "loose.json"
    path.write_text(json.dumps({"nodes": [[0, 0], [1, 0], [0, 1]], "bonds": [], "pinned": [], "units": [0, 1, 2]}))
    traj = ea.simulate(ea.Physics(scene="network", geometry=str(path), sigma=0.0), duration=5, engine=engine)
    assert np.array_equal(traj.nodes[-1], traj.nodes[0])

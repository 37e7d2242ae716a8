"""Units with their own force and alignment length: the record and the file carry them (a factor of the run's sigma,
a length in place of the run's alignment_length), both engines run them and agree, a unit of force 0 is passive, and
a network without them runs exactly as before (every unit the run's sigma and alignment_length)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import HAND_WRITTEN as PLAIN_NETWORK

import elastoactive as ea
from elastoactive.analysis.network import stability
from elastoactive.core.errors import ParameterError
from elastoactive.networks.files import network_from_dict, network_to_dict, read_network, write_network
from elastoactive.networks.geometry import make_network, turning_scale, unit_alignment_lengths, unit_forces
from elastoactive.networks.state import initial_state
from elastoactive.reduced import network as model

HAND_WRITTEN = {
    **PLAIN_NETWORK,
    "unit_force": [1.0, 0.6, 1.5, 0.8, 1.2],
    "unit_alignment_length": [0.1, 0.15, 0.08, 0.12, 0.1],
}
"""A network written by hand: 12 nodes, 3 pinned, 5 units of unequal forces and alignment lengths (listed in the
order of "units", not node order)."""

KW = dict(sigma=0.2, alignment_length=0.1)


def _file(tmp_path, data: dict, name: str = "net.json") -> str:
    path = tmp_path / name
    path.write_text(json.dumps(data))
    return str(path)


def _plain(data: dict) -> dict:
    return {k: v for k, v in data.items() if k not in ("unit_force", "unit_alignment_length")}


# ------------------------------------------------------------------------------------------------ the record, the file
def test_the_units_values_follow_the_order_units_lists_them():
    network = network_from_dict(HAND_WRITTEN)
    nodes = np.flatnonzero(network.active)
    assert nodes.tolist() == [1, 5, 6, 9, 10]
    listed = dict(zip(HAND_WRITTEN["units"], zip(HAND_WRITTEN["unit_force"], HAND_WRITTEN["unit_alignment_length"])))
    assert network.unit_force.tolist() == [listed[i][0] for i in nodes]
    assert network.unit_alignment_length.tolist() == [listed[i][1] for i in nodes]
    assert unit_forces(network, 0.2).tolist() == [0.2 * listed[i][0] for i in nodes]
    assert unit_alignment_lengths(network, 0.5).tolist() == [listed[i][1] for i in nodes]


def test_without_their_own_values_every_unit_has_the_runs():
    network = network_from_dict(_plain(HAND_WRITTEN))
    assert network.unit_force is None and network.unit_alignment_length is None
    assert unit_forces(network, 0.2).tolist() == [0.2] * 5
    assert unit_alignment_lengths(network, 0.1).tolist() == [0.1] * 5
    assert turning_scale(network, 0.1) == 1.0
    assert "unit_force" not in network_to_dict(network)  # a file without them is written without them
    one = network_from_dict(HAND_WRITTEN | {"unit_force": 0.5})  # one value: every unit's
    assert one.unit_force.tolist() == [0.5] * 5 and one.unit_alignment_length is not None


def test_the_fastest_unit_sets_the_turning_scale():
    network = network_from_dict(HAND_WRITTEN)
    # the run's Pi = 0.2 / 0.1; the fastest unit turns at 0.2 x 1.5 / 0.08
    assert turning_scale(network, 0.1) == pytest.approx((1.5 / 0.08) / (1 / 0.1), rel=1e-14)


def test_a_file_with_the_units_values_reads_back_the_same_network(tmp_path):
    network = network_from_dict(HAND_WRITTEN)
    again = read_network(write_network(network, tmp_path / "again.json"))
    for name in ("unit_force", "unit_alignment_length", "active", "positions", "bonds"):
        assert np.array_equal(getattr(again, name), getattr(network, name)), name


@pytest.mark.parametrize(
    "change, word",
    [
        ({"unit_force": [1.0, 2.0]}, "unit_force"),
        ({"unit_force": [1.0, -0.5, 1.0, 1.0, 1.0]}, "unit_force"),
        ({"unit_force": [1.0, np.inf, 1.0, 1.0, 1.0]}, "unit_force"),
        ({"unit_force": "strong"}, "unit_force"),
        ({"unit_alignment_length": [0.1, 0.0, 0.1, 0.1, 0.1]}, "unit_alignment_length"),
        ({"unit_alignment_length": -0.1}, "unit_alignment_length"),
        ({"unit_alignment_length": [[0.1]]}, "unit_alignment_length"),
    ],
)
def test_a_bad_unit_value_is_refused_in_one_line_naming_it(tmp_path, change, word):
    data = HAND_WRITTEN | change
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ParameterError, match=rf"\b{word}\b") as err:
        read_network(path)
    assert "\n" not in str(err.value)
    with pytest.raises(ParameterError, match=rf"\b{word}\b"):
        make_network(data["nodes"], data["bonds"], pinned=data["pinned"], units=data["units"], **{word: data[word]})


def test_a_bad_unit_value_names_the_units_node():
    with pytest.raises(ParameterError, match=r"unit_force must be finite and >= 0, got -1.0 for the unit on node 9"):
        make_network(
            HAND_WRITTEN["nodes"], HAND_WRITTEN["bonds"], pinned=[0, 8, 3], units=[9, 1], unit_force=[-1.0, 1.0]
        )


# ------------------------------------------------------------------------------------------------ the reduced model
def test_the_compiled_right_hand_side_and_the_jacobian_carry_each_units_values():
    network = network_from_dict(HAND_WRITTEN)
    system = model.network_system(network, 0.3, 0.1)
    rng = np.random.default_rng(4)
    y = model.pack(system, initial_state(network, 0.2, 1)) + 0.01 * rng.standard_normal(system.state_size)
    assert np.allclose(model.rhs(system)(0.0, y), model.rhs_reference(system)(0.0, y), rtol=1e-13, atol=1e-14)
    f, eps = model.rhs(system), 1e-7
    numeric = np.column_stack(
        [(f(0.0, y + eps * e) - f(0.0, y - eps * e)) / (2 * eps) for e in np.eye(system.state_size)]
    )
    dense = model.jacobian(system, y)
    assert np.abs(dense - numeric).max() <= 1e-6 * np.abs(numeric).max()
    assert np.abs(model.jacobian(system, y, sparse=True).toarray() - dense).max() <= 1e-14
    # the same arithmetic as units of the run's values when the units' own equal them
    same = model.network_system(network._replace(unit_force=None, unit_alignment_length=None), 0.3, 0.1)
    equal = model.network_system(
        network._replace(unit_force=np.ones(5), unit_alignment_length=np.full(5, 0.1)), 0.3, 0.1
    )
    assert np.array_equal(model.rhs(same)(0.0, y), model.rhs(equal)(0.0, y))
    assert not np.array_equal(model.rhs(same)(0.0, y), model.rhs(system)(0.0, y))


# ------------------------------------------------------------------------------------------------ both engines
@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
def test_units_given_the_runs_values_run_exactly_as_units_without_them(tmp_path, engine):
    plain = _plain(HAND_WRITTEN)
    given = plain | {"unit_force": 1.0, "unit_alignment_length": KW["alignment_length"]}
    runs = [
        ea.simulate(
            ea.Physics(scene="network", geometry=_file(tmp_path, data, f"{i}.json"), **KW), duration=10, engine=engine
        )
        for i, data in enumerate((plain, given))
    ]
    assert np.array_equal(runs[0].nodes, runs[1].nodes) and np.array_equal(runs[0].polarity, runs[1].polarity)


def test_a_hand_written_network_of_unequal_units_agrees_in_both_engines(tmp_path):
    physics = ea.Physics(scene="network", geometry=_file(tmp_path, HAND_WRITTEN), **KW)
    network = physics.scene_def.network(physics)
    assert (network.n_nodes, network.pinned.sum(), network.active.sum()) == (12, 3, 5)
    reduced, mujoco = (ea.simulate(physics, duration=60, engine=e) for e in ("reduced", "mujoco"))
    plain = ea.simulate(
        ea.Physics(scene="network", geometry=_file(tmp_path, _plain(HAND_WRITTEN), "plain.json"), **KW),
        duration=60,
        engine="reduced",
    )
    assert np.abs(reduced.nodes[-1] - plain.nodes[-1]).max() > 1e-2  # the units' own values change the motion
    m_reduced, m_mujoco = ea.measure(reduced), ea.measure(mujoco)
    assert m_reduced.extra["polarity_speed"] > 0.1  # the units turn: not two rests compared
    for name in ("polarization", "polarity_speed", "polarity_rate"):  # measured: within 0.1%
        assert m_mujoco.extra[name] == pytest.approx(m_reduced.extra[name], rel=0.01), name
    assert m_mujoco.extra["network_state"] == m_reduced.extra["network_state"]
    assert m_mujoco.amplitude == pytest.approx(m_reduced.amplitude, rel=0.01)
    if m_reduced.frequency is None:  # an irregular beat (no frequency) in both
        assert m_mujoco.frequency is None
    else:
        assert m_mujoco.frequency == pytest.approx(m_reduced.frequency, rel=0.01)
    # MuJoCo's automatic step resolves the fastest unit, 0.2 x 1.5 / 0.08 = 3.75 k / gamma (not the run's Pi = 2)
    assert mujoco.info["automatic_numerics"]["dt"] <= 0.00125 / 3.75 + 1e-15


def test_a_unit_of_force_zero_is_passive_in_both_engines(tmp_path):
    """A unit of factor 0 pushes nothing: the nodes move as in the network without it (the others' polarities too),
    while its own polarity still turns toward its node's velocity, the same in both engines."""
    passive = dict(HAND_WRITTEN, unit_force=[1.0, 0.6, 1.5, 0.0, 1.2])  # node 10's unit: force 0
    without = dict(HAND_WRITTEN, units=[5, 6, 9, 1], unit_force=[1.0, 0.6, 1.5, 1.2])
    without["unit_alignment_length"] = [0.1, 0.15, 0.08, 0.1]
    runs = {}
    for name, data in (("passive", passive), ("without", without)):
        physics = ea.Physics(scene="network", geometry=_file(tmp_path, data, f"{name}.json"), **KW)
        for engine in ("reduced", "mujoco"):  # the two networks' adaptive steps differ: a tight tolerance
            runs[name, engine] = ea.simulate(
                physics, duration=30, engine=engine, rtol=1e-9 if engine == "reduced" else None
            )
    for engine, tol in (("reduced", 1e-6), ("mujoco", 1e-12)):
        a, b = runs["passive", engine], runs["without", engine]
        assert np.abs(a.nodes - b.nodes).max() <= tol, engine
        assert np.abs(a.polarity[:, :4] - b.polarity).max() <= tol, engine  # node 10's unit is the last
        assert np.ptp(a.polarity[:, 4]) > 0.1, engine  # a passive unit's polarity turns with its node
    turned = [runs["passive", e].polarity[-1, 4] - runs["passive", e].polarity[0, 4] for e in ("reduced", "mujoco")]
    assert turned[1] == pytest.approx(turned[0], abs=0.02)


def test_the_stability_bracket_of_unequal_units_needs_the_runs_alignment_length():
    """Units with their own alignment lengths weigh the bracket by f_u l_a / l_u: without the run's l_a (the reference
    of Pi) it refuses in one line; with it, the bracket (tests/analysis/test_network_stability_weighted.py)."""
    with pytest.raises(ParameterError, match=r"^stability: .*unit_alignment_length.*alignment_length") as err:
        stability.threshold(network_from_dict(HAND_WRITTEN), starts=1, samples=2)
    assert "\n" not in str(err.value)
    found = stability.threshold(network_from_dict(HAND_WRITTEN), starts=1, samples=2, alignment_length=0.1)
    assert 0 < found.softest < found.coupling <= found.ceiling
    assert stability.threshold(network_from_dict(_plain(HAND_WRITTEN)), starts=1, samples=2).softest > 0

"""The hexagonal patch and the trap unit (analysis.network.geometry): node and bond counts, bond lengths,
boundary masks, refusals."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis.network import Network, hexagonal_patch, ring_index, trap_unit
from elastoactive.core.errors import ParameterError


@pytest.mark.parametrize("rings, nodes", [(1, 7), (2, 19), (3, 37), (4, 61), (5, 91), (6, 127)])
def test_hexagonal_patch_counts(rings, nodes):
    net = hexagonal_patch(rings)
    assert net.positions.shape == (nodes, 2) == (1 + 3 * rings * (rings + 1), 2)
    assert net.bonds.shape == (3 * rings * (3 * rings + 1), 2)
    # every bond has unit length, and every pair of nodes at unit distance is a bond (no duplicates)
    d = np.linalg.norm(net.positions[net.bonds[:, 0]] - net.positions[net.bonds[:, 1]], axis=1)
    np.testing.assert_allclose(d, 1.0, atol=1e-12)
    pairs = {tuple(sorted(b)) for b in net.bonds.tolist()}
    assert len(pairs) == len(net.bonds)
    all_d = np.linalg.norm(net.positions[:, None] - net.positions[None], axis=-1)
    i, j = np.nonzero(np.triu(np.abs(all_d - 1.0) < 1e-9, 1))
    assert set(zip(i.tolist(), j.tolist())) == pairs
    # bulk nodes have six neighbours, corners three
    degree = np.bincount(net.bonds.ravel(), minlength=nodes)
    ring = ring_index(rings)
    assert np.all(degree[ring < rings] == 6)
    assert np.sort(degree[ring == rings])[:6].tolist() == [3] * 6
    np.testing.assert_allclose(net.rest_lengths, 1.0)
    np.testing.assert_allclose(net.stiffness, 1.0)
    np.testing.assert_allclose(net.anchors, net.positions)
    assert net.trap == 0.0


def test_boundary_masks():
    pinned = hexagonal_patch(2, "pinned")
    assert pinned.pinned.sum() == 12 and np.all(pinned.active == ~pinned.pinned)
    assert np.array_equal(pinned.pinned, ring_index(2) == 2)
    assert np.linalg.norm(pinned.positions[pinned.pinned], axis=1).min() > np.sqrt(3) - 1e-9
    free = hexagonal_patch(2, "free")
    assert not free.pinned.any() and free.active.all()
    centre = hexagonal_patch(3, "centre")
    assert centre.pinned.tolist() == [True] + [False] * 36
    np.testing.assert_allclose(centre.positions[0], 0.0)
    assert centre.active.sum() == 36


def test_trap_unit():
    net = trap_unit(0.5)
    assert isinstance(net, Network) and net.positions.shape == (1, 2) and net.bonds.shape == (0, 2)
    assert net.active.tolist() == [True] and net.pinned.tolist() == [False] and net.trap == 0.5


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: hexagonal_patch(0), "rings"),
        (lambda: hexagonal_patch(7), "rings"),
        (lambda: hexagonal_patch(2, "clamped"), "boundary"),
        (lambda: trap_unit(0.0), "trap"),
    ],
)
def test_refusals_name_the_parameter(call, name):
    with pytest.raises(ParameterError, match=name):
        call()


def test_initial_state_is_seeded_and_holds_the_pins():
    from elastoactive.analysis.network import initial_state

    net = hexagonal_patch(2)
    a, b, c = initial_state(net, 0.01, 3), initial_state(net, 0.01, 3), initial_state(net, 0.01, 4)
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.polarity, b.polarity)
    assert not np.array_equal(a.polarity, c.polarity)
    push = np.linalg.norm(a.positions - net.positions, axis=1)
    assert np.all(push[net.pinned] == 0) and 0 < push[~net.pinned].max() <= 0.01
    assert a.polarity.shape == (7,) and np.all((a.polarity >= 0) & (a.polarity < 2 * np.pi))

"""The initial state of a network run, the same for both engines: the nodes at rest plus small seeded pushes, the
active units' polarities seeded uniformly on the circle (the experiments start from units pointing anywhere)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .geometry import Network


class NetworkState(NamedTuple):
    """A network's state: lab positions of every node (pinned ones at their rest position) and the polarity
    angles psi of the active units, in node order."""

    positions: np.ndarray  # (P, 2)
    polarity: np.ndarray  # (A,) with A = network.active.sum()


def initial_state(network: Network, perturbation: float, seed: int) -> NetworkState:
    """Free nodes pushed from rest by independent seeded displacements of length up to `perturbation` (units a,
    uniform directions); polarities uniform in [0, 2 pi). One generator, seeded by `seed`: pushes first, then
    polarities."""
    rng = np.random.default_rng(seed)
    count = network.n_nodes
    length = perturbation * rng.random(count)
    angle = 2.0 * np.pi * rng.random(count)
    push = np.column_stack([length * np.cos(angle), length * np.sin(angle)])
    push[network.pinned] = 0.0
    polarity = 2.0 * np.pi * rng.random(int(np.count_nonzero(network.active)))
    return NetworkState(network.positions + push, polarity)

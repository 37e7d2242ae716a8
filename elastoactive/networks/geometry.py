"""Geometry of elastic networks of active units: where the nodes sit, which springs join them, which are held.

Pure numpy. A `Network` is everything the two engines need to build the same structure: the nodes' rest positions,
the springs (node pairs, rest lengths, stiffnesses in units of k), which nodes are pinned at their rest position,
which carry an active unit, and an optional isotropic harmonic trap pulling every free node to its anchor.

Units: spring stiffness k = 1, rest length a = 1 (the lattice spacing).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from elastoactive.errors import ParameterError

BOUNDARIES = ("pinned", "free", "centre")
"""How a hexagonal patch is held: its outer ring pinned, nothing pinned, or only its centre node pinned."""
MAX_RINGS = 6
"""Largest hexagonal patch (127 nodes)."""

_NEIGHBOURS = ((1, 0), (0, 1), (-1, 1))
"""Axial steps to three of a triangular-lattice node's six neighbours (the other three are their opposites)."""


class Network(NamedTuple):
    """An elastic network of active units (units k = 1, a = 1)."""

    positions: np.ndarray  # (P, 2) rest positions of the nodes
    bonds: np.ndarray  # (B, 2) int: node indices joined by a spring
    rest_lengths: np.ndarray  # (B,)
    stiffness: np.ndarray  # (B,) spring stiffness (units k)
    pinned: np.ndarray  # (P,) bool: node held fixed at its rest position
    active: np.ndarray  # (P,) bool: node carries an active unit
    anchors: np.ndarray  # (P, 2) the trap's centre for each node
    trap: float  # stiffness of an isotropic harmonic trap pulling each free node to its anchor (0: none)

    @property
    def n_nodes(self) -> int:
        return len(self.positions)

    @property
    def free(self) -> np.ndarray:
        """(P,) bool: nodes that move."""
        return ~self.pinned


def hexagonal_axial(rings: int) -> np.ndarray:
    """(P, 2) int axial coordinates (q, r) of a hexagon of `rings` rings, ring by ring from the centre (the centre,
    then ring 1, ...), each ring counter-clockwise."""
    out = [(0, 0)]
    corners = ((1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1))
    for ring in range(1, rings + 1):
        for side in range(6):
            (cq, cr), (nq, nr) = corners[side], corners[(side + 1) % 6]
            for step in range(ring):
                out.append((ring * cq + step * (nq - cq), ring * cr + step * (nr - cr)))
    return np.asarray(out, dtype=int)


def ring_index(rings: int) -> np.ndarray:
    """(P,) the ring each node of hexagonal_patch(rings) lies on (0: the centre)."""
    axial = hexagonal_axial(rings)
    q, r = axial[:, 0], axial[:, 1]
    return np.maximum(np.maximum(np.abs(q), np.abs(r)), np.abs(q + r))


def hexagonal_patch(rings: int, boundary: str = "pinned") -> Network:
    """A triangular lattice of spacing 1 cut to a hexagon of `rings` rings about the origin: 1 + 3R(R+1) nodes,
    3R(3R+1) unit springs. boundary "pinned": the outer ring pinned and passive, the inner nodes active; "free":
    every node free and active; "centre": the centre node pinned and passive, the others active. No trap."""
    if isinstance(rings, bool) or not isinstance(rings, (int, np.integer)) or not 1 <= rings <= MAX_RINGS:
        raise ParameterError(
            f"rings (rings of the hexagonal patch R) must be an integer in 1..{MAX_RINGS}, got {rings!r}"
        )
    if boundary not in BOUNDARIES:
        raise ParameterError(f"boundary must be one of {', '.join(BOUNDARIES)}, got {boundary!r}")
    axial = hexagonal_axial(int(rings))
    index = {tuple(c): i for i, c in enumerate(axial.tolist())}
    bonds = []
    for i, (q, r) in enumerate(axial.tolist()):
        for dq, dr in _NEIGHBOURS:
            j = index.get((q + dq, r + dr))
            if j is not None:
                bonds.append((i, j))
    bonds = np.asarray(bonds, dtype=int)
    positions = np.column_stack([axial[:, 0] + 0.5 * axial[:, 1], 0.5 * np.sqrt(3.0) * axial[:, 1]])
    ring = ring_index(int(rings))
    if boundary == "pinned":
        pinned = ring == rings
    elif boundary == "centre":
        pinned = ring == 0
    else:
        pinned = np.zeros(len(axial), dtype=bool)
    return Network(
        positions=positions,
        bonds=bonds,
        rest_lengths=np.ones(len(bonds)),
        stiffness=np.ones(len(bonds)),
        pinned=pinned,
        active=~pinned,
        anchors=positions.copy(),
        trap=0.0,
    )


def trap_unit(trap: float = 1.0) -> Network:
    """A single active node at the origin held by an isotropic harmonic trap of stiffness `trap` (units k)."""
    trap = float(trap)
    if not np.isfinite(trap) or trap <= 0:
        raise ParameterError(f"trap (stiffness of the harmonic trap) must be > 0, got {trap}")
    return Network(
        positions=np.zeros((1, 2)),
        bonds=np.empty((0, 2), dtype=int),
        rest_lengths=np.empty(0),
        stiffness=np.empty(0),
        pinned=np.zeros(1, dtype=bool),
        active=np.ones(1, dtype=bool),
        anchors=np.zeros((1, 2)),
        trap=trap,
    )

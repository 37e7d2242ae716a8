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

    @property
    def n_bonds(self) -> int:
        return len(self.bonds)


def make_network(
    nodes,
    bonds,
    pinned=(),
    units=None,
    stiffness=1.0,
    rest_lengths=None,
    trap: float = 0.0,
) -> Network:
    """A checked Network from plain data (units k = 1, a = 1).

    nodes         (P, 2) rest positions
    bonds         (B, 2) pairs of distinct node indices joined by a spring (each pair at most once)
    pinned        indices of the nodes held at their rest position
    units         indices of the nodes carrying an active unit (None: every node not pinned)
    stiffness     one stiffness for every spring, or (B,) values > 0
    rest_lengths  (B,) rest lengths > 0 (None: each bond's length between its nodes' positions)
    trap          stiffness of an isotropic trap pulling each free node to its rest position (0: none)

    A bad field is refused in one line naming it (`check`)."""
    positions = _array("nodes", nodes, float)
    count = len(positions) if positions.ndim == 2 else 0
    bonds = _array("bonds", bonds, int, empty=(0, 2))
    pinned_mask = _mask("pinned", pinned, count)
    active = ~pinned_mask if units is None else _mask("units", units, count)
    stiffness = _array("stiffness", stiffness, float)
    if stiffness.ndim == 0:
        stiffness = np.full(len(bonds), float(stiffness))
    if rest_lengths is None:
        if positions.ndim == 2 and positions.shape[1:] == (2,) and bonds.ndim == 2 and bonds.shape[1:] == (2,):
            inside = np.all((bonds >= 0) & (bonds < count), axis=1)
            rest_lengths = np.zeros(len(bonds))
            ends = bonds[inside]
            rest_lengths[inside] = np.linalg.norm(positions[ends[:, 1]] - positions[ends[:, 0]], axis=1)
        else:
            rest_lengths = np.ones(len(bonds))
    network = Network(
        positions=positions,
        bonds=bonds,
        rest_lengths=_array("rest_lengths", rest_lengths, float),
        stiffness=stiffness,
        pinned=pinned_mask,
        active=active,
        anchors=positions.copy(),
        trap=float(trap),
    )
    check(network)
    return network


def _array(name: str, values, kind: type, empty: tuple[int, ...] | None = None) -> np.ndarray:
    """`values` as a numpy array of `kind`, or a ParameterError naming the field."""
    try:
        out = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"network {name} must be numbers, got {values!r:.80}") from None
    if empty is not None and out.size == 0:
        return np.empty(empty, dtype=kind)
    if kind is int:
        if not np.all(np.isfinite(out)) or np.any(out != np.round(out)):
            raise ParameterError(f"network {name} must be integer node indices")
        return out.astype(int)
    return out


def _mask(name: str, indices, count: int) -> np.ndarray:
    """(count,) bool mask of a list of node indices, or a ParameterError naming the field."""
    indices = _array(name, indices, int, empty=(0,))
    if indices.ndim != 1:
        raise ParameterError(f"network {name} must be a list of node indices, got shape {indices.shape}")
    bad = indices[(indices < 0) | (indices >= count)]
    if bad.size:
        raise ParameterError(f"network {name}: node {int(bad[0])} does not exist (nodes 0..{count - 1})")
    if len(np.unique(indices)) != len(indices):
        raise ParameterError(f"network {name}: a node is listed twice")
    mask = np.zeros(count, dtype=bool)
    mask[indices] = True
    return mask


def check(network: Network) -> None:
    """Refuse a network the engines cannot run as given, in one line naming the field: positions (P, 2) finite with
    P >= 1 and no two nodes at one place; bonds (B, 2) pairs of distinct existing nodes, each pair once; rest lengths
    and stiffnesses B finite values > 0; pinned and active (P,) masks, no unit on a pinned node; anchors (P, 2)
    finite; trap finite >= 0."""
    positions = np.asarray(network.positions, dtype=float)
    if positions.ndim != 2 or positions.shape[1] != 2 or len(positions) == 0:
        raise ParameterError(f"network nodes must be (P, 2) positions with P >= 1, got shape {positions.shape}")
    if not np.all(np.isfinite(positions)):
        raise ParameterError(
            f"network nodes: node {int(np.flatnonzero(~np.isfinite(positions))[0] // 2)} is not finite"
        )
    count = len(positions)
    _, first, counts = np.unique(positions, axis=0, return_index=True, return_counts=True)
    if np.any(counts > 1):
        raise ParameterError(f"network nodes: node {int(first[counts > 1][0])} and another sit at the same position")
    bonds = np.asarray(network.bonds)
    if bonds.ndim != 2 or bonds.shape[1] != 2:
        raise ParameterError(f"network bonds must be (B, 2) node pairs, got shape {bonds.shape}")
    for b, (i, j) in enumerate(bonds.tolist()):
        if not (0 <= i < count and 0 <= j < count):
            raise ParameterError(
                f"network bonds: bond {b} ({i}, {j}) names a node that does not exist (0..{count - 1})"
            )
        if i == j:
            raise ParameterError(f"network bonds: bond {b} joins node {i} to itself")
    if len(bonds):
        pairs = np.sort(bonds, axis=1)
        _, first, counts = np.unique(pairs, axis=0, return_index=True, return_counts=True)
        if np.any(counts > 1):
            b = int(first[counts > 1][0])
            raise ParameterError(f"network bonds: the pair ({bonds[b, 0]}, {bonds[b, 1]}) is bonded twice")
    for name in ("rest_lengths", "stiffness"):
        values = np.asarray(getattr(network, name), dtype=float)
        if values.shape != (len(bonds),):
            raise ParameterError(
                f"network {name} must have one value per bond ({len(bonds)}), got shape {values.shape}"
            )
        bad = np.flatnonzero(~(np.isfinite(values) & (values > 0)))
        if bad.size:
            raise ParameterError(f"network {name} must be finite and > 0, got {values[bad[0]]} for bond {bad[0]}")
    for name in ("pinned", "active"):
        mask = np.asarray(getattr(network, name))
        if mask.shape != (count,) or mask.dtype != bool:
            raise ParameterError(f"network {name} must be a ({count},) boolean mask, got {mask.dtype} {mask.shape}")
    both = np.flatnonzero(np.asarray(network.pinned) & np.asarray(network.active))
    if both.size:
        raise ParameterError(f"network units: node {int(both[0])} is pinned and cannot carry a unit")
    anchors = np.asarray(network.anchors, dtype=float)
    if anchors.shape != (count, 2) or not np.all(np.isfinite(anchors)):
        raise ParameterError(f"network anchors must be ({count}, 2) finite positions, got shape {anchors.shape}")
    trap = network.trap
    if (
        isinstance(trap, bool)
        or not isinstance(trap, (int, float, np.floating))
        or not (np.isfinite(trap) and trap >= 0)
    ):
        raise ParameterError(f"network trap must be a finite stiffness >= 0, got {trap!r}")


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
    return _triangular_hexagon(int(rings), boundary)


def _triangular_hexagon(rings: int, boundary: str) -> Network:
    """hexagonal_patch's network for any number of rings (its arguments already checked)."""
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
    ring = np.maximum(np.maximum(np.abs(axial[:, 0]), np.abs(axial[:, 1])), np.abs(axial.sum(axis=1)))
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

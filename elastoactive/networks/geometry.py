"""Geometry of elastic networks of active units: where the nodes sit, which springs join them, which are held.

Pure numpy. A `Network` is everything the two engines need to build the same structure: the nodes' rest positions,
the springs (node pairs, rest lengths, stiffnesses in units of k), which nodes are pinned at their rest position,
which carry an active unit, and an optional isotropic harmonic trap pulling every free node to its anchor. Each unit
may have its own force (a factor of the run's sigma) and alignment length (in place of the run's alignment_length);
left out (None), every unit has the run's, and a run is the same to the last digit.

Units: spring stiffness k = 1, rest length a = 1 (the lattice spacing).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from elastoactive.core.errors import ParameterError

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
    unit_force: np.ndarray | None = None  # (A,) each unit's force as a factor of sigma, node order (None: 1 each)
    unit_alignment_length: np.ndarray | None = None  # (A,) each unit's l_a, units a (None: the run's alignment_length)

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

    @property
    def n_units(self) -> int:
        return int(np.count_nonzero(self.active))


def unit_forces(network: Network, sigma: float) -> np.ndarray:
    """(A,) each unit's active force F_u / (k a) in node order: sigma times its factor (exactly sigma without
    factors)."""
    if network.unit_force is None:
        return np.full(network.n_units, float(sigma))
    return float(sigma) * np.asarray(network.unit_force, dtype=float)


def unit_alignment_lengths(network: Network, alignment_length: float) -> np.ndarray:
    """(A,) each unit's alignment length l_u (units a) in node order: its own, else the run's `alignment_length`."""
    if network.unit_alignment_length is None:
        return np.full(network.n_units, float(alignment_length))
    return np.array(network.unit_alignment_length, dtype=float)


def has_unit_fields(network: Network) -> bool:
    """Whether some unit has a force or alignment length of its own (not the run's sigma and alignment_length)."""
    return network.unit_force is not None or network.unit_alignment_length is not None


def turning_scale(network: Network, alignment_length: float) -> float:
    """The fastest unit's turning rate over the run's Pi = sigma / l_a: max_u f_u l_a / l_u (f_u its force factor,
    l_u its alignment length); exactly 1 when every unit has the run's force and alignment length."""
    if not has_unit_fields(network) or network.n_units == 0:
        return 1.0
    lengths = unit_alignment_lengths(network, alignment_length)
    return float(np.max(unit_forces(network, 1.0) * float(alignment_length) / lengths))


def make_network(
    nodes,
    bonds,
    pinned=(),
    units=None,
    stiffness=1.0,
    rest_lengths=None,
    trap: float = 0.0,
    unit_force=None,
    unit_alignment_length=None,
) -> Network:
    """A checked Network from plain data (units k = 1, a = 1).

    nodes         (P, 2) rest positions
    bonds         (B, 2) pairs of distinct node indices joined by a spring (each pair at most once)
    pinned        indices of the nodes held at their rest position
    units         indices of the nodes carrying an active unit (None: every node not pinned)
    stiffness     one stiffness for every spring, or (B,) values > 0
    rest_lengths  (B,) rest lengths > 0 (None: each bond's length between its nodes' positions)
    trap          stiffness of an isotropic trap pulling each free node to its rest position (0: none)
    unit_force    each unit's force as a factor >= 0 of the run's sigma: one for every unit, or one per unit in the
                  order `units` lists them (node order when None); None: 1 for every unit (0: a passive unit, whose
                  polarity still turns with its node)
    unit_alignment_length  each unit's alignment length > 0 (units a), given as unit_force; None: the run's

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
        unit_force=_per_unit("unit_force", unit_force, units, active),
        unit_alignment_length=_per_unit("unit_alignment_length", unit_alignment_length, units, active),
    )
    check(network)
    return network


def _per_unit(name: str, values, units, active: np.ndarray) -> np.ndarray | None:
    """A per-unit field in node order: None stays None; one value is every unit's; a list holds one value per unit in
    the order `units` lists them (node order when units is None)."""
    if values is None:
        return None
    out = _array(name, values, float)
    count = int(np.count_nonzero(active))
    if out.ndim == 0:
        return np.full(count, float(out))
    if out.shape != (count,):
        raise ParameterError(f"network {name} must be one value, or one per unit ({count}), got shape {out.shape}")
    if units is not None:
        order = np.argsort(np.asarray(units, dtype=int).reshape(-1), kind="stable")
        out = out[order]
    return out


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
    finite; trap finite >= 0; unit_force None or (A,) finite values >= 0, unit_alignment_length None or (A,) finite
    values > 0 (A units)."""
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
    units = np.flatnonzero(np.asarray(network.active))
    for name, low in (("unit_force", 0.0), ("unit_alignment_length", None)):
        values = getattr(network, name)
        if values is None:
            continue
        values = np.asarray(values, dtype=float)
        if values.shape != units.shape:
            raise ParameterError(
                f"network {name} must have one value per unit ({units.size}), got shape {values.shape}"
            )
        bad = np.flatnonzero(~(np.isfinite(values) & ((values >= 0) if low == 0.0 else (values > 0))))
        if bad.size:
            limit = ">= 0" if low == 0.0 else "> 0"
            raise ParameterError(
                f"network {name} must be finite and {limit}, got {values[bad[0]]} for the unit on node {units[bad[0]]}"
            )


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

"""Generators of elastic networks: periodic lattices cut to a patch, and disordered networks.

Every generator returns a checked `Network` (units k = 1, bond length a = 1) whose rest lengths are the bonds' lengths
(no pre-stress), with its nodes ordered from the patch's centre outward (node 0 the most central: the one a "centre"
boundary pins) and every spring of stiffness 1:

  triangular         coordination 6; the hexagonal patch is `hexagonal_patch`'s, node for node
  kagome             corner-sharing triangles, coordination 4
  square             coordination 4; square-diagonals adds both diagonals of every square (springs of length sqrt 2)
  honeycomb          coordination 3 (floppy: it has zero modes even with its edge pinned)
  delaunay           the patch's edge at spacing 1, then random points (at least MIN_SEPARATION apart, as many as the
                     triangular patch has inside its edge) joined by their Delaunay triangulation (scipy.spatial)

A patch is hexagonal (corners at distance `size` along 0, 60, ... degrees: a triangular hexagon of `size` rings) or
rectangular (|x|, |y| <= size). Its edge is the nodes with fewer bonds than the lattice has in the bulk (delaunay: the
perimeter's nodes). The boundary holds it as `hexagonal_patch`'s does: "pinned" (the edge pinned), "free" (nothing),
"centre" (node 0 pinned); every node not pinned carries an active unit. `dilution` removes that fraction of the bonds
at random (seeded by `seed`, after the edge is found).

scipy.spatial is imported inside the generators that search neighbours (_bonds_at, delaunay_points), the
builders' boundary: a network read from its file does not load it.
"""

from __future__ import annotations

import functools

import numpy as np

from ..core.errors import ParameterError
from .geometry import BOUNDARIES, Network, _triangular_hexagon, make_network

LATTICES = ("triangular", "kagome", "square", "square-diagonals", "honeycomb", "delaunay")
"""The generators `generate` offers."""
PATCHES = ("hexagonal", "rectangular")
"""The shapes a lattice is cut to."""
MAX_SIZE = 60
"""Largest patch size (a triangular hexagon of 60 rings: 10 981 nodes)."""
MIN_SEPARATION = 0.6
"""Closest distance (units a) between two of a delaunay network's random points."""
TOLERANCE = 1e-9
"""Distances (units a) within which two lengths count as equal (bonds, the patch's edge)."""

_SQRT3 = float(np.sqrt(3.0))

_CELLS = {
    # (primitive vectors, basis, bond lengths): nearest neighbours at distance 1
    "triangular": (((1.0, 0.0), (0.5, _SQRT3 / 2)), ((0.0, 0.0),), (1.0,)),
    "kagome": (((2.0, 0.0), (1.0, _SQRT3)), ((0.0, 0.0), (1.0, 0.0), (0.5, _SQRT3 / 2)), (1.0,)),
    "square": (((1.0, 0.0), (0.0, 1.0)), ((0.0, 0.0),), (1.0,)),
    "square-diagonals": (((1.0, 0.0), (0.0, 1.0)), ((0.0, 0.0),), (1.0, float(np.sqrt(2.0)))),
    "honeycomb": (((_SQRT3, 0.0), (_SQRT3 / 2, 1.5)), ((0.0, 0.0), (0.0, 1.0)), (1.0,)),
}


def inside(points: np.ndarray, patch: str, size: float) -> np.ndarray:
    """(M,) bool: points in the closed patch of `size` (hexagonal: the hexagon with corners at distance `size` along
    0, 60, ... degrees; rectangular: |x|, |y| <= size)."""
    if patch == "rectangular":
        return np.all(np.abs(points) <= size + TOLERANCE, axis=1)
    apothem = size * _SQRT3 / 2
    out = np.ones(len(points), dtype=bool)
    for angle in (np.pi / 6, np.pi / 2, 5 * np.pi / 6):
        out &= np.abs(points @ np.array([np.cos(angle), np.sin(angle)])) <= apothem + TOLERANCE
    return out


def _centre_out(points: np.ndarray) -> np.ndarray:
    """Order of the points from the origin outward, ties counter-clockwise from the +x axis."""
    radius = np.round(np.hypot(points[:, 0], points[:, 1]), 9)
    angle = np.round(np.mod(np.arctan2(points[:, 1], points[:, 0]), 2 * np.pi), 9)
    return np.lexsort((angle, radius))


def _bonds_at(points: np.ndarray, lengths: tuple[float, ...]) -> np.ndarray:
    """(B, 2) the pairs of points at one of the `lengths` apart (i < j, sorted)."""
    from scipy.spatial import cKDTree  # start-up time: scipy only to build a network

    pairs = np.array(sorted(cKDTree(points).query_pairs(max(lengths) + 1e-6)), dtype=int).reshape(-1, 2)
    distance = np.linalg.norm(points[pairs[:, 1]] - points[pairs[:, 0]], axis=1)
    keep = np.zeros(len(pairs), dtype=bool)
    for length in lengths:
        keep |= np.abs(distance - length) <= 1e-6
    return pairs[keep]


def lattice_points(lattice: str, patch: str, size: int) -> tuple[np.ndarray, np.ndarray]:
    """((P, 2) positions ordered from the centre out, (B, 2) bonds) of a periodic lattice cut to a patch."""
    (a1, a2), basis, lengths = _CELLS[lattice]
    a1, a2, basis = np.asarray(a1), np.asarray(a2), np.asarray(basis)
    span = int(np.ceil(2 * size / min(np.linalg.norm(a1), np.linalg.norm(a2) * _SQRT3 / 2))) + 2
    m, n = np.meshgrid(np.arange(-span, span + 1), np.arange(-span, span + 1), indexing="ij")
    cells = m.reshape(-1, 1) * a1 + n.reshape(-1, 1) * a2
    points = (cells[:, None, :] + basis[None, :, :]).reshape(-1, 2)
    points = points[inside(points, patch, size)]
    points = points[_centre_out(points)]
    return points, _bonds_at(points, lengths)


def edge_of(count: int, bonds: np.ndarray) -> np.ndarray:
    """(P,) bool: the nodes with fewer bonds than the most any node has (the bulk's coordination)."""
    degree = np.bincount(bonds.ravel(), minlength=count)
    return degree < degree.max()


def perimeter(patch: str, size: int) -> np.ndarray:
    """(E, 2) points along the patch's border at spacing 1 (the corners included)."""
    if patch == "rectangular":
        corners = np.array([(size, -size), (size, size), (-size, size), (-size, -size)], dtype=float)
        steps = 2 * size
    else:
        angle = np.arange(6) * np.pi / 3
        corners = size * np.column_stack([np.cos(angle), np.sin(angle)])
        steps = size
    out = []
    for k in range(len(corners)):
        start, end = corners[k], corners[(k + 1) % len(corners)]
        out.extend(start + (end - start) * s / steps for s in range(steps))
    return np.asarray(out)


def delaunay_points(patch: str, size: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """((P, 2) positions ordered from the centre out, (B, 2) bonds, (P,) bool edge) of a disordered network: the
    perimeter's points, then random points inside the patch at least MIN_SEPARATION from every other point (as many
    as the triangular patch has inside its edge, fewer if the darts stop landing), joined by their Delaunay
    triangulation."""
    from scipy.spatial import Delaunay  # start-up time: scipy only to build a network

    border = perimeter(patch, size)
    lattice, bonds = lattice_points("triangular", patch, size)
    wanted = int(np.count_nonzero(~edge_of(len(lattice), bonds)))
    rng = np.random.default_rng(seed)
    cells: dict[tuple[int, int], list[np.ndarray]] = {}  # a grid of cells MIN_SEPARATION wide: the points in each

    def cell(point: np.ndarray) -> tuple[int, int]:
        return int(np.floor(point[0] / MIN_SEPARATION)), int(np.floor(point[1] / MIN_SEPARATION))

    def free(point: np.ndarray) -> bool:
        i, j = cell(point)
        return all(
            np.hypot(*(point - q)) >= MIN_SEPARATION
            for di in (-1, 0, 1)
            for dj in (-1, 0, 1)
            for q in cells.get((i + di, j + dj), ())
        )

    for point in border:
        cells.setdefault(cell(point), []).append(point)
    added: list[np.ndarray] = []
    misses = 0
    while len(added) < wanted and misses < 200 * max(wanted, 1):
        darts = rng.uniform(-size, size, (1024, 2))
        for candidate in darts[inside(darts, patch, size - MIN_SEPARATION)]:
            if len(added) == wanted:
                break
            if not free(candidate):
                misses += 1
                continue
            added.append(candidate)
            cells.setdefault(cell(candidate), []).append(candidate)
    positions = np.vstack([border, np.asarray(added).reshape(-1, 2)])
    edge = np.zeros(len(positions), dtype=bool)
    edge[: len(border)] = True
    order = _centre_out(positions)
    positions, edge = positions[order], edge[order]
    triangles = Delaunay(positions, qhull_options="QJ").simplices
    pairs = np.sort(np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [0, 2]]]), axis=1)
    return positions, np.unique(pairs, axis=0), edge


def _check(lattice: str, patch: str, size, boundary: str, dilution, seed) -> tuple[int, float, int]:
    if lattice not in LATTICES:
        raise ParameterError(f"geometry must be one of {', '.join(LATTICES)} or a network file, got {lattice!r}")
    if patch not in PATCHES:
        raise ParameterError(f"patch must be one of {', '.join(PATCHES)}, got {patch!r}")
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or not 1 <= size <= MAX_SIZE:
        raise ParameterError(f"size (size of the patch) must be an integer in 1..{MAX_SIZE}, got {size!r}")
    if boundary not in BOUNDARIES:
        raise ParameterError(f"boundary must be one of {', '.join(BOUNDARIES)}, got {boundary!r}")
    if isinstance(dilution, bool) or not isinstance(dilution, (int, float)) or not 0 <= dilution < 1:
        raise ParameterError(f"dilution (fraction of bonds removed) must lie in [0, 1), got {dilution!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ParameterError(f"network_seed (seed of the network's randomness) must be an integer >= 0, got {seed!r}")
    return int(size), float(dilution), int(seed)


def generate(
    lattice: str = "triangular",
    patch: str = "hexagonal",
    size: int = 2,
    boundary: str = "pinned",
    dilution: float = 0.0,
    seed: int = 0,
) -> Network:
    """The network of a lattice (LATTICES) cut to a patch (PATCHES) of `size`, held by `boundary` (BOUNDARIES), with
    a fraction `dilution` of its bonds removed at random (`seed` also seeds a delaunay network's points). A bad
    argument is refused in one line naming it, and so is a network that is none: without a bond (a patch too small
    to hold one, or a dilution that removes them all), or one its boundary holds by no node (`held`). The triangular
    hexagon is `hexagonal_patch(size, boundary)`'s to the last digit (without its limit on the rings)."""
    size, dilution, seed = _check(lattice, patch, size, boundary, dilution, seed)
    network = _generate(lattice, patch, size, boundary, dilution, seed)
    held(network, lattice, patch, size, boundary, dilution, seed)
    return Network(*(np.copy(field) if isinstance(field, np.ndarray) else field for field in network))


def held(network: Network, lattice: str, patch: str, size: int, boundary: str, dilution: float, seed: int) -> None:
    """Refuse, in one line naming the parameter, a generated network without a bond (naming size, or dilution where
    the undiluted patch has bonds) or whose boundary (pinned, centre) pins no node (naming size)."""
    where = f"the {lattice} lattice cut to a {patch} patch of size {size}"
    if len(network.bonds) == 0:
        if dilution > 0 and len(_generate(lattice, patch, size, boundary, 0.0, seed).bonds):
            raise ParameterError(
                f"dilution = {dilution:g} removes every bond of {where}: no network is left; use a smaller dilution "
                "or a larger size"
            )
        nodes = f"{network.n_nodes} node" + ("" if network.n_nodes == 1 else "s")
        raise ParameterError(
            f"size = {size}: {where} holds {nodes} and no bond: no network; use size >= "
            f"{_smallest_bonded(lattice, patch, size)}"
        )
    if boundary != "free" and not np.any(network.pinned):
        raise ParameterError(
            f"size = {size}: boundary {boundary} pins no node of {where} (its nodes all have as many bonds); use a "
            "larger size, or boundary free"
        )


def _smallest_bonded(lattice: str, patch: str, size: int) -> int:
    """The smallest patch size above `size` whose undiluted lattice holds a bond."""
    while size < MAX_SIZE and not len(lattice_points(lattice, patch, size + 1)[1]):
        size += 1
    return size + 1


@functools.lru_cache(maxsize=32)
def _generate(lattice: str, patch: str, size: int, boundary: str, dilution: float, seed: int) -> Network:
    if lattice == "triangular" and patch == "hexagonal" and dilution == 0:
        return _triangular_hexagon(size, boundary)
    if lattice == "delaunay":
        positions, bonds, edge = delaunay_points(patch, size, seed)
    else:
        positions, bonds = lattice_points(lattice, patch, size)
        edge = edge_of(len(positions), bonds)
    if dilution > 0:
        rng = np.random.default_rng([seed, 1])
        removed = rng.choice(len(bonds), size=int(round(dilution * len(bonds))), replace=False)
        bonds = np.delete(bonds, removed, axis=0)
    if boundary == "pinned":
        pinned = np.flatnonzero(edge)
    elif boundary == "centre":
        pinned = np.array([0])
    else:
        pinned = np.empty(0, dtype=int)
    return make_network(positions, bonds, pinned=pinned)

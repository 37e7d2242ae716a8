"""The scene `network`: any elastic network of self-aligning active units, from a generator or a file.

Beyond the paper, as `lattice` (whose equations, units, observables and linear stability it shares: docs/network.md):
the network is `geometry`, either a generator of elastoactive.networks.lattices (triangular, kagome, square,
square-diagonals, honeycomb lattices cut to a `patch` of `size`, or a delaunay network of random points; `boundary`
pinned, free or centre; a fraction `dilution` of the bonds removed at random, seeded by `network_seed`, which also
seeds a delaunay network's points), or the path of a network file (elastoactive.networks.files: nodes, bonds, pinned
nodes, units). A file's network is held by what it pins: nothing (free), one node (it turns about it: centre) or more
(held: pinned). The units' force is the run's sigma, times each unit's `unit_force` where the file gives one, and
their alignment length the run's alignment_length, or each unit's `unit_alignment_length` (elastoactive.networks.
geometry; such units' linear stability: the weights of analysis.network.stability).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core import parameters
from ..core.errors import ParameterError
from ..core.parameters import Parameter
from ..core.params import Physics
from ..networks.files import SUFFIX, read_network
from ..networks.geometry import Network
from ..networks.lattices import LATTICES, MAX_SIZE, PATCHES, generate
from .base import ValidationCase
from .lattice import HOLD_WORDS, Lattice

GEOMETRY = Parameter(
    "geometry",
    "triangular",
    f"the network: a generator ({', '.join(LATTICES)}) or the path of a network file ({SUFFIX}, docs/network.md)",
    kind=str,
    title="the network's generator or file",
)
PATCH = Parameter(
    "patch",
    "hexagonal",
    "the shape a generated network is cut to: hexagonal (corners at distance size) or rectangular (|x|, |y| <= size)",
    kind=str,
    choices=PATCHES,
    title="the generated network's patch",
)
SIZE = Parameter(
    "size",
    2,
    f"size of a generated network's patch in bond lengths (1..{MAX_SIZE}; a hexagon of size R: the lattice's R rings)",
    kind=int,
    low=1,
    high=MAX_SIZE,
    title="size of the patch",
)
DILUTION = Parameter(
    "dilution",
    0.0,
    "fraction of a generated network's bonds removed at random (seeded by network_seed)",
    low=0.0,
    high=1.0,
    high_open=True,
    title="fraction of bonds removed",
)
NETWORK_SEED = Parameter(
    "network_seed",
    0,
    "seed of a generated network's randomness (the bonds a dilution removes, a delaunay network's points)",
    kind=int,
    low=0,
    title="seed of the network's randomness",
)
GENERATOR_ONLY = ("patch", "size", "boundary", "dilution", "network_seed")
"""The parameters that shape a generated network (a network file gives its own nodes, bonds, pins and units)."""


def is_file(geometry: str) -> bool:
    """Whether `geometry` names a network file rather than a generator."""
    return geometry not in LATTICES


class NetworkFromData(Lattice):
    name = "network"
    summary = (
        "any elastic network of self-aligning active units: a generated lattice (triangular, kagome, square, "
        "honeycomb, delaunay; diluted) or a network file"
    )
    parameters = (GEOMETRY, PATCH, SIZE, "boundary", DILUTION, NETWORK_SEED)

    def network(self, physics: Physics) -> Network:
        if is_file(physics.geometry):
            if not physics.geometry.endswith(SUFFIX):
                raise ParameterError(
                    f"geometry must be one of {', '.join(LATTICES)} or a network file (*{SUFFIX}), "
                    f"got {physics.geometry!r}"
                )
            return read_network(Path(physics.geometry).expanduser())
        return generate(
            physics.geometry, physics.patch, physics.size, physics.boundary, physics.dilution, physics.network_seed
        )

    def check(self, physics: Physics) -> None:
        if is_file(physics.geometry):
            for name in GENERATOR_ONLY:
                if getattr(physics, name) != parameters.get(name).default:
                    raise ParameterError(
                        f"{name} has no effect on a network file's network (geometry={physics.geometry!r} gives its "
                        "own nodes, bonds, pinned nodes and units)"
                    )
        elif physics.network_seed != NETWORK_SEED.default and physics.geometry != "delaunay" and physics.dilution == 0:
            raise ParameterError(
                f"network_seed has no effect on a {physics.geometry} network without dilution (it seeds the bonds a "
                "dilution removes and a delaunay network's points)"
            )
        super().check(physics)
        network = self.network(physics)
        if not np.any(network.active):
            raise ParameterError(
                f"geometry: the network {physics.geometry!r} carries no active unit; nothing drives it"
            )

    def shaping_parameters(self, physics: Physics) -> tuple[str, ...]:
        """A file's network: its geometry alone (GENERATOR_ONLY shape a generated one only)."""
        own = self.own_parameter_names()
        return tuple(k for k in own if k not in GENERATOR_ONLY) if is_file(physics.geometry) else own

    def hold(self, physics: Physics) -> str:
        """Generated: its boundary. A file's: by how many nodes it pins (none: free, one: centre, more: pinned)."""
        if not is_file(physics.geometry):
            return physics.boundary
        pinned = int(np.count_nonzero(self.network(physics).pinned))
        return "free" if pinned == 0 else "centre" if pinned == 1 else "pinned"

    def held_text(self, physics: Physics) -> str:
        """A file's: the nodes it pins (its own words); a generated network's: its boundary option."""
        if not is_file(physics.geometry):
            return super().held_text(physics)
        pinned = int(np.count_nonzero(self.network(physics).pinned))
        return (
            f"the file {physics.geometry} pins {pinned} node{'' if pinned == 1 else 's'}, which lets it "
            + (HOLD_WORDS[self.hold(physics)])
        )

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (
            ValidationCase(self.physics(geometry="kagome", size=2, sigma=0.2, alignment_length=0.1), 300.0),
            ValidationCase(self.physics(geometry="delaunay", size=2, sigma=0.2, alignment_length=0.1), 300.0),
        )


SCENE = NetworkFromData()

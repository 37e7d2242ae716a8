"""A network as a plain JSON file, read and written here (the format is documented in docs/network.md).

    {
      "format": "elastoactive network",
      "version": 1,
      "nodes": [[0.0, 0.0], [1.0, 0.0], [0.5, 0.866]],    rest positions (units a), one [x, y] per node
      "bonds": [[0, 1], [1, 2], [0, 2]],                   springs: pairs of node indices (from 0)
      "stiffness": 1.0,                                    optional: one value, or one per bond (units k; default 1)
      "rest_lengths": [1.0, 1.0, 1.0],                     optional: one per bond (default: the nodes' distance)
      "pinned": [0, 1],                                    optional: nodes held at their rest position (default none)
      "units": [2],                                        optional: nodes carrying an active unit (default: every
                                                           node not pinned)
      "trap": 0.0,                                         optional: a trap's stiffness pulling each free node to its
                                                           rest position (default 0: none)
      "unit_force": [0.5],                                 optional: each unit's force as a factor of the run's sigma,
                                                           one value or one per unit in the order of "units"
                                                           (default 1)
      "unit_alignment_length": [0.05]                      optional: each unit's alignment length (units a), one value
                                                           or one per unit as unit_force (default: the run's)
    }

Without unit_force and unit_alignment_length every unit has the run's force sigma and alignment length. Any other
key, a missing one or a bad value is refused in one line naming the field and the file.
"""

from __future__ import annotations

import functools
import json
import math
import os
from pathlib import Path

import numpy as np

from ..core.errors import ParameterError
from .geometry import Network, check, make_network

FORMAT = "elastoactive network"
"""The file's "format" value."""
VERSION = 1
"""The format's version, the file's "version" value."""
SUFFIX = ".json"
"""A network file's name ends so."""
REQUIRED = ("nodes", "bonds")
OPTIONAL = (
    "format",
    "version",
    "stiffness",
    "rest_lengths",
    "pinned",
    "units",
    "trap",
    "unit_force",
    "unit_alignment_length",
)


def network_from_dict(data: dict, source: str = "network data") -> Network:
    """The checked Network of a parsed network file (`source` names it in messages)."""
    if not isinstance(data, dict):
        raise ParameterError(f"{source}: a network file holds one JSON object, got {type(data).__name__}")
    unknown = [key for key in data if key not in REQUIRED + OPTIONAL]
    if unknown:
        raise ParameterError(f"{source}: unknown field {unknown[0]!r} (fields: {', '.join(REQUIRED + OPTIONAL)})")
    for key in REQUIRED:
        if key not in data:
            raise ParameterError(f"{source}: the field {key!r} is missing")
    if data.get("format", FORMAT) != FORMAT:
        raise ParameterError(f"{source}: format must be {FORMAT!r}, got {data['format']!r}")
    if data.get("version", VERSION) != VERSION:
        raise ParameterError(f"{source}: version must be {VERSION}, got {data['version']!r}")
    trap = data.get("trap", 0.0)
    if isinstance(trap, bool) or not isinstance(trap, (int, float)) or not math.isfinite(trap) or trap < 0:
        raise ParameterError(f"{source}: trap must be a finite stiffness >= 0, got {trap!r}")
    try:
        return make_network(
            data["nodes"],
            data["bonds"],
            pinned=data.get("pinned", ()),
            units=data.get("units"),
            stiffness=data.get("stiffness", 1.0),
            rest_lengths=data.get("rest_lengths"),
            trap=float(trap),
            unit_force=data.get("unit_force"),
            unit_alignment_length=data.get("unit_alignment_length"),
        )
    except ParameterError as error:
        raise ParameterError(f"{source}: {error}") from None


def network_to_dict(network: Network) -> dict:
    """The network file's object of a network: every field written out (the units' own force and alignment length
    when they have them, in node order as "units" lists them), so that reading it gives the same arrays."""
    check(network)
    if not np.array_equal(np.asarray(network.anchors, dtype=float), np.asarray(network.positions, dtype=float)):
        raise ParameterError("network anchors: a network file anchors each node at its rest position")
    own = {
        name: np.asarray(getattr(network, name), dtype=float).tolist()
        for name in ("unit_force", "unit_alignment_length")
        if getattr(network, name) is not None
    }
    return {
        "format": FORMAT,
        "version": VERSION,
        "nodes": np.asarray(network.positions, dtype=float).tolist(),
        "bonds": np.asarray(network.bonds, dtype=int).tolist(),
        "stiffness": np.asarray(network.stiffness, dtype=float).tolist(),
        "rest_lengths": np.asarray(network.rest_lengths, dtype=float).tolist(),
        "pinned": np.flatnonzero(network.pinned).tolist(),
        "units": np.flatnonzero(network.active).tolist(),
        "trap": float(network.trap),
    } | own


def write_network(network: Network, path: str | os.PathLike) -> Path:
    """Write `network` to the JSON file `path` (its name ending in SUFFIX); returns the path."""
    path = Path(path)
    if path.suffix != SUFFIX:
        raise ParameterError(f"network file {str(path)!r}: its name must end in {SUFFIX}")
    text = json.dumps(network_to_dict(network), indent=1)
    path.write_text(text + "\n")
    return path


def read_network(path: str | os.PathLike) -> Network:
    """The checked Network of the JSON file `path` (read once per version of the file; each call its own arrays)."""
    path = Path(path)
    if path.suffix != SUFFIX:
        raise ParameterError(f"network file {str(path)!r}: its name must end in {SUFFIX}")
    try:
        stat = path.resolve().stat()
    except OSError as error:
        raise ParameterError(f"network file {str(path)!r} cannot be read: {error.strerror}") from None
    network = _read(str(path.resolve()), stat.st_mtime_ns, stat.st_size)
    return Network(*(np.copy(field) if isinstance(field, np.ndarray) else field for field in network))


@functools.lru_cache(maxsize=16)
def _read(path: str, mtime: int, size: int) -> Network:
    try:
        data = json.loads(Path(path).read_text())
    except OSError as error:
        raise ParameterError(f"network file {path!r} cannot be read: {error.strerror}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as error:
        raise ParameterError(f"network file {path!r} is not JSON: {error}") from None
    return network_from_dict(data, f"network file {path!r}")

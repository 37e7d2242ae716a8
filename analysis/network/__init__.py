"""Elastic networks of self-aligning active units (Baconnier et al., Nature Physics 2022): geometry (`geometry`),
the reduced overdamped model, its linear stability and observables. Pure functions on numpy arrays."""

from ...networks.geometry import BOUNDARIES, MAX_RINGS, Network, hexagonal_patch, ring_index, trap_unit
from ...networks.state import NetworkState, initial_state

__all__ = [
    "BOUNDARIES",
    "MAX_RINGS",
    "Network",
    "NetworkState",
    "hexagonal_patch",
    "initial_state",
    "ring_index",
    "trap_unit",
]

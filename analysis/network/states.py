"""The named state of a network run: frozen, collective, mixed chirality, heterogeneous, oscillating or irregular, from
its units' polarities over the measured window, with each ring's rate of turning (docs/network.md, "Named states").

The rule, in this order (T the window's length, dpsi_i = psi_i(end) - psi_i(start) a unit's net turn, unwrapped):

  frozen         every unit's mean |dpsi/dt| is below `still` (still_rate: STILL_FRACTION of the turning scale
                 Pi = sigma / l_a, and never below SOLVER_JITTER x the solver's relative tolerance x Pi)
  oscillating    some unit moves, none turns a full turn (|dpsi_i| < 2 pi), and some unit swings back within the
                 window: its range max psi_i - min psi_i exceeds its net |dpsi_i| by SWING_BACK of the range or more
  undetermined   some unit moves, none turns a full turn, and none swings back: every unit moves one way by less than
                 a turn, which a slow steady turn, a creep towards rest and a swing slower than the window all do; the
                 window cannot tell them apart (NamedState.note: the window a full turn at the units' rates needs)
  mixed          units turn full turns in both senses (mixed chirality)
  collective     every unit turns, all in one sense, and no unit slips a turn against another
                 (max dpsi - min dpsi < 2 pi: one frequency, to the window's resolution 2 pi / T)
  heterogeneous  one sense, but the rates differ: the units nearest the edge turn slowest, slower than the fastest ring
                 by at least a turn over the window (2 pi / T)
  irregular      one sense, rates differing with no such order (none of the above)

A unit's ring is its depth: the fewest bonds from it to the network's edge (`depth`). The thresholds are one turn
over the window (the resolution of a rate measured on it) and the still level, a fraction of the units' own turning
scale far above the solver's error: 1e-3 Pi, and at least 1e3 rtol Pi in the reduced engine (1e-3 Pi again at its
automatic rtol 1e-6 for networks), where still units' measured |dpsi/dt| is 30-160 rtol Pi, the adaptive steps'
jitter (docs/performance.md, section 10).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...networks.geometry import Network
from .observables import SOLVER_JITTER, STILL_FRACTION, unwrapped

STATES = ("frozen", "collective", "mixed", "heterogeneous", "oscillating", "irregular", "undetermined")
"""The named states, in the order a sweep codes them (their index)."""
STATE_MEANING = {
    "frozen": "every unit still",
    "collective": "every unit turns, one sense, one frequency",
    "mixed": "units turn in both senses (mixed chirality)",
    "heterogeneous": "one sense, the edge slower than the interior",
    "oscillating": "units swing without a full turn",
    "irregular": "one sense, rates differing without an edge-to-interior order",
    "undetermined": "units move one way by less than a turn: the window cannot tell a slow drift from an oscillation",
}
"""What each state means, in a few words (docs, figure legends)."""
FULL_TURN = 2.0 * np.pi
"""A unit turns when its net turn over the window is at least one turn; two units share a frequency when their net
turns differ by less than one turn."""
SWING_BACK = 0.1
"""A unit swings back within the window when its range exceeds its net turn by this fraction of the range or more
(an oscillation seen over about 0.6 of its period or longer; a one-way drift: 0)."""


class NamedState(NamedTuple):
    """A run's named state and what it was read from (units of rates: rad per gamma / k)."""

    name: str  # one of STATES
    rates: np.ndarray  # (A,) each unit's net turning rate over the window, signed
    speeds: np.ndarray  # (A,) each unit's mean |dpsi/dt|
    ring_depths: np.ndarray  # (R,) the depths of the units' rings, from the edge in
    ring_rates: np.ndarray  # (R,) mean |net rate| of each ring's units
    counter_fraction: float  # share of the turning units that turn against the majority's sense (0 .. 0.5)
    still: float  # the still level used
    window: float  # the window's length T (gamma / k)

    @property
    def edge_rate(self) -> float:
        """Mean |net rate| of the ring of units nearest the edge."""
        return float(self.ring_rates[0])

    @property
    def bulk_rate(self) -> float:
        """Mean |net rate| of the ring of units deepest inside."""
        return float(self.ring_rates[-1])

    @property
    def needed_window(self) -> float:
        """The window over which the slowest moving unit, at its net rate, would turn a full turn (inf when none
        moves): an undetermined state's units turn, or swing back, within it."""
        moving = np.abs(self.rates[self.speeds >= self.still])
        moving = moving[moving > 0]
        return float(FULL_TURN / moving.min()) if moving.size else float("inf")

    @property
    def note(self) -> str:
        """What an undetermined state means for its run, in one line ("" for the other states)."""
        if self.name != "undetermined":
            return ""
        return (
            f"the window of {self.window:.4g} gamma/k cannot tell a slow drift from an oscillation (every unit moves "
            f"one way by less than a turn); run longer: a window of {self.needed_window:.3g} or more"
        )


def depth(network: Network) -> np.ndarray:
    """(P,) the fewest bonds from each node to the network's edge (0 on it). The edge is its pinned nodes when it pins
    two or more (held), else the nodes with fewer bonds than the most any node has (a free or centre-pinned
    network's outer nodes). Nodes joined to no edge node get the largest depth found plus one."""
    count = network.n_nodes
    pinned = np.asarray(network.pinned, dtype=bool)
    if np.count_nonzero(pinned) >= 2:
        edge = pinned
    else:
        degree = np.bincount(np.asarray(network.bonds).ravel(), minlength=count)
        edge = degree < degree.max() if count > 1 else np.ones(count, dtype=bool)
    neighbours = [[] for _ in range(count)]
    for i, j in np.asarray(network.bonds):
        neighbours[i].append(j)
        neighbours[j].append(i)
    out = np.full(count, -1)
    front = list(np.flatnonzero(edge))
    out[front] = 0
    while front:
        following = []
        for node in front:
            for other in neighbours[node]:
                if out[other] < 0:
                    out[other] = out[node] + 1
                    following.append(other)
        front = following
    out[out < 0] = out.max() + 1
    return out


def still_rate(scale: float, rtol: float | None = None) -> float:
    """The mean |dpsi/dt| below which a unit is still: STILL_FRACTION x the turning scale (Pi = sigma / l_a), at least
    SOLVER_JITTER x the solver's relative tolerance x the scale (None: a fixed-step engine)."""
    level = STILL_FRACTION if rtol is None else max(STILL_FRACTION, SOLVER_JITTER * float(rtol))
    return level * float(scale)


def classify(t: np.ndarray, polarity: np.ndarray, depths: np.ndarray, still: float) -> NamedState:
    """The named state of units whose angles are `polarity` (T, A) at times `t` (the measured window), on rings of
    depth `depths` (A,) from the edge, a unit being still below `still` (still_rate). The rule: the module's
    docstring."""
    t = np.asarray(t, dtype=float)
    psi = unwrapped(polarity)
    depths = np.asarray(depths)
    span = float(t[-1] - t[0])
    turns = psi[-1] - psi[0]
    rates = turns / span
    speeds = np.abs(np.gradient(psi, t, axis=0)).mean(axis=0)
    ring_depths = np.unique(depths)
    ring_rates = np.array([np.abs(rates[depths == d]).mean() for d in ring_depths])
    turning = np.abs(turns) >= FULL_TURN
    senses = np.sign(turns[turning])
    minority = min(np.count_nonzero(senses > 0), np.count_nonzero(senses < 0))
    counter = float(minority / senses.size) if senses.size else 0.0

    def named(name: str) -> NamedState:
        return NamedState(name, rates, speeds, ring_depths, ring_rates, counter, float(still), span)

    moving = speeds >= still
    if not np.any(moving):
        return named("frozen")
    if not np.any(turning):
        reach = psi.max(axis=0) - psi.min(axis=0)
        swung = reach - np.abs(turns) >= SWING_BACK * reach
        return named("oscillating" if np.any(swung & moving) else "undetermined")
    if minority > 0:
        return named("mixed")
    if np.all(turning) and turns.max() - turns.min() < FULL_TURN:
        return named("collective")
    resolution = FULL_TURN / span
    if ring_rates[0] == ring_rates.min() and ring_rates.max() - ring_rates[0] >= resolution:
        return named("heterogeneous")
    return named("irregular")

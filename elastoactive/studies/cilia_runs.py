"""What the cilia studies share (cilium_states, cilia_pair_sync, cilia_row_waves): cilia of the scene `cilium` standing
on the no-slip wall through the Rotne-Prager-Blake mobility, run by the reduced engine (elastoactive.reduced.fluid)
from starts the studies set themselves, and the numbers read off their tips.

Starts. A single cilium starts from a push (`push`): planar (in the chain's xy plane, the lab's xz plane, which the
wall's mirror symmetry y -> -y keeps invariant bit for bit), a helix (as much out of that plane), or tilted (planar
plus TILT out of it). A pair or a row starts on the isolated cilium's limit cycle (`limit_cycle`: one period of
its shapes, sampled CYCLE_SAMPLES times), cilium m at a chosen phase of it (`on_cycle`): the start's phase lags are
then the lags of the tips' signals at t = 0 (up to the cycle's own phase, the same for every cilium), not a push
whose phase the run sets.

Phases. Every cilium's tip is projected on one axis in the wall's plane (analysis.cilia.tip_signals) and its Hilbert
phase read (analysis.cilia.pair_locking); the whirls' senses are the signs of analysis.motion3d's whirl rates.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..analysis.motion3d import measure3d
from ..core.errors import ParameterError
from ..reduced.fluid import Beds, lab_positions, solve_fluid
from ..scenes.cilium import FLUID_TOLERANCES, ROTATION

RADIUS = 0.1
"""Bead radius a / l of every cilium of the studies (the scenes' usual value: a slender chain, a / l << 1)."""
BASE_HEIGHT = 0.5
"""Height h of every cilium's base above the wall (l): the scene cilium's default."""
PUSH = 0.3
"""The push's angle scale: link k of N turned by PUSH s_k (s_k = k / N) in the chain's y, and (helix) PUSH s_k^2
in z."""
TILT = 1e-3
"""The tilted start's out-of-plane push (PUSH's form in z, this scale): a planar start barely out of its plane."""
STARTS = ("planar", "tilted", "helix")
CYCLES = ("beat", "whirl")
"""The isolated cilium's limit cycles a pair or row starts on: the planar beat (from the planar push; it stays in
the lab's xz plane, the plane of the bases) and the whirl (from the helix)."""
CYCLE_SETTLE = 40
"""Expected periods (FREQUENCY_EXPONENT's law) the isolated cilium runs before its limit cycle is sampled."""
CYCLE_SAMPLES = 200
"""Shapes per period of a limit cycle."""
SAMPLES_PER_PERIOD = 40
"""Samples per period of the runs whose phases are read (the Hilbert phase of a tip signal)."""
FREQUENCY_EXPONENT = 1.25
"""The expected frequency f_c (sigma / sigma_c)^FREQUENCY_EXPONENT that plans run lengths (N = 5 and 7 on the wall at
a / l = 0.1: the whirl's 1.8 f_c at 1.5 sigma_c, 4.5 f_c at 3, 10 f_c at 6)."""


def wall_beds(n: int, sigma: float, bases) -> Beds:
    """Cilia of n links at `bases` (C, 3) on the wall, through the Rotne-Prager-Blake mobility (a / l = RADIUS)."""
    return Beds(n, float(sigma), np.asarray(bases, dtype=float), ROTATION, "rpb", RADIUS).checked()


def row_bases(count: int, spacing: float) -> np.ndarray:
    """Base points (count, 3) of cilia `spacing` apart along x at height BASE_HEIGHT (scenes.cilium.bases')."""
    c = np.arange(count, dtype=float)
    return np.stack([c * spacing, np.zeros_like(c), np.full_like(c, BASE_HEIGHT)], axis=1)


def push(n: int, start: str) -> np.ndarray:
    """The start's chain-frame tangents (N, 3), unit length (STARTS)."""
    if start not in STARTS:
        raise ParameterError(f"start must be one of {', '.join(STARTS)}, got {start!r}")
    s = np.arange(1, n + 1) / n
    z = {"planar": 0.0 * s, "tilted": TILT * s, "helix": PUSH * s * s}[start]
    t = np.column_stack([np.ones(n), PUSH * s, z])
    return t / np.linalg.norm(t, axis=1)[:, None]


def expected_period(f_c: float, load: float) -> float:
    """The period FREQUENCY_EXPONENT's law expects at sigma = load sigma_c (tau)."""
    return 1.0 / (f_c * load**FREQUENCY_EXPONENT)


def run(beds: Beds, ts: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Chain-frame tangents (T, C, N, 3) from start (C, N, 3), at the scene's fluid tolerances."""
    rtol, atol = FLUID_TOLERANCES
    return solve_fluid(beds, ts, start, rtol=rtol, atol=atol)


def tips(path: np.ndarray, beds: Beds) -> np.ndarray:
    """The particles' lab positions (T, C, N, 3) of a run's tangents."""
    t = path / np.linalg.norm(path, axis=-1, keepdims=True)
    return lab_positions(t, beds)


class Cycle(NamedTuple):
    """One period of an isolated cilium's limit cycle."""

    shapes: np.ndarray
    """Chain-frame tangents (CYCLE_SAMPLES, N, 3) at evenly spaced phases of one period."""
    period: float
    state: str
    """analysis.motion3d's state of the cycle (beat or whirl, as asked; otherwise the study says so)."""


def limit_cycle(n: int, sigma: float, cycle: str, f_c: float, load: float) -> Cycle:
    """The isolated cilium's beat (from the planar push) or whirl (from the helix) at sigma, after CYCLE_SETTLE
    expected periods, one period of it sampled CYCLE_SAMPLES times."""
    if cycle not in CYCLES:
        raise ParameterError(f"cycle must be one of {', '.join(CYCLES)}, got {cycle!r}")
    beds = wall_beds(n, sigma, row_bases(1, 1.0))
    settle = CYCLE_SETTLE * expected_period(f_c, load)
    ts = np.linspace(0.0, settle, CYCLE_SETTLE * SAMPLES_PER_PERIOD + 1)
    path = run(beds, ts, push(n, "planar" if cycle == "beat" else "helix")[None])[:, 0]
    m = measure3d(ts, path, transient=0.6 * settle)
    period = 1.0 / m.frequency
    ts = np.linspace(0.0, period, CYCLE_SAMPLES + 1)
    shapes = run(beds, ts, path[-1][None])[:-1, 0]
    return Cycle(shapes, period, m.state)


def on_cycle(cycle: Cycle, phases) -> np.ndarray:
    """Tangents (C, N, 3): cilium c at phase phases[c] (rad) of the cycle (the sample nearest it)."""
    k = len(cycle.shapes)
    index = [int(round((float(p) / (2 * math.pi)) % 1.0 * k)) % k for p in phases]
    return np.stack([cycle.shapes[i] for i in index])

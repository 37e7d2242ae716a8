"""Observables of a network run, as pure functions of its record (times, node positions, polarities).

polarization        time mean of |(1/A) sum_i n_i|: the units' polar order (1: all point the same way)
polarity_rate       mean over the window and the units of dpsi_i/dt (rad per gamma / k): the polarities' common
                    turning rate, its sign the sense of rotation (0 at a fixed point, and near 0 when as many units
                    turn one way as the other)
polarity_speed      mean over the window and the units of |dpsi_i/dt|: how fast the units turn whatever their sense
                    (actuation ~ |polarity_rate| / polarity_speed)
actuation           |<dpsi/dt>| / <|dpsi/dt|> over the units and the window: 1 when every unit turns the same way
                    at the same rate (collective actuation), near 0 for incoherent turning, 0 for still units
mode energies       the displacements from rest (the patch's rigid motion taken out, `body_positions`) projected on
                    the dynamical matrix's normal modes, energy lambda_m <a_m^2> / 2 per mode, canonical within a
                    degenerate eigenspace (its principal axes); `condensation` is the share of the two most energetic
                    modes (1: the dynamics has condensed on two modes), `dominant_modes` their 1-based ranks by
                    stiffness (1: the softest; 0: none, an undeformed patch)
mode space          the eigenspace holding the most energy (a degenerate pair counted as one): its softest mode's
                    rank, its dimension and its energy share (`mode_space`)
rotation, drift     the patch's rigid motion: its rotation angle about a point (its least-squares rotation of the
                    displacements) and mean rate, and its centroid's drift (distance over the window's length)
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

STILL_RATE = 1e-6
"""rad / (gamma / k): units turning slower than this on average are still (actuation 0), at the least."""
STILL_FRACTION = 1e-3
"""Units whose mean |dpsi/dt| is below this fraction of their turning scale sigma / l_a are still: the decaying
residue of a rest state (~1e-5 rad per gamma / k after 100 gamma / k) has no direction worth a ratio (and a unit
is still in the named states, analysis.network.states)."""
SOLVER_JITTER = 1e3
"""An adaptive solver's error in a unit's |dpsi/dt| is below this many times its relative tolerance x the turning
scale Pi: still units measured 30-160 rtol Pi (the steps' jitter about a fixed point, sampled every 0.05 gamma / k;
docs/performance.md, section 10). The named states' still level never goes below it, and polarity_speed's error
counts it (block_errors)."""


CHUNK = 64
"""Samples per pass where an observable of every unit is reduced sample by sample (polarization): temporaries of
CHUNK x units stay small."""


def window(t: np.ndarray, transient: float) -> np.ndarray:
    """Boolean mask of the samples after the transient (measured from the first sample)."""
    t = np.asarray(t, dtype=float)
    return t - t[0] >= transient - 1e-12 * max(1.0, transient)


def unwrapped(polarity: np.ndarray) -> np.ndarray:
    """(T, A) angles continuous in time: as given where no step between samples exceeds pi (the reduced engine's
    polarities are never wrapped: checked, not copied), else np.unwrap along time. Equal to np.unwrap either way."""
    psi = np.asarray(polarity, dtype=float)
    if psi.shape[0] < 2 or float(np.abs(np.diff(psi, axis=0)).max(initial=0.0)) <= np.pi:
        return psi
    return np.unwrap(psi, axis=0)


def polarization(polarity: np.ndarray) -> float:
    """Time mean of |(1/A) sum_i exp(i psi_i)| over the samples given ((T, A) angles), CHUNK samples at a time (no
    complex (T, A) temporary: a large network's record is hundreds of MB)."""
    psi = np.asarray(polarity, dtype=float)
    if psi.shape[0] == 0:
        return float("nan")
    order = [
        np.hypot(np.cos(part).mean(axis=1), np.sin(part).mean(axis=1))
        for part in (psi[k : k + CHUNK] for k in range(0, psi.shape[0], CHUNK))
    ]
    return float(np.concatenate(order).mean())


def turning_rates(t: np.ndarray, polarity: np.ndarray) -> np.ndarray:
    """(T, A) dpsi/dt by finite differences of the unwrapped angles."""
    return np.gradient(unwrapped(polarity), np.asarray(t, dtype=float), axis=0)


def polarity_speed(t: np.ndarray, polarity: np.ndarray) -> float:
    """Mean |dpsi/dt| over the samples and the units: how fast the units turn, whichever way (rad per gamma / k)."""
    return float(np.abs(turning_rates(t, polarity)).mean())


def polarity_rate(t: np.ndarray, polarity: np.ndarray) -> float:
    """Mean dpsi/dt over the samples and the units: (psi(end) - psi(start)) / duration, averaged over the units."""
    psi = unwrapped(polarity)
    return float(((psi[-1] - psi[0]) / (t[-1] - t[0])).mean())


def actuation(t: np.ndarray, polarity: np.ndarray, scale: float = 0.0, rtol: float | None = None) -> float:
    """|<dpsi/dt>| / <|dpsi/dt|> over the units and samples (0 when the units are still: turning on average slower than
    STILL_RATE or STILL_FRACTION x `scale`, their turning scale sigma / l_a, or, for an adaptive solver's run of
    relative tolerance `rtol`, than SOLVER_JITTER x rtol x scale: the named states' still level)."""
    rates = turning_rates(t, polarity)
    magnitude = float(np.abs(rates).mean())
    jitter = 0.0 if rtol is None else SOLVER_JITTER * float(rtol)
    if magnitude < max(STILL_RATE, max(STILL_FRACTION, jitter) * scale):
        return 0.0
    return float(abs(rates.mean()) / magnitude)


ERROR_BLOCKS = 8
"""Consecutive equal blocks of the measured window whose spread gives a time mean's standard error (block_errors)."""


class BlockErrors(NamedTuple):
    """Errors of a run's time means: the standard error from the spread of their values on ERROR_BLOCKS consecutive
    blocks of the window, std / sqrt(blocks) (NaN when a block holds fewer than 3 samples), and, for an adaptive
    solver's run, its own error added in quadrature (block_errors)."""

    polarization: float
    polarity_speed: float  # rad per gamma / k
    actuation: float


def block_errors(
    t: np.ndarray, polarity: np.ndarray, scale: float = 0.0, rtol: float | None = None, blocks: int = ERROR_BLOCKS
) -> BlockErrors:
    """BlockErrors of polarization, polarity_speed and actuation (`scale`: the turning scale Pi) over the samples
    given. The blocks are treated as independent: a state whose time means wander more slowly than a block (1/8 of
    the window) has a larger error than this says. rtol: an adaptive solver's relative tolerance (None: a fixed-step
    engine, whose error validate bounds): its error, rtol in polarization and actuation and SOLVER_JITTER rtol Pi in
    polarity_speed, is added in quadrature: above what was measured against runs at rtol 1e-11 (a still patch at
    rtol 1e-5 to 1e-3: 0.004-0.45 rtol in polarization, up to 0.8 rtol in actuation, 34 rtol Pi in polarity_speed;
    docs/performance.md, section 10)."""
    t = np.asarray(t, dtype=float)
    psi = unwrapped(polarity)
    size = len(t) // blocks
    if size < 3:
        return BlockErrors(float("nan"), float("nan"), float("nan"))
    values = np.array(
        [
            (
                polarization(psi[k : k + size]),
                polarity_speed(t[k : k + size], psi[k : k + size]),
                actuation(t[k : k + size], psi[k : k + size], scale, rtol),
            )
            for k in range(0, size * blocks, size)
        ]
    )
    spread = values.std(axis=0, ddof=1) / np.sqrt(blocks)
    solver = np.zeros(3) if rtol is None else float(rtol) * np.array([1.0, SOLVER_JITTER * scale, 1.0])
    return BlockErrors(*(float(e) for e in np.hypot(spread, solver)))


DEGENERATE = 1e-8
"""Relative gap (to the stiffest mode's eigenvalue) below which two normal modes share an eigenspace."""
ENERGY_TIE = 1e-9
"""Relative gap (to the largest mode energy) below which two modes' energies are equal: round-off, not physics,
would order them (ranked_modes gives a tie to the lower rank)."""
UNDEFORMED = 1e-8
"""A patch whose elastic energy is below this fraction of its scale sigma^2 A (A units of force sigma on springs of
stiffness 1; `floor` of mode_energies) is undeformed, displacements below ~1e-4 sigma: its energy has no modes to
condense on (condensation NaN, dominant modes 0). A freely translating patch whose units have aligned is one."""


class ModeEnergies(NamedTuple):
    energy: np.ndarray  # (M,) time-mean elastic energy per normal mode, ascending stiffness
    condensation: float  # share of the total in the two most energetic modes (NaN: undeformed)
    dominant_modes: tuple[int, int]  # their 1-based ranks by stiffness, the most energetic first (0: none)
    total: float = float("nan")  # the elastic energy the shares are of: the modes' sum, or the whole when given


def eigenspaces(values: np.ndarray) -> list[np.ndarray]:
    """The index groups of equal eigenvalues (ascending values; equal within DEGENERATE of the largest)."""
    values = np.asarray(values, dtype=float)
    if values.size == 0:
        return []
    gap = DEGENERATE * max(float(np.abs(values).max()), 1e-300)
    cuts = np.flatnonzero(np.diff(values) > gap) + 1
    return np.split(np.arange(values.size), cuts)


def mode_energies(
    displacements: np.ndarray, values: np.ndarray, vectors: np.ndarray, floor: float = 0.0, total: float | None = None
) -> ModeEnergies:
    """Energy per normal mode of the free nodes' displacements from rest ((T, 2F), node-interleaved) on the modes
    (values ascending, vectors as columns): E_m = lambda_m <a_m^2> / 2 with a_m = u . v_m.

    The energies do not depend on which basis an eigensolver returned for a degenerate eigenspace: within each, the
    modes are its principal axes of <a a^T> (the most energetic first, on the lowest rank), so a state has one
    labelling; ties between modes (energies equal within ENERGY_TIE) go to the lower rank. A total at or below
    `floor` leaves no modes to name. `total`: the whole time-mean elastic energy when the modes are only the softest
    of a large network (the shares are then of it); None: the modes' sum (every mode given)."""
    amplitudes = np.asarray(displacements) @ vectors
    second = amplitudes.T @ amplitudes / max(len(amplitudes), 1)  # <a a^T>
    held = np.zeros(len(values))
    for space in eigenspaces(values):
        held[space] = np.sort(np.linalg.eigvalsh(second[np.ix_(space, space)]))[::-1]
    energy = 0.5 * np.clip(values, 0.0, None) * np.clip(held, 0.0, None)
    total = float(energy.sum()) if total is None else float(total)
    order = ranked_modes(energy, 2)
    if not total > floor:
        return ModeEnergies(energy, float("nan"), (0, 0), total)
    top = (int(order[0]) + 1, int(order[1]) + 1) if energy.size > 1 else (int(order[0]) + 1, 0)
    return ModeEnergies(energy, float(energy[order[:2]].sum() / total), top, total)


def ranked_modes(energy: np.ndarray, count: int) -> np.ndarray:
    """The indices of the `count` most energetic modes, the most energetic first; energies within ENERGY_TIE of the
    largest (relative) are equal, and of equal ones the lower rank comes first, so that round-off in the energies
    never decides an order."""
    energy = np.asarray(energy, dtype=float)
    tie = ENERGY_TIE * max(float(np.abs(energy).max(initial=0.0)), 1e-300)
    left = np.arange(energy.size)
    order = []
    for _ in range(min(count, energy.size)):
        best = int(np.flatnonzero(energy[left] >= energy[left].max() - tie)[0])  # the lowest rank among the ties
        order.append(int(left[best]))
        left = np.delete(left, best)
    return np.array(order, dtype=int)


class ModeSpace(NamedTuple):
    """The eigenspace of the dynamical matrix holding the most elastic energy, named as a subspace (a degenerate
    pair is one space, not two modes whose labels a basis would choose)."""

    rank: int  # 1-based rank by stiffness of its softest mode (0: none, an undeformed patch)
    size: int  # its dimension (2: a degenerate pair; 0: none)
    share: float  # its share of the elastic energy (NaN: undeformed)


def mode_space(modes: ModeEnergies, values: np.ndarray) -> ModeSpace:
    """The most energetic eigenspace of `modes` (mode_energies on the eigenvalues `values`): the energies of each
    group of equal eigenvalues (eigenspaces) summed, which no choice of basis within a group changes."""
    if not np.isfinite(modes.condensation):
        return ModeSpace(0, 0, float("nan"))
    spaces = eigenspaces(values)
    held = np.array([modes.energy[space].sum() for space in spaces])
    best = int(np.argmax(held))
    return ModeSpace(int(spaces[best][0]) + 1, int(spaces[best].size), float(held[best] / modes.total))


def rotation_angle(positions: np.ndarray, rest: np.ndarray, centre: np.ndarray | None = None) -> np.ndarray:
    """(T,) the rigid rotation that best maps the rest positions (P, 2) onto positions (T, P, 2), unwrapped: the
    angle of sum_i (r_i x x_i, r_i . x_i), with r and x taken from `centre` (a fixed point, e.g. a pinned node) or,
    when None, each from its own centroid (least squares, Kabsch in 2D)."""
    rest = np.asarray(rest, dtype=float)
    positions = np.asarray(positions, dtype=float)
    origin = rest.mean(axis=0) if centre is None else np.asarray(centre, dtype=float)
    r = rest - origin
    total = r.sum(axis=0)  # 0 about the centroid: x's own centroid then drops out of both sums
    if centre is None:
        total = np.zeros(2)
    # the sums over the nodes as two matrix-vector products over the flat (T, 2P) positions (no (T, P) temporaries)
    flat = positions.reshape(positions.shape[:-2] + (-1,))
    cross = flat @ np.column_stack([-r[:, 1], r[:, 0]]).ravel() - (total[0] * origin[1] - total[1] * origin[0])
    dot = flat @ r.ravel() - total @ origin
    return np.unwrap(np.arctan2(cross, dot))


def body_positions(positions: np.ndarray, rest: np.ndarray, centre: np.ndarray | None = None) -> np.ndarray:
    """Positions (T, P, 2) with the patch's rigid motion taken out: each sample turned back by rotation_angle about
    `centre` (a fixed point) or, when None, moved so its centroid sits on the rest centroid and turned back about it.
    What is left is the patch's deformation, in the rest frame."""
    rest = np.asarray(rest, dtype=float)
    positions = np.asarray(positions, dtype=float)
    angle = rotation_angle(positions, rest, centre)
    if centre is None:
        origin = rest.mean(axis=0)
        x = positions - positions.mean(axis=-2, keepdims=True)
    else:
        origin = np.asarray(centre, dtype=float)
        x = positions - origin
    c, s = np.cos(angle)[..., None], np.sin(angle)[..., None]
    return origin + np.stack([c * x[..., 0] + s * x[..., 1], -s * x[..., 0] + c * x[..., 1]], axis=-1)


def drift(t: np.ndarray, positions: np.ndarray) -> float:
    """Mean speed of the nodes' centroid over the samples given (positions (T, P, 2)): the distance it moved over the
    time it took (units a per gamma / k)."""
    centroid = np.asarray(positions, dtype=float).mean(axis=-2)
    return float(np.linalg.norm(centroid[-1] - centroid[0]) / (t[-1] - t[0]))

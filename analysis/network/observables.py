"""Observables of a network run, as pure functions of its record (times, node positions, polarities).

  polarization        time mean of |(1/A) sum_i n_i|: the units' polar order (1: all point the same way)
  polarity_rate       mean over the window and the units of dpsi_i/dt (rad per gamma / k): the polarities' common
                      turning rate, its sign the sense of rotation (0 at a fixed point)
  actuation           |<dpsi/dt>| / <|dpsi/dt|> over the units and the window: 1 when every unit turns the same way
                      at the same rate (collective actuation), near 0 for incoherent turning, 0 for still units
  mode energies       the displacements from rest projected on the dynamical matrix's normal modes, energy
                      lambda_m <a_m^2> / 2 per mode; `condensation` is the share of the two most energetic modes
                      (1: the dynamics has condensed on two modes), `dominant_modes` their 1-based ranks by stiffness
                      (1: the softest)
  rotation            the patch's rigid rotation angle about a point (its least-squares rotation of the
                      displacements), and its mean rate
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

STILL_RATE = 1e-6
"""rad / (gamma / k): units turning slower than this on average are still (actuation 0), at the least."""
STILL_FRACTION = 1e-3
"""Units whose mean |dpsi/dt| is below this fraction of their turning scale sigma / l_a are still: the decaying
residue of a rest state (~1e-5 rad per gamma / k after 100 gamma / k) has no direction worth a ratio."""


def window(t: np.ndarray, transient: float) -> np.ndarray:
    """Boolean mask of the samples after the transient (measured from the first sample)."""
    t = np.asarray(t, dtype=float)
    return t - t[0] >= transient - 1e-12 * max(1.0, transient)


def polarization(polarity: np.ndarray) -> float:
    """Time mean of |(1/A) sum_i exp(i psi_i)| over the samples given ((T, A) angles)."""
    return float(np.abs(np.exp(1j * np.asarray(polarity)).mean(axis=1)).mean())


def turning_rates(t: np.ndarray, polarity: np.ndarray) -> np.ndarray:
    """(T, A) dpsi/dt by finite differences of the unwrapped angles."""
    return np.gradient(np.unwrap(np.asarray(polarity), axis=0), np.asarray(t, dtype=float), axis=0)


def polarity_rate(t: np.ndarray, polarity: np.ndarray) -> float:
    """Mean dpsi/dt over the samples and the units: (psi(end) - psi(start)) / duration, averaged over the units."""
    psi = np.unwrap(np.asarray(polarity), axis=0)
    return float(((psi[-1] - psi[0]) / (t[-1] - t[0])).mean())


def actuation(t: np.ndarray, polarity: np.ndarray, scale: float = 0.0) -> float:
    """|<dpsi/dt>| / <|dpsi/dt|> over the units and samples (0 when the units are still: turning on average slower than
    STILL_RATE or STILL_FRACTION x `scale`, their turning scale sigma / l_a)."""
    rates = turning_rates(t, polarity)
    magnitude = float(np.abs(rates).mean())
    if magnitude < max(STILL_RATE, STILL_FRACTION * scale):
        return 0.0
    return float(abs(rates.mean()) / magnitude)


class ModeEnergies(NamedTuple):
    energy: np.ndarray            # (M,) time-mean elastic energy per normal mode, ascending stiffness
    condensation: float           # share of the total in the two most energetic modes
    dominant_modes: tuple[int, int]  # their 1-based ranks by stiffness, the most energetic first


def mode_energies(displacements: np.ndarray, values: np.ndarray, vectors: np.ndarray) -> ModeEnergies:
    """Energy per normal mode of the free nodes' displacements from rest ((T, 2F), node-interleaved) on the modes
    (values ascending, vectors as columns): E_m = lambda_m <a_m^2> / 2 with a_m = u . v_m."""
    amplitudes = np.asarray(displacements) @ vectors
    energy = 0.5 * np.clip(values, 0.0, None) * (amplitudes**2).mean(axis=0)
    total = float(energy.sum())
    order = np.argsort(energy)[::-1]
    top = (int(order[0]) + 1, int(order[1]) + 1) if energy.size > 1 else (int(order[0]) + 1, 0)
    share = float(energy[order[:2]].sum() / total) if total > 0 else float("nan")
    return ModeEnergies(energy, share, top)


def rotation_angle(positions: np.ndarray, rest: np.ndarray, centre: np.ndarray | None = None) -> np.ndarray:
    """(T,) the rigid rotation that best maps the rest positions (P, 2) onto positions (T, P, 2), unwrapped: the
    angle of sum_i (r_i x x_i, r_i . x_i), with r and x taken from `centre` (a fixed point, e.g. a pinned node) or,
    when None, each from its own centroid (least squares, Kabsch in 2D)."""
    rest = np.asarray(rest, dtype=float)
    positions = np.asarray(positions, dtype=float)
    if centre is None:
        r = rest - rest.mean(axis=0)
        x = positions - positions.mean(axis=-2, keepdims=True)
    else:
        r, x = rest - centre, positions - centre
    cross = (r[:, 0] * x[..., 1] - r[:, 1] * x[..., 0]).sum(axis=-1)
    dot = (r[:, 0] * x[..., 0] + r[:, 1] * x[..., 1]).sum(axis=-1)
    return np.unwrap(np.arctan2(cross, dot))

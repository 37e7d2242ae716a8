r"""What a chain does in three dimensions, from its link tangents: the tip's path across the clamp axis, how planar it
is, and how fast it turns (a whirl) or swings (a beat).

The tip r_N = sum_k t_k moves across the clamp axis e_x in the (y, z) plane. After the transient, with the mean
removed, the covariance of that path has principal axes major >= minor:

  tip_amplitude   half the peak-to-peak of the tip's displacement along the major axis (l): the beat's or the
                  whirl's lateral reach
  frequency       f tau of that displacement (upward crossings of its mean, analysis.observables.frequency): a beat's
                  or a whirl's cycles per tau
  tip_aspect      sqrt(minor / major variance): 0 for a beat in a plane, 1 for a circular whirl
  whirl_rate      <y z' - z y'> / (2 pi <y^2 + z^2>) (cycles per tau, signed: > 0 turning from +y to +z, i.e.
                  counter-clockwise seen from the tip looking back at the clamp): +-f for a circular whirl, 0 for a
                  beat in a plane, f 2 a b / (a^2 + b^2) for an elliptical path of semi-axes a, b
  tip_radius      mean distance of the tip from the clamp axis (l)
  bend            mean angle between the first and the last link (rad): constant along a rigid whirl, the planar
                  |Theta| for a planar chain

`classify` names the state: 'rest' (no motion), 'beat' (tip_aspect < BEAT_ASPECT), 'whirl' (tip_aspect >
WHIRL_ASPECT and a steady rotation), 'other' between. Pure functions: arrays in, numbers out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import observables as obs

__all__ = ["Motion3D", "BEAT_ASPECT", "WHIRL_ASPECT", "REST_AMPLITUDE", "classify", "measure3d", "tip_path"]

BEAT_ASPECT = 0.05
"""Below this tip_aspect the chain beats in a plane."""
WHIRL_ASPECT = 0.9
"""Above this tip_aspect (and turning one way) the chain whirls."""
REST_AMPLITUDE = 1e-6
"""Below this tip_amplitude (l) the chain is at rest."""


@dataclass(frozen=True)
class Motion3D:
    """The 3D observables of one chain's steady motion (see the module docstring)."""

    tip_amplitude: float
    frequency: float
    tip_aspect: float
    whirl_rate: float
    tip_radius: float
    bend: float
    state: str


def tip_path(tangents: np.ndarray) -> np.ndarray:
    """The tip's position r_N (T, 3) of tangents (T, N, 3)."""
    return np.asarray(tangents, dtype=float).sum(axis=-2)


def classify(tip_amplitude: float, tip_aspect: float, whirl_rate: float, frequency: float) -> str:
    """'rest', 'beat', 'whirl' or 'other' (module docstring)."""
    if not tip_amplitude > REST_AMPLITUDE:
        return "rest"
    if tip_aspect < BEAT_ASPECT:
        return "beat"
    if tip_aspect > WHIRL_ASPECT and frequency > 0 and abs(abs(whirl_rate) / frequency - 1.0) < 0.1:
        return "whirl"
    return "other"


def measure3d(t, tangents, transient: float | None = None) -> Motion3D:
    """The 3D observables of tangents (T, N, 3) sampled at uniform times t (T,), after the transient (default: the
    first half of the record)."""
    t = np.asarray(t, dtype=float)
    tangents = np.asarray(tangents, dtype=float)
    ts, tip = obs.steady_part(t, tip_path(tangents)[:, 1:], transient=transient)
    _, tans = obs.steady_part(t, tangents, transient=transient)
    lateral = tip - tip.mean(axis=0)
    variance, axes = np.linalg.eigh(np.cov(lateral.T))
    major = lateral @ axes[:, 1]
    amplitude = float(0.5 * (major.max() - major.min()))
    frequency = obs.frequency(ts, major, transient=0.0)  # ts is already the steady part: count over all of it
    aspect = float(np.sqrt(max(variance[0], 0.0) / variance[1])) if variance[1] > 0 else 0.0
    y, z = lateral[:, 0], lateral[:, 1]
    dt = ts[1] - ts[0]
    yd, zd = np.gradient(y, dt), np.gradient(z, dt)
    spread = np.mean(y * y + z * z)
    whirl = float(np.mean(y * zd - z * yd) / (2 * np.pi * spread)) if spread > 0 else 0.0
    radius = float(np.mean(np.hypot(tip[:, 0], tip[:, 1])))
    first, last = tans[:, 0], tans[:, -1]
    cosine = np.einsum("ta,ta->t", first, last) / np.linalg.norm(first, axis=1) / np.linalg.norm(last, axis=1)
    bend = float(np.mean(np.arccos(np.clip(cosine, -1.0, 1.0))))
    return Motion3D(amplitude, frequency, aspect, whirl, radius, bend, classify(amplitude, aspect, whirl, frequency))

"""Observables of a free chain in a dish (a harmonic trap centred at the origin), and its state.

Small pure functions: numpy arrays in, numbers out. Conventions as in
:mod:`elastoactive.analysis.observables` (``t`` (T,) strictly increasing times in tau, ``theta``
(T, N) absolute pendulum angles in radians, continuous in time, ``transient`` the time in tau
discarded from ``t[0]``, ``None``: the first half of the record's duration), and:

- ``head`` is a (T, 2) array: the position (x, y) of the head point, in units of l, relative to the
  dish's centre. The head is the pivot of the first pendulum, free to slide: the chain's front
  piece, which carries one particle's drag and no active force.
- Particle i sits at r_i = head + sum_{k <= i} e(theta_k), with e(a) = (cos a, sin a) and links of
  length l = 1.
- The centre of mass is the mean over the N + 1 points that carry drag, the head and the N
  particles (every point has the same drag; in the overdamped limit that is the weight that
  matters).
- Rates are in rad per tau, counter-clockwise positive. The body's rotation rate is
  :func:`observables.rotation_rate` (the mean d theta_1/dt); it is not repeated here.

:func:`dish_state` sorts a run into ``"rest"``, ``"spin"``, ``"orbit"``, ``"crawl"``, ``"beat"`` or
``"irregular"``, with the thresholds below (module constants, each used in one place).
"""

from __future__ import annotations

import math

import numpy as np

from . import observables as obs

__all__ = [
    "REST_RATE",
    "REST_MOTION",
    "REST_SLOWDOWN",
    "SPIN_RADIUS",
    "RIGID_RTOL",
    "DRIFT_RTOL",
    "MIN_ORBIT_RADIUS",
    "MAX_POLAR_STEP",
    "BEAT_SPREAD",
    "STATES",
    "positions",
    "centre_of_mass",
    "orbit_angle",
    "orbit_rate",
    "orbit_radius",
    "mean_curvature",
    "dish_state",
]


REST_RATE = 1e-3
"""rad/tau: a body rotation rate or an orbit rate of at most this in magnitude is no rotation (one turn
in about 6000 tau). Also the absolute part of the drift tolerance (see :data:`DRIFT_RTOL`)."""
REST_MOTION = 1e-2
"""l: a chain that does not rotate is at rest when the root-mean-square displacement of its N + 1 points
about their mean positions over the steady part is at most this ..."""
REST_SLOWDOWN = 0.7
"""... or when it is still gliding to its resting place: the points' root-mean-square speed over the last
quarter of the steady part is at most this fraction of that over the first quarter. A chain relaxing in the
trap slows down by about exp(-k 3T/4) between the two quarters of a steady part of length T (0.51 for trap
0.003 and 0.11 for trap 0.01 over a 300 tau steady part); one that beats in place, or drifts at constant
speed, does not slow down and is irregular."""
SPIN_RADIUS = 0.1
"""A rotating chain spins in place when its centre of mass stays, on average, within this fraction of the
chain's length N l of the dish's centre (0.7 l for N = 7)."""
RIGID_RTOL = 0.02
"""A rotating chain away from the centre orbits rigidly when its body rotation rate and its orbit rate
agree within this fraction of the larger of the two; otherwise it crawls."""
DRIFT_RTOL = 0.1
"""The rates are steady when each, measured over the first and over the second half of the steady part,
agrees within DRIFT_RTOL times the larger plus :data:`REST_RATE`; otherwise the state is irregular. The
beat's wobble of theta_1 biases a slope over half the window, which sets how small this can be."""
MIN_ORBIT_RADIUS = 1e-6
"""l: the polar angle of a centre of mass closer than this to the centre is undefined (orbit rate NaN)."""
MAX_POLAR_STEP = math.pi / 2
"""rad: a polar angle that changes by more than this between two samples cannot be unwrapped reliably
(the centre of mass passes too close to the centre for the sampling); the orbit rate is then NaN."""
BEAT_SPREAD = 0.01
"""A chain that neither turns nor goes round beats in place when the cycle periods and amplitudes of its Theta
vary by at most this (std / mean; results.PERIODIC_SPREAD's level): the flagellar beat, its head held by the dish."""
STATES = ("rest", "spin", "orbit", "crawl", "beat", "irregular")
"""The values :func:`dish_state` returns."""


# --------------------------------------------------------------------------- validation


def _as_chain(theta, head) -> tuple[np.ndarray, np.ndarray]:
    a = obs._as_theta(theta)
    h = np.asarray(head, dtype=float)
    if h.ndim != 2 or h.shape[1] != 2:
        raise ValueError(f"head must be a 2-D array of shape (T, 2); got shape {h.shape}")
    if h.shape[0] != a.shape[0]:
        raise ValueError(f"head has {h.shape[0]} samples but theta has {a.shape[0]}; lengths must match")
    if not np.all(np.isfinite(h)):
        raise ValueError("head contains non-finite values (nan or inf)")
    return a, h


def _steady_chain(t, theta, head, transient, min_samples=2):
    """(t, theta, head) restricted to the steady part, validated."""
    a, h = _as_chain(theta, head)
    ta, _ = obs._as_series(t, a, name="theta", ndim=(2,))
    m = obs._steady_mask(ta, transient, 0.5)
    if np.count_nonzero(m) < min_samples:
        raise ValueError(
            f"only {np.count_nonzero(m)} samples remain after discarding transients; need at least {min_samples}"
        )
    return ta[m], a[m], h[m]


# --------------------------------------------------------------------------- geometry


def positions(theta, head) -> np.ndarray:
    """Points of the chain, (T, N + 1, 2) in units of l: the head (index 0), then particles 1 .. N.

    theta: (T, N) absolute angles in radians; head: (T, 2) head positions in l.
    r_0 = head, r_i = head + sum_{k <= i} (cos theta_k, sin theta_k).
    """
    a, h = _as_chain(theta, head)
    steps = np.stack([np.cos(a), np.sin(a)], axis=-1)  # (T, N, 2)
    out = np.empty((a.shape[0], a.shape[1] + 1, 2))
    out[:, 0] = h
    out[:, 1:] = h[:, None, :] + np.cumsum(steps, axis=1)
    return out


def centre_of_mass(theta, head, *, include_head: bool = True) -> np.ndarray:
    """Centre of mass (T, 2) in l: the mean over the N + 1 points, the head counted as one of them.

    The head carries one particle's drag (the chain's front piece), so it weighs as a particle.
    ``include_head=False``: the mean over the N particles only (the convention of the issue's quick
    model: its orbit radii 1.40 at trap 0.1 and 0.27 at trap 0.3 are of this centre).
    """
    p = positions(theta, head)
    return (p if include_head else p[:, 1:]).mean(axis=1)


def _polar_angle(com: np.ndarray) -> np.ndarray | None:
    """Unwrapped polar angle of (T, 2) points about the origin, or None when it is undefined or ambiguous."""
    r = np.hypot(com[:, 0], com[:, 1])
    if r.min() < MIN_ORBIT_RADIUS:
        return None
    phi = np.arctan2(com[:, 1], com[:, 0])
    step = np.angle(np.exp(1j * np.diff(phi)))
    if step.size and np.max(np.abs(step)) > MAX_POLAR_STEP:
        return None
    return phi[0] + np.concatenate([[0.0], np.cumsum(step)])


def orbit_angle(t, theta, head, transient: float | None = None, *, include_head: bool = True) -> np.ndarray:
    """Unwrapped polar angle (radians) of the centre of mass about the dish's centre, over the steady part.

    One value per steady sample (aligned with ``observables.steady_part(t, theta, transient=transient)[0]``),
    continuous in time. All NaN when the centre of mass comes within :data:`MIN_ORBIT_RADIUS` of
    the centre, or moves round it by more than :data:`MAX_POLAR_STEP` between two samples: the
    angle is then undefined or cannot be unwrapped. ``include_head``: see :func:`centre_of_mass`.
    """
    ts, a, h = _steady_chain(t, theta, head, transient)
    phi = _polar_angle(centre_of_mass(a, h, include_head=include_head))
    return np.full(ts.size, math.nan) if phi is None else phi


def _slope(t: np.ndarray, y: np.ndarray) -> float:
    return float(np.polyfit(t, y, 1)[0])


def orbit_rate(t, theta, head, transient: float | None = None, *, include_head: bool = True) -> float:
    """Mean angular velocity of the centre of mass about the dish's centre, rad per tau.

    Slope of a least-squares line through the unwrapped polar angle of the centre of mass
    (:func:`orbit_angle`) over the steady part, as :func:`observables.rotation_rate` does for
    theta_1. NaN when that angle is undefined (a centre of mass at the centre, e.g. a chain
    spinning about its own centre of mass there). ``include_head``: see :func:`centre_of_mass`.
    """
    ts, a, h = _steady_chain(t, theta, head, transient)
    phi = _polar_angle(centre_of_mass(a, h, include_head=include_head))
    return math.nan if phi is None else _slope(ts, phi)


def orbit_radius(t, theta, head, transient: float | None = None, *, include_head: bool = True) -> float:
    """Mean distance (in l) of the centre of mass from the dish's centre over the steady part.

    ``include_head``: see :func:`centre_of_mass` (the radius depends on it; the rates of a rigid
    turn do not).
    """
    _, a, h = _steady_chain(t, theta, head, transient)
    com = centre_of_mass(a, h, include_head=include_head)
    return float(np.mean(np.hypot(com[:, 0], com[:, 1])))


def mean_curvature(theta, t=None, transient: float | None = None, *, absolute: bool = False) -> float:
    """Mean curvature of the chain in rad per l, averaged along the chain and over the steady part.

    At each time the bends theta_{i+1} - theta_i (i = 1 .. N-1, links of length l) are averaged
    along the chain, then over time. Signed by default (counter-clockwise bending positive; the
    signed mean along the chain is (theta_N - theta_1) / (N - 1) = Theta / (N - 1), so a chain
    that bends both ways can average to zero); ``absolute=True`` averages |theta_{i+1} - theta_i|
    instead (how bent, whatever the sense). Transients are discarded as elsewhere when ``t`` (in
    tau) is given; without ``t`` the last half of the samples is kept and ``transient`` must be None.
    theta needs N >= 2.
    """
    a = obs._as_theta(theta)
    if a.shape[1] < 2:
        raise ValueError(f"theta needs at least 2 particles for a curvature; got shape {a.shape}")
    bends = np.diff(a, axis=1)
    per_time = np.abs(bends).mean(axis=1) if absolute else bends.mean(axis=1)
    if t is None:
        if transient is not None:
            raise ValueError("transient is a time in tau: pass t as well")
        return float(per_time[per_time.size // 2 :].mean())
    _, ks = obs._steady(t, per_time, transient, name="theta", min_samples=1)
    return float(ks.mean())


# --------------------------------------------------------------------------- classification


def _steady_rates(ts: np.ndarray, a: np.ndarray, h: np.ndarray) -> tuple[float, float]:
    """(body rotation rate, orbit rate) over the given samples, rad per tau (orbit NaN when undefined)."""
    omega = obs.rotation_rate(ts, a, transient=0.0)
    phi = _polar_angle(centre_of_mass(a, h))
    return omega, (math.nan if phi is None else _slope(ts, phi))


def _at_rest(ts: np.ndarray, p: np.ndarray) -> bool:
    """Whether points p (T, M, 2) barely move (:data:`REST_MOTION`) or slow down (:data:`REST_SLOWDOWN`)."""
    motion = math.sqrt(float(np.mean(np.sum((p - p.mean(axis=0)) ** 2, axis=-1))))
    if motion <= REST_MOTION:
        return True
    speed2 = np.sum(np.diff(p, axis=0) ** 2, axis=-1).mean(axis=1) / np.diff(ts) ** 2  # mean over points of |v|^2
    quarter = speed2.size // 4
    first, last = speed2[:quarter].mean(), speed2[-quarter:].mean()
    return math.sqrt(last) <= REST_SLOWDOWN * math.sqrt(first)


def _beats(ts: np.ndarray, big_theta: np.ndarray) -> bool:
    """Whether Theta = theta_N - theta_1 beats periodically: at least two whole cycles whose periods and amplitudes
    vary by at most :data:`BEAT_SPREAD` (std / mean)."""
    c = obs.cycles(ts, big_theta, transient=0.0)
    return c.count >= 2 and max(c.period_spread, c.amplitude_spread) <= BEAT_SPREAD


def _drifts(r1: float, r2: float) -> bool:
    if math.isnan(r1) != math.isnan(r2):
        return True
    if math.isnan(r1):
        return False
    return abs(r1 - r2) > DRIFT_RTOL * max(abs(r1), abs(r2)) + REST_RATE


def dish_state(t, theta, head, transient: float | None = None) -> str:
    """The chain's steady pattern in the dish, one of :data:`STATES`.

    With omega the body rotation rate (:func:`observables.rotation_rate`), Omega the orbit rate
    (:func:`orbit_rate`), R the orbit radius (:func:`orbit_radius`), all over the steady part:

    - ``"irregular"`` if omega or Omega over the first half of the steady part differs from that over
      the second half (tolerance :data:`DRIFT_RTOL`; Omega defined in one half and not the other
      counts as a change);
    - ``"rest"`` if |omega| and |Omega| (when defined) are at most :data:`REST_RATE` and the points'
      root-mean-square displacement is at most :data:`REST_MOTION` (no motion), or their speed falls
      by :data:`REST_SLOWDOWN` across the steady part (still gliding to rest: a longer record would
      show it settle);
    - ``"spin"`` if |omega| > :data:`REST_RATE` and R < :data:`SPIN_RADIUS` N: it rotates in place
      about the centre (Omega may be undefined, or equal to omega: a rigid turn about a point near
      the centre of mass);
    - ``"orbit"`` if R is larger, |Omega| > :data:`REST_RATE` and omega equals Omega within
      :data:`RIGID_RTOL`: the chain goes round the centre like a rigid body;
    - ``"crawl"`` if R is larger, |Omega| > :data:`REST_RATE` and omega differs from Omega: it goes
      round the centre while its body turns at another rate (the supplement's "crawls in circles";
      includes a body that does not turn at all);
    - ``"beat"`` if it neither turns nor goes round nor rests, and Theta = theta_N - theta_1 beats
      periodically (:data:`BEAT_SPREAD`): the flagellar beat in place, the dish holding the head;
    - ``"irregular"`` otherwise, none of these steady patterns (e.g. a chain that drifts at a steady
      speed, or turns away from the centre without going round it).

    The centre of mass is that of the N + 1 points (:func:`centre_of_mass`).
    """
    ts, a, h = _steady_chain(t, theta, head, transient, min_samples=6)
    half = ts.size // 2
    first = _steady_rates(ts[:half], a[:half], h[:half])
    second = _steady_rates(ts[half:], a[half:], h[half:])
    if _drifts(first[0], second[0]) or _drifts(first[1], second[1]):
        return "irregular"
    omega, big_omega = _steady_rates(ts, a, h)
    turns = abs(omega) > REST_RATE
    goes_round = not math.isnan(big_omega) and abs(big_omega) > REST_RATE
    if not turns and not goes_round:
        if _at_rest(ts, positions(a, h)):
            return "rest"
        return "beat" if _beats(ts, a[:, -1] - a[:, 0]) else "irregular"
    com = centre_of_mass(a, h)
    radius = float(np.mean(np.hypot(com[:, 0], com[:, 1])))
    if turns and radius < SPIN_RADIUS * a.shape[1]:
        return "spin"
    if not goes_round:
        return "irregular"
    if abs(omega - big_omega) <= RIGID_RTOL * max(abs(omega), abs(big_omega)):
        return "orbit"
    return "crawl"

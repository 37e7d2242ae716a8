r"""Self-contact between the capsules of a chain's links (plain numpy): geometry, clearance, the penalty.

Capsules
--------
Link i of a chain runs from its pivot P_{i-1} (the chain's pivot for i = 0: the origin, or the head of a free
chain) to particle i, P_i = P_{i-1} + e_i, e_i = (cos th_i, sin th_i). Its capsule (a Hexbug: CONTACT_LENGTH =
0.7 l long, caps included, centred on the link; radius R = ChainSystem.contact_radius) is the set of points within
R of its core, the segment

    P_{i-1} + s e_i,   s in [s_a, s_b],   s_a = (1 - CONTACT_LENGTH) / 2 + R,   s_b = (1 + CONTACT_LENGTH) / 2 - R.

Two capsules overlap when the distance d between their cores' closest points is below 2R; the clearance is
d - 2R (negative: the depth of the overlap). Only non-adjacent links of the same chain (|i - j| >= 2) interact:
neighbours share a particle and overlap by construction (their capsules would jam every joint), and the two
chains of a pair never touch (in MuJoCo they stand side by side; in the reduced model each has its own pivot).

Penalty (the reduced model's contact, kernels.eval_rhs_general, equations.rhs_reference)
-----------------------------------------------------------------------------------------
For every pair of non-adjacent links (i, j) the penalty acts on the four core ends against the other core:

    U = K/2 sum_{pairs (i, j)} [ sum_{p in ends(i)} max(0, 2R - dist(p, core j))^2
                                + sum_{p in ends(j)} max(0, 2R - dist(p, core i))^2 ]

(K = ChainSystem.contact_stiffness). The force of one end term is K (2R - dist) u on the end p and the opposite on
its closest point c on the other core, u = (p - c) / dist: equal and opposite along the line joining the points,
so contacts exert no net force and no net torque on the chain. Through the points' Jacobians (a point at fraction
s of link i, P_{i-1} + s e_i: d/dth_k = n_k for k < i, s n_i for k = i, the identity for the head) the generalised
force is that of the force split between the link's ends, (1 - s) on P_{i-1} and s on P_i.

Why the ends, and not the one pair of closest points of the two cores. In the plane, two cores that do not
cross have their closest points at an end of one of them, so the cores' distance d is the smallest of the four
end distances, and for a single contact (one end against the other core, the common case: a T or a V) this
penalty is exactly K/2 max(0, 2R - d)^2. But d, a minimum of four smooth distances, has a kink where two of them
tie, i.e. exactly when the cores are parallel, and that is where a folded chain pressed together settles (the
contact torques turn touching links parallel). A penalty on d alone then makes the closest points jump from one
end to the other as the links pass through parallel: a discontinuous torque and a sliding mode, on which the
adaptive integrator took steps of ~1e-6 tau (1.8 million evaluations for 2 tau of a pressed N = 9 hairpin).
The sum over ends is continuously differentiable (the distance of a point to a segment is C1 off the segment),
and touching parallel links carry two contacts, one at each end of the overlap, as MuJoCo's capsule-capsule
collision gives them. Where two ends touch each other (corner to corner), both of their terms are on: the
contact is twice as stiff there. Consequences: the reported clearance (capsule_clearance, the cores' smallest
distance d - 2R, MuJoCo's geometry) equals minus the penalty's overlap for a single contact, and a pressed
parallel contact's overlap is half what one contact would need.

Crossing cores. If two cores cross in their interiors (an X, deep overlap, outside the model's validity) and
all four ends are farther than 2R from the other core, the penalty is zero; reaching an X needs an end to
cross the other core against the full barrier K 2R, and capsule_clearance reports the crossing (-2R). An end
exactly on the other core (dist <= CROSSING_DISTANCE) has no separation direction: the force is then K 2R
(the penalty's limit) along the normal n_j of the touched link j, signed to push the midpoint of the end's own
core away from core j's line (+ n_j when (m_i - c) . n_j >= 0, + n_j too when it lies on that line). The kernel
and this module use the same rules, so their results agree there as well.
"""

from __future__ import annotations

import numpy as np

from .system import CONTACT_LENGTH

__all__ = [
    "CROSSING_DISTANCE",
    "capsule_clearance",
    "contact_forces",
    "contact_pairs",
    "core_span",
    "point_segment",
    "segment_closest",
]

CROSSING_DISTANCE = 1e-12
"""Distance of a core end to the other core below which the end counts as on it (see the module docstring)."""

PARALLEL = 1e-12
"""Relative size of the 2 x 2 determinant a e - b^2 below which two cores count as parallel (segment_closest)."""


def core_span(radius: float) -> tuple[float, float]:
    """(s_a, s_b): the fractions of a link between which its capsule's core runs."""
    return (1.0 - CONTACT_LENGTH) / 2.0 + radius, (1.0 + CONTACT_LENGTH) / 2.0 - radius


def contact_pairs(n: int) -> list[tuple[int, int]]:
    """The interacting link pairs (i, j), i < j, of a chain of n links: every pair with j - i >= 2."""
    return [(i, j) for i in range(n) for j in range(i + 2, n)]


def segment_closest(p1, d1, p2, d2):
    """Closest points of the segments p1 + u d1 and p2 + v d2, u, v in [0, 1] (C. Ericson, Real-Time Collision
    Detection, 5.1.9), elementwise over leading axes (points of shape (..., 2)). Returns (u, v). Both segments
    must have a length (|d1|, |d2| > 0). Parallel segments (a e - b^2 <= PARALLEL a e) take u = 0 first.
    kernels._segment_closest is the same arithmetic."""
    r = p1 - p2
    a = np.sum(d1 * d1, axis=-1)
    e = np.sum(d2 * d2, axis=-1)
    f = np.sum(d2 * r, axis=-1)
    c = np.sum(d1 * r, axis=-1)
    b = np.sum(d1 * d2, axis=-1)
    denom = a * e - b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.where(denom > PARALLEL * a * e, np.clip((b * f - c * e) / denom, 0.0, 1.0), 0.0)
        v = (b * u + f) / e
        low = v < 0.0
        high = v > 1.0
        u = np.where(low, np.clip(-c / a, 0.0, 1.0), np.where(high, np.clip((b - c) / a, 0.0, 1.0), u))
    v = np.clip(v, 0.0, 1.0)
    return u, v


def _links(theta: np.ndarray, head) -> tuple[np.ndarray, np.ndarray]:
    """(pivots P_{i-1}, directions e_i), each (T, N, 2), of the chains theta (T, N) pivoted at head (T, 2)."""
    e = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    ends = np.cumsum(e, axis=1)
    pivots = np.concatenate([np.zeros_like(ends[:, :1]), ends[:, :-1]], axis=1)
    if head is not None:
        pivots = pivots + np.asarray(head, dtype=float).reshape(-1, 1, 2)
    return pivots, e


def _smallest_distance(theta, head, s_a: float, s_b: float) -> tuple[np.ndarray, bool]:
    """(per sample, the smallest distance between the segments s in [s_a, s_b] of non-adjacent links of one chain;
    whether theta was a single sample). theta, head: as capsule_clearance."""
    theta = np.asarray(theta, dtype=float)
    single = theta.ndim == 1
    theta = np.atleast_2d(theta)
    if head is not None:
        head = np.broadcast_to(np.asarray(head, dtype=float), (theta.shape[0], 2))
    pivots, e = _links(theta, head)
    starts = pivots + s_a * e
    spans = (s_b - s_a) * e
    best = np.full(theta.shape[0], np.inf)
    for i, j in contact_pairs(theta.shape[1]):
        u, v = segment_closest(starts[:, i], spans[:, i], starts[:, j], spans[:, j])
        ci = starts[:, i] + u[:, None] * spans[:, i]
        cj = starts[:, j] + v[:, None] * spans[:, j]
        best = np.minimum(best, np.hypot(*(ci - cj).T))
    return best, single


def capsule_clearance(theta, radius: float, head=None) -> np.ndarray:
    """Per sample, the smallest clearance d - 2R between the capsules of non-adjacent links (|i - j| >= 2) of one
    chain (negative: overlap depth), in units of l.

    theta: absolute angles, shape (T, N) (or (N,) for one sample); radius: the capsules' radius R (0 gives the
    cores' smallest distance); head: the pivot's position, (T, 2) or (2,) (default: the origin). Returns shape
    (T,) (a float for one sample); +inf where there is no such pair (N < 3). For a pair of chains call it per chain
    (the chains do not touch each other)."""
    best, single = _smallest_distance(theta, head, *core_span(float(radius)))
    best = best - 2.0 * radius
    return float(best[0]) if single else best


def link_distance(theta, head=None) -> np.ndarray:
    """Per sample, the smallest distance between non-adjacent links, whole links from particle to particle (0: two
    links cross, the chain passes through itself). theta, head and the result's shape: as capsule_clearance."""
    best, single = _smallest_distance(theta, head, 0.0, 1.0)
    return float(best[0]) if single else best


def point_segment(p, a, d) -> float:
    """Fraction t in [0, 1] of the point a + t d of a segment closest to the point p (kernels._point_segment)."""
    return float(np.clip(np.dot(p - a, d) / np.dot(d, d), 0.0, 1.0))


def contact_forces(pivots: np.ndarray, e: np.ndarray, radius: float, stiffness: float):
    """The penalty's point forces of one chain (one sample): a list of (link, fraction s along it, force (2,)),
    two entries (equal and opposite) per touching end, and U (the module docstring: the ends of each core against
    the other core; an end on the other core). pivots, e: (N, 2) each."""
    s_a, s_b = core_span(radius)
    span = s_b - s_a
    out = []
    energy = 0.0
    for i, j in contact_pairs(e.shape[0]):
        for own, other in ((i, j), (j, i)):
            start = pivots[other] + s_a * e[other]
            d = span * e[other]
            mid = pivots[own] + 0.5 * (s_a + s_b) * e[own]
            for s_end in (s_a, s_b):
                p = pivots[own] + s_end * e[own]
                t = point_segment(p, start, d)
                c = start + t * d
                sep = p - c
                dist = float(np.hypot(*sep))
                if dist >= 2.0 * radius:
                    continue
                if dist > CROSSING_DISTANCE:
                    unit = sep / dist
                else:
                    normal = np.array([-e[other, 1], e[other, 0]])
                    unit = normal if np.dot(mid - c, normal) >= 0.0 else -normal
                    dist = 0.0
                overlap = 2.0 * radius - dist
                energy += 0.5 * stiffness * overlap * overlap
                force = stiffness * overlap * unit
                out.append((own, s_end, force))
                out.append((other, s_a + t * span, -force))
    return out, energy

"""The chain on a free ball pivot in three dimensions: the rotating pin (scenes.rotating_pin) off the table. No spring
holds the first link; above the planar rotating pin's threshold the bent chain turns rigidly about a fixed axis through
the pivot, in a plane that its start sets (docs/model3d.md, section 7).

The clamped 3D chain's kind (scenes.clamped3d: its state, engines, automatic numerics, drawing) with clamped = False.
Its observables are the rigid turn's: rotation_rate, |omega| of the best rigid rotation of the tangents (the sense is a
direction in 3D, not a sign), and turn_tilt, the angle between the turn's axis and e_z (0: a turn in the table's
plane). Its beat signal is the bend between the first and the last link, constant in a rigid turn (no beat).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..analysis import observables as obs
from ..core.observables import Observable
from ..core.trajectory import Trajectory
from ..core.units import Signal
from .base import Onset, PathView, ValidationCase
from .clamped3d import Clamped3D

if TYPE_CHECKING:  # typing only: params imports the registry that holds scenes
    from ..core.params import Physics

BEND = Signal("bend", "bend, the angle between the first and the last link", "rad")


def turn_vectors(t: np.ndarray, tangents: np.ndarray) -> np.ndarray:
    """The angular velocity omega (T, 3) of the best rigid rotation t_k' = omega x t_k of unit tangents (T, N, 3) at
    each sample (central differences in time): the least-squares solution of sum_k (1 - t_k t_k^T) omega =
    sum_k t_k x t_k', exact for a rigid turn."""
    rates = np.gradient(tangents, t, axis=0)
    eye = np.eye(3)
    a = np.einsum("tn,ij->tij", np.ones(tangents.shape[:2]), eye) - np.einsum("tni,tnj->tij", tangents, tangents)
    b = np.cross(tangents, rates).sum(axis=1)
    return np.linalg.solve(a, b[..., None])[..., 0]


def turn_quotient(operator: np.ndarray, n: int) -> np.ndarray:
    """The linear operator (2N x 2N, q ordered as analysis.stability_fluid's: one chain's y then z) on the quotient by
    the rigid turns about the pivot (q = 1 in either plane, which every L = -G (H - sigma S) of a free pivot sends to
    0): in the basis whose first vector in each plane is that turn, its block without the turns' rows and columns
    (2N - 2 x 2N - 2). Its spectrum is L's without the turns' two zeros."""
    size = operator.shape[0]
    basis = np.eye(size)
    for plane in range(size // n):
        basis[plane * n : (plane + 1) * n, plane * n] = 1.0
    turned = np.linalg.solve(basis, operator @ basis)
    keep = np.array([i for i in range(size) if i % n])
    return turned[np.ix_(keep, keep)]


def rotation_threshold_fluid(beds) -> tuple[float, float]:
    """(sigma_r, omega): the first sigma where the largest real part of the free pivot's operator through the fluid
    (analysis.stability_fluid.linear_operator_fluid of one unclamped chain, on turn_quotient) crosses 0, and |Im| of
    that eigenvalue there (0: a real crossing, the steady turn). A geometric scan up from a quarter of the lab-frame
    drag's threshold, then brentq. At the local drag's mobility it is analysis.stability.rotation_threshold."""
    from scipy.optimize import brentq  # start-up time: scipy

    from ..analysis import stability  # start-up time: the stability analyses load scipy
    from ..analysis.stability_fluid import linear_operator_fluid, mobility_operator

    g = mobility_operator(beds)

    def spectrum(sigma: float) -> np.ndarray:
        return np.linalg.eigvals(turn_quotient(linear_operator_fluid(beds, sigma, g), beds.n))

    def growth(sigma: float) -> float:
        return float(spectrum(sigma).real.max())

    local = stability.rotation_threshold(beds.n)
    lo = 0.25 * local
    while growth(lo) >= 0:
        lo /= 4.0
    hi = lo
    while growth(hi) < 0:
        lo, hi = hi, 1.25 * hi
    sigma_r = float(brentq(growth, lo, hi, xtol=1e-15, rtol=1e-12))
    lam = spectrum(sigma_r)
    return sigma_r, float(abs(lam[np.argmax(lam.real)].imag))


class Pivot3D(Clamped3D):
    name = "rotating-pin-3d"
    summary = (
        "chain on a free ball pivot, in three dimensions: turns rigidly about a fixed axis above the pin's threshold"
    )
    clamped = False
    planar_scene = "rotating-pin"
    term_parameters = ("n", "sigma", "drag_ratio", "bead_radius")
    """Every particle loaded: the planar rotating pin's threshold (analysis.stability.rotation_threshold) is the fully
    loaded chain's, so a partial load has no onset to hold the 3D turn to. The fluid (bead_radius) as clamped-3d's:
    the free-space RPY mobility among the beads, in both engines."""
    paced_by_beat = False
    compared = ("rotation_rate",)
    observables = (
        "rotation_rate",  # the rotating pin's (scenes.rotating_pin): here |omega| of the rigid turn, rad/tau
        Observable("turn_tilt", "rad", "angle between the turn's axis and e_z (0: a turn in the xy plane)",
                   error="absolute", floor=0.0),
    )  # fmt: skip

    def beat_signal(self, physics: Physics) -> Signal:
        return BEND

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        t = self.tangents(traj)
        return [np.arccos(np.clip(np.einsum("ta,ta->t", t[:, 0], t[:, -1]), -1.0, 1.0))]

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float | str]:
        ts, tangents = obs.steady_part(traj.t, self.tangents(traj), transient=transient)
        omega = turn_vectors(ts, tangents).mean(axis=0)
        rate = float(np.linalg.norm(omega))
        tilt = float(np.arccos(min(1.0, abs(omega[2]) / rate))) if rate > 0 else float("nan")
        return {"rotation_rate": rate, "turn_tilt": tilt}

    def onset(self, physics: Physics) -> Onset:
        """The planar rotating pin's threshold (analysis.stability.rotation_threshold) with the lab-frame drag; through
        the fluid, the fluid operator's (rotation_threshold_fluid), which the mobility moves: the crossing eigenvalue
        meets the rigid turns' zero, where the mobility enters."""
        from ..analysis import stability  # start-up time: scipy

        kind = "steady rotation (a real eigenvalue crosses 0)"
        if self._independent(physics):
            return Onset(stability.rotation_threshold(physics.n), 0.0, kind)
        sigma_r, omega = rotation_threshold_fluid(self.beds(physics))
        return Onset(sigma_r, omega, f"{kind} through the fluid (a / l = {physics.bead_radius:g})")

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        """N = 7 at sigma = 0.8, the planar rotating pin's case, from the seeded non-planar start."""
        return (ValidationCase(self.physics(n=7, sigma=0.8), 300.0),)

    def tip_views(self, traj: Trajectory, keep: np.ndarray) -> tuple[PathView, ...]:
        """The tip's path in the plane of the turn (where a rigid turn is a circle about the pivot), then in three
        dimensions. The plane is the path's best fit (its normal the path's direction of least spread), its axes u
        along e_x's projection on it (e_y's where e_x is its normal) and v = normal x u: a turn in the xy plane is
        drawn on x and y."""
        tips = self.tip(traj)[keep]
        path = tips.reshape(-1, 3)
        normal = np.linalg.svd(path - path.mean(axis=0), full_matrices=False)[2][-1]
        u = next(u for e in np.eye(3)[:2] if np.linalg.norm(u := e - (e @ normal) * normal) > 1e-6)
        u /= np.linalg.norm(u)
        v = np.cross(normal if normal[2] >= 0 else -normal, u)
        plane = np.stack([tips @ u, tips @ v], axis=-1)
        return PathView(plane, ("u", "v"), "in the plane of the turn"), PathView(tips, ("x", "y", "z"), "3D")

    def video_period(self, traj: Trajectory) -> float | None:
        """One turn per second of video."""
        omega = self.measure_extra(traj, 0.5 * float(traj.t[-1]))["rotation_rate"]
        return 2.0 * math.pi / omega if omega > 1e-3 else None


SCENE = Pivot3D()

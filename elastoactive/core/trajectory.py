"""A simulated trajectory: sample times and absolute angles, the same for both engines, and what follows from them:
every particle's position (a chain's, from its angles; a network's nodes, as recorded), the tips, the centres of drag,
and an xarray Dataset with units.

Lengths are in the scene's unit (l, the link length, for a chain; a, the rest spacing, for a network), times in tau.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import ParameterError
from .params import Physics
from .units import CHAIN, scene_units

TIME_UNITS = CHAIN.time_units
"""The unit of a chain's times (tau = gamma l^2 / C1); a scene's own: units.scene_units(scene).time_units (gamma/k
for a network)."""


def particle_positions(physics: Physics, theta, head=None) -> np.ndarray:
    """Every particle's position from the absolute angles: r_i = r_pivot + sum_{j <= i} (cos theta_j, sin theta_j).

    Parameters
    ----------
    physics : Physics
        The chain scene (its chains, particles per chain and each chain's pivot offset, Scene.chain_offset).
    theta : array_like, shape (..., n_angles)
        Absolute angles (rad), chain 1 then chain 2.
    head : array_like, shape (..., 2), optional
        The first chain's pivot for a scene whose pivot moves (the paraboloid's head, a moving clamp); a head of
        another width (a star's hub angle) moves no pivot.

    Returns
    -------
    numpy.ndarray, shape (..., n_chains, n, 2)
        Positions in units of l; particle i of a chain sits one link from particle i - 1, particle 0 one link from
        its chain's pivot.
    """
    theta = np.asarray(theta, dtype=float)
    if theta.ndim < 1 or theta.shape[-1] != physics.n_chains * physics.n:
        raise ParameterError(
            f"theta must have {physics.n_chains * physics.n} angles per sample ({physics.n_chains} chain(s) of "
            f"{physics.n}) for {physics.scene}; got shape {theta.shape}"
        )
    a = theta.reshape(theta.shape[:-1] + (physics.n_chains, physics.n))
    xy = np.stack([np.cumsum(np.cos(a), axis=-1), np.cumsum(np.sin(a), axis=-1)], axis=-1)
    for k in range(physics.n_chains):
        xy[..., k, :, 1] += physics.scene_def.chain_offset(physics, k)
    if head is not None and np.shape(head)[-1] == 2:  # a moving pivot; a star's head is its hub's angle
        xy[..., 0, :, :] += np.asarray(head, dtype=float)[..., None, :]
    return xy


def _array(name: str, values, ndim: int, samples: int | None = None) -> np.ndarray:
    """values as a float array of `ndim` dimensions (and `samples` rows); a ParameterError naming the field else."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"Trajectory.{name} must be an array of numbers, got {type(values).__name__}") from None
    if array.ndim != ndim or (samples is not None and array.shape[0] != samples):
        rows = "" if samples is None else f", one row per time of t ({samples})"
        raise ParameterError(f"Trajectory.{name} must have {ndim} dimension(s){rows}; got shape {array.shape}")
    return array


@dataclass
class Trajectory:
    """A simulated trajectory, the same for both engines.

    Attributes
    ----------
    t : numpy.ndarray, shape (T,)
        Sample times in tau.
    theta : numpy.ndarray, shape (T, n_angles)
        Absolute angles (rad) of every link, chain 1 then chain 2; shape (T, 0) for a network scene.
    physics : Physics
        The scene and parameters that ran.
    engine : str
        "mujoco" or "reduced".
    wall_time_s : float
        The engine's wall time.
    info : dict
        Solver information (the reduced engine's method, MuJoCo's steps); `ea.load` adds the run's summary.json
        under "summary".
    head : numpy.ndarray or None, shape (T, 2)
        The first pendulum's pivot for a scene whose pivot moves (Scene.head_coordinates: the paraboloid; a moving
        clamp), a star's hub angle (T, 1); None where the pivot sits at the origin.
    polarity : numpy.ndarray or None, shape (T, units)
        Absolute angles psi of the self-aligning active units (one per loaded particle, chain 1 then chain 2; a
        network's: one per active unit, in node order), else None.
    nodes : numpy.ndarray or None, shape (T, P, 2)
        Lab positions of every node of a network scene (Scene.network), else None.

    Positions follow from these: `positions` (every particle, or a network's nodes), `tip`, `centre_of_drag`, and
    `to_xarray` gives them all as an xarray Dataset with units.
    """

    t: np.ndarray
    theta: np.ndarray
    physics: Physics
    engine: str
    wall_time_s: float = 0.0
    info: dict = field(default_factory=dict)
    head: np.ndarray | None = None
    polarity: np.ndarray | None = None
    nodes: np.ndarray | None = None

    def __post_init__(self) -> None:
        """The records as float arrays (a Trajectory built from lists measures as one from an engine does), their
        shapes checked: t (T,), theta (T, n_angles), head (T, 2), polarity (T, units), nodes (T, P, 2)."""
        self.t = _array("t", self.t, 1)
        self.theta = _array("theta", self.theta, 2, len(self.t))
        for name, ndim in (("head", 2), ("polarity", 2), ("nodes", 3)):
            if getattr(self, name) is not None:
                setattr(self, name, _array(name, getattr(self, name), ndim, len(self.t)))

    def chain(self, k: int) -> np.ndarray:
        """Angles of chain k (0 or 1), shape (T, N)."""
        n = self.physics.n
        return self.theta[:, k * n : (k + 1) * n]

    @property
    def length_units(self) -> str:
        """The unit of this trajectory's positions (its scene's: l for a chain, a for a network)."""
        return self.physics.scene_def.length_units

    def positions(self) -> np.ndarray:
        """Every particle's position at every sample time (the scene's kind says which: Scene.positions).

        Returns
        -------
        numpy.ndarray
            A chain scene: shape (T, n_chains, n, 2), (x, y) of particle i (0-based, as the model's sites
            ``particle_{i}``) of each chain in units of l, from the angles and the moving pivot (`head`) if any. A
            chain in three dimensions (clamped-3d): shape (T, 1, n, 3), (x, y, z) in units of l, from its azimuths
            and elevations; a run's trajectory.npz holds the same array as ``position``. A network scene: its nodes,
            shape (T, nodes, 2) in units of a, as recorded.
        """
        return self.physics.scene_def.positions(self)

    def tip(self) -> np.ndarray:
        """The last particle of every chain at every sample time.

        Returns
        -------
        numpy.ndarray, shape (T, n_chains, 2)
            (x, y) of each chain's tip in units of l (``positions()[:, :, -1]``).

        Raises
        ------
        ParameterError
            For a network scene, which has no tip (`positions` gives its nodes).
        """
        return self.physics.scene_def.tip(self)

    def centre_of_drag(self) -> np.ndarray:
        """The mean position of the points that carry drag: every particle (node), and a free head (the paraboloid's,
        a free ring's root: ChainSystem.head_free), each carrying one particle's drag. With isotropic drag it is the
        point whose velocity the total force sets (total force / total drag).

        Returns
        -------
        numpy.ndarray
            A chain scene: shape (T, n_chains, 2), one centre per chain (units l); a network: shape (T, 2) (units a).
        """
        return self.physics.scene_def.centre_of_drag(self)

    def to_xarray(self):
        """The trajectory as an xarray Dataset, every variable and coordinate with a short ``long_name`` (what
        xarray's own plots label an axis with) and a longer ``description``, every variable with ``units``.

        Returns
        -------
        xarray.Dataset
            Coordinate ``time`` (tau), and ``xy`` where a variable has lab-frame components in the plane; a chain
            scene's ``chain`` and ``particle`` (0-based, as the model's sites) with ``theta`` (time, chain, particle;
            rad), ``position`` (time, chain, particle, xy; l) and ``tip`` (time, chain, xy; l); a chain in three
            dimensions has ``tangent`` (time, chain, particle, xyz; 1), ``position`` (time, chain, particle, xyz; l)
            and ``tip`` (time, chain, xyz; l) instead, on the coordinate ``xyz``; a network's ``node`` (with
            ``pinned``, the nodes held at rest) and ``position`` (time, node, xy; a). ``head`` and ``polarity``
            (time, unit) when recorded, the ``unit`` dimension with where each unit sits (a network's ``unit_node``, a
            chain's ``unit_chain`` and ``unit_particle``). Attributes: the scene, the engine and every parameter that
            acts (Physics.relevant).
        """
        import xarray as xr  # start-up time: xarray loads pandas

        units = self.length_units
        time_units = scene_units(self.physics.scene_def).time_units
        coords = {"time": ("time", self.t, {"units": time_units, "long_name": "time", "description": "sample time"})}
        state_coords, data = self.physics.scene_def.state_variables(self)  # the scene's kind: angles or nodes
        coords.update(state_coords)
        if self.head is not None:
            moving = self.head.shape[1] == 2
            data["head"] = (
                ("time", "xy") if moving else ("time", "head_coordinate"),
                self.head,
                {"units": units, "long_name": "pivot position", "description": "position of the moving pivot"}
                if moving
                else {"units": "rad", "long_name": "hub angle", "description": "angle of the star's hub"},
            )
        if self.polarity is not None:
            data["polarity"] = (
                ("time", "unit"),
                self.polarity,
                {"units": "rad", "long_name": "polarity", "description": "polarity angle psi of each active unit"},
            )
        if any("xy" in dims for dims, *_ in data.values()):  # lab-frame components in the plane
            coords["xy"] = ("xy", ["x", "y"], {"long_name": "component", "description": "lab-frame component"})
        attrs = {"scene": self.physics.scene, "engine": self.engine}
        for name, value in self.physics.relevant().items():
            if name != "scene":
                attrs[name] = int(value) if isinstance(value, bool) else value
        return xr.Dataset(data, coords=coords, attrs=attrs)

"""Where a run starts: a chain's angles, or a network's node positions and unit polarities, given or taken from the
last sample of a saved run (ea.simulate(..., start=...), `elastoactive ramp --start-from`).

A `Start` is one of the two kinds of state the engines take (a chain's theta0; a network's NetworkState, state0).
A start taken from a run (a Trajectory, a saved run's folder) carries that run's Physics, its `origin`. Before a run,
`Start.checked` holds the start to the scene, refusing in one line that names the option (`start` in Python,
`--start-from` on the command line) and both scenes:

  the run's scene     a start from a run of another scene, or of the same scene with another shape (N, the chains,
                      the network's nodes and units), is refused unless the scene accepts it (Scene.accepts_start:
                      by default the same scene and the same state shape)
  the kind of state   a chain's angles for a network, or a network's nodes for a chain
  the size            a given chain's angles, counted against the scene's (Scene.angle_count)
  the constraints     a state the scene's constraints do not hold (Scene.start_violation: an open chain off a ring's
                      or a two-pinned chain's pin)

The engine then checks what only it can (a network's nodes and units against its network, its pinned nodes at rest:
engines.network_reduced.start_state). A chain starts from its angles only (a term's polarities start along the
follower direction, as from the scene's own state).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .core.errors import ParameterError
from .core.params import Physics
from .core.trajectory import Trajectory
from .networks.state import NetworkState
from .records import load_trajectory


@dataclass(frozen=True)
class Start:
    """A state to start from: `theta` (a chain's absolute angles, chain 1 then chain 2) or `positions` (P, 2) and
    `polarity` (A,) (a network's nodes, pinned ones at rest, and its active units' angles in node order); `source`
    says where it comes from (a run's folder and time, or "given"); `origin` is the Physics of the run it was taken
    from (None: a state given as numbers)."""

    theta: np.ndarray | None = None
    positions: np.ndarray | None = None
    polarity: np.ndarray | None = None
    source: str = "given"
    origin: Physics | None = None

    def __post_init__(self) -> None:
        chain = self.theta is not None
        network = self.positions is not None or self.polarity is not None
        if chain == network:
            raise ParameterError(
                "start: give either a chain's angles (theta) or a network's positions and polarity, not "
                + ("both" if chain else "neither")
            )
        if network and (self.positions is None or self.polarity is None):
            raise ParameterError("start: a network's state needs both its positions and its polarity")

    def checked(self, physics: Physics, option: str = "start") -> Start:
        """This start, held to the scene of `physics` (the module's docstring); a ParameterError naming `option` (the
        caller's word for it: "start", "--start-from") when it is not a state of that scene."""
        scene = physics.scene_def
        if self.origin is not None and not scene.accepts_start(self.origin, physics):
            wanted = physics.scene if self.origin.scene != physics.scene else _described(physics)
            raise ParameterError(
                f"{option}: the run is of scene {_described(self.origin)}, not {_described(physics)}; start from a run "
                f"of {wanted}"
            )
        takes_angles = physics.n_angles > 0
        if self.theta is not None and not takes_angles:
            raise ParameterError(
                f"{option}: a chain's angles cannot start {_described(physics)}, a {scene.kind} (its state: node "
                "positions and unit polarities)"
            )
        if self.theta is None and takes_angles:
            raise ParameterError(
                f"{option}: a network's nodes and polarities cannot start {_described(physics)}, a {scene.kind} "
                "(its state: its angles)"
            )
        if self.theta is not None:
            finite_angles(self.theta, option)
            count = np.asarray(self.theta).size
            if count != physics.n_angles:
                raise ParameterError(f"{option}: {count} angles given; {_described(physics)} takes {physics.n_angles}")
            violation = scene.start_violation(physics, np.asarray(self.theta, dtype=float).reshape(-1))
            if violation:
                raise ParameterError(f"{option}: {violation}; not a state of {_described(physics)}")
        return self

    def engine_options(self) -> dict:
        """The engines' keyword for this state: theta0 (a chain's angles) or state0 (a network's NetworkState)."""
        if self.theta is not None:
            return {"theta0": np.asarray(self.theta, dtype=float)}
        return {"state0": NetworkState(np.asarray(self.positions, dtype=float), np.asarray(self.polarity, dtype=float))}


def finite_angles(value, option: str) -> np.ndarray:
    """A chain's angles as given (a start's, theta0): one-dimensional, every one a finite number; a ParameterError
    naming `option` otherwise. How many a scene takes, its engine checks."""
    try:
        theta = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"{option}: a chain's angles must be numbers, got {type(value).__name__}") from None
    if theta.ndim != 1:
        raise ParameterError(
            f"{option}: a chain's angles must be one-dimensional (chain 1 then chain 2), got shape {theta.shape}"
        )
    bad = np.flatnonzero(~np.isfinite(theta))
    if bad.size:
        raise ParameterError(f"{option}: angle {int(bad[0])} is {theta[bad[0]]}; every angle must be finite")
    return theta


def _described(physics: Physics) -> str:
    """A scene and its state's shape in a message: "one-pinned (N = 7)"."""
    return f"{physics.scene} ({physics.scene_def.state_label(physics)})"


def last_state(trajectory: Trajectory, source: str = "") -> Start:
    """The state at a trajectory's last sample: its nodes and polarities for a network, its angles for a chain; its
    origin the trajectory's physics."""
    where = f"{source or trajectory.physics.scene} at t = {float(trajectory.t[-1]):g}"
    origin = trajectory.physics
    if trajectory.nodes is not None and trajectory.theta.shape[1] == 0:
        polarity = np.empty(0) if trajectory.polarity is None else trajectory.polarity[-1]
        return Start(positions=np.array(trajectory.nodes[-1]), polarity=np.array(polarity), source=where, origin=origin)
    return Start(theta=np.array(trajectory.theta[-1]), source=where, origin=origin)


def read_start(folder) -> Start:
    """The last state of the run saved in `folder` (`elastoactive run --out`: its trajectory.npz, checked against its
    summary's checksums); one line naming the folder when it holds no run."""
    folder = Path(folder).expanduser()
    path = folder / "trajectory.npz" if folder.is_dir() else folder
    if not path.is_file() or path.name != "trajectory.npz":
        raise ParameterError(f"start: {folder} holds no saved run (a folder written by `elastoactive run --out`)")
    return last_state(load_trajectory(path), source=str(folder))


def as_start(value) -> Start:
    """A Start from what a caller gives: a Start, a Trajectory (its last sample), a run's folder (str or Path), a
    NetworkState, a (positions, polarity) pair, or a chain's angles (one array)."""
    if isinstance(value, Start):
        return value
    if isinstance(value, Trajectory):
        return last_state(value)
    if isinstance(value, (str, Path)):
        return read_start(value)
    if isinstance(value, NetworkState) or (isinstance(value, tuple) and len(value) == 2):
        positions, polarity = value
        return Start(positions=np.asarray(positions, dtype=float), polarity=np.asarray(polarity, dtype=float))
    try:
        theta = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise TypeError(
            "start must be an ea.Trajectory, a run's folder, a NetworkState, (positions, polarity) or a chain's angles;"
            f" got {type(value).__name__}"
        ) from None
    return Start(theta=theta)

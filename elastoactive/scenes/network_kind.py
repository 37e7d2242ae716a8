"""The network kind of scene: an elastic network of nodes joined by springs, its active nodes carrying units whose
polarity turns (elastoactive.networks: the Network record), its state the node positions (Trajectory.nodes) and the
units' polarities (Trajectory.polarity).

A network scene (lattice, network, trapped-unit) subclasses `NetworkScene` (or elastoactive.scenes.lattice's
ActiveNetwork, which adds the observables every network with self-aligning units shares) and defines `network`.
Besides the kind contract (elastoactive.scenes.base) a network scene has:

  network             `network(physics)`: the Network record both engines simulate and the renderer draws;
                      `initial_network`: its state at t = 0
  units               elastoactive.core.units.NETWORK (k = gamma = a = 1)

Its engines are elastoactive.engines.network_mujoco and network_reduced, its builder elastoactive.mjcf.network, its
painter elastoactive.render.network; the hooks import them inside the hook (the engine boundary: a chain's run never
loads them, and the scenes load before the engines, which read the scene registry).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..core.errors import ParameterError
from ..core.units import NETWORK
from ..networks.geometry import Network, has_unit_fields
from ..networks.state import NetworkState, initial_state
from ..terms.unit_noise import unit_noise
from .base import Onset, Scene

if TYPE_CHECKING:  # typing only: these modules import the registry that holds scenes
    from ..core.params import Numerics, Physics
    from ..core.trajectory import Trajectory


LARGE_TOLERANCES = (1e-6, 1e-8)
"""A large network's automatic (rtol, atol) in the reduced engine (NetworkScene.reduced_tolerances): its time means'
change from a run at rtol 1e-11 stays far below their reported errors, at 55-65% of rtol 1e-8's right-hand sides
(docs/performance.md, section 10), and the named states' still level stays 1e-3 Pi (analysis.network.states:
1e3 rtol Pi, where still units' jitter measures up to 160 rtol Pi); at rtol 1e-5 it would rise tenfold and move the
freezing points of ramps down."""


POLARITY_ARROW = 0.4
"""Length (units a) of a unit's polarity arrow in ea.plot.shape: shorter than the rest spacing, so that neighbours'
arrows do not cross."""


class NetworkScene(Scene):
    """A scene of an elastic network of active units (module docstring)."""

    kind = "network"
    units = NETWORK
    """k = gamma = a = 1: times in gamma / k, sigma = F_a / (k a) (elastoactive.core.units)."""
    agreement = 0.02
    """MuJoCo's nodes carry a small mass (the overdamped limit's mass_ratio) that the reduced model has not, and a
    pinned node gives under MuJoCo's soft equality: the node positions agree to ~1% over a short run."""
    base_file = "network.xml"
    state_units = "a"
    state_name = "displacement"
    mujoco_batched = False
    seeded_start = True
    paced_by_beat = False
    sized_by_n = False
    builder = "elastoactive.mjcf.network"

    # ------------------------------------------------------------------ the network
    def network(self, physics: Physics) -> Network:
        """The elastic network of active units this scene simulates (both engines build it; the renderer draws it)."""
        raise self._kind_hook("network")

    def initial_network(self, physics: Physics, numerics: Numerics) -> NetworkState:
        """The state at t = 0, read by both engines: nodes at rest plus seeded pushes of up to numerics.perturbation
        (units a), polarities seeded uniformly on the circle (numerics.seed)."""
        return initial_state(self.network(physics), numerics.perturbation, numerics.seed)

    def extent_points(self, physics: Physics) -> np.ndarray:
        return self.network(physics).positions

    # ------------------------------------------------------------------ engines (the engine boundary)
    def run_mujoco(
        self,
        physics: Physics,
        numerics: Numerics,
        duration: float,
        *,
        theta0=None,
        state0=None,
        progress: bool = False,
        on_sample=None,
        install_callbacks: bool = True,
    ) -> Trajectory:
        from ..engines.network_mujoco import simulate_network_mujoco  # engine boundary: chains never load it

        if theta0 is not None:
            raise ParameterError(f"theta0: {physics.scene} is a network (its initial state: Scene.initial_network)")
        return simulate_network_mujoco(
            physics,
            numerics,
            duration,
            network=self.network(physics),
            state0=state0,
            progress=progress,
            on_sample=on_sample,
            install_callbacks=install_callbacks,
        )

    def run_reduced(
        self,
        physics: Physics,
        numerics: Numerics,
        duration: float,
        *,
        theta0=None,
        state0=None,
        rtol: float | None = None,
        atol: float | None = None,
        method: str | None = None,
        **chain_options,
    ) -> Trajectory:
        """engines.network_reduced (rtol, atol: default reduced_tolerances); the chain model's options (beta,
        inertial, progress) do not apply. A method with noise on the units is refused, as a chain's with noise: the
        noise takes fixed Euler-Maruyama steps, which no ODE method chooses."""
        from ..engines.network_reduced import simulate_network_reduced  # engine boundary: chains never load it

        if method is not None and unit_noise(physics, numerics).active:
            raise ParameterError(
                f"method = {method}: with noise on the units (rotational_diffusion, translational_diffusion) the "
                "reduced engine takes fixed Euler-Maruyama steps of --dt; leave --method out"
            )

        return simulate_network_reduced(
            physics, numerics, duration, theta0=theta0, state0=state0, rtol=rtol, atol=atol, method=method
        )

    def reduced_tolerances(self, physics: Physics) -> tuple[float, float]:
        """A network's automatic (rtol, atol), chosen on the measured error against cost (docs/performance.md, section
        10): a chain's where the run is cheap whatever its tolerance (a network of at most reduced.network.DENSE_MODES
        free coordinates: 1000 gamma / k of 127 nodes in ~1.5 s of CPU), LARGE_TOLERANCES above, where it is not."""
        from ..reduced.network import is_large  # engine boundary: the reduced engine's own module

        return LARGE_TOLERANCES if is_large(self.network(physics)) else super().reduced_tolerances(physics)

    def record_columns(self, physics: Physics) -> int:
        """Two per node (Trajectory.nodes) and one per unit (Trajectory.polarity)."""
        network = self.network(physics)
        return 2 * network.n_nodes + int(np.count_nonzero(network.active))

    def state_label(self, physics: Physics) -> str:
        """The network's nodes and units, for messages: "7 nodes, 1 unit"."""
        network = self.network(physics)
        units = int(np.count_nonzero(network.active))
        return f"{network.n_nodes} nodes, {units} unit{'' if units == 1 else 's'}"

    def record_numerics(self, physics: Physics, numerics: Numerics, duration: float) -> Numerics:
        """A large network's record coarsened (engines.network_step.network_sampling)."""
        from ..engines.network_step import network_sampling  # engine boundary: chains never load it

        return network_sampling(physics, numerics, duration)

    def check_timestep(self, physics: Physics, numerics: Numerics, safety: float, accuracy: bool, **options):
        """The network's own linearisation (engines.network_mujoco.check_network_timestep): its fastest rate."""
        from ..engines.network_mujoco import check_network_timestep  # engine boundary: chains never load it
        from ..engines.timestep import StabilityLimits

        rate = check_network_timestep(physics, numerics)
        spring_dt = 2.0 / rate if rate > 0 else math.inf  # nothing stiff (no bond, no trap, no force): any step
        return StabilityLimits(spring_dt=spring_dt, drag_dt=math.inf, follower_dt=math.inf, fastest_rate=rate)

    def reduced_methods(self) -> tuple[str, ...]:
        from ..engines.network_reduced import METHODS  # engine boundary: the engines load numba

        return tuple(METHODS)

    # ------------------------------------------------------------------ trajectory
    def positions(self, traj: Trajectory) -> np.ndarray:
        """The nodes, shape (T, nodes, 2) in units of a, as recorded."""
        return traj.nodes.copy()

    def tip(self, traj: Trajectory) -> np.ndarray:
        raise ParameterError(
            f"Trajectory.tip: the {traj.physics.scene} scene is a network, which has no tip; "
            "Trajectory.positions() gives its nodes"
        )

    def centre_of_drag(self, traj: Trajectory) -> np.ndarray:
        """Shape (T, 2): the nodes' mean (units a)."""
        return self.positions(traj).mean(axis=-2)

    def state_variables(self, traj: Trajectory) -> tuple[dict, dict]:
        """The nodes' positions (time, node, xy); the coordinates say which nodes are pinned (``pinned`` on
        ``node``) and, where polarities are recorded, which node each unit sits on (``unit_node`` on ``unit``, the
        polarity's dimension)."""
        network = self.network(traj.physics)
        coords = {
            "node": (
                "node",
                np.arange(traj.nodes.shape[1]),
                {"long_name": "node", "description": "node index, 0-based"},
            ),
            "pinned": (
                "node",
                np.asarray(network.pinned, dtype=bool),
                {"long_name": "pinned", "description": "whether the node is held at its rest position"},
            ),
        }
        if traj.polarity is not None:
            coords["unit"] = ("unit", np.arange(network.n_units), {"long_name": "unit", "description": "unit index"})
            coords["unit_node"] = (
                "unit",
                np.flatnonzero(network.active),
                {"long_name": "node of the unit", "description": "index of the node the active unit sits on"},
            )
        data = {
            "position": (
                ("time", "node", "xy"),
                traj.nodes,
                {"units": self.length_units, "long_name": "node position", "description": "lab-frame node position"},
            )
        }
        return coords, data

    def state_difference(self, traj: Trajectory, reference: Trajectory, early: np.ndarray) -> tuple[float, float]:
        """The largest node position difference (units a), relative to the largest displacement from rest."""
        n = early.size
        rest = self.network(reference.physics).positions
        diff = np.abs(traj.nodes[:n][early] - reference.nodes[:n][early]).max()
        return float(diff), float(np.abs(reference.nodes[:n][early] - rest).max())

    # ------------------------------------------------------------------ drawing
    def caption_line(self, physics: Physics) -> str:
        nodes = len(self.network(physics).positions)
        return "   ".join([physics.scene, f"{nodes} nodes", f"σ = {physics.sigma:.3g}", *self.caption(physics)])

    def painter(self, traj: Trajectory, **options):
        from ..render import check_picture  # engine boundary: rendering loads MuJoCo and GL
        from ..render.network import NetworkPainter

        check_picture(width=options["width"], height=options["height"], trail=options["trail"])
        return NetworkPainter(traj, **options)

    def draw_shape(self, ax, traj: Trajectory, i: int, labels: list[str]) -> None:
        """The springs in grey, the free nodes as dots, the pinned nodes as dark squares (label 'pinned') and, where
        polarities are recorded, an arrow of length POLARITY_ARROW along each unit's polarity (cos psi, sin psi) from
        its node (a quiver labelled 'polarity')."""
        network, nodes = self.network(traj.physics), traj.nodes[i]
        for a, b in network.bonds:
            ax.plot(nodes[[a, b], 0], nodes[[a, b], 1], color="0.6", lw=0.8)
        free, pinned = nodes[~network.pinned], nodes[network.pinned]
        ax.plot(free[:, 0], free[:, 1], "o", ms=3, label="free node")
        if len(pinned):
            ax.plot(pinned[:, 0], pinned[:, 1], "s", color="0.2", ms=5, label="pinned")
        if traj.polarity is not None and network.n_units:
            psi, at = traj.polarity[i], nodes[network.active]
            ax.quiver(
                at[:, 0],
                at[:, 1],
                POLARITY_ARROW * np.cos(psi),
                POLARITY_ARROW * np.sin(psi),
                angles="xy",
                scale_units="xy",
                scale=1.0,
                color="tab:orange",
                width=0.006,
                label="polarity",
            )
        ax.legend(fontsize="small")

    # ------------------------------------------------------------------ stability
    def coupling(self, physics: Physics, sigma: float | None = None) -> float:
        """Pi = l_e / l_a at `sigma` (default physics.sigma): l_e = F_a / k with the springs' k = 1."""
        return (physics.sigma if sigma is None else sigma) / physics.alignment_length

    def shaping_parameters(self, physics: Physics) -> tuple[str, ...]:
        """The scene's own parameters that shape this physics' network (what a report describes it by): all of them,
        unless a scene's network comes from elsewhere (a file's) and some leave it untouched."""
        return self.own_parameter_names()

    def stability_report(
        self, physics: Physics, sigma: float | None, onset: Onset | None = None, eigenvalue: complex | None = None
    ) -> list[str]:
        """The onset in the coupling Pi = l_e / l_a (coupling). Where its fixed points form a family: what is proved
        (every one stable below lambda_1, none above the ceiling) apart from what a search found (one stable up to at
        least its Pi), and, at `sigma`, which of these the given Pi falls in."""
        la = physics.alignment_length
        onset = self.onset(physics) if onset is None else onset
        own = ", ".join(f"{k} = {getattr(physics, k)}" for k in self.shaping_parameters(physics))
        lines = [f"{physics.scene}, {own}, l_a = {la:g}:", f"  onset: {onset.kind}"]

        def at(value: float) -> str:
            return f"Pi = {self.coupling(physics, value):.6g}, sigma = {value:.6g}"

        lowest = "lambda_1 / max_u w_u, w_u = f_u l_a / l_u" if has_unit_fields(self.network(physics)) else "lambda_1"
        if onset.sigma_all is None:
            lines.append(f"  at sigma_c = {onset.sigma_c:.10g} (Pi_c = {self.coupling(physics, onset.sigma_c):.6g})")
        else:
            lines += [
                f"  every fixed point is stable below {at(onset.sigma_c)} ({lowest}, proved)",
                f"  some fixed point is stable up to at least {at(onset.sigma_all)} (the best found)",
                f"  no fixed point is stable above {at(onset.sigma_ceiling)} (proved ceiling)",
                "  between, which fixed points are stable depends on their polarities",
            ]
        if sigma is not None:
            lam = self.leading_eigenvalue(physics, sigma) if eigenvalue is None else eigenvalue
            which = "the least stable fixed point's" if onset.sigma_all is not None else "the rest state's"
            state = "unstable" if lam.real > 0 else "stable"
            line = (
                f"  at sigma = {sigma:g} (Pi = {self.coupling(physics, sigma):.6g}): {which} growth rate "
                f"{lam.real:+.6g} k/gamma ({state}"
            )
            if onset.sigma_all is not None and lam.real > 0:
                line += (
                    "; some fixed point is stable"
                    if sigma < onset.sigma_all
                    else "; no fixed point is stable"
                    if sigma > onset.sigma_ceiling
                    else "; whether some fixed point is stable is not settled"
                )
            lines.append(line + ")")
        return lines

"""A hexagonal patch of triangular lattice carrying self-aligning active units: an active solid.

Beyond the paper (its outlook's two-dimensional structures and non-follower forces): the active solid of Baconnier et
al., "Selective and collective actuation in active solids", Nature Physics 18, 1234 (2022). Nodes on a triangular
lattice of spacing a, cut to a hexagon of R rings (`rings`, 1 + 3R(R+1) nodes), joined by springs of stiffness k and
rest length a; `boundary` holds it: the outer ring pinned (the experiment's), nothing, or only the centre node (the
patch can turn about it). Every free node carries a self-aligning unit: force F_a n_i = sigma n_i, polarity turning
toward the node's velocity over the alignment length l_a (`alignment_length`):

    dx_i/dt = sigma n_i + F_i,        dpsi_i/dt = (1 / l_a) (dx_i/dt) . n_perp_i

Units: k = 1, gamma = 1, a = 1 (time in gamma / k); sigma = F_a / (k a) = l_e / a, so the elasto-active coupling is
Pi = l_e / l_a = sigma / alignment_length. The chain's n and the chain terms' parameters (drag ratio, noise,
contact, loaded) do not act on a network (refused as such); its units are always self-aligning (`--active follower`
is refused in one line).

Observables: the beat of the pinned patch's mean displacement along x, or of the rate of a patch's rigid motion (its
rotation rate, centre-pinned; its centroid's velocity, free), the units' polarization, their signed mean turning rate,
mean turning speed and coherence (actuation), the share of elastic energy on the two most energetic normal modes of
the patch's deformation (its rigid motion taken out) and which modes those are (analysis.network.observables), and the
patch's rigid rotation rate and drift. docs/network.md has the physics, the linear stability and the transition.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from ..analysis.network import BOUNDARIES, MAX_RINGS, Network, hexagonal_patch, states
from ..analysis.network import observables as nobs
from ..core.errors import ParameterError
from ..core.observables import Observable
from ..core.parameters import Parameter
from ..core.params import Physics, option
from ..core.trajectory import Trajectory
from ..core.units import Signal
from ..terms import polarity_terms, turning_rate, unit_noise
from .base import Onset, ValidationCase
from .network_kind import NetworkScene

RINGS = Parameter(
    "rings",
    2,
    f"rings R of the hexagonal patch (1 + 3R(R+1) nodes, R = 1..{MAX_RINGS})",
    kind=int,
    low=1,
    high=MAX_RINGS,
    title="rings of the hexagonal patch R",
    symbol="R",
)
BOUNDARY = Parameter(
    "boundary",
    "pinned",
    "how the patch is held: pinned (its outer ring), free, or centre (only its centre node, so it can turn)",
    kind=str,
    choices=BOUNDARIES,
    title="the patch's boundary",
)

NETWORK_TERMS = ("sigma", "active", "alignment_length", *unit_noise.NAMES)
"""The terms' parameters that act on a network: the active force, the units' direction law and length, their noise."""
SELF_ALIGNING_ONLY = ((*polarity_terms()[0].polarity_switch, "a network's active units are self-aligning"),)

MEANING = tuple(states.STATE_MEANING.items())
"""The named states and what each means (the network_state observable's long name)."""
NETWORK_OBSERVABLES = (
    Observable("polarization", "1", "time mean of the active units' polar order |<n_i>|", error="absolute", floor=0.0),
    Observable("polarity_rate", "rad/tau", "mean turning rate d psi / dt of the active units (signed)", floor=1e-4),
    Observable(
        "polarity_speed", "rad/tau", "mean |d psi / dt| of the active units: how fast they turn, either way", floor=1e-4
    ),
    Observable(
        "actuation",
        "1",
        "coherence of the units' turning |<d psi/dt>| / <|d psi/dt|> (1: collective actuation, 0: still)",
        error="absolute",
        floor=0.0,
    ),
    Observable(
        "condensation",
        "1",
        "share of the elastic energy on the two most energetic normal modes",
        error="absolute",
        floor=0.0,
    ),
    Observable(
        "dominant_mode",
        "1",
        "rank by stiffness (1: softest) of the most energetic normal mode of the deformation (0: none, undeformed)",
        error="none",
    ),
    Observable(
        "second_mode", "1", "rank by stiffness of the second most energetic normal mode (0: none)", error="none"
    ),
    Observable(
        "mode_space",
        "1",
        "rank by stiffness of the softest mode of the eigenspace holding the most elastic energy (0: none)",
        error="none",
    ),
    Observable("mode_space_size", "1", "dimension of that eigenspace (2: a degenerate pair; 0: none)", error="none"),
    Observable("mode_space_share", "1", "share of the elastic energy in that eigenspace", error="absolute", floor=0.0),
    Observable(
        "network_state",
        "1",
        "named state of the units (analysis.network.states: " + "; ".join(f"{k}: {v}" for k, v in MEANING) + ")",
        error="none",
        categories=states.STATES,
    ),
    Observable("edge_rate", "rad/tau", "mean |net turning rate| of the units nearest the edge", floor=1e-4),
    *(
        Observable(
            f"{name}_error",
            units,
            f"standard error of {name} from its spread over {nobs.ERROR_BLOCKS} blocks of the measured window",
            error="none",
        )
        for name, units in (("polarization", "1"), ("polarity_speed", "rad/tau"), ("actuation", "1"))
    ),
    Observable("bulk_rate", "rad/tau", "mean |net turning rate| of the units deepest inside", floor=1e-4),
    Observable(
        "counter_fraction",
        "1",
        "share of the turning units that turn against the majority's sense (0: one sense; 0.5: as many each way)",
        error="absolute",
        floor=0.0,
    ),
)
"""What every network scene measures (analysis.network.observables)."""
PATCH_OBSERVABLES = (
    Observable("patch_rotation_rate", "rad/tau", "mean rate of the patch's rigid rotation (least squares)", floor=1e-4),
    Observable(
        "patch_drift",
        "a/tau",
        "mean speed of the patch's centroid (its rigid translation) over the measured window",
        floor=1e-4,
    ),
)
"""The patch's rigid motion (the lattice's own)."""
DISPLACEMENT = Signal("u_x", "u_x = the free nodes' mean displacement along x", "a")
"""A held network's beat signal (ActiveNetwork.beat_signals)."""


HOLD_WORDS = {"free": "move and turn", "centre": "turn about its pinned node", "pinned": "hold still"}
"""What each way of holding a network (Lattice.hold) leaves it free to do, in messages."""


class ActiveNetwork(NetworkScene):
    """What the network scenes share: the parameters that act on them, the self-aligning units, the observables."""

    term_parameters: ClassVar[tuple[str, ...]] = NETWORK_TERMS
    fixed: ClassVar[tuple[tuple[str, Any, str], ...]] = SELF_ALIGNING_ONLY
    observables: ClassVar[tuple[Observable | str, ...]] = NETWORK_OBSERVABLES
    compared: ClassVar[tuple[str, ...]] = ("amplitude", "frequency", "polarity_rate")
    no_linear_operator = (
        "its fixed points form a family (one per choice of the polarities): "
        "elastoactive.analysis.network.stability gives the coupling where the last one loses "
        "stability (docs/network.md)"
    )

    def check(self, physics: Physics) -> None:
        network = self.network(physics)
        if network is not None and network.pinned.all():
            raise ParameterError(f"boundary: every node of the {self.name} network is pinned; nothing can move")

    def label(self, physics: Physics) -> str:
        own = " ".join(
            f"{k}={getattr(physics, k):.4g}" if isinstance(getattr(physics, k), float) else f"{k}={getattr(physics, k)}"
            for k in self.own_parameter_names()
        )
        return f"{self.name} {own} sigma={physics.sigma:g} l_a={physics.alignment_length:g}".replace("  ", " ")

    coupling_formula: ClassVar[str] = "σ / l_a"
    """The coupling Pi = l_e / l_a in the scene's parameters (as drawn in captions)."""

    def caption(self, physics: Physics) -> list[str]:
        return [f"l_a = {physics.alignment_length:.3g}", f"Π = {self.coupling_formula} = {self.coupling(physics):.3g}"]

    # ------------------------------------------------------------------ observables
    def body_nodes(self, traj: Trajectory) -> np.ndarray:
        """(T, P, 2) the nodes with the network's rigid motion taken out (here none: a network held in place)."""
        return traj.nodes

    def free_displacements(self, traj: Trajectory, keep: np.ndarray | None = None) -> np.ndarray:
        """(T, 2F) the free nodes' displacements from rest in the network's own frame (body_nodes), node-interleaved
        (the normal modes' coordinates); at the samples `keep` (a mask of traj.t) when given."""
        network = self.network(traj.physics)
        nodes = self.body_nodes(traj)
        if keep is not None:  # the window is the record's tail: a view, not a copy of hundreds of MB
            tail = int(np.argmax(keep)) if keep.any() else len(keep)
            nodes = nodes[tail:] if keep[tail:].all() else nodes[keep]
        free = np.flatnonzero(~network.pinned)
        u = np.take(nodes, free, axis=1)
        u -= network.positions[free]
        return u.reshape(len(nodes), -1)

    def beat_signal(self, physics: Physics) -> Signal:
        """What beat_signals measures, for labels and units."""
        return DISPLACEMENT

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        """The mean displacement along x of the free nodes (units a)."""
        network = self.network(traj.physics)
        return [traj.nodes[:, ~network.pinned, 0].mean(axis=1) - network.positions[~network.pinned, 0].mean()]

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        from ..reduced.network import elastic_energy, is_large, normal_modes  # start-up time: numba

        keep = nobs.window(traj.t, transient)
        t, psi = traj.t[keep], traj.polarity[keep]
        network = self.network(traj.physics)
        values, vectors = normal_modes(network)  # a large network's softest only: its shares are of the whole energy
        scale = traj.physics.sigma**2 * np.count_nonzero(network.active)  # a unit's force on a unit spring: sigma^2
        u = self.free_displacements(traj, keep)
        total = float(elastic_energy(network, u).mean()) if is_large(network) else None
        modes = nobs.mode_energies(u, values, vectors, nobs.UNDEFORMED * scale, total)
        space = nobs.mode_space(modes, values)
        rtol = traj.info.get("rtol") if isinstance(traj.info, dict) else None  # the reduced engine's; MuJoCo: none
        solver_rtol = rtol if isinstance(rtol, (int, float)) else None
        still = states.still_rate(turning_rate(traj.physics), solver_rtol)
        named = states.classify(t, psi, states.depth(network)[network.active], still)
        errors = nobs.block_errors(t, psi, turning_rate(traj.physics), solver_rtol)
        return {
            "polarization": nobs.polarization(psi),
            "polarity_rate": nobs.polarity_rate(t, psi),
            "polarity_speed": nobs.polarity_speed(t, psi),
            "actuation": nobs.actuation(t, psi, turning_rate(traj.physics), solver_rtol),
            "condensation": modes.condensation,
            "dominant_mode": float(modes.dominant_modes[0]),
            "second_mode": float(modes.dominant_modes[1]),
            "mode_space": float(space.rank),
            "mode_space_size": float(space.size),
            "mode_space_share": space.share,
            "network_state": named.name,
            "edge_rate": named.edge_rate,
            "bulk_rate": named.bulk_rate,
            "counter_fraction": named.counter_fraction,
            **{f"{name}_error": value for name, value in errors._asdict().items()},
        }


class Lattice(ActiveNetwork):
    name = "lattice"
    summary = (
        "a hexagonal patch of triangular lattice with self-aligning active units (Baconnier et al.'s active solid)"
    )
    parameters = (RINGS, BOUNDARY)
    observables = NETWORK_OBSERVABLES + PATCH_OBSERVABLES

    def network(self, physics: Physics) -> Network:
        return hexagonal_patch(physics.rings, physics.boundary)

    def hold(self, physics: Physics) -> str:
        """How the network is held (BOUNDARIES): pinned (no rigid motion), centre (it can turn about its one pinned
        node, `centre`) or free."""
        return physics.boundary

    def held_text(self, physics: Physics) -> str:
        """How the network is held, in the words the user chose it by: its boundary option."""
        return f"{option('boundary', physics.boundary)} lets it {HOLD_WORDS[self.hold(physics)]}"

    def centre(self, physics: Physics) -> np.ndarray | None:
        """The pinned node the network turns about (held by its centre), else None (a free network's centroid)."""
        network = self.network(physics)
        return network.positions[np.flatnonzero(network.pinned)[0]] if self.hold(physics) == "centre" else None

    def beat_signal(self, physics: Physics) -> Signal:
        """What beat_signals measures: by how the patch is held."""
        if self.hold(physics) == "centre":
            return Signal("Omega", "Omega = the patch's rotation rate", "rad/tau")
        if self.hold(physics) == "free":
            return Signal("v_x", "v_x = the patch's centroid velocity along x", "a/tau")
        return DISPLACEMENT

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        """Pinned: the free nodes' mean displacement along x (units a). A patch that can move rigidly beats in the rate
        of that motion, whose steady part is no beat: centre-pinned, the patch's rotation rate (alternating rotation
        beats; a steady turn does not, patch_rotation_rate has it); free, its centroid's velocity along x (units a per
        gamma / k: a patch circling beats; a steady drift does not, patch_drift has it)."""
        if self.hold(traj.physics) == "pinned":
            return super().beat_signals(traj)
        if self.hold(traj.physics) == "centre":
            return [np.gradient(self._rotation(traj), traj.t)]
        return [np.gradient(traj.nodes[:, :, 0].mean(axis=1), traj.t)]

    def body_nodes(self, traj: Trajectory) -> np.ndarray:
        """The nodes in the patch's own frame: turned back about the pinned centre, or (free) moved back to the rest
        centroid and turned back; a pinned patch has no rigid motion."""
        if self.hold(traj.physics) == "pinned":
            return traj.nodes
        network = self.network(traj.physics)
        return nobs.body_positions(traj.nodes, network.positions, self.centre(traj.physics))

    def _rotation(self, traj: Trajectory) -> np.ndarray:
        network = self.network(traj.physics)
        return nobs.rotation_angle(traj.nodes, network.positions, self.centre(traj.physics))

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float]:
        out = super().measure_extra(traj, transient)
        keep = nobs.window(traj.t, transient)
        t = traj.t[keep]
        angle = nobs.rotation_angle(traj.nodes[keep], self.network(traj.physics).positions, self.centre(traj.physics))
        out["patch_rotation_rate"] = float((angle[-1] - angle[0]) / (t[-1] - t[0]))
        out["patch_drift"] = nobs.drift(t, traj.nodes[keep])
        return out

    no_linear_operator = ""

    def _threshold(self, physics: Physics):
        from ..analysis.network import stability  # start-up time: scipy only for the stability analysis

        if self.hold(physics) != "pinned":
            raise ParameterError(
                f"stability: the {self.name}'s linear stability needs a patch held in place, and "
                f"{self.held_text(physics)} (a patch free to move or turn has zero modes: no threshold)"
            )
        return stability.threshold(self.network(physics), samples=1, alignment_length=physics.alignment_length)

    def onset(self, physics: Physics) -> Onset:
        """A family of fixed points, one per choice of the polarities, each losing stability through a real
        eigenvalue of -D + Pi Q: every one is stable below Pi = lambda_1 (sigma_c = lambda_1 l_a, the onset reported);
        some fixed point found stays stable up to sigma_all = Pi_found l_a (the best of a search, so where the last
        loses stability is at or above it); none is stable above sigma_ceiling = the proved ceiling x l_a
        (analysis.network.stability, docs/network.md). Units of their own weigh Q by w_u = f_u l_a / l_u (the run's
        l_a the reference): the onset is then lambda_1 / max_u w_u and the ceilings carry the weights."""
        bracket = self._threshold(physics)
        la = physics.alignment_length
        if bracket.floppy:
            kind = (
                f"a floppy network ({bracket.floppy} zero modes): almost every fixed point is unstable at any "
                "coupling, none at all above the proved ceiling (no search)"
            )
        elif bracket.starts == 0:
            kind = (
                "a family of fixed points (one per choice of polarities), each through a real eigenvalue (a large "
                "network: no search over the polarities; the best found is lambda_1)"
            )
        else:
            kind = (
                f"a family of fixed points (one per choice of polarities), each through a real eigenvalue "
                f"(searched over the polarities from {bracket.starts} starts, {bracket.reached} ending at the best "
                "found)"
            )
        return Onset(
            sigma_c=bracket.softest * la,
            omega_c=0.0,
            sigma_all=bracket.coupling * la,
            sigma_ceiling=bracket.ceiling * la,
            kind=kind,
        )

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        """The least stable fixed point's largest growth rate (stability.least_stable_growth): Pi - lambda_1 with
        equal units on every free node (Q <= I, with equality on the softest mode when every unit's n_perp lies along
        it), zero at sigma_c; with units of their own or on some nodes only, zero at or above sigma_c."""
        from ..analysis.network import stability  # start-up time: scipy only for the stability analysis

        if self.hold(physics) != "pinned":
            self._threshold(physics)  # refuses, naming the boundary
        la = physics.alignment_length
        return complex(stability.least_stable_growth(self.network(physics), sigma / la, la))

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        return (ValidationCase(self.physics(rings=2, boundary="pinned", sigma=0.2, alignment_length=0.1), 300.0),)


SCENE = Lattice()

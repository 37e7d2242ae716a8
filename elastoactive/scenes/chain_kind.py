"""The chain kind of scene: chains of N particles joined by links of length l on hinges, their state the links'
absolute angles theta (Trajectory.theta).

A chain scene (one-pinned, two-pinned, the ring, the star, ...) subclasses `ChainScene` and overrides what differs
from a single clamped chain (the one-pinned scene overrides nothing but its name). Besides the kind contract
(elastoactive.scenes.base) a chain scene has:

  shape               `n_chains` (or `chain_count`), `clamped`, `pinned`, `head_coordinates` (or `head_count`: a
                      moving pivot), `stiffness` of each chain, `min_n`
  MJCF                `base_file` (in mjcf/) and `build`, which adds the scene's own elements (pins, coupling,
                      keyframes) to the chain(s) that elastoactive.mjcf.chain generates (`chain_prefixes`,
                      `chain_offset`)
  reduced model       `reduced_system`: the typed record the reduced solver integrates, in units of chain 1's joint
                      stiffness (`stiffness`, as MuJoCo's hinges carry it); `inertial_model`
  initial state       `initial_angles`; `start_violation`: a given start off the scene's pin (START_PIN_GAP)

The kind's hooks import their engine, builder and renderer inside the hook (the engine boundary: a chain's run loads
only the engine in use, and the scenes load before the engines, which read the scene registry).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..analysis import observables as obs
from ..core.constants import BEAD_INERTIA_FACTOR
from ..core.errors import ParameterError
from ..core.params import Numerics
from ..core.trajectory import particle_positions
from ..core.units import CHAIN
from ..reduced.regime import overdamped_rate
from ..reduced.system import ChainSystem
from .base import Onset, Scene

if TYPE_CHECKING:  # typing only
    from ..core.params import Physics
    from ..core.trajectory import Trajectory


START_PIN_GAP = 1e-2
"""How far (l) a start's last particle may lie from the pin that holds it (a two-pinned chain's end, a ring's
closure) before the start is refused (ChainScene.start_violation): far above a run's own drift, far below a start
of another shape."""


class ChainScene(Scene):
    """A scene of chains (module docstring): defaults describe a single clamped chain."""

    kind = "chain"
    units = CHAIN
    state_units = "rad"
    state_name = "angle"
    mujoco_batched = True
    paced_by_beat = True
    sized_by_n = True
    builder = "elastoactive.mjcf.chain"

    n_chains: ClassVar[int] = 1
    """Chains of the scene (the most, for a scene whose number of chains is a parameter: `chain_count`)."""
    clamped: ClassVar[bool] = True
    """Whether a spring holds the first pendulum against the clamp (False: a free pin)."""
    head_coordinates: ClassVar[int] = 0
    """Coordinates of a moving pivot (the head) before the angles: 0 (pinned at the origin) or 2 (x_h, y_h; MuJoCo's
    slide joints, the reduced model's last two state variables, Trajectory.head); 1: the angle phi of a hub the chains
    hang on (the star: MuJoCo's hub hinge, the reduced model's last state variable, Trajectory.head[:, 0])."""

    # ------------------------------------------------------------------ shape
    def head_count(self, physics: Physics) -> int:
        """Coordinates of the moving pivot for this physics (head_coordinates; a scene whose pivot moves only for some
        parameter values, the free ring, overrides it)."""
        return self.head_coordinates

    def chain_count(self, physics: Physics) -> int:
        """Number of chains of this physics (Physics.n_chains): n_chains, or a parameter's value (the star's arms)."""
        return self.n_chains

    def angle_count(self, physics: Physics) -> int:
        """Columns of Trajectory.theta: N per chain."""
        return physics.n * self.chain_count(physics)

    def stiffness(self, physics: Physics) -> tuple[float, ...]:
        """Joint stiffness of each chain in units of C1 (one per chain that elastoactive.mjcf.chain builds)."""
        return (1.0,) * self.chain_count(physics)

    # ------------------------------------------------------------------ MJCF
    def chain_prefixes(self) -> tuple[str, ...]:
        """Name prefix of each chain's elements in the MJCF."""
        return ("",) if self.n_chains == 1 else tuple(f"chain{k + 1}_" for k in range(self.n_chains))

    def chain_offset(self, physics: Physics, k: int) -> float:
        """Lateral (y) position of chain k's clamp: side by side, far enough apart to see both."""
        return -float(max(physics.n, 3)) * k

    def build(self, spec, physics: Physics, numerics: Numerics) -> None:
        """Add the scene's own elements to `spec` (an mujoco.MjSpec holding the generated chains)."""

    # ------------------------------------------------------------------ reduced model
    def reduced_stiffness(self, physics: Physics) -> tuple[float, float, str]:
        """(k, rho, why not): the joint stiffness k of chain 1 (`stiffness`, units C1) and chain 2's over it, rho, as
        the reduced kernels take them (chain 1 at 1, chain 2 at rho, every arm of a star at 1); `why not` is "" when
        they take this scene's, else why not (the record then holds chain 1's, which run_reduced refuses)."""
        stiffness = tuple(float(c) for c in self.stiffness(physics))
        k = stiffness[0]
        rho = stiffness[1] / k if len(stiffness) == 2 else 1.0
        if not (math.isfinite(k) and k > 0 and math.isfinite(rho) and rho > 0):
            return 1.0, 1.0, f"the joint stiffnesses must be finite and > 0, got {stiffness}"
        if len(stiffness) > 2 and any(c != k for c in stiffness):
            return k, 1.0, f"the reduced model's chains beyond the second share chain 1's stiffness, got {stiffness}"
        return k, rho, ""

    def reduced_system(self, physics: Physics) -> ChainSystem:
        """The reduced model of this scene: overdamped (mass_ratio 0); the engine sets the particle mass for the
        inertial model (engines.reduced.system_of), whose beads have MuJoCo's rotational inertia (mjcf/common.xml).

        In units of chain 1's joint stiffness k (reduced_stiffness): the kernels hold chain 1's at 1 and chain 2's at
        rho, so every other force and drag of the record (sigma, kappa, the trap, the contact penalty, the hub's spring
        and the drags) is divided by k: D theta' = -k E + F is (D / k) theta' = -E + F / k, the same motion in the same
        time. A subclass that sets such a force after this call gives it over k too. The inertial model's mass and
        a term's own forces (node forces, polarity units, a moving clamp) are not in the record: run_reduced refuses
        them where k is not 1."""
        k, rho, _ = self.reduced_stiffness(physics)
        system = ChainSystem(
            n=physics.n,
            n_chains=self.chain_count(physics),
            clamped=self.clamped,
            pinned=self.pinned,
            sigma=0.0,
            gamma_l=1.0,
            gamma_t=1.0,
            kappa=0.0,
            rho=1.0,
            delta=0.0,
            mass_ratio=0.0,
            inertia_factor=BEAD_INERTIA_FACTOR,
        )
        for term in physics.active_terms():  # the follower's sigma, the drag's gamma_l, the contact's penalty, ...
            system = term.reduced_system(system, physics)
        if k == 1.0:
            return system._replace(rho=rho)
        forces = ("sigma", "gamma_l", "gamma_t", "kappa", "trap", "contact_stiffness", "hub_stiffness", "hub_drag")
        return system._replace(rho=rho, **{name: getattr(system, name) / k for name in forces})

    def reduced_refusal(self, physics: Physics, numerics: Numerics, inertial: bool | None) -> str:
        """Why the reduced engine does not run this physics (run_reduced refuses it in one line), or "": a stiffness
        its kernels do not take, or, where chain 1's stiffness k is not 1, what the record in units of k leaves out
        (reduced_system: the inertial model's mass, a term's node forces, polarity units or moving clamp)."""
        k, _, why = self.reduced_stiffness(physics)
        if why:
            return why
        if k == 1.0:
            return ""
        own = [t.name for t in physics.active_terms() if t.node_forces(physics) or t.clamp_motion(physics)]
        own += [t.name for t in physics.active_terms() if t.polarity_switch is not None]
        if own:
            return f"chain 1's joint stiffness is {k:g} C1, and the term {own[0]}'s own forces are in units of C1"
        if inertial is None:
            from ..engines.regime import regime  # engine boundary: the reduced engine's overdamped limit

            inertial = regime(physics, numerics).inertial
        if inertial:
            return f"chain 1's joint stiffness is {k:g} C1, and the inertial model's mass is not scaled with it"
        return ""

    def inertial_model(self, physics: Physics) -> bool:
        """A chain scene's reduced engine has an inertial model (the free ring's is overdamped only: it overrides),
        where chain 1's joint stiffness is 1 (reduced_system)."""
        return self.reduced_stiffness(physics)[0] == 1.0

    def start_violation(self, physics: Physics, theta: np.ndarray) -> str:
        """A pinned chain's start whose last particle lies farther than START_PIN_GAP from its pin (the reduced
        model's constraint, reduced.constraints.pin_residual: a two-pinned chain's end, a ring's closure)."""
        system = self.reduced_system(physics)
        if not system.pinned:
            return ""
        from ..reduced.constraints import pin_residual  # plain numpy: the pins' constraint, as the engines hold it

        gap = float(np.hypot(*pin_residual(np.asarray(theta, dtype=float)[: physics.n], system.delta)))
        if gap <= START_PIN_GAP:
            return ""
        return f"its last particle is {gap:.3g} l from the pin that holds it (at most {START_PIN_GAP:g} l)"

    # ------------------------------------------------------------------ initial state
    def fastest_overdamped_rate(self, physics: Physics) -> float:
        """The reduced model's fastest overdamped rate about the scene's unperturbed start (regime.overdamped_rate)."""
        theta = np.asarray(self.initial_angles(physics, Numerics(perturbation=0.0)), dtype=float)
        return float(overdamped_rate(self.reduced_system(physics), theta))

    def initial_angles(self, physics: Physics, numerics: Numerics) -> np.ndarray:
        """Absolute angles at t = 0: each chain's static shape under seeded small pushes."""
        from ..reduced.initial import pushed_chains  # initial imports scipy (start-up time)

        return pushed_chains(physics.n, self.chain_count(physics), numerics.perturbation, numerics.seed)

    # ------------------------------------------------------------------ observables
    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        """Theta = theta_N - theta_1 of each chain."""
        return [obs.curvature(traj.chain(k)) for k in range(self.chain_count(traj.physics))]

    # ------------------------------------------------------------------ engines (the engine boundary)
    def run_mujoco(self, physics: Physics, numerics: Numerics, duration: float, **options) -> Trajectory:
        from ..engines.mujoco import simulate_chain_mujoco  # engine boundary: load only the engine in use

        return simulate_chain_mujoco(physics, numerics, duration, **options)

    def run_reduced(self, physics: Physics, numerics: Numerics, duration: float, **options) -> Trajectory:
        from ..engines.reduced import simulate_chain_reduced  # engine boundary: load only the engine in use

        refusal = self.reduced_refusal(physics, numerics, options.get("inertial"))
        if refusal:
            raise ParameterError(f"engine reduced: {refusal} (Scene.stiffness of {self.name}); use the MuJoCo engine")
        return simulate_chain_reduced(physics, numerics, duration, **options)

    def check_timestep(self, physics: Physics, numerics: Numerics, safety: float, accuracy: bool, **options):
        from ..engines.timestep import check_chain_timestep  # engine boundary: the timestep check loads mujoco

        return check_chain_timestep(physics, numerics, safety, accuracy, **options)

    def reduced_methods(self) -> tuple[str, ...]:
        from ..reduced.settings import METHODS  # engine boundary: the reduced engine's settings

        return tuple(METHODS)

    # ------------------------------------------------------------------ trajectory
    def positions(self, traj: Trajectory) -> np.ndarray:
        """Shape (T, n_chains, n, 2): (x, y) of particle i of each chain in units of l, from the angles and the moving
        pivot (`head`) if any."""
        return particle_positions(traj.physics, traj.theta, traj.head)

    def tip(self, traj: Trajectory) -> np.ndarray:
        return self.positions(traj)[:, :, -1, :]

    def centre_of_drag(self, traj: Trajectory) -> np.ndarray:
        """Shape (T, n_chains, 2), one centre per chain (units l); a free head (the paraboloid's, a free ring's root:
        ChainSystem.head_free) carries one particle's drag and counts in chain 1's centre."""
        centre = self.positions(traj).mean(axis=-2)
        head = traj.head
        if head is None or head.shape[1] != 2 or not getattr(self.reduced_system(traj.physics), "head_free", False):
            return centre
        n = traj.physics.n
        centre[:, 0] = (n * centre[:, 0] + head) / (n + 1)  # the free head: chain 1's pivot
        return centre

    def state_variables(self, traj: Trajectory) -> tuple[dict, dict]:
        """The angles (time, chain, particle), the positions (time, chain, particle, xy) and the tips (time, chain,
        xy); where polarities are recorded, the chain and the particle each unit sits on (``unit_chain``,
        ``unit_particle`` on ``unit``, the polarity's dimension: the loaded particles, chain 1 then chain 2)."""
        physics = traj.physics
        chains, n, units = physics.n_chains, physics.n, self.length_units
        coords = {
            "chain": ("chain", np.arange(chains), {"long_name": "chain", "description": "chain index, 0-based"}),
            "particle": (
                "particle",
                np.arange(n),
                {"long_name": "particle", "description": "particle index, 0-based (the model's site particle_i)"},
            ),
        }
        if traj.polarity is not None:
            chain, particle = np.nonzero(np.tile(physics.load_mask(), (chains, 1)))
            if chain.size == traj.polarity.shape[1]:
                coords["unit"] = ("unit", np.arange(chain.size), {"long_name": "unit", "description": "unit index"})
                for name, values in (("chain", chain), ("particle", particle)):
                    coords[f"unit_{name}"] = (
                        "unit",
                        values,
                        {"long_name": f"{name} of the unit", "description": f"the {name} the self-aligning unit is on"},
                    )
        position = self.positions(traj)
        data = {
            "theta": (
                ("time", "chain", "particle"),
                traj.theta.reshape(len(traj.t), chains, n),
                {"units": "rad", "long_name": "link angle", "description": "absolute angle of each link"},
            ),
            "position": (
                ("time", "chain", "particle", "xy"),
                position,
                {"units": units, "long_name": "particle position", "description": "lab-frame particle position"},
            ),
            "tip": (
                ("time", "chain", "xy"),
                position[:, :, -1, :],
                {"units": units, "long_name": "tip position", "description": "lab-frame position of the last particle"},
            ),
        }
        return coords, data

    def state_difference(self, traj: Trajectory, reference: Trajectory, early: np.ndarray) -> tuple[float, float]:
        """The largest angle difference (rad), relative to the largest angle of the reference there."""
        n = early.size
        diff = np.abs(traj.theta[:n][early] - reference.theta[:n][early]).max()
        return float(diff), float(np.abs(reference.theta[:n][early]).max())

    # ------------------------------------------------------------------ drawing
    def caption_line(self, physics: Physics) -> str:
        parts = [physics.scene, f"N = {physics.n}", f"σ = {physics.sigma:.3g}", *self.caption(physics)]
        if physics.drag_ratio != 1.0:
            parts.append(f"γL/γT = {physics.drag_ratio:.3g}")
        if physics.noise > 0:
            parts.append(f"noise {physics.noise:.3g}")
        return "   ".join(parts)

    def painter(self, traj: Trajectory, **options):
        from ..render import ChainPainter  # engine boundary: rendering loads MuJoCo and GL

        return ChainPainter(traj, **options)

    def draw_shape(self, ax, traj: Trajectory, i: int, labels: list[str]) -> None:
        """Every chain from its pivot (a square), its particles joined by its links."""
        xy = traj.positions()[i]
        for k, (label, chain) in enumerate(zip(labels, xy, strict=False)):
            pivot = chain[0] - (np.cos(traj.theta[i, k * traj.physics.n]), np.sin(traj.theta[i, k * traj.physics.n]))
            points = np.vstack([pivot, chain])
            ax.plot(points[:, 0], points[:, 1], "-o", ms=4, label=label or None)
            ax.plot(*pivot, "ks", ms=6)
        if len(xy) > 1:
            ax.legend(fontsize="small")

    # ------------------------------------------------------------------ stability
    def stability_report(
        self, physics: Physics, sigma: float | None, onset: Onset | None = None, eigenvalue: complex | None = None
    ) -> list[str]:
        """The straight chain's onset (sigma_c, omega_c and their N scalings), the growth at `sigma`, and, for a
        scene whose large-N limit is the continuum filament (`filament`) loaded on every particle, the filament's
        onset at this N."""
        n = physics.n
        onset = self.onset(physics) if onset is None else onset
        sigma_c, omega_c = onset.sigma_c, onset.omega_c
        own = "".join(
            f", {k} = {v}" if isinstance(v := getattr(physics, k), str) else f", {k} = {v:g}"
            for k in self.own_parameter_names()
        )
        lines = [f"{physics.scene}, N = {n}{own}:"]
        if math.isfinite(sigma_c):
            lines.append(
                f"  onset: {onset.kind} at sigma_c = {sigma_c:.10g} (N^3 sigma_c = {n**3 * sigma_c:.6g}), "
                f"omega_c = {omega_c:.6g} rad/tau (f_c tau = {omega_c / (2 * math.pi):.6g}, N^4 omega_c = "
                f"{n**4 * omega_c:.6g})"
            )
        else:  # stable over the whole range the scene searched
            lines.append(f"  onset: {onset.kind}")
        if sigma is not None:
            lam = self.leading_eigenvalue(physics, sigma) if eigenvalue is None else eigenvalue
            state = "unstable" if lam.real > 0 else "stable"
            lines.append(
                f"  at sigma = {sigma:g}: growth rate {lam.real:+.6g} /tau, angular frequency "
                f"{abs(lam.imag):.6g} rad/tau ({state}"
                + (f"; sigma / sigma_c = {sigma / sigma_c:.4g})" if math.isfinite(sigma_c) else ")")
            )
        if self.filament and physics.all_loaded:  # the filament's load is distributed over every particle
            from ..analysis.continuum import continuum_critical  # start-up time: scipy only for this command

            s_c, w_c = continuum_critical()
            lines.append(
                f"  continuum filament (clamped, distributed follower load f, drag zeta): S_c = f L^3 / B = "
                f"{s_c:.4f}, omega_c = {w_c:.4f} B / (zeta L^4); at N = {n} (sigma = S / N^3, omega in 1 / (N^4 "
                f"tau)): sigma = {s_c / n**3:.6g}, omega = {w_c / n**4:.6g} rad/tau; the chain's N^3 sigma_c is "
                f"{100 * (n**3 * sigma_c / s_c - 1):+.2f}% from it"
            )
        return lines

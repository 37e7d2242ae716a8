"""What a scene is: the plug-in contract every scene module fulfils.

A scene module defines one subclass of `Scene` and registers one instance of it. The instance
knows everything specific to the scene; the rest of the package asks it (through the registry,
`elastoactive.scenes`) and never compares against a scene's name:

  parameters          the scene's own physics parameters (elastoactive.parameters.Parameter specs it declares, or
                      names of parameters declared elsewhere), beyond the chain's n and the terms' (sigma, drag,
                      noise, contact: elastoactive.terms), and `check` for constraints on them (e.g. N >= 2 with both
                      ends pinned)
  MJCF                `base_file` (in mjcf/) and `build`, which adds the scene's own elements (pins,
                      coupling, keyframes) to the chain(s) that elastoactive.mjcf.chain generates
  reduced model       `reduced_system`: the typed record the reduced solver integrates
  initial state       `initial_angles`
  observables         `observables` (elastoactive.observables.Observable specs it declares: name, units, long name,
                      how validate compares it, ...; or names of declared ones) and `measure_extra` (their
                      values); `compared`, the ones `validate` holds to its tolerance
  validation          `validation_cases` (paper cases), `extreme_cases` (stability grid)
  linear stability    `onset` and `leading_eigenvalue` of the linear operator about the base state (or
                      `no_linear_operator`: why there is none), `filament`: whether the continuum filament is its
                      limit (elastoactive stability)
  drawing             `caption`, `extent_points`, `decorate`, `video_period`
  networks            `network` (None for chains): the elastic network of self-aligning active units a network scene
                      simulates (elastoactive.analysis.network.Network), which the engines dispatch on;
                      `initial_network` its state at t = 0; `term_parameters` and `fixed`: which of the chain's and
                      terms' parameters act on it; `beat_signal`: the scalar whose beat amplitude and frequency measure

Defaults describe a single clamped chain (the one-pinned scene needs to override nothing but its
name); a new scene overrides what differs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..analysis import observables as obs
from ..analysis.network import Network, NetworkState, initial_state
from ..cases import ValidationCase
from ..constants import BEAD_INERTIA_FACTOR
from ..errors import ParameterError
from ..observables import Observable, names_of
from ..parameters import Parameter
from ..parameters import get as parameter_spec
from ..reduced.system import ChainSystem

if TYPE_CHECKING:  # typing only: these modules import the registry that holds scenes
    from ..params import Numerics, Physics
    from ..trajectory import Trajectory


@dataclass(frozen=True)
class Onset:
    """Where a scene's base state loses stability (Scene.onset): at sigma_c, with the unstable mode's angular
    frequency omega_c (rad / tau; 0 for a real eigenvalue), and how (`kind`, in words)."""

    sigma_c: float
    omega_c: float
    kind: str
    sigma_all: float | None = None
    """Where the base states form a family (a network's fixed points, one per choice of the polarities): sigma_c is
    where the first of them loses stability; some base state found stays stable up to sigma_all (the last loses
    stability at or above it: a lower bound, from a search); None for a single base state."""
    sigma_ceiling: float | None = None
    """For a family: no base state is stable above this (a proved upper bound on where the last loses stability)."""


class Scene:
    """A scene: its parameters, MJCF, reduced-model terms, initial state, observables, checks, drawing."""

    name: ClassVar[str] = ""
    """Registry key and CLI name, e.g. 'one-pinned'."""
    summary: ClassVar[str] = ""
    """One line for the CLI's help."""
    base_file: ClassVar[str] = ""
    """MJCF file in mjcf/ with the scene's options, defaults and markers (opens in MuJoCo's viewer)."""
    parameters: ClassVar[tuple[Parameter | str, ...]] = ()
    """The scene's own physics parameters: specs it declares (registered with the scene), or names of declared ones."""
    min_n: ClassVar[int] = 1
    n_chains: ClassVar[int] = 1
    """Chains of the scene (the most, for a scene whose number of chains is a parameter: `chain_count`)."""
    clamped: ClassVar[bool] = True
    """Whether a spring holds the first pendulum against the clamp (False: a free pin)."""
    head_coordinates: ClassVar[int] = 0
    """Coordinates of a moving pivot (the head) before the angles: 0 (pinned at the origin) or 2 (x_h, y_h; MuJoCo's
    slide joints, the reduced model's last two state variables, Trajectory.head); 1: the angle phi of a hub the chains
    hang on (the star: MuJoCo's hub hinge, the reduced model's last state variable, Trajectory.head[:, 0])."""
    pinned: ClassVar[bool] = False
    """Whether the last particle is held by a pin (a MuJoCo equality; monitored for drift)."""
    observables: ClassVar[tuple[Observable | str, ...]] = ()
    """Results beyond the beat's (amplitude, frequency, ...: elastoactive.observables.BEAT), values of
    `measure_extra`: specs the scene declares (registered with the scene), or names of declared ones."""
    occasional_observables: ClassVar[tuple[Observable | str, ...]] = ()
    """Observables `measure_extra` reports only for some parameter values (the free ring's centre_drift): declared
    as `observables` are, but not part of every run's record (a sweep adds the variable when a point first reports it;
    validate does not compare them)."""
    compared: ClassVar[tuple[str, ...]] = ("amplitude", "frequency")
    """Observables that validate holds to its tolerance (relative error)."""
    no_linear_operator: ClassVar[str] = "no linear operator is written for it"
    """Why the scene has no linear operator about a base state that does not move with sigma (empty when it has one:
    `onset` and `leading_eigenvalue` are then overridden)."""
    filament: ClassVar[bool] = False
    """Whether the clamped continuum filament under a distributed follower load is the scene's large-N limit."""
    paper: ClassVar[bool] = False
    """One of the paper's own chains: its validation cases are the ones the accuracy study (checks.accuracy) times
    every engine setting on."""
    term_parameters: ClassVar[tuple[str, ...] | None] = None
    """The chain's and the terms' parameters that act on the scene (None: all of them, n included: a chain scene). A
    network scene names the few that act on its units (sigma, active, alignment_length): n, the drag ratio, noise,
    contact and the other terms' parameters are then refused as having no effect on it."""
    fixed: ClassVar[tuple[tuple[str, Any, str], ...]] = ()
    """(parameter, value, why) the scene holds fixed (a network's units are self-aligning): Physics sets the value
    and refuses another one in one line, giving the reason."""

    # ------------------------------------------------------------------ parameters
    @classmethod
    def own_parameter_names(cls) -> tuple[str, ...]:
        """Names of the scene's own parameters (`parameters`)."""
        return tuple(p.name if isinstance(p, Parameter) else p for p in cls.parameters)

    @classmethod
    def observable_names(cls) -> tuple[str, ...]:
        """Names of the scene's own observables (`observables`), in the order declared."""
        return names_of(cls.observables)

    def check(self, physics: Physics) -> None:
        """Scene-specific checks of the parameters (the generic ranges are checked by Physics)."""
        if physics.n < self.min_n:
            raise ParameterError(f"n (number of particles N) must be >= {self.min_n} for {self.name}, got {physics.n}")

    def head_count(self, physics: Physics) -> int:
        """Coordinates of the moving pivot for this physics (head_coordinates; a scene whose pivot moves only for some
        parameter values, the free ring, overrides it)."""
        return self.head_coordinates

    def chain_count(self, physics: Physics) -> int:
        """Number of chains of this physics (Physics.n_chains): n_chains, or a parameter's value (the star's arms)."""
        return self.n_chains

    def stiffness(self, physics: Physics) -> tuple[float, ...]:
        """Joint stiffness of each chain in units of C1 (one per chain that elastoactive.mjcf.chain builds)."""
        return (1.0,) * self.chain_count(physics)

    def physics(self, **values: Any) -> Physics:
        """Physics of this scene with the given parameters (the others at their defaults)."""
        from ..params import Physics  # params imports the registry that holds this class

        return Physics(scene=self.name, **values)

    def base_physics(self) -> Physics:
        """The physics the base file describes (the builder at it reproduces the file's model:
        tests/mjcf/test_scenes.py): the paper's N = 7, sigma = 0.8, the other parameters at their defaults."""
        return self.physics(n=7, sigma=0.8)

    def label(self, physics: Physics) -> str:
        """Short description of a case, e.g. 'two-pinned N=7 sigma=0.8 delta=0.1'."""
        text = f"{self.name} N={physics.n} sigma={physics.sigma:g}"
        for key in self.own_parameter_names():
            value = getattr(physics, key)
            text += f" {key}={value:.4g}"
        for term in physics.active_terms():
            if term.labelled:
                values = ((p.name, getattr(physics, p.name)) for p in term.parameters)
                text += "".join(f" {k}={v:.4g}" if isinstance(v, float) else f" {k}={v}" for k, v in values)
        return text

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
    def reduced_system(self, physics: Physics) -> ChainSystem:
        """The reduced model of this scene: overdamped (mass_ratio 0); the engine sets the particle mass for the
        inertial model (engines.reduced.system_of), whose beads have MuJoCo's rotational inertia (mjcf/common.xml)."""
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
        return system

    def inertial_model(self, physics: Physics) -> bool:
        """Whether the reduced engine has an inertial model of the scene with these parameters (particles of mass
        mass_ratio, engines.reduced): a chain scene's does; a network's model is overdamped only, and so is the free
        ring's (their engines refuse a mass outside that limit)."""
        return True

    # ------------------------------------------------------------------ initial state
    def initial_angles(self, physics: Physics, numerics: Numerics) -> np.ndarray:
        """Absolute angles at t = 0: each chain's static shape under seeded small pushes."""
        from ..initial import pushed_chains  # initial imports scipy (start-up time)

        return pushed_chains(physics.n, self.chain_count(physics), numerics.perturbation, numerics.seed)

    # ------------------------------------------------------------------ observables
    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float | str]:
        """Values of `observables` (amplitude and frequency are measured for every scene)."""
        return {}

    # ------------------------------------------------------------------ validation
    def validation_cases(self) -> tuple[ValidationCase, ...]:
        """The cases `validate` runs for this scene."""
        return ()

    def extreme_cases(self, quick: bool = False) -> tuple[Physics, ...]:
        """Stiff and extreme parameter sets of the stability grid (scripts/stability_grid.py)."""
        return ()

    # ------------------------------------------------------------------ linear stability
    def onset(self, physics: Physics) -> Onset:
        """Where the base state loses stability (sigma_c, omega_c) for these parameters (sigma aside)."""
        raise ParameterError(f"stability: {self.name} has no linear operator here ({self.no_linear_operator})")

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        """The least stable eigenvalue of the linear operator about the base state at sigma."""
        raise ParameterError(f"stability: {self.name} has no linear operator here ({self.no_linear_operator})")

    # ------------------------------------------------------------------ drawing
    def caption(self, physics: Physics) -> list[str]:
        """Parameter parts of a video caption, after scene, N and sigma."""
        parts = [f"{parameter_spec(k).symbol or k} = {getattr(physics, k):.3g}" for k in self.own_parameter_names()]
        if physics.contact:
            parts.append(
                f"contact R = {physics.contact_radius:.3g}"
                + (f" μ = {physics.contact_friction:.3g}" if physics.contact_friction > 0 else "")
            )
        return parts

    def extent_points(self, physics: Physics) -> np.ndarray:
        """Fixed points (k, 2) besides the particles that a camera must keep in view (e.g. a pin)."""
        return np.empty((0, 2))

    def decorate(self, frame) -> None:
        """Draw scene-specific extras into a video frame; `frame` is the renderer's painter, which offers
        frame.spring(chain_a, particle_a, chain_b, particle_b)."""

    def video_period(self, traj: Trajectory) -> float | None:
        """Time (tau) one second of video shows when the chain does not beat (None: the default)."""
        return None

    # ------------------------------------------------------------------ networks
    def network(self, physics: Physics) -> Network | None:
        """The elastic network of active units this scene simulates, or None for a chain scene (the default); both
        engines dispatch on it."""
        return None

    def initial_network(self, physics: Physics, numerics: Numerics) -> NetworkState:
        """A network scene's state at t = 0, read by both engines: nodes at rest plus seeded pushes of up to
        numerics.perturbation (units a), polarities seeded uniformly on the circle (numerics.seed)."""
        network = self.network(physics)
        if network is None:
            raise ParameterError(f"{self.name} is a chain scene: it has no network")
        return initial_state(network, numerics.perturbation, numerics.seed)

    def angle_count(self, physics: Physics) -> int:
        """Columns of Trajectory.theta: N per chain (a network scene: 0, its state is Trajectory.nodes)."""
        return 0 if self.network(physics) is not None else physics.n * self.chain_count(physics)

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        """The scalar signals whose beat (amplitude, frequency, periodicity) results.measure reports, one per chain:
        Theta = theta_N - theta_1 of each chain."""
        return [obs.curvature(traj.chain(k)) for k in range(self.chain_count(traj.physics))]

    def __repr__(self) -> str:
        return f"<scene {self.name!r}>"

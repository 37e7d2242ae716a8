"""What a scene is: the plug-in contract every scene fulfils, and the kinds of scene.

A scene is of one *kind*, a subclass of `Scene` that knows how that kind of structure is built, run, recorded and
drawn: `ChainScene` (elastoactive.scenes.chain_kind: chains of particles on hinges, state: absolute angles) and
`NetworkScene` (elastoactive.scenes.network_kind: an elastic network of nodes carrying self-aligning units, state: node
positions and polarities). A scene module defines one subclass of a kind and registers one instance of it; the rest of
the package asks the instance (through the registry, `elastoactive.scenes`) and never asks which kind it is, nor
compares against a scene's name (tests/project/test_layering.py holds both).

Adding a kind (e.g. chains in three dimensions): a new module in elastoactive/scenes/ defining a subclass of `Scene`
that implements every hook of the kind contract below (the ones `Scene` leaves raising NotImplementedError); its
engine adapters, builder and painter live in new modules of their packages, which the hooks import at their engine
boundary (inside the hook, said once in the kind module's docstring). No module outside scenes/ is edited. A kind
may also subclass a kind and override the hooks that differ (its own engines, positions, painter).
tests/scenes/test_kinds.py defines a third kind in a test file alone and runs it. The kind contract, what the package
asks of every scene:

  identity            `kind` (a word for messages: "chain"), `units` (elastoactive.core.units: its positions are in
                      units.length), `beat_signal` (what its beat is measured on),
                      `state_units` and `state_name` (what validate compares sample by sample: "rad", "angle")
  engines             `run_mujoco` and `run_reduced` (the engine adapters: (physics, numerics, duration, **options)
                      -> Trajectory), `mujoco_batched` (whether MuJoCo runs of it share engines.mujoco_batch; False:
                      each runs alone through run_mujoco), `check_timestep` (the MuJoCo pre-flight check),
                      `reduced_methods` (the reduced engine's solvers), `seeded_start` (whether its initial state is
                      off every base state whatever the perturbation)
  builder             `builder` (the module that builds its MJCF model; elastoactive.mjcf.chain refuses the others)
  shape               `chain_count`, `head_count`, `angle_count` (Physics.n_chains, Trajectory.head's and theta's
                      columns), `min_n`, `pinned`, `inertial_model` (defaults: one chain, no head, no angles)
  trajectory          `positions`, `tip`, `centre_of_drag`, `state_variables` (Trajectory's positions and its
                      xarray variables), `file_variables` (which of those a run's trajectory.npz holds too),
                      `state_difference` (validate's sample-by-sample comparison)
  drawing             `painter` (render's video painter), `draw_shape` (ea.plot.shape), `tip_views`
                      (ea.plot.tip_path; default: the xy plane), `paced_by_beat` (whether a video's pace follows
                      the beat of `beat_signals`)
  stability           `sized_by_n` (whether N sizes it), `stability_report` (the lines `elastoactive stability`
                      prints)

and the scene's own part, which every kind shares:

  parameters          the scene's own physics parameters (elastoactive.core.parameters.Parameter specs it declares, or
                      names of parameters declared elsewhere), and `check` for constraints on them; `term_parameters`
                      and `fixed`: which of the terms' parameters act on it
  observables         `observables` (elastoactive.core.observables.Observable specs it declares: name, units, long name,
                      how validate compares it, ...; or names of declared ones), `beat_signals` (the scalars whose
                      beat amplitude and frequency measure) and `measure_extra` (their values); `compared`, the ones
                      `validate` holds to its tolerance
  validation          `validation_cases` (paper cases), `extreme_cases` (stability grid)
  linear stability    `onset` and `leading_eigenvalue` of the linear operator about the base state (or
                      `no_linear_operator`: why there is none), `filament`: whether the continuum filament is its
                      limit (elastoactive stability)
  drawing             `caption`, `extent_points`, `decorate`, `video_period`

Each kind's docstring lists its own part of the contract (a chain's pins, clamps, prefixes and reduced record; a
network's Network record and initial state).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..core.cases import ValidationCase
from ..core.errors import ParameterError
from ..core.observables import Observable, names_of
from ..core.parameters import Parameter
from ..core.parameters import get as parameter_spec
from ..core.units import CHAIN, THETA, Signal, Units

if TYPE_CHECKING:  # typing only: these modules import the registry that holds scenes
    from ..core.params import Numerics, Physics
    from ..core.trajectory import Trajectory

__all__ = ["Onset", "PathView", "Scene", "ValidationCase"]


CHAIN_TOLERANCES = (1e-9, 1e-11)
"""A chain's reduced-engine (rtol, atol) when a run gives none (Scene.reduced_tolerances)."""


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


@dataclass(frozen=True)
class PathView:
    """One view of the tips' paths that ea.plot.tip_path draws (Scene.tip_views): `points`, shape (T, chains, 2) for
    a plane or (T, chains, 3) for a 3D view, in the scene's length unit; `axes`, the symbol of each of its axes in
    TeX ('x', 'y', 'z', or the directions of a plane of the motion's own); `title`, what the view shows ('' for the
    lab frame's xy plane)."""

    points: np.ndarray
    axes: tuple[str, ...]
    title: str = ""


class Scene:
    """A scene: the part every kind shares (parameters, observables, checks, drawing) and the kind contract's hooks,
    which a kind (ChainScene, NetworkScene) implements. Subclass a kind, not this class."""

    name: ClassVar[str] = ""
    """Registry key and CLI name, e.g. 'one-pinned'."""
    summary: ClassVar[str] = ""
    """One line for the CLI's help."""
    base_file: ClassVar[str] = ""
    """MJCF file in mjcf/ with the scene's options, defaults and markers (opens in MuJoCo's viewer)."""
    parameters: ClassVar[tuple[Parameter | str, ...]] = ()
    """The scene's own physics parameters: specs it declares (registered with the scene), or names of declared ones."""
    min_n: ClassVar[int] = 1
    """The fewest particles per chain (n) the scene takes."""
    pinned: ClassVar[bool] = False
    """Whether the last particle is held by a pin (a MuJoCo equality; monitored for drift)."""
    observables: ClassVar[tuple[Observable | str, ...]] = ()
    """Results beyond the beat's (amplitude, frequency, ...: elastoactive.core.observables.BEAT), values of
    `measure_extra`: specs the scene declares (registered with the scene), or names of declared ones."""
    occasional_observables: ClassVar[tuple[Observable | str, ...]] = ()
    """Observables `measure_extra` reports only for some parameter values (the free ring's centre_drift): declared
    as `observables` are, but not part of every run's record (a sweep adds the variable when a point first reports it;
    validate does not compare them)."""
    compared: ClassVar[tuple[str, ...]] = ("amplitude", "frequency")
    """Observables that validate holds to its tolerance (relative error)."""
    agreement: ClassVar[float] = 0.01
    """The largest relative difference between the two engines' states over a short run of the scene (its largest
    difference over the largest value: state_difference) that it promises at the default numerics; the conformance
    kit (elastoactive.testing) holds both engines to it."""
    no_linear_operator: ClassVar[str] = "no linear operator is written for it"
    """Why the scene has no linear operator about a base state that does not move with sigma (empty when it has one:
    `onset` and `leading_eigenvalue` are then overridden)."""
    operator_parameters: ClassVar[tuple[str, ...]] = ()
    """Term parameters (beyond n) its linear operator reads, which `elastoactive stability` takes as options beside
    the scene's own (a cilium's bead_radius)."""
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

    # ------------------------------------------------------------------ the kind contract (module docstring)
    kind: ClassVar[str] = ""
    """What kind of structure the scene is, in a word for messages ('chain', 'network')."""
    units: ClassVar[Units] = CHAIN
    """The scene's system of units (elastoactive.core.units): what its numbers are measured in; each kind sets
    its own."""
    state_units: ClassVar[str] = ""
    """The unit of what validate compares sample by sample (state_difference)."""
    state_name: ClassVar[str] = ""
    """What validate compares sample by sample, in a word ('angle', 'displacement')."""
    mujoco_batched: ClassVar[bool] = False
    """Whether MuJoCo runs of the scene go through the batched engine (engines.mujoco_batch); False: a batch runs each
    alone on one of its threads, through run_mujoco(..., install_callbacks=False)."""
    seeded_start: ClassVar[bool] = False
    """Whether the initial state is off every base state whatever the perturbation (a network's seeded polarities),
    so that a run at perturbation 0 is let through (params.check_start)."""
    paced_by_beat: ClassVar[bool] = False
    """Whether a video's pace follows the beat of `beat_signals` (one beat a second); else `video_period`."""
    sized_by_n: ClassVar[bool] = False
    """Whether N (particles per chain) sizes the scene (elastoactive stability takes --n)."""
    builder: ClassVar[str] = ""
    """The module that builds the scene's MJCF model (elastoactive.mjcf.chain refuses the scenes it does not build)."""
    file_variables: ClassVar[tuple[str, ...]] = ()
    """Variables of `state_variables` that a run's trajectory.npz holds besides its records (records.write_run), each
    with its dimensions, units and long name, for readers of the file without the package (the 3D chain's particle
    positions); none by default, so a kind's file holds its records only."""

    @property
    def length_units(self) -> str:
        """The unit of the scene's positions (Trajectory.length_units): its units' length."""
        return self.units.length

    def beat_signal(self, physics: Physics) -> Signal:
        """What beat_signals measures, for labels and units (elastoactive.core.units.Signal)."""
        return THETA

    def _kind_hook(self, hook: str):
        return NotImplementedError(
            f"scene {self.name!r} implements no kind: {type(self).__name__}.{hook} is a hook of the kind contract; "
            "subclass a kind (elastoactive.scenes.ChainScene, NetworkScene), not Scene"
        )

    def run_mujoco(self, physics: Physics, numerics: Numerics, duration: float, **options) -> Trajectory:
        """The MuJoCo engine's run of this scene (engines.mujoco.simulate_mujoco hands it here); options:
        theta0, progress, on_sample, install_callbacks."""
        raise self._kind_hook("run_mujoco")

    def run_reduced(self, physics: Physics, numerics: Numerics, duration: float, **options) -> Trajectory:
        """The reduced engine's run of this scene (engines.reduced.simulate_reduced hands it here)."""
        raise self._kind_hook("run_reduced")

    def reduced_tolerances(self, physics: Physics) -> tuple[float, float]:
        """(rtol, atol) of the reduced engine's adaptive solvers when a run gives none (engines.reduced's
        simulate_reduced): a chain's 1e-9, 1e-11, far below its observables' errors; a network kind chooses its own."""
        return CHAIN_TOLERANCES

    def record_numerics(self, physics: Physics, numerics: Numerics, duration: float) -> Numerics:
        """The numerics a run of `duration` records with (the pre-flight gate and `run` ask it before
        Numerics.for_duration): these; a network kind coarsens a large record's default sample interval."""
        return numerics

    def check_timestep(self, physics: Physics, numerics: Numerics, safety: float, accuracy: bool, **options):
        """The MuJoCo pre-flight check of a timestep (engines.timestep.check_timestep hands it here): refuses, naming
        the setting, or returns the run's engines.timestep.StabilityLimits."""
        raise self._kind_hook("check_timestep")

    def reduced_methods(self) -> tuple[str, ...]:
        """The solvers the reduced engine offers for this scene (its `method` option)."""
        raise self._kind_hook("reduced_methods")

    def positions(self, traj: Trajectory) -> np.ndarray:
        """Every particle's (node's) position at every sample time (Trajectory.positions)."""
        raise self._kind_hook("positions")

    def tip(self, traj: Trajectory) -> np.ndarray:
        """The last particle of every chain at every sample time (Trajectory.tip), or a ParameterError saying why
        the scene has none."""
        raise self._kind_hook("tip")

    def centre_of_drag(self, traj: Trajectory) -> np.ndarray:
        """The mean position of the points that carry drag (Trajectory.centre_of_drag)."""
        raise self._kind_hook("centre_of_drag")

    def state_variables(self, traj: Trajectory) -> tuple[dict, dict]:
        """(coordinates, data variables) of the trajectory's state for Trajectory.to_xarray: each name -> (dims,
        values, attrs with units and long_name)."""
        raise self._kind_hook("state_variables")

    def state_difference(self, traj: Trajectory, reference: Trajectory, early: np.ndarray) -> tuple[float, float]:
        """(largest difference, its scale) between two trajectories' states over the samples `early` of the shared
        times (validate's angle error: state_units)."""
        raise self._kind_hook("state_difference")

    def painter(self, traj: Trajectory, **options):
        """The renderer's painter of a trajectory of this scene (elastoactive.render)."""
        raise self._kind_hook("painter")

    def draw_shape(self, ax, traj: Trajectory, i: int, labels: list[str]) -> None:
        """Draw the structure at sample i on matplotlib axes `ax` (ea.plot.shape); labels: one per chain."""
        raise self._kind_hook("draw_shape")

    def tip_views(self, traj: Trajectory, keep: np.ndarray) -> tuple[PathView, ...]:
        """The views of the tips' paths over the samples `keep` that ea.plot.tip_path draws, the first one on the
        axes it is given: the lab frame's xy plane (a structure in three dimensions: views in which its motion
        shows); a ParameterError from `tip` for a structure without one."""
        return (PathView(self.tip(traj)[keep], ("x", "y")),)

    def stability_report(
        self, physics: Physics, sigma: float | None, onset: Onset | None = None, eigenvalue: complex | None = None
    ) -> list[str]:
        """The lines `elastoactive stability` prints: the onset, and the growth at `sigma` when given (`onset` and
        `eigenvalue`: this physics' Scene.onset and leading_eigenvalue at `sigma` where already computed)."""
        raise self._kind_hook("stability_report")

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        """The scalar signals whose beat (amplitude, frequency, periodicity) results.measure reports, one per chain."""
        raise self._kind_hook("beat_signals")

    # ------------------------------------------------------------------ shape every kind answers
    def chain_count(self, physics: Physics) -> int:
        """Number of chains of this physics (Physics.n_chains)."""
        return 1

    def head_count(self, physics: Physics) -> int:
        """Coordinates of a moving pivot (Trajectory.head's columns) for this physics: 0, none."""
        return 0

    def record_columns(self, physics: Physics) -> int:
        """Numbers a run records per sample besides its time (the size of trajectory.npz, checked before a run): one
        per angle and per moving pivot coordinate (a network kind: its nodes' positions and units' polarities)."""
        return physics.n_angles + (self.head_count(physics) or 0)

    def angle_count(self, physics: Physics) -> int:
        """Columns of Trajectory.theta (Physics.n_angles)."""
        return 0

    def inertial_model(self, physics: Physics) -> bool:
        """Whether the reduced engine has an inertial model of the scene with these parameters (particles of mass
        mass_ratio, engines.reduced)."""
        return False

    # ------------------------------------------------------------------ starts (elastoactive.starts)
    def state_label(self, physics: Physics) -> str:
        """The shape of the scene's state in a few words, for messages: "N = 7", "2 chains of N = 7"; a scene not
        sized by N: the numbers a sample records."""
        if not self.sized_by_n:
            return f"{self.record_columns(physics)} numbers a sample"
        chains = self.chain_count(physics)
        return f"N = {physics.n}" if chains == 1 else f"{chains} chains of N = {physics.n}"

    def accepts_start(self, origin: Physics, physics: Physics) -> bool:
        """Whether the last state of a run of `origin` (another scene, or this one with other parameters) is a state of
        this scene at `physics`: the same scene with the same shape of state (state_label, record_columns). A scene
        whose states another scene shares (the same coordinates, the same constraints) may say so here."""
        return (
            origin.scene == physics.scene
            and self.state_label(origin) == self.state_label(physics)
            and self.record_columns(origin) == self.record_columns(physics)
        )

    def start_violation(self, physics: Physics, theta: np.ndarray) -> str:
        """Why the angles `theta` (of the right count) are not a state of this scene at `physics` (a constraint they
        break, in words with its size), or "" when they are; none by default."""
        return ""

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

    def physics(self, **values: Any) -> Physics:
        """Physics of this scene with the given parameters (the others at their defaults)."""
        from ..core.params import Physics  # params imports the registry that holds this class

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

    def fastest_overdamped_rate(self, physics: Physics) -> float:
        """The fastest overdamped relaxation rate at the scene's base state, 1/tau (what MuJoCo's step must resolve:
        Numerics.for_physics)."""
        raise self._kind_hook("fastest_overdamped_rate")

    # ------------------------------------------------------------------ drawing
    def caption_line(self, physics: Physics) -> str:
        """The caption band's one line of a picture or video of this scene (scene, size, sigma, then `caption`)."""
        raise self._kind_hook("caption_line")

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
        """Time (tau) one second of video shows when the structure does not beat (None: the default)."""
        return None

    def __repr__(self) -> str:
        return f"<scene {self.name!r}>"

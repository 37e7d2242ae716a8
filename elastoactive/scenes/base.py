"""What a scene is: the plug-in contract every scene module fulfils.

A scene module defines one subclass of `Scene` and registers one instance of it. The instance
knows everything specific to the scene; the rest of the package asks it (through the registry,
`elastoactive.scenes`) and never compares against a scene's name:

  parameters          which physics parameters the scene uses, beyond n, sigma, drag_ratio, noise,
                      and `check` for constraints on them (e.g. N >= 2 with both ends pinned)
  MJCF                `base_file` (in mjcf/) and `build`, which adds the scene's own elements (pins,
                      coupling, keyframes) to the chain(s) that elastoactive.model generates
  reduced model       `reduced_system`: the typed record the reduced solver integrates
  initial state       `initial_angles`
  observables         `observables` (names) and `measure_extra` (their values); `compared`, the
                      ones `validate` holds to its tolerance
  validation          `validation_cases` (paper cases), `extreme_cases` (stability grid)
  drawing             `caption`, `extent_points`, `decorate`, `video_period`

Defaults describe a single clamped chain (the one-pinned scene needs to override nothing but its
name); a new scene overrides what differs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..analysis.reduced.system import BEAD_INERTIA_FACTOR, ChainSystem
from ..errors import ParameterError

if TYPE_CHECKING:  # typing only: these modules import the registry that holds scenes
    from ..params import Numerics, Physics
    from ..trajectory import Trajectory

CONTACT_STIFFNESS = 1.0e3
"""The reduced model's self-contact penalty K (force K x overlap, units C1 / l^2): overlaps ~ force / K ~ 1e-3 l.
MuJoCo's contact is nearly hard instead (elastoactive.model.contact_solref); the two agree as K grows and dt
shrinks (docs/model.md, "Self-contact")."""
COMMON_PARAMETERS = ("n", "sigma", "drag_ratio", "noise")
"""Physics parameters every chain scene uses."""
NOISE_PARAMETERS = ("noise_correlation", "noise_calculus")
"""Physics parameters of the noise, used (and reported) when noise > 0."""
CONTACT_PARAMETERS = ("contact", "contact_radius", "contact_friction")
"""Physics parameters of self-contact, used (and reported) when contact is on."""


@dataclass(frozen=True)
class ValidationCase:
    """A case `validate` runs through both engines (and `accuracy` measures error against cost).

    convergence: also part of `validate --convergence` (one case per scene is enough there).
    """

    physics: "Physics"
    duration: float
    convergence: bool = True


class Scene:
    """A scene: its parameters, MJCF, reduced-model terms, initial state, observables, checks, drawing."""

    name: ClassVar[str] = ""
    """Registry key and CLI name, e.g. 'one-pinned'."""
    summary: ClassVar[str] = ""
    """One line for the CLI's help."""
    base_file: ClassVar[str] = ""
    """MJCF file in mjcf/ with the scene's options, defaults and markers (opens in MuJoCo's viewer)."""
    parameters: ClassVar[tuple[str, ...]] = ()
    """Physics parameters of this scene beyond COMMON_PARAMETERS."""
    min_n: ClassVar[int] = 1
    n_chains: ClassVar[int] = 1
    clamped: ClassVar[bool] = True
    """Whether a spring holds the first pendulum against the clamp (False: a free pin)."""
    head_coordinates: ClassVar[int] = 0
    """Coordinates of a moving pivot (the head) before the angles: 0 (pinned at the origin) or 2 (x_h, y_h; MuJoCo's
    slide joints, the reduced model's last two state variables, Trajectory.head)."""
    pinned: ClassVar[bool] = False
    """Whether the last particle is held by a pin (a MuJoCo equality; monitored for drift)."""
    observables: ClassVar[tuple[str, ...]] = ()
    """Results beyond amplitude and frequency (their meaning: elastoactive.results.OBSERVABLES)."""
    compared: ClassVar[tuple[str, ...]] = ("amplitude", "frequency")
    """Observables that validate holds to its tolerance (relative error)."""

    # ------------------------------------------------------------------ parameters
    def relevant(self, physics: "Physics | None" = None) -> tuple[str, ...]:
        """Names of the physics parameters this scene uses (the others are ignored and not reported). Given a
        physics, NOISE_PARAMETERS are among them only when its noise is > 0, `loaded` only when it is not
        "all", and CONTACT_PARAMETERS only with contact on."""
        names = ("scene",) + COMMON_PARAMETERS + self.parameters
        if physics is not None and physics.noise > 0:
            names += NOISE_PARAMETERS
        if physics is not None and getattr(physics, "loaded", "all") != "all":
            names += ("loaded",)
        if physics is not None and getattr(physics, "contact", False):
            names += CONTACT_PARAMETERS
        return names

    def check(self, physics: "Physics") -> None:
        """Scene-specific checks of the parameters (the generic ranges are checked by Physics)."""
        if physics.n < self.min_n:
            raise ParameterError(f"n (number of particles N) must be >= {self.min_n} for {self.name}, got {physics.n}")

    def stiffness(self, physics: "Physics") -> tuple[float, ...]:
        """Joint stiffness of each chain in units of C1."""
        return (1.0,) * self.n_chains

    def physics(self, **values: Any) -> "Physics":
        """Physics of this scene with the given parameters (the others at their defaults)."""
        from ..params import Physics  # params imports the registry that holds this class

        return Physics(scene=self.name, **values)

    def label(self, physics: "Physics") -> str:
        """Short description of a case, e.g. 'two-pinned N=7 sigma=0.8 delta=0.1'."""
        text = f"{self.name} N={physics.n} sigma={physics.sigma:g}"
        for key in self.parameters:
            value = getattr(physics, key)
            text += f" {key}={value:.4g}"
        return text

    # ------------------------------------------------------------------ MJCF
    def chain_prefixes(self) -> tuple[str, ...]:
        """Name prefix of each chain's elements in the MJCF."""
        return ("",) if self.n_chains == 1 else tuple(f"chain{k + 1}_" for k in range(self.n_chains))

    def chain_offset(self, physics: "Physics", k: int) -> float:
        """Lateral (y) position of chain k's clamp: side by side, far enough apart to see both."""
        return -float(max(physics.n, 3)) * k

    def build(self, spec, physics: "Physics", numerics: "Numerics") -> None:
        """Add the scene's own elements to `spec` (an mujoco.MjSpec holding the generated chains)."""

    # ------------------------------------------------------------------ reduced model
    def reduced_system(self, physics: "Physics") -> ChainSystem:
        """The reduced model of this scene: overdamped (mass_ratio 0); the engine sets the particle mass for the
        inertial model (engines.reduced.system_of), whose beads have MuJoCo's rotational inertia (mjcf/common.xml)."""
        system = ChainSystem(
            n=physics.n, n_chains=self.n_chains, clamped=self.clamped, pinned=self.pinned, sigma=physics.sigma,
            gamma_l=physics.drag_ratio, gamma_t=1.0, kappa=0.0, rho=1.0, delta=0.0,
            mass_ratio=0.0, inertia_factor=BEAD_INERTIA_FACTOR,
        )
        if physics.contact:  # MuJoCo's near-hard contact becomes a steep penalty (docs/model.md, "Self-contact")
            system = system._replace(contact_radius=physics.contact_radius, contact_stiffness=CONTACT_STIFFNESS)
        return system

    # ------------------------------------------------------------------ initial state
    def initial_angles(self, physics: "Physics", numerics: "Numerics") -> np.ndarray:
        """Absolute angles at t = 0: each chain's static shape under seeded small pushes."""
        from ..initial import pushed_chains  # initial imports scipy (start-up time)

        return pushed_chains(physics.n, self.n_chains, numerics.perturbation, numerics.seed)

    # ------------------------------------------------------------------ observables
    def measure_extra(self, traj: "Trajectory", transient: float) -> dict[str, float | str]:
        """Values of `observables` (amplitude and frequency are measured for every scene)."""
        return {}

    # ------------------------------------------------------------------ validation
    def validation_cases(self) -> tuple[ValidationCase, ...]:
        """The cases `validate` runs for this scene."""
        return ()

    def extreme_cases(self, quick: bool = False) -> tuple["Physics", ...]:
        """Stiff and extreme parameter sets of the stability grid (scripts/stability_grid.py)."""
        return ()

    # ------------------------------------------------------------------ drawing
    def caption(self, physics: "Physics") -> list[str]:
        """Parameter parts of a video caption, after scene, N and sigma."""
        symbols = {"delta": "δ", "kappa": "κ", "rho": "ρ"}
        parts = [f"{symbols.get(k, k)} = {getattr(physics, k):.3g}" for k in self.parameters]
        if physics.contact:
            parts.append(f"contact R = {physics.contact_radius:.3g}"
                         + (f" μ = {physics.contact_friction:.3g}" if physics.contact_friction > 0 else ""))
        return parts

    def extent_points(self, physics: "Physics") -> np.ndarray:
        """Fixed points (k, 2) besides the particles that a camera must keep in view (e.g. a pin)."""
        return np.empty((0, 2))

    def decorate(self, frame) -> None:
        """Draw scene-specific extras into a video frame; `frame` is the renderer's painter, which offers
        frame.spring(chain_a, particle_a, chain_b, particle_b)."""

    def video_period(self, traj: "Trajectory") -> float | None:
        """Time (tau) one second of video shows when the chain does not beat (None: the default)."""
        return None

    def __repr__(self) -> str:
        return f"<scene {self.name!r}>"

"""What a physical term is: the plug-in contract of a force law, a field or an interaction.

A term module defines one subclass of `Term` and registers one instance of it (elastoactive.terms.register).
The instance holds everything the term adds, and the rest of the package asks it:

  parameters      its `Parameter` specs (elastoactive.core.parameters): name, default, range, help, units, and which
                  switch must be on for each to act; Physics checks them, the CLI offers them, sweeps sweep them
  prepare         normalises its values once the others are known (e.g. `loaded`'s indices against N)
  active          whether it acts in a given Physics (a term whose parameters are all at rest does nothing, so a
                  run without it is bit for bit what it was before the term existed)
  MJCF            `build`: the elements it adds to the scene's MjSpec (a tendon, an option, a site)
  reduced model   `reduced_system`: the fields it sets on the scene's ChainSystem record, read by the compiled
                  kernels; or, for a term the kernels do not know, `node_forces`: a force on every particle as a
                  function of their positions, added to the reduced model's generalised forces; or `clamp_motion`:
                  a prescribed motion of chain 1's clamp (its point and its angle), which both engines apply
  observables     `observables` (elastoactive.core.observables.Observable specs, or names of declared ones) and
                  `measure` (their values from a trajectory)
  validation      `validation_cases`: runs `validate` holds both engines to with the term on

A term is universal: once registered, every scene has its parameters (a scene's own parameters are the scene's:
elastoactive.scenes.base.Scene.parameters).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar, NamedTuple

import numpy as np

from ..core.observables import Observable, names_of
from ..core.parameters import Parameter

NodeForces = Callable[[np.ndarray], np.ndarray]
"""positions (particles, 2) -> forces (particles, 2), in units C1 / l: the particles of chain 1, then chain 2."""


class PeriodicForce(NamedTuple):
    """A node force that does not depend on the positions: vector sin(omega t + phase) on one particle (index over
    chain 1's particles, then chain 2's; vector in C1 / l, lab frame). It is a law of (t, positions) like any other
    (calling it gives the forces on every particle), and the reduced engine evaluates it inside its compiled
    right-hand side (elastoactive.reduced.node_kernels) instead of calling it."""

    particle: int
    vector: tuple[float, float]
    omega: float
    phase: float = 0.0

    def __call__(self, t, positions):
        force = np.zeros_like(positions)
        force[self.particle] = np.asarray(self.vector, dtype=float) * np.sin(self.omega * t + self.phase)
        return force


class ClampMotion(NamedTuple):
    """A prescribed motion of chain 1's clamp: its point moves by displacement(t) (lab x, y in l) with velocity(t),
    and its spring's rest angle turns to angle(t) (rad: the clamp spring acts as C1 (theta_1 - angle(t))).
    Each function takes a time (tau) or an array of times and returns (..., 2) or (...) numbers."""

    displacement: Callable
    velocity: Callable
    angle: Callable
    translates: bool
    """Whether the point moves (False: only the angle turns; the pivot stays put)."""


class Term:
    """A physical term: its parameters, MJCF element, reduced-model contribution and observables.

    The hooks take a `physics` (elastoactive.core.params.Physics), `numerics` (elastoactive.core.params.Numerics),
    `system` (the reduced model's elastoactive.reduced.ChainSystem) and `traj`
    (elastoactive.core.trajectory.Trajectory); they are not imported here, since Physics reads the terms' parameters
    from the term table."""

    name: ClassVar[str] = ""
    """Registry key, e.g. 'contact'."""
    summary: ClassVar[str] = ""
    """One line: what it adds."""
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    observables: ClassVar[tuple[Observable | str, ...]] = ()
    """Results it adds (their values: `measure`): specs the term declares (registered with the term), or names of
    declared ones."""
    agreement: ClassVar[float | None] = None
    """Where the engines model the term differently (MuJoCo's near-hard contact against the reduced model's steep
    penalty), the relative difference between their states over a short run that it allows while it acts, beyond the
    scene's own (Scene.agreement); None: the scene's."""
    measured_at_rest: ClassVar[bool] = True
    """Whether `measure` also runs while the term is at rest, wherever its parameters act on the scene (`takes`): its
    observables then have their values at rest (a force's work is 0), so that a run or a sweep point at the defaults
    reports them. False: they exist only while the term acts (self-contact's clearance, a drive's gain against the
    beat) and are reported only then; a sweep leaves them NaN where the term rests."""
    labelled: ClassVar[bool] = True
    """Whether a case's label (Scene.label) names its parameters when it is active (the built-in terms' are named by
    the scenes' own labels and captions)."""
    named_only: ClassVar[bool] = False
    """Whether only the scenes that name its parameters in their term_parameters take them: the chain scenes that take
    every term (term_parameters None) then refuse them as having no effect (the hydrodynamics term, which the planar
    chains' engines do not carry)."""

    @classmethod
    def observable_names(cls) -> tuple[str, ...]:
        """Names of the term's observables (`observables`), in the order declared."""
        return names_of(cls.observables)

    def prepare(self, values: dict) -> None:
        """Normalise this term's values in `values` (every parameter of the physics, checked one by one) in place;
        raise ParameterError for a combination the specs cannot check alone."""

    def check(self, physics) -> None:
        """Raise ParameterError for a scene or combination the term cannot act on (called by Physics once the scene
        is known, only when the term is active)."""

    def active(self, physics) -> bool:
        """Whether the term acts: by default, whether any of its parameters differs from its default."""
        return any(getattr(physics, p.name) != p.default for p in self.parameters)

    def takes(self, physics) -> bool:
        """Whether any of the term's parameters acts on the physics' scene (the scene has them, their switches on)."""
        return any(physics.acts(p.name) for p in self.parameters)

    def measured(self, physics) -> bool:
        """Whether a run of `physics` reports the term's observables: it acts, or it is measured at rest
        (`measured_at_rest`) and takes part in the scene (`takes`)."""
        return self.active(physics) or (self.measured_at_rest and bool(self.observables) and self.takes(physics))

    def build(self, spec, physics, numerics) -> None:
        """Add the term's MJCF elements to `spec` (an mujoco.MjSpec holding the scene's chains); only called when
        the term is active."""

    def rate(self, physics) -> float:
        """The fastest rate (1 / tau) this term imposes that MuJoCo steps explicitly (a prescribed motion's or force's
        angular frequency, a polarity's turning): the pre-flight check wants dt x rate <= params.RESOLUTION.
        Default 0."""
        return 0.0

    def slower(self, physics, rate: float) -> str:
        """This term's own setting that would bring its rate down to `rate`, e.g. 'alignment_length >= 0.02'; a
        phrase that follows 'or' in a refusal (slower_advice). Default: the term's parameters, named, to be set so
        that its rate is at most `rate`."""
        names = ", ".join(p.name for p in self.parameters)
        return (
            f"the {self.name} term's setting"
            + (f" ({names})" if names else "")
            + f" that brings its rate to {rate:.2g}/tau or below"
        )

    def start(self, physics, model, data) -> None:
        """Set what the term needs in MuJoCo's initial state (`data` at the initial positions, before mj_forward;
        only called when the term is active). Default: nothing."""

    def reduced_system(self, system, physics):
        """The scene's reduced-model record with this term's fields set (only called when the term is active)."""
        return system

    def node_forces(self, physics) -> NodeForces | None:
        """For a term the compiled kernels do not know: the force on every particle from their positions, which the
        reduced engine adds to the generalised forces (None: the term's reduced contribution is in the record)."""
        return None

    def clamp_motion(self, physics) -> ClampMotion | None:
        """A prescribed motion of chain 1's clamp (elastoactive.engines.node_forces adds its drag and spring terms
        to the reduced model; the term's `build` moves the clamp in MuJoCo); None: the clamp stays put."""
        return None

    def inertial_model(self, physics) -> bool:
        """Whether the reduced engine's inertial model (mass_ratio outside the overdamped limit) includes this term
        while it acts: a term of the compiled kernels' record does; node forces and a moving clamp are added to the
        overdamped model only (elastoactive.engines.node_forces), where the engine refuses a mass in one line."""
        return self.node_forces(physics) is None and self.clamp_motion(physics) is None

    def measure(self, traj, transient: float) -> dict[str, float | str]:
        """Values of `observables` (each of `reported(physics)` at least)."""
        return {}

    def reported(self, physics) -> tuple[str, ...]:
        """The observables `measure` reports for a run of `physics` (Term.measured): all of them by default; a term
        with observables that only some settings define (the rotating clamp's lag) leaves the others out here."""
        return self.observable_names()

    def load_mask(self, physics) -> np.ndarray | None:
        """For the term that places the active force on the particles (the follower's `loaded`): the boolean mask of
        the particles of one chain that carry it (Physics.load_mask); None for the others."""
        return None

    # ------------------------------------------------------------------ polarity: units whose direction turns
    polarity_switch: ClassVar[tuple[str, Any] | None] = None
    """For a term that gives particles (nodes) a polarity, an angle psi that turns and is state in both engines
    (Trajectory.polarity): the (parameter, value) that switches its units on, e.g. ('active', 'self-aligning'); None:
    the term carries no polarity. A polarity-carrying term implements the hooks below; the engines and builders find it
    through the registry (elastoactive.terms.polarity_term, polarity_addresses, ...), never by its name."""

    def turning_rate(self, physics) -> float:
        """The fastest rate at which the term's units turn (1 / tau; 0 when none acts)."""
        return 0.0

    def check_reduced_span(self, physics, duration: float) -> None:
        """Refuse, in one line naming the setting, a reduced run whose units are too stiff for its duration."""

    def add_unit(self, spec, site: str, physics, slide: str | None = None) -> None:
        """Mark the MJCF site `site` as one of the term's units (a network builder's node; a chain's particle is
        marked by the term's own `build`); `slide`: a slide joint of the site's body that may carry the unit."""
        raise NotImplementedError(f"the {self.name} term carries no polarity")

    def polarity_addresses(self, model) -> np.ndarray:
        """Where each of the term's units keeps its polarity in mjData.act (units in model order)."""
        return np.empty(0, dtype=int)

    def align_polarity(self, model, data) -> None:
        """Set the polarity of the term's units on chains at t = 0 (after mj_forward), e.g. along the follower
        direction of their site."""

    def initial_polarity(self, theta: np.ndarray, mask: np.ndarray) -> np.ndarray:
        """The reduced engine's polarity of the loaded particles (load mask `mask` over theta's columns) of chains with
        absolute angles theta at t = 0, as align_polarity gives MuJoCo's units."""
        raise NotImplementedError(f"the {self.name} term carries no polarity")

    def short_case(self, physics):
        """The physics of a short run in which the term acts visibly within a few time units (the conformance kit's
        case for it, elastoactive.testing): by default its first validation case's, else None (the kit switches it on
        in the first scene that takes it). `physics` is the Physics class, as for validation_cases."""
        cases = self.validation_cases(physics)
        return cases[0].physics if cases else None

    def validation_cases(self, physics) -> tuple:
        """Cases (elastoactive.core.cases.ValidationCase) that `validate` runs through both engines with this term on,
        besides the scenes' own; `physics` is the Physics class (passed in: it reads the terms' parameters from this
        registry, so a term module does not import it)."""
        return ()

    def __repr__(self) -> str:
        return f"<term {self.name!r}>"


ALIASING = 1.0
"""Most radians a term's fastest rate (Term.rate) may turn between two samples before the record may alias it (the
results' note; the coarsest record a large network's automatic sampling takes, engines.network_step)."""


def fastest_term(physics) -> tuple[float, Term | None]:
    """(rate, term): the active term with the fastest Term.rate, or (0.0, None) when no term imposes one."""
    rate, term = max(
        ((t.rate(physics), t) for t in physics.active_terms()), key=lambda pair: pair[0], default=(0.0, None)
    )
    return (rate, term) if rate > 0 else (0.0, None)


def slower_advice(term: Term, physics, rate: float) -> str:
    """' or <the term's slower setting>' for a refusal or note that advises a finer dt first (Term.slower), or '' when
    the term names none (a plug-in term's slower may return an empty string)."""
    slower = str(term.slower(physics, rate) or "").strip()
    return f" or {slower}" if slower else ""

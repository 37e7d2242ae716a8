"""Dimensionless parameters of the paper and the numerical settings of a run.

Units: pendulum length l = 1, joint stiffness C (C1 for the pair) = 1 and transverse drag
gamma = 1, so the time unit is tau = gamma l^2 / C = 1 and the active force is F_a = sigma.
Every other module takes its physics from here; `elastoactive.mjcf.chain` is the one place
that turns these numbers into MJCF attributes. Which parameters a scene uses, and any
constraint on them beyond the generic ranges checked here, is the scene's business
(`elastoactive.scenes`).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from . import parameters as _parameters
from . import registry, surface
from . import term_registry as _terms
from .errors import ParameterError
from .parameters import COUPLING, finite
from .units import NETWORK, Worded

INTEGRATORS = ("implicitfast", "implicit", "discrete", "Euler", "RK4")
DEFAULT_SCENE = "one-pinned"
"""The scene a Physics() without a scene describes: the paper's flagellar beating."""

LEADING = ("n", "sigma", "drag_ratio", "noise")
"""The parameters every summary reports first, in this order; then the scene's own, then the terms' others."""


def scene_parameters(scene) -> tuple[str, ...]:
    """Every parameter a scene has, in reporting order: LEADING, the scene's own, then the terms' others; last, the
    coupling Pi where the scene has one (has_coupling), given in place of sigma and not recorded."""
    if scene.term_parameters is not None:  # a network scene: only the terms' parameters that act on its units
        acting = tuple(scene.term_parameters)
        names = tuple(k for k in LEADING if k in acting) + tuple(scene.own_parameter_names()) + acting
    else:  # a chain scene: every term's parameters but those of a term that only the scenes naming them take
        terms = tuple(p.name for t in _terms.terms() if not getattr(t, "named_only", False) for p in t.parameters)
        names = LEADING + tuple(scene.own_parameter_names()) + terms
    return tuple(dict.fromkeys(names)) + ((COUPLING.name,) if has_coupling(scene) else ())


def has_coupling(scene) -> bool:
    """Whether a scene has the coupling Pi (Scene.coupling(physics, sigma): linear in sigma)."""
    return callable(getattr(scene, "coupling", None))


def _coupled(definition, scene: str, values: dict) -> dict:
    """`values` with the coupling Pi, where given, turned into the sigma that gives it on this scene: Pi is linear in
    sigma (Scene.coupling), so sigma = Pi / coupling(at sigma = 1). Pi beside sigma is refused in one line."""
    if COUPLING.name not in values:
        return values
    rest = {k: v for k, v in values.items() if k != COUPLING.name}
    if COUPLING.instead_of in rest:
        raise ParameterError(
            f"give sigma or Pi, not both (on {scene} Pi = {definition.coupling_formula}, and sigma follows from it)"
        )
    coupling = COUPLING.check(values[COUPLING.name])
    return {**rest, COUPLING.instead_of: coupling / definition.coupling(Physics(scene=scene, **rest), 1.0)}


class Physics:
    """The model in the paper's dimensionless numbers: a scene and the values of its parameters.

    Physics(scene=name, n=7, sigma=0.8, delta=0.1) for the two-pinned scene. Every parameter is declared once by
    its owner (elastoactive.core.parameters): n by the chain; sigma and loaded by the follower force, drag_ratio by the
    drag, noise, noise_correlation and noise_calculus by the noise, contact, contact_radius and contact_friction by
    self-contact (elastoactive.terms); delta, kappa, rho, trap by their scenes. Each value is checked by its spec
    (one rule, one message naming it). A value given where it does not act is refused: a parameter the scene does
    not have (delta on one-pinned), or one whose switch is off (contact_radius without contact, noise_correlation
    with noise 0) unless it is the default it would take anyway. Parameters not given take their defaults; reading
    one the scene does not have gives its default.

    scene       name of a registered scene (elastoactive.scenes.names())
    n           particles per chain (N >= 1; N >= 2 when both ends are pinned)
    sigma       elasto-active number F_a l / C1
    delta       compression of the two-pinned chain, end held at (N l (1 - delta), 0)
    kappa       coupling stiffness K l^2 / C1 of the pair's first pendula
    rho         stiffness ratio C2 / C1 of the pair (second chain has sigma / rho)
    drag_ratio  gamma_L / gamma_T, longitudinal over transverse drag (1 = isotropic)
    noise       amplitude a of multiplicative noise: F_a (1 + eta); white: <eta eta'> = a^2 delta(t-t')
    noise_correlation  correlation time tau_c of the noise (0: white); tau_c > 0: eta is an Ornstein-Uhlenbeck
                process, <eta(t) eta(t')> = a^2 / (2 tau_c) exp(-|t - t'| / tau_c), of the same intensity
                as the white noise of amplitude a (its limit as tau_c -> 0)
    noise_calculus  reading of white noise: "ito" or "stratonovich" (the white limit of coloured noise,
                Wong-Zakai); unused for coloured noise. Acts only when noise > 0
    loaded      particles carrying the follower force: "all" (the paper), "tip" (the last particle: the
                tip-loaded column) or 1-based indices "1,3,7"; the same particles on both chains of a pair.
                Reported only when not "all" (load_mask: the boolean mask per particle)
    contact     self-contact (off by default): each link carries a capsule of radius contact_radius and length
                CONTACT_LENGTH that collides with the capsules of non-adjacent links of its own chain (never
                neighbours, never the other chain of a pair); contact_radius and contact_friction act only with
                contact on
    trap        the paraboloid dish's harmonic trap: force -k r on every particle and on the head, k l^2 / C1
    """

    __slots__ = ("scene", "_values")

    def __init__(self, scene: str = DEFAULT_SCENE, **values) -> None:
        try:
            definition = registry.get(scene)
        except registry.UnknownScene:
            raise ParameterError(f"scene must be one of {', '.join(registry.names())}; got {scene!r}") from None
        usable = scene_parameters(definition)
        for name in values:
            if name not in usable:
                if _parameters.known(name):
                    raise ParameterError(f"{name} has no effect on scene {scene} (its parameters: {', '.join(usable)})")
                raise ParameterError(
                    f"unknown parameter {name!r}; the parameters of scene {scene}: {', '.join(usable)}"
                )
        values = _coupled(definition, scene, values)
        resolved = {}
        for name in usable:
            if name == COUPLING.name:  # given in place of sigma: not a value of its own
                continue
            spec = _parameters.get(name)
            resolved[name] = spec.check(values[name]) if name in values else spec.default
        for name, value, why in definition.fixed:  # values the scene holds (a network's units are self-aligning)
            if name in values and resolved[name] != value:
                raise ParameterError(f"{name} must be {value} on scene {scene} ({why}), got {resolved[name]!r}")
            resolved[name] = value
        for term in _terms.terms():
            if all(p.name in resolved for p in term.parameters):  # a network scene lacks the chain terms' ones
                term.prepare(resolved)
        for name in values:  # a value its switch leaves unused is refused, unless it is the default it takes anyway
            spec = _parameters.get(name)
            switch = spec.needs
            if switch is not None and not spec.acts_in(resolved) and resolved[name] != spec.default:
                raise ParameterError(spec.unused_text(resolved))
        object.__setattr__(self, "scene", scene)
        object.__setattr__(self, "_values", resolved)
        definition.check(self)
        for term in self.active_terms():  # a term that cannot act on this scene refuses it (Term.check)
            term.check(self)

    # ------------------------------------------------------------------ a frozen record
    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        values = object.__getattribute__(self, "_values")
        if name in values:
            return values[name]
        if name == COUPLING.name:  # the coupling of a scene that has one (else None, its spec's default)
            definition = self.scene_def
            return definition.coupling(self) if has_coupling(definition) else None
        if _parameters.known(name):
            return _parameters.get(name).default
        raise AttributeError(f"Physics has no parameter {name!r}")

    def __setattr__(self, name, value):
        raise AttributeError("Physics is frozen: use physics.replace(...)")

    def __delattr__(self, name):
        raise AttributeError("Physics is frozen")

    def _key(self) -> tuple:
        return (self.scene, tuple(self._values.items()))

    def __eq__(self, other) -> bool:
        return isinstance(other, Physics) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __reduce__(self):
        return (_restore, (self.scene, self.given()))

    def __repr__(self) -> str:
        return (
            f"Physics(scene={self.scene!r}, "
            + ", ".join(f"{k}={v!r}" for k, v in self.relevant().items() if k != "scene")
            + ")"
        )

    def given(self) -> dict:
        """The values that act (the scene's parameters, less those whose switch is off): what rebuilds this."""
        return {k: v for k, v in self._values.items() if self._acts(k)}

    def _acts(self, name: str) -> bool:
        spec = _parameters.get(name)
        return spec.acts_in(self._values)

    def acts(self, name: str) -> bool:
        """Whether the parameter `name` acts in this physics: its scene has it and its switch (if any) is on."""
        return name in self._values and self._acts(name)

    def require_acting(self, names) -> None:
        """Refuse, in one line, any of `names` (values a user gave, e.g. on the command line) that this physics leaves
        unused because its switch is off, even at its default value (which the constructor lets through: it is what
        the physics takes anyway, but a user who typed it expects it to act)."""
        for name in names:
            spec = _parameters.get(name)
            if spec.needs is not None and not spec.acts_in(self._values):
                raise ParameterError(spec.unused_text(self._values))

    def replace(self, **changes) -> Physics:
        """This physics with some values changed (and checked); values that stop acting (a switch turned off, a
        scene without them) are dropped."""
        scene = changes.pop("scene", self.scene)
        usable = scene_parameters(registry.get(scene)) if scene in registry.names() else ()
        kept = {k: v for k, v in self.given().items() if k in usable and k not in changes}
        if COUPLING.name in changes:  # the coupling given anew sets sigma
            kept.pop(COUPLING.instead_of, None)
        values = {**kept, **changes}
        for name in list(kept):
            switch = _parameters.get(name).needs
            spec = _parameters.get(name)
            if (
                switch is not None
                and (switch in values or spec.or_needs in values or spec.unless in values)
                and not spec.acts_in({**self._values, **values})
            ):
                del values[name]
        return Physics(scene=scene, **values)

    # ------------------------------------------------------------------ derived
    def load_mask(self) -> np.ndarray:
        """Boolean mask of the particles of one chain that carry the follower force (all True for "all"): the term
        that places the active force says (Term.load_mask)."""
        return next(m for t in _terms.terms() if (m := t.load_mask(self)) is not None)

    @property
    def stochastic(self) -> bool:
        """Whether a parameter declared stochastic is > 0 (core.parameters.stochastic): the reduced engine then steps
        the run at numerics.dt with the draws of numerics.seed."""
        return _parameters.stochastic(self)

    @property
    def all_loaded(self) -> bool:
        return self.loaded == "all"

    @property
    def scene_def(self):
        """The registered Scene object this physics belongs to (elastoactive.scenes)."""
        return registry.get(self.scene)

    @property
    def n_chains(self) -> int:
        return self.scene_def.chain_count(self)

    @property
    def n_angles(self) -> int:
        """Columns of a trajectory's theta: N per chain (0 for a network scene)."""
        return self.scene_def.angle_count(self)

    @property
    def stiffness(self) -> tuple[float, ...]:
        """Joint stiffness C of each chain in units of C1."""
        return self.scene_def.stiffness(self)

    @property
    def clamped(self) -> bool:
        """Whether the first pendulum has a spring against the clamp."""
        return self.scene_def.clamped

    def active_terms(self) -> tuple:
        """The registered terms that act in this physics (elastoactive.terms)."""
        return tuple(t for t in _terms.terms() if t.active(self))

    def measured_terms(self) -> tuple:
        """The registered terms whose observables a run of this physics reports (Term.measured)."""
        return tuple(t for t in _terms.terms() if t.measured(self))

    def relevant(self) -> dict:
        """The parameters this run reports (summary.json, labels): the scene and every value that acts, less the
        quiet ones at their default (contact off, loaded "all", a plug-in term at rest), so that a summary records
        what it recorded before those parameters existed."""
        out = {"scene": self.scene}
        for name, value in self._values.items():
            spec = _parameters.get(name)
            if not self._acts(name) or (spec.quiet_default and value == spec.default):
                continue
            out[name] = value
        return out


def _restore(scene: str, values: dict) -> Physics:
    return Physics(scene=scene, **values)


class _Unset:
    """Marks a Numerics default the user did not choose (Numerics.automatic). The value is an ordinary number or
    text (float / str subclass): it compares, hashes, prints and serialises as the plain value, so a run with the
    defaults computes, records and reads back exactly as before."""

    __slots__ = ()


class _UnsetFloat(_Unset, float):
    __slots__ = ()

    def __repr__(self) -> str:
        return float.__repr__(self)


class _UnsetStr(_Unset, str):
    __slots__ = ()

    def __repr__(self) -> str:
        return str.__repr__(self)


DEFAULT_DT = _UnsetFloat(0.0025)
DEFAULT_MASS_RATIO = _UnsetFloat(1e-4)
DEFAULT_INTEGRATOR = _UnsetStr("implicitfast")
DEFAULT_SAMPLE_DT = _UnsetFloat(0.05)
MAX_PERTURBATION = math.pi
"""The largest seeded initial push (Numerics.perturbation): an angle past pi wraps round, a node moved past pi a
crosses its neighbours."""
MAX_SEED = 2**53
"""Largest seed: MuJoCo's noise callback reads it from a model numeric, a double, which holds every integer up to 2^53
exactly, so that both engines draw the same noise from it."""
AUTO_SAMPLES = 100_000
"""Most samples a run records when its sample_dt is left at the default (Numerics.for_duration): a long chain's beat
period grows like N^4 (about 1e6 tau at N = 80), and 0.05 would record millions of samples per beat."""


@dataclass(frozen=True)
class Numerics:
    """Numerical settings of a MuJoCo run (times in units of tau).

    dt           timestep
    mass_ratio   particle mass m / (gamma tau): the inertial time in units of tau
    integrator   MuJoCo integrator
    perturbation largest angle (rad) of the seeded initial push away from the base state (a network's: the nodes'
                 largest displacement, in a)
    sample_dt    spacing of the recorded trajectory: a whole number of steps of dt (a dt left at its default is the
                 largest whole fraction of sample_dt at most DEFAULT_DT)

    Automatic numerics for long chains: when dt, mass_ratio and integrator are all left at their defaults
    (`automatic`), a MuJoCo run of a chain of LONG_CHAIN particles or more uses `for_physics(physics)`
    instead: the cheaper of explicit drag (Euler) with a matched particle mass, several times cheaper per step than
    implicitfast's dense drag derivatives, and implicitfast with a dt that resolves the chain's fastest rate (the
    defaults where they do: long_chain_numerics). Either passes the pre-flight check. Shorter chains, and any run
    where one of the three is given, use the values as they are (a given value always wins, even one equal to the
    default).
    """

    dt: float = field(default=DEFAULT_DT, metadata={"help": "MuJoCo timestep in tau"})
    mass_ratio: float = field(
        default=DEFAULT_MASS_RATIO,
        metadata={
            "help": "particle mass m / (gamma tau); the overdamped limit is 0",
            "worded": (Worded(NETWORK.name, "node mass m k / gamma^2; the overdamped limit is 0"),),
        },
    )
    integrator: str = field(default=DEFAULT_INTEGRATOR, metadata={"help": "MuJoCo integrator", "choices": INTEGRATORS})
    perturbation: float = field(
        default=1e-2,
        metadata={
            "help": "size of the random initial kick, rad",
            "worded": (Worded(NETWORK.name, "size of the random initial push of the nodes, a"),),
        },
    )
    sample_dt: float = field(
        default=DEFAULT_SAMPLE_DT,
        metadata={
            "help": "spacing of the recorded trajectory, tau (default 0.05, coarser for runs that would record more "
            "than 100000 samples)"
        },
    )
    seed: int = field(default=0, metadata={"help": "seed of the initial perturbation and the noise"})

    def __post_init__(self) -> None:
        for name in ("dt", "mass_ratio", "perturbation", "sample_dt"):
            if not isinstance(getattr(self, name), _Unset):  # a default stays marked as one (automatic)
                object.__setattr__(self, name, finite(name, getattr(self, name)))
        if not 0 < self.dt <= 0.1:
            raise ParameterError(f"dt (timestep, in tau) must lie in (0, 0.1], got {self.dt}")
        if not 1e-7 <= self.mass_ratio <= MAX_MASS_RATIO:
            raise ParameterError(
                f"mass_ratio (m / gamma tau) must lie in [1e-7, {MAX_MASS_RATIO:g}], got {self.mass_ratio} (above "
                "the overdamped limit both engines model the inertial chain: elastoactive.engines.timestep.regime)"
            )
        if self.integrator not in INTEGRATORS:
            raise ParameterError(f"integrator must be one of {', '.join(INTEGRATORS)}, got {self.integrator!r}")
        if not 0 <= self.perturbation <= MAX_PERTURBATION:
            raise ParameterError(
                f"perturbation = {self.perturbation:g}: the seeded initial push lies in [0, pi] (its largest angle, "
                "rad; a network's largest node displacement, a): a push past pi is no longer a push away from the base "
                "state"
            )
        if not self.sample_dt > 0:
            raise ParameterError(
                f"sample_dt (spacing of the recorded samples, in tau) must be > 0, got {self.sample_dt}"
            )
        ratio = self.sample_dt / self.dt
        if isinstance(self.dt, _Unset) and (ratio < 1 or abs(ratio - round(ratio)) > 1e-6 * ratio):
            # dt left at its default: the largest whole fraction of sample_dt below it (the reduced engine, which has
            # no dt, takes any sample_dt; MuJoCo steps a little finer), still a default (automatic)
            object.__setattr__(self, "dt", _UnsetFloat(_whole_fraction(self.sample_dt, self.dt)))
        if self.sample_dt < self.dt:
            raise ParameterError(f"sample_dt ({self.sample_dt}) must be >= dt ({self.dt})")
        ratio = self.sample_dt / self.dt
        if abs(ratio - round(ratio)) > 1e-6 * ratio:
            raise ParameterError(
                f"sample_dt ({self.sample_dt}) must be a whole multiple of dt ({self.dt}), e.g. "
                f"{round(ratio) * self.dt:.6g}, so that both engines record at the same times"
            )
        # an integer as Parameter.check takes n: a numpy integer, or a number with an integer value, is one
        whole = isinstance(self.seed, numbers.Integral) or (
            isinstance(self.seed, numbers.Real) and float(self.seed).is_integer()
        )
        if isinstance(self.seed, (bool, np.bool_)) or not whole or not 0 <= self.seed <= MAX_SEED:
            raise ParameterError(f"seed must be a non-negative integer at most 2^53 = {MAX_SEED}, got {self.seed!r}")
        object.__setattr__(self, "seed", int(self.seed))

    @property
    def steps_per_sample(self) -> int:
        return max(1, int(round(self.sample_dt / self.dt)))

    def given(self) -> tuple[str, ...]:
        """Which of dt, mass_ratio and integrator were chosen (not left at their defaults)."""
        return tuple(name for name in ("dt", "mass_ratio", "integrator") if not isinstance(getattr(self, name), _Unset))

    @property
    def automatic(self) -> bool:
        """Whether dt, mass_ratio and integrator were all left at their defaults: the MuJoCo engine may then
        choose them for the physics (for_physics)."""
        return all(isinstance(getattr(self, name), _Unset) for name in ("dt", "mass_ratio", "integrator"))

    def for_physics(self, physics) -> Numerics:
        """The numerics a MuJoCo run of `physics` uses: these, or, when they are `automatic` and the chain has
        LONG_CHAIN particles or more, long_chain_numerics(physics, self) if that is expected to be cheaper."""
        if not self.automatic or physics.n < LONG_CHAIN:
            return self
        return long_chain_numerics(physics, self)

    def for_duration(self, duration: float) -> Numerics:
        """These numerics, or, where sample_dt was left at its default and the run would record more than AUTO_SAMPLES
        samples, a coarser sample_dt: the fewest whole steps of dt that keep the count at most AUTO_SAMPLES. A given
        sample_dt is kept as it is."""
        duration = finite("duration", duration)
        if not isinstance(self.sample_dt, _Unset) or duration / self.sample_dt <= AUTO_SAMPLES:
            return self
        return dataclasses.replace(self, sample_dt=self.dt * math.ceil(duration / AUTO_SAMPLES / self.dt - 1e-9))

    def sample_count(self, duration: float) -> int:
        """How many samples a run of `duration` records (sample_times' size), checked against MAX_SAMPLES without
        allocating them."""
        duration = finite("duration", duration)
        if duration < 0:
            raise ParameterError(f"duration (in tau) must be >= 0, got {duration}")
        spacing = self.steps_per_sample * self.dt
        count = math.floor(duration / spacing + 1e-9) + 1
        if count > MAX_SAMPLES:
            raise ParameterError(
                f"duration ({duration:g} tau) at sample_dt = {spacing:g} would record {count:.3g} samples "
                f"(limit {MAX_SAMPLES:.0e}); shorten {option('duration')} or raise {option('sample_dt')}"
            )
        return count

    def sample_times(self, duration: float) -> np.ndarray:
        """Recording times k * sample_dt, k = 0 .. floor(duration / sample_dt): the same grid for
        both engines (sample_dt is a whole number of MuJoCo steps)."""
        return self.steps_per_sample * self.dt * np.arange(self.sample_count(duration))

    def check_duration(self, duration: float) -> float:
        """A run length the engines can record and measure: at least MIN_SAMPLES samples."""
        duration = finite("duration", duration)
        if duration <= 0:
            raise ParameterError(f"duration (in tau) must be > 0, got {duration:g}")
        count = self.sample_count(duration)
        if count < MIN_SAMPLES:
            # the advice must pass the transient's check too: the default transient (results.default_transient)
            # discards the first half of the run, and the second half must still hold MIN_SAMPLES samples
            shortest = 2 * (MIN_SAMPLES - 1) * self.steps_per_sample * self.dt
            raise ParameterError(
                f"duration ({duration:g} tau) holds {count} sample(s) at sample_dt = {self.sample_dt:g}; at least "
                f"{MIN_SAMPLES} are needed to measure a run, after its transient (by default the first half): "
                f"lengthen {option('duration')} (>= {shortest:.4g} tau) or lower {option('sample_dt')}"
            )
        return duration

    @classmethod
    def preset(cls, name: str, **overrides) -> Numerics:
        """Named settings: 'accurate' (the default: every validate error <= 1%) or 'fast'
        (dt = 0.01: amplitude and frequency within 0.3%, about four times faster; for sweeps)."""
        if name not in PRESETS:
            raise ParameterError(f"preset must be one of {', '.join(PRESETS)}, got {name!r}")
        return cls(**{**PRESETS[name], **overrides})


MAX_MASS_RATIO = 100.0
"""Largest particle mass m / (gamma tau) Numerics accepts (heavy chains beat slowly: f tau ~ 0.018 at m = 10)."""
MAX_SAMPLES = 50_000_000
"""Most samples one run records (about 2.8 GB of angles at N = 7): beyond it the run would exhaust memory."""
MIN_SAMPLES = 10
"""Fewest samples a run must record to be measured."""

PRESETS = {
    "accurate": dict(dt=DEFAULT_DT, mass_ratio=DEFAULT_MASS_RATIO),  # the defaults (automatic for long chains)
    "fast": dict(dt=0.01, mass_ratio=1e-3),
}

LONG_CHAIN = 30
"""Chains of this many particles or more run with long_chain_numerics when their numerics are automatic. From
here on implicitfast's step, whose dense drag derivatives cost O(N^3), is more than twice Euler's (measured
per step, thread time: 2.1x at N = 30, 5.4x at 100, 8.3x at 200; docs/performance.md)."""
RESOLUTION = 0.2
"""dt x rate below which an integrator resolves a mode of that rate (implicitfast, Euler, RK4, implicit; the pre-flight
check, elastoactive.engines.timestep, holds every run to it; docs/performance.md)."""
RESOLVED_INERTIA = 0.05
"""mass_ratio x rate that the automatic numerics keep below: half the overdamped limit (analysis.reduced.regime's 0.1),
so that the inertial lag stays a small error."""
LONG_CHAIN_MASS = 2e-3
"""Largest particle mass ratio long_chain_numerics picks."""
LONG_CHAIN_RESOLUTION = 0.55
"""long_chain_numerics keeps mass_ratio x rate^2 <= this (rate: the fastest overdamped rate at the base state).
Calibrated on one-pinned, sigma 0.05, 20 tau, against the reduced model (largest angle error relative to the largest
angle; it grows about linearly with the mass): 0.02% at N = 30 and 0.3% at N = 100 (mass 2e-3, rate 14.5),
0.8% at N = 200 (rate 22.9: mass 1.05e-3) (docs/performance.md, tests/engines/test_long_chains.py)."""
LONG_CHAIN_DT_PER_MASS = 1.6
"""dt / mass_ratio of long_chain_numerics (isotropic drag; over max(1, drag_ratio) otherwise): Euler's explicit drag
is stable for dt < 2 m / gamma (the lab drag of equal point masses is gamma / m times their mass matrix), so this is
80% of that limit. Euler's time-stepping error and the inertial lag partly cancel, the more so the closer dt / m is
to 2: at N = 200, m = 1e-3, the angle error is 1.8%, 1.45% and 0.80% at dt / m = 1, 1.25 and 1.67."""
LONG_CHAIN_STEP_COST = (2.0, 0.7)
"""(c, p): Euler's step is at least c (N / LONG_CHAIN)^p times cheaper than implicitfast's (2 at N = 30, 4.6 at
100, 7.5 at 200; measured 2.1, 5.4, 8.3: see LONG_CHAIN). long_chain_numerics keeps the defaults when its
smaller dt would take more steps than that makes up for."""
_RATES: dict = {}


def _fastest_rate(physics) -> float:
    """Fastest overdamped rate at the scene's base state (Scene.fastest_overdamped_rate), cached."""
    rate = _RATES.get(physics)
    if rate is None:
        rate = _RATES[physics] = float(physics.scene_def.fastest_overdamped_rate(physics))
        if len(_RATES) > 1024:
            _RATES.pop(next(iter(_RATES)))
    return rate


def _whole_fraction(sample_dt: float, target: float) -> float:
    """The largest dt <= target that divides sample_dt into whole steps."""
    return sample_dt / max(1, math.ceil(sample_dt / target - 1e-9))


def resolving_numerics(physics, numerics: Numerics) -> Numerics:
    """`numerics` (implicitfast's implicit drag) with dt and mass_ratio small enough to resolve the chain's fastest
    overdamped rate: dt x rate <= RESOLUTION (dt a whole fraction of sample_dt) and mass_ratio x rate <=
    RESOLVED_INERTIA; unchanged where they already do."""
    rate = _fastest_rate(physics)
    if rate <= 0:
        return numerics
    dt = min(numerics.dt, _whole_fraction(numerics.sample_dt, RESOLUTION / rate))
    m = min(numerics.mass_ratio, RESOLVED_INERTIA / rate)
    if dt == numerics.dt and m == numerics.mass_ratio:
        return numerics
    return dataclasses.replace(numerics, dt=dt, mass_ratio=max(m, 1e-7))


def long_chain_numerics(physics, numerics: Numerics | None = None) -> Numerics:
    """The cheaper of two settings that resolve a long chain (the other settings of `numerics` kept):

    * explicit drag with a matched mass: integrator Euler, mass_ratio m = min(LONG_CHAIN_MASS,
      LONG_CHAIN_RESOLUTION / rate^2) and dt = LONG_CHAIN_DT_PER_MASS x m / max(1, drag_ratio) rounded down to a
      whole fraction of sample_dt; m x rate stays below 0.1 (the overdamped limit, analysis.reduced.regime): the
      run models the paper's overdamped chain, as the defaults do;
    * implicitfast at `numerics`' dt and mass, made smaller where they do not resolve the fastest rate
      (resolving_numerics): the defaults themselves for moderate rates, a smaller dt at high sigma or N.

    Euler's step is cheaper by LONG_CHAIN_STEP_COST; it is chosen when that makes up for its smaller dt."""
    numerics = Numerics() if numerics is None else numerics
    rate = _fastest_rate(physics)
    m = LONG_CHAIN_MASS if rate <= 0 else min(LONG_CHAIN_MASS, LONG_CHAIN_RESOLUTION / rate**2)
    m = max(m, 1e-7)
    dt = _whole_fraction(numerics.sample_dt, LONG_CHAIN_DT_PER_MASS * m / max(1.0, float(physics.drag_ratio)))
    implicit = resolving_numerics(physics, numerics)
    c, p = LONG_CHAIN_STEP_COST
    if dt * c * (physics.n / LONG_CHAIN) ** p < implicit.dt:
        return implicit
    return dataclasses.replace(numerics, integrator="Euler", dt=dt, mass_ratio=m)


def check_start(physics: Physics, numerics: Numerics) -> None:
    """Refuse perturbation = 0 where nothing else moves the run off the scene's base state and that state is unstable
    (Scene.leading_eigenvalue at the physics' sigma has a positive real part): the run would sit on the unstable state
    up to round-off and report it, not the motion. Both engines' runs ask it (engines.run_engine, the MuJoCo batch).
    Noise, a term's force or a moving clamp (Term.node_forces, Term.clamp_motion), a scene seeded off its base states
    (Scene.seeded_start: a network's polarities) and a scene without a linear operator at its base state are let
    through."""
    if numerics.perturbation > 0 or physics.noise > 0 or physics.scene_def.seeded_start:
        return
    if any(t.node_forces(physics) is not None or t.clamp_motion(physics) is not None for t in physics.active_terms()):
        return
    try:
        growth = complex(physics.scene_def.leading_eigenvalue(physics, physics.sigma)).real
    except ParameterError:  # no linear operator about this scene's base state: nothing to tell
        return
    if growth > 0:
        raise ParameterError(
            f"perturbation = 0 starts the run exactly on the base state of scene {physics.scene}, which is unstable "
            f"at sigma = {physics.sigma:g} (growth rate {growth:.3g}/tau): the run would stay on it up to round-off "
            f"and report that state, not the motion; give {option('perturbation')} > 0 (default 0.01)"
        )


def parameter_fields(cls) -> tuple:
    """What a user sets, with its help text (`.name`, `.metadata["help"]`): the Parameter specs of every declared
    physics parameter (elastoactive.core.parameters, in declaration order) for Physics; the dataclass fields of
    Numerics."""
    if cls is Physics:
        names = LEADING + _parameters.names()
        return tuple(_parameters.get(name) for name in dict.fromkeys(names))
    return tuple(f for f in dataclasses.fields(cls) if "help" in f.metadata)


def option(name: str, value=None) -> str:
    """The setting `name` (a Numerics field, a physics parameter or an argument of a run such as duration), with `value`
    when given, as the caller's surface spells it (core.surface.option): `--dt` on the command line, `numerics.dt` in
    Python."""
    numerics = {f.name for f in dataclasses.fields(Numerics)}
    return surface.option(f"numerics.{name}" if name in numerics else name, value)


def replace(obj, **changes):
    """A Physics or Numerics with some values changed, re-validated."""
    if isinstance(obj, Physics):
        return obj.replace(**changes)
    return dataclasses.replace(obj, **changes)

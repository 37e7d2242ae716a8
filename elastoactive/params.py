"""Dimensionless parameters of the paper and the numerical settings of a run.

Units: pendulum length l = 1, joint stiffness C (C1 for the pair) = 1 and transverse drag
gamma = 1, so the time unit is tau = gamma l^2 / C = 1 and the active force is F_a = sigma.
Every other module takes its physics from here; `elastoactive.model` is the one place
that turns these numbers into MJCF attributes. Which parameters a scene uses, and any
constraint on them beyond the generic ranges checked here, is the scene's business
(`elastoactive.scenes`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from . import registry
from .analysis.reduced.system import CONTACT_LENGTH
from .errors import ParameterError

NOISE_CALCULI = ("ito", "stratonovich")
INTEGRATORS = ("implicitfast", "implicit", "discrete", "Euler", "RK4")
DEFAULT_SCENE = "one-pinned"
"""The scene a Physics() without a scene describes: the paper's flagellar beating."""


def _finite(name: str, value: float) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(value):
        raise ParameterError(f"{name} must be finite, got {value}")
    return value


def _loaded_indices(text: str, n: int) -> list[int]:
    """The 1-based particle indices of a `loaded` value other than "all" and "tip" (checked)."""
    parts = [p.strip() for p in text.split(",")]
    try:
        idx = [int(p) for p in parts]
    except ValueError:
        raise ParameterError(
            f"loaded must be all, tip, or comma-separated 1-based particle indices like 1,3,7; got {text!r}") from None
    bad = [i for i in idx if not 1 <= i <= n]
    if bad:
        raise ParameterError(f"loaded: particle indices must lie in 1..{n} (N = {n}), got {bad[0]} in {text!r}")
    dup = sorted({i for i in idx if idx.count(i) > 1})
    if dup:
        raise ParameterError(f"loaded: particle index {dup[0]} appears more than once in {text!r}")
    return idx


def _loaded(value, n: int) -> str:
    """The checked, normalised `loaded` value: "all", "tip", or sorted indices "1,3,7"."""
    if not isinstance(value, str):
        if isinstance(value, (list, tuple)) and all(isinstance(i, int) and not isinstance(i, bool) for i in value):
            value = ",".join(str(i) for i in value)
        else:
            raise ParameterError(f"loaded must be a string (all, tip, or indices like 1,3,7), got {value!r}")
    text = value.strip().lower()
    if text in ("all", "tip"):
        return text
    if not text:
        raise ParameterError("loaded must be all, tip, or comma-separated 1-based particle indices like 1,3,7; got ''")
    return ",".join(str(i) for i in sorted(_loaded_indices(text, n)))


def _load_mask(loaded: str, n: int) -> np.ndarray:
    mask = np.zeros(n, dtype=bool)
    if loaded == "all":
        mask[:] = True
    elif loaded == "tip":
        mask[-1] = True
    else:
        mask[np.array(_loaded_indices(loaded, n)) - 1] = True
    return mask


@dataclass(frozen=True)
class Physics:
    """The model in the paper's dimensionless numbers.

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
                Wong-Zakai); unused for coloured noise. Reported only when noise > 0
    loaded      particles carrying the follower force: "all" (the paper), "tip" (the last particle: the
                tip-loaded column) or 1-based indices "1,3,7"; the same particles on both chains of a pair.
                Reported only when not "all" (load_mask: the boolean mask per particle)
    contact     self-contact (off by default): each link carries a capsule of radius contact_radius and length
                CONTACT_LENGTH that collides with the capsules of non-adjacent links of its own chain (never
                neighbours, never the other chain of a pair); contact_radius and contact_friction are reported
                only with contact on
    trap        the paraboloid dish's harmonic trap: force -k r on every particle and on the head, k l^2 / C1
    """

    scene: str = DEFAULT_SCENE
    n: int = field(default=7, metadata={"help": "particles per chain N"})
    sigma: float = field(default=0.8, metadata={"help": "elasto-active number F_a l / C1"})
    delta: float = field(default=0.1, metadata={"help": "compression of the two-pinned chain, in [0, 1)"})
    kappa: float = field(default=1.0, metadata={"help": "coupling stiffness K l^2 / C1 of the pair's first pendula"})
    rho: float = field(default=4.0 / 3.0, metadata={"help": "stiffness ratio C2 / C1 of the pair; chain 2 has sigma/rho"})
    drag_ratio: float = field(default=1.0, metadata={"help": "anisotropy gamma_L / gamma_T of the drag (1: isotropic)"})
    noise: float = field(default=0.0, metadata={"help": "amplitude a of multiplicative white noise on F_a"})
    noise_correlation: float = field(default=0.0, metadata={
        "help": "correlation time tau_c of the noise, in tau (0: white; > 0: Ornstein-Uhlenbeck of variance "
                "a^2 / (2 tau_c))"})
    noise_calculus: str = field(default="ito", metadata={
        "help": "reading of white noise (reduced engine; MuJoCo: ito, or stratonovich as small tau_c)",
        "choices": NOISE_CALCULI})
    loaded: str = field(default="all", metadata={
        "help": "particles carrying the follower force: all, tip, or 1-based indices like 1,3,7"})
    contact: bool = field(default=False, metadata={
        "help": "self-contact: the links' capsules collide with non-adjacent links of the same chain"})
    contact_radius: float = field(default=0.1, metadata={
        "help": "radius of each link's capsule, in l (with --contact; the capsule is 0.7 l long)"})
    contact_friction: float = field(default=0.0, metadata={
        "help": "friction coefficient between capsules (with --contact; 0: frictionless)"})
    trap: float = field(default=0.1, metadata={
        "help": "stiffness k l^2 / C1 of the dish's harmonic trap -k r on every particle and the head"})

    def __post_init__(self) -> None:
        try:
            scene = registry.get(self.scene)
        except registry.UnknownScene:
            raise ParameterError(f"scene must be one of {', '.join(registry.names())}; got {self.scene!r}") from None
        if isinstance(self.n, bool) or not isinstance(self.n, int) and not (
            isinstance(self.n, float) and self.n.is_integer()
        ):
            raise ParameterError(f"n (number of particles N) must be an integer, got {self.n!r}")
        object.__setattr__(self, "n", int(self.n))
        if self.n < 1:
            raise ParameterError(f"n (number of particles N) must be >= 1, got {self.n}")
        if self.n > 1000:
            raise ParameterError(f"n (number of particles N) must be <= 1000, got {self.n}")
        if not isinstance(self.contact, (bool, np.bool_)):
            raise ParameterError(f"contact must be true or false, got {self.contact!r}")
        object.__setattr__(self, "contact", bool(self.contact))
        for name in ("sigma", "delta", "kappa", "rho", "drag_ratio", "noise", "noise_correlation", "contact_radius",
                     "contact_friction", "trap"):
            object.__setattr__(self, name, _finite(name, getattr(self, name)))
        if self.sigma < 0:
            raise ParameterError(f"sigma (elasto-active number) must be >= 0, got {self.sigma}")
        if not 0 <= self.delta < 1:
            raise ParameterError(f"delta (compression) must lie in [0, 1), got {self.delta}")
        if self.kappa < 0:
            raise ParameterError(f"kappa (coupling stiffness) must be >= 0, got {self.kappa}")
        if self.rho <= 0:
            raise ParameterError(f"rho (stiffness ratio C2/C1) must be > 0, got {self.rho}")
        if self.drag_ratio <= 0:
            raise ParameterError(f"drag_ratio (gamma_L/gamma_T) must be > 0, got {self.drag_ratio}")
        if self.noise < 0:
            raise ParameterError(f"noise (amplitude a) must be >= 0, got {self.noise}")
        if self.noise_correlation < 0:
            raise ParameterError(f"noise_correlation (tau_c, 0: white) must be >= 0, got {self.noise_correlation}")
        if self.noise_calculus not in NOISE_CALCULI:
            raise ParameterError(f"noise_calculus must be one of {', '.join(NOISE_CALCULI)}, got {self.noise_calculus!r}")
        if not 0 < self.contact_radius < CONTACT_LENGTH / 2:
            raise ParameterError(f"contact_radius (capsule radius, in l) must lie in (0, {CONTACT_LENGTH / 2:g}) (the "
                                 f"capsule is {CONTACT_LENGTH:g} l long), got {self.contact_radius}")
        if self.contact_friction < 0:
            raise ParameterError(f"contact_friction (friction coefficient) must be >= 0, got {self.contact_friction}")
        if self.trap < 0:
            raise ParameterError(f"trap (trap stiffness k l^2 / C1) must be >= 0, got {self.trap}")
        object.__setattr__(self, "loaded", _loaded(self.loaded, self.n))
        scene.check(self)

    def load_mask(self) -> np.ndarray:
        """Boolean mask of the particles of one chain that carry the follower force (all True for "all")."""
        return _load_mask(self.loaded, self.n)

    @property
    def all_loaded(self) -> bool:
        return self.loaded == "all"

    @property
    def scene_def(self):
        """The registered Scene object this physics belongs to (elastoactive.scenes)."""
        return registry.get(self.scene)

    @property
    def n_chains(self) -> int:
        return self.scene_def.n_chains

    @property
    def n_angles(self) -> int:
        return self.n * self.n_chains

    @property
    def stiffness(self) -> tuple[float, ...]:
        """Joint stiffness C of each chain in units of C1."""
        return self.scene_def.stiffness(self)

    @property
    def clamped(self) -> bool:
        """Whether the first pendulum has a spring against the clamp."""
        return self.scene_def.clamped

    def relevant(self) -> dict:
        """The parameters this scene uses (the others are ignored and not reported); the noise's correlation time
        and calculus only when noise > 0 (so that noise-free summaries are what they were before they existed)."""
        return {k: getattr(self, k) for k in self.scene_def.relevant(self)}


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


@dataclass(frozen=True)
class Numerics:
    """Numerical settings of a MuJoCo run (times in units of tau).

    dt           timestep
    mass_ratio   particle mass m / (gamma tau): the inertial time in units of tau
    integrator   MuJoCo integrator
    perturbation largest angle (rad) of the seeded initial push away from the base state
    sample_dt    spacing of the recorded trajectory

    Automatic numerics for long chains: when dt, mass_ratio and integrator are all left at their defaults
    (`automatic`), a MuJoCo run of a chain of LONG_CHAIN particles or more uses `for_physics(physics)`
    instead: explicit drag (Euler) with a matched particle mass, several times cheaper per step than
    implicitfast's dense drag derivatives (long_chain_numerics). Shorter chains, and any run where one of the
    three is given, use the values as they are (a given value always wins, even one equal to the default).
    """

    dt: float = field(default=DEFAULT_DT, metadata={"help": "MuJoCo timestep in tau"})
    mass_ratio: float = field(default=DEFAULT_MASS_RATIO, metadata={
        "help": "particle mass m / (gamma tau); the overdamped limit is 0"})
    integrator: str = field(default=DEFAULT_INTEGRATOR, metadata={"help": "MuJoCo integrator", "choices": INTEGRATORS})
    perturbation: float = field(default=1e-2, metadata={"help": "size of the random initial kick, rad"})
    sample_dt: float = field(default=0.05, metadata={"help": "spacing of the recorded trajectory, tau"})
    seed: int = field(default=0, metadata={"help": "seed of the initial perturbation and the noise"})

    def __post_init__(self) -> None:
        for name in ("dt", "mass_ratio", "perturbation", "sample_dt"):
            if not isinstance(getattr(self, name), _Unset):  # a default stays marked as one (automatic)
                object.__setattr__(self, name, _finite(name, getattr(self, name)))
        if not 0 < self.dt <= 0.1:
            raise ParameterError(f"dt (timestep, in tau) must lie in (0, 0.1], got {self.dt}")
        if not 1e-7 <= self.mass_ratio <= MAX_MASS_RATIO:
            raise ParameterError(
                f"mass_ratio (m / gamma tau) must lie in [1e-7, {MAX_MASS_RATIO:g}], got {self.mass_ratio} (above "
                "the overdamped limit both engines model the inertial chain: elastoactive.diagnose.regime)"
            )
        if self.integrator not in INTEGRATORS:
            raise ParameterError(f"integrator must be one of {', '.join(INTEGRATORS)}, got {self.integrator!r}")
        if self.perturbation < 0:
            raise ParameterError(f"perturbation must be >= 0, got {self.perturbation}")
        if self.sample_dt < self.dt:
            raise ParameterError(f"sample_dt ({self.sample_dt}) must be >= dt ({self.dt})")
        ratio = self.sample_dt / self.dt
        if abs(ratio - round(ratio)) > 1e-6 * ratio:
            raise ParameterError(
                f"sample_dt ({self.sample_dt}) must be a whole multiple of dt ({self.dt}), e.g. "
                f"{round(ratio) * self.dt:.6g}, so that both engines record at the same times"
            )
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ParameterError(f"seed must be a non-negative integer, got {self.seed!r}")

    @property
    def steps_per_sample(self) -> int:
        return max(1, int(round(self.sample_dt / self.dt)))

    @property
    def automatic(self) -> bool:
        """Whether dt, mass_ratio and integrator were all left at their defaults: the MuJoCo engine may then
        choose them for the physics (for_physics)."""
        return all(isinstance(getattr(self, name), _Unset) for name in ("dt", "mass_ratio", "integrator"))

    def for_physics(self, physics) -> "Numerics":
        """The numerics a MuJoCo run of `physics` uses: these, or, when they are `automatic` and the chain has
        LONG_CHAIN particles or more, long_chain_numerics(physics, self) if that is expected to be cheaper."""
        if not self.automatic or physics.n < LONG_CHAIN:
            return self
        return long_chain_numerics(physics, self)

    def sample_times(self, duration: float) -> np.ndarray:
        """Recording times k * sample_dt, k = 0 .. floor(duration / sample_dt): the same grid for
        both engines (sample_dt is a whole number of MuJoCo steps)."""
        duration = _finite("duration", duration)
        if duration < 0:
            raise ParameterError(f"duration (in tau) must be >= 0, got {duration}")
        spacing = self.steps_per_sample * self.dt
        count = math.floor(duration / spacing + 1e-9) + 1
        if count > MAX_SAMPLES:
            raise ParameterError(
                f"duration ({duration:g} tau) at sample_dt = {spacing:g} would record {count:.3g} samples "
                f"(limit {MAX_SAMPLES:.0e}); shorten --duration or raise --sample-dt")
        return spacing * np.arange(count)

    def check_duration(self, duration: float) -> float:
        """A run length the engines can record and measure: at least MIN_SAMPLES samples."""
        duration = _finite("duration", duration)
        if duration <= 0:
            raise ParameterError(f"duration (in tau) must be > 0, got {duration:g}")
        count = self.sample_times(duration).size
        if count < MIN_SAMPLES:
            raise ParameterError(
                f"duration ({duration:g} tau) holds {count} sample(s) at sample_dt = {self.sample_dt:g}; at least "
                f"{MIN_SAMPLES} are needed to measure a run: lengthen --duration (>= "
                f"{(MIN_SAMPLES - 1) * self.steps_per_sample * self.dt:.4g} tau) or lower --sample-dt")
        return duration

    @classmethod
    def preset(cls, name: str, **overrides) -> "Numerics":
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
LONG_CHAIN_MASS = 2e-3
"""Largest particle mass ratio long_chain_numerics picks."""
LONG_CHAIN_RESOLUTION = 0.55
"""long_chain_numerics keeps mass_ratio x rate^2 <= this (rate: the fastest overdamped rate at the base state).
Calibrated on one-pinned, sigma 0.05, 20 tau, against the reduced model (largest angle error relative to the largest
angle; it grows about linearly with the mass): 0.02% at N = 30 and 0.3% at N = 100 (mass 2e-3, rate 14.5),
0.8% at N = 200 (rate 22.9: mass 1.05e-3) (docs/performance.md, tests/test_long_chains.py)."""
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
    """Fastest overdamped rate at the scene's base state (analysis.reduced.overdamped_rate, numpy), cached."""
    rate = _RATES.get(physics)
    if rate is None:
        from .analysis.reduced.regime import overdamped_rate  # start-up time: only long chains need their rates

        system = physics.scene_def.reduced_system(physics)
        theta = np.asarray(physics.scene_def.initial_angles(physics, Numerics(perturbation=0.0)), dtype=float)
        rate = _RATES[physics] = float(overdamped_rate(system, theta))
        if len(_RATES) > 1024:
            _RATES.pop(next(iter(_RATES)))
    return rate


def long_chain_numerics(physics, numerics: Numerics | None = None) -> Numerics:
    """Explicit drag with a matched mass for a long chain: integrator Euler, mass_ratio
    m = min(LONG_CHAIN_MASS, LONG_CHAIN_RESOLUTION / rate^2) and dt = LONG_CHAIN_DT_PER_MASS x m / max(1, drag_ratio)
    rounded down to a whole fraction of sample_dt (the other settings of `numerics` kept). m x rate stays below
    0.1 (the overdamped limit, analysis.reduced.regime): the run models the paper's overdamped chain, as the
    defaults do. Returns `numerics` unchanged when the smaller dt would cost more steps than Euler's cheaper step
    makes up for (LONG_CHAIN_STEP_COST)."""
    numerics = Numerics() if numerics is None else numerics
    rate = _fastest_rate(physics)
    m = LONG_CHAIN_MASS if rate <= 0 else min(LONG_CHAIN_MASS, LONG_CHAIN_RESOLUTION / rate**2)
    m = max(m, 1e-7)
    target = LONG_CHAIN_DT_PER_MASS * m / max(1.0, float(physics.drag_ratio))
    dt = numerics.sample_dt / max(1, math.ceil(numerics.sample_dt / target - 1e-9))
    c, p = LONG_CHAIN_STEP_COST
    if dt * c * (physics.n / LONG_CHAIN) ** p < numerics.dt:
        return numerics
    return dataclasses.replace(numerics, integrator="Euler", dt=dt, mass_ratio=m)


def parameter_fields(cls) -> tuple[dataclasses.Field, ...]:
    """The fields of Physics (less `scene`) or Numerics that a user sets, with their help text."""
    return tuple(f for f in dataclasses.fields(cls) if "help" in f.metadata)


def replace(obj, **changes):
    """dataclasses.replace that re-validates."""
    return dataclasses.replace(obj, **changes)

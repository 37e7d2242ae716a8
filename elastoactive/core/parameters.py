"""Parameter specs: each physical parameter's name, default, kind, range and help, written once.

A `Parameter` is declared by whatever owns it: the chain itself (n), a physical term (sigma and loaded by the
follower force, drag_ratio by the drag, the noise's three, self-contact's three: elastoactive.terms), or a scene
(delta by two-pinned, kappa and rho by coupled-pair, trap by paraboloid). Its owner registers it here; the rest of
the package asks this table:

  Physics            checks every value by its spec (`Parameter.check`: one rule, one message naming it) and
                     refuses a value given where it does not act (a scene without it, or a switch that is off:
                     `Parameter.needs`)
  the CLI            one option per spec (elastoactive.cli.options), its help and choices from here
  sweeps             which names can be swept, and each coordinate's long name and units in the netCDF

A parameter's help and units are written in the chain's symbols (l, tau); a scene of other units reads them in its
own (`help_in`, `units_in`: elastoactive.core.units), with the spec's `worded` help where the chain's words do not fit.

A leaf module: it imports nothing of the package but its errors and elastoactive.core.units.
"""

from __future__ import annotations

import math
import numbers
import sys
from dataclasses import dataclass
from typing import Any

from .constants import MAX_PARTICLES
from .errors import ParameterError
from .table import Registry
from .units import CHAIN, Units, Worded, worded

KINDS = (float, int, bool, str)


@dataclass(frozen=True)
class Parameter:
    """One physical parameter.

    name        the keyword (Physics(name=...)), the CLI option (--name with '-' for '_'), the sweep coordinate
    default     its value when not given
    help        one line for the CLI's help and the netCDF coordinate's long name
    kind        float, int, bool or str
    low, high   the range (None: unbounded); low_open / high_open exclude the bound
    choices     the allowed values of a str parameter
    title       what it is, in messages: "n (number of particles N) must be ..."
    symbol      short symbol for captions and labels (e.g. "δ"); default the name
    units       units of the value for the netCDF ("1": dimensionless, "tau", "l")
    needs       name of a switch parameter that must be on (True or > 0) for this one to act: a value given while
                it is off is refused (contact_radius needs contact, noise_correlation needs noise)
    needs_value with `needs`: the choice the (str) switch must have instead (alignment_length needs
                active = self-aligning)
    or_needs, or_needs_value
                another way for it to act: the (str) parameter `or_needs` has the choice `or_needs_value`
                (clamp_frequency acts with clamp_amplitude > 0, or with clamp_motion = rotating, which needs no
                amplitude)
    unless      name of a switch that, when on, leaves this one unused even where `needs` is met (noise_calculus
                reads white noise only: it does nothing while noise_correlation > 0 makes the noise coloured)
    unless_why  with `unless`: what the switch being on means, in messages ("coloured noise")
    quiet_default  reported in summaries only when it differs from its default (contact, loaded, and any
                parameter a plug-in term adds, so that runs without it record what they recorded before it existed)
    worded      its help in a scene of other units, where the chain's words do not fit (units.Worded: sigma is
                'F_a / (k a)' on a network)
    instead_of  the parameter it is given in place of (the coupling Pi in place of sigma): Physics turns it into that
                one by the scene (Scene.coupling) and records that one; it has no default of its own (`default` is
                None) and is given only to the scenes that have it
    stochastic  a value > 0 makes a run stochastic: the reduced engine then steps it at numerics.dt with the draws of
                numerics.seed, so both act (the chain's noise, a network's diffusions; `stochastic`, Physics.stochastic)
    """

    name: str
    default: Any
    help: str
    kind: type = float
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple[str, ...] | None = None
    title: str = ""
    symbol: str = ""
    units: str = "1"
    needs: str | None = None
    needs_value: str | None = None
    or_needs: str | None = None
    or_needs_value: str | None = None
    unless: str | None = None
    unless_why: str = ""
    quiet_default: bool = False
    worded: tuple[Worded, ...] = ()
    instead_of: str | None = None
    stochastic: bool = False

    def __post_init__(self) -> None:
        if not self.name.isidentifier():
            raise ValueError(f"a parameter's name must be an identifier, got {self.name!r}")
        if self.kind not in KINDS:
            raise ValueError(f"parameter {self.name}: kind must be one of float, int, bool, str, got {self.kind!r}")
        if self.needs_value is not None and self.needs is None:
            raise ValueError(f"parameter {self.name}: needs_value without needs")
        if (self.or_needs is None) != (self.or_needs_value is None) or (self.or_needs and self.needs is None):
            raise ValueError(f"parameter {self.name}: or_needs and or_needs_value go together, with needs")
        if self.unless is not None and self.needs is None:
            raise ValueError(f"parameter {self.name}: unless without needs")
        if self.instead_of is not None:
            if self.default is not None or self.needs is not None:
                raise ValueError(f"parameter {self.name}: given instead of {self.instead_of}, it has no default")
            return
        self.check(self.default)

    @property
    def label(self) -> str:
        """How messages name it: 'delta (compression)'."""
        return f"{self.name} ({self.title})" if self.title else self.name

    def help_in(self, units: Units = CHAIN) -> str:
        """Its help in a scene of units `units`: the `worded` one for them, else the help in their symbols."""
        return worded(self.help, self.worded, units)

    def units_in(self, units: Units = CHAIN) -> str:
        """Its units in a scene of units `units` (Units.of)."""
        return units.of(self.units)

    @property
    def option(self) -> str:
        """The command-line option: --contact-radius."""
        return "--" + self.name.replace("_", "-")

    @property
    def metadata(self) -> dict:
        """The help and choices as dataclass field metadata reads (the CLI and sweeps read Numerics' fields so)."""
        return {"help": self.help, "choices": self.choices}

    def range_text(self) -> str:
        """The allowed range, e.g. '[0, 1)' or '>= 0'."""
        if self.low is not None and self.high is not None:
            return f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}{')' if self.high_open else ']'}"
        if self.low is not None:
            return f"{'>' if self.low_open else '>='} {self.low:g}"
        if self.high is not None:
            return f"{'<' if self.high_open else '<='} {self.high:g}"
        return "any finite number"

    def check(self, value) -> Any:
        """The value as its kind (a numpy integer or float is its Python number), checked against the range and
        choices; a ParameterError naming the parameter otherwise."""
        if self.kind is bool:
            if _is_bool(value):
                return bool(value)
            raise ParameterError(f"{self.label} must be true or false, got {value!r}")
        if self.kind is str:
            if not isinstance(value, str):
                raise ParameterError(f"{self.label} must be a string, got {value!r}")
            if self.choices is not None and value not in self.choices:
                raise ParameterError(f"{self.name} must be one of {', '.join(self.choices)}, got {value!r}")
            return value
        if _is_bool(value):
            raise ParameterError(f"{self.label} must be a number, got {value!r}")
        if self.kind is int:
            if isinstance(value, numbers.Integral):
                value = int(value)
            elif isinstance(value, numbers.Real) and float(value).is_integer():
                value = int(value)
            else:
                raise ParameterError(f"{self.label} must be an integer, got {value!r}")
        else:
            value = finite(self.name, value)
        low_bad = self.low is not None and (value <= self.low if self.low_open else value < self.low)
        high_bad = self.high is not None and (value >= self.high if self.high_open else value > self.high)
        if low_bad or high_bad:
            if self.low is not None and self.high is not None:
                raise ParameterError(f"{self.label} must lie in {self.range_text()}, got {value}")
            raise ParameterError(f"{self.label} must be {self.range_text()}, got {value}")
        return value

    def is_on(self, value) -> bool:
        """Whether a switch is on (for `needs`): True, or a number > 0."""
        return bool(value) if self.kind is bool else (value > 0 if self.kind in (int, float) else bool(value))

    def need_met(self, switch_value) -> bool:
        """Whether this parameter acts when its switch (`needs`) has `switch_value`: the switch is on, or has the
        choice `needs_value`. True for a parameter without a switch."""
        if self.needs is None:
            return True
        if self.needs_value is not None:
            return switch_value == self.needs_value
        return get(self.needs).is_on(switch_value)

    def acts_in(self, values) -> bool:
        """Whether this parameter acts among `values` (a mapping holding its switches): need_met by `needs`, or the
        alternative `or_needs` has the choice `or_needs_value`."""
        if self.needs is None:
            return True
        if self.unless is not None and self.unless in values and get(self.unless).is_on(values[self.unless]):
            return False
        if self.or_needs is not None and values.get(self.or_needs) == self.or_needs_value:
            return True
        return self.need_met(values[self.needs])

    def unused_text(self, values) -> str:
        """Why this parameter does not act among `values` (acts_in is False), and what to do, in one clause:
        'has no effect without contact (contact = False); set contact too, or leave contact_radius out'."""
        if self.unless is not None and self.unless in values and get(self.unless).is_on(values[self.unless]):
            why = f" ({self.unless_why})" if self.unless_why else ""
            off = get(self.unless).default
            off = f"{off:g}" if isinstance(off, float) else off
            return (
                f"{self.name} has no effect with {self.unless} = {values[self.unless]}{why}; set {self.unless} = "
                f"{off} too, or leave {self.name} out"
            )
        return (
            f"{self.name} has no effect without {self.need_text} ({self.needs} = {values[self.needs]}); set "
            f"{self.needs} too, or leave {self.name} out"
        )

    @property
    def need_text(self) -> str:
        """What this parameter needs, in messages: 'contact', 'active = self-aligning'."""
        text = self.needs if self.needs_value is None else f"{self.needs} = {self.needs_value}"
        return text if self.or_needs is None else f"{text} or {self.or_needs} = {self.or_needs_value}"


def finite(name: str, value) -> float:
    """`value` as a finite float; a ParameterError naming `name` if it is not a number, or not finite."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(value):
        raise ParameterError(f"{name} must be finite, got {value}")
    return value


def _is_bool(value) -> bool:
    """Whether `value` is a truth value, Python's or numpy's (a value can be numpy's only once numpy is loaded: the
    records do not load it themselves)."""
    numpy = sys.modules.get("numpy")
    return isinstance(value, bool) or (numpy is not None and isinstance(value, numpy.bool_))


_TABLE: Registry[Parameter] = Registry("parameter", replaceable=False, built_ins=True)
"""Every declared parameter spec with who declared it (elastoactive.core.table.Registry)."""


def register(spec: Parameter, owner: str) -> Parameter:
    """Add a spec to the table under its name; `owner` names who declares it (a term or a scene). Registering the
    same spec again is a no-op; another spec under a taken name is refused."""
    return _TABLE.register(spec, owner=owner)


def unregister(name: str) -> None:
    """Remove a spec (tests that add a plug-in term clean up with this)."""
    _TABLE.unregister(name)


def get(name: str) -> Parameter:
    """The spec called `name` (elastoactive.core.table.UnknownName, a KeyError, if none)."""
    return _TABLE.get(name)


def owner(name: str) -> str:
    """Who declared the parameter `name`."""
    return _TABLE.owner(name)


def known(name: str) -> bool:
    return _TABLE.known(name)


def names() -> tuple[str, ...]:
    """Every declared parameter, in declaration order."""
    return _TABLE.names()


def stochastic_names() -> tuple[str, ...]:
    """The parameters declared `stochastic`: a value > 0 of any makes a run stochastic."""
    return tuple(name for name in names() if get(name).stochastic)


def stochastic(values, axes=None) -> bool:
    """Whether a run, or some point of a sweep, is stochastic: a parameter declared `stochastic` is > 0 among `axes`
    (a grid: name -> its values) or, where it is not on the axes, in `values` (name -> value, or a Physics; a name
    not given takes its default). The one rule for every check of whether dt and the seed act on the reduced
    engine."""
    axes = axes or {}
    for name in stochastic_names():
        if name in axes:
            value = axes[name]
        else:
            value = values.get(name) if hasattr(values, "get") else getattr(values, name, None)
            value = get(name).default if value is None else value
        points = value if hasattr(value, "__iter__") and not isinstance(value, str) else (value,)
        if any(point is not None and float(point) > 0 for point in points):
            return True
    return False


# The chain's own parameter and the coupling, declared with the table: whatever registers next (a term, a scene,
# imported in any order), every scene has the chain, and they lead the table.
N = register(
    Parameter("n", 7, "particles per chain N", kind=int, low=1, high=MAX_PARTICLES, title="number of particles N"),
    "the chain",
)
"""The one parameter of the chain itself; every other belongs to a term (elastoactive.terms) or a scene."""
COUPLING = register(
    Parameter(
        "Pi",
        None,
        "elasto-active coupling Pi = l_e / l_a (l_e = F_a / k), given instead of sigma: the scene turns it into "
        "sigma (lattice, network: sigma = Pi l_a; trapped-unit: sigma = Pi k_t l_a) and records sigma",
        low=0.0,
        title="elasto-active coupling",
        symbol="Π",
        instead_of="sigma",
    ),
    "the coupling",
)
"""The coupling Pi of the scenes that have one (Scene.coupling: the network scenes), given in place of sigma."""

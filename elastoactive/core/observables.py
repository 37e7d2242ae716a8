"""Observable specs: what each reported number means, written once by whatever measures it.

An `Observable` is declared by what measures it: the beat observables every scene reports (amplitude, frequency,
period_spread, harmonics: here, `BEAT`), a scene (Scene.observables: the two-pinned chain's snap_amplitude, the
dish's orbit_rate, ...) or a physical term (Term.observables: self-contact's contact_fraction, ...). The scene and
term registries register a plug-in's specs here as they register its parameters; the rest of the package asks this
table through `get` and `find`:

  summary.json       the results a run records (results.Results.as_dict)
  validate           how two engines' values of it are compared (`error`, `floor`)
  the pre-flight     the fewest particles a chain needs to measure it (`min_n`: results.check_measurable)
  sweeps             each variable's units and long name in the netCDF, per chain or not, a category's index

A scene reports each observable in its own units (`described`: a network's frequency in k/gamma, its amplitude in a,
not the chain's 1/tau and rad): specs write their units in the chain's symbols, and `worded` long names where a scene
of other units calls the quantity something else (elastoactive.core.units).

A leaf module: it imports nothing of the package but elastoactive.core.units. (The functions that compute observables
from a trajectory are elastoactive.analysis.)
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, replace

from .table import load_built_ins
from .units import CHAIN, THETA, Signal, Units, Worded, worded

ERRORS = ("relative", "absolute", "none")
"""How validate compares two values of an observable (Observable.error)."""


@dataclass(frozen=True)
class Observable:
    """One observable a run reports.

    name        its key in Results (Results.value, Results.extra), summary.json's results, the sweep's variable
    units       units of the value ("1": dimensionless, "rad", "1/tau", "l", ...), the netCDF variable's units
    long_name   what it is, in one line: the netCDF variable's long_name
    per_chain   one value per chain for a scene with several chains (the coupled pair, the star's arms)
    error       how validate compares two values: "relative" (absolute below `floor`), "absolute", or "none" (not
                compared)
    floor       with error = "relative": the magnitude below which the difference is compared absolutely
    categories  a categorical observable's values (text; a sweep stores their index, and names them in the netCDF)
    min_n       the fewest particles per chain for which it is defined (a shorter chain is refused before a run)
    worded      its long name in a scene of other units, where the chain's words do not fit (units.Worded: the
                trapped unit's orbit_radius is its node's, not 'the N particles' centre of mass')
    """

    name: str
    units: str
    long_name: str
    per_chain: bool = False
    error: str = "relative"
    floor: float = 1e-3
    categories: tuple[str, ...] = ()
    min_n: int = 1
    worded: tuple[Worded, ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise ValueError(f"an observable's name must be an identifier, got {self.name!r}")
        if self.error not in ERRORS:
            raise ValueError(f"observable {self.name}: error must be one of {', '.join(ERRORS)}, got {self.error!r}")


HARMONICS = 5
"""Harmonics of Theta every run reports (Results.harmonics)."""


def beat_specs(signal: Signal) -> tuple[Observable, ...]:
    """The beat observables (amplitude, frequency, period_spread, harmonics) of a scene whose beat is measured on
    `signal` (Scene.beat_signal): their units and long names about that signal."""
    return (
        Observable("amplitude", signal.units, f"amplitude of {signal.text} (half peak-to-peak)", per_chain=True),
        Observable("frequency", "1/tau", f"oscillation frequency of {signal.symbol}", per_chain=True),
        Observable(
            "period_spread",
            "1",
            f"std / mean of the cycle periods of {signal.symbol} (NaN with fewer than 2 cycles)",
            per_chain=True,
            error="none",
        ),
        Observable(
            "harmonics",
            "1",
            f"amplitudes of harmonics 1-{HARMONICS} of {signal.symbol} relative to the fundamental (NaN without a "
            "periodic beat)",
            per_chain=True,
            error="none",
        ),
    )


BEAT = beat_specs(THETA)
"""The beat observables every scene reports (results.measure), whatever its own."""

_TABLE: dict[str, tuple[Observable, str]] = {}
"""Every declared observable spec with who declared it; read through `_read` (declaring is no read)."""


def _read() -> dict[str, tuple[Observable, str]]:
    """The table, once the package's own terms and scenes have declared theirs (elastoactive.core.table)."""
    load_built_ins()
    return _TABLE


def described(spec: Observable, units: Units = CHAIN, signal: Signal = THETA) -> Observable:
    """`spec` as a scene of units `units` whose beat is measured on `signal` reports it: a beat observable's (BEAT)
    units and long name about that signal (beat_specs), the others' units in the scene's symbols (Units.of) and
    their long name in its words (Observable.worded, else Units.words)."""
    if spec in BEAT:
        spec = beat_specs(signal)[BEAT.index(spec)]
    return replace(spec, units=units.of(spec.units), long_name=worded(spec.long_name, spec.worded, units))


def register(spec: Observable, owner: str) -> Observable:
    """Add a spec under its name; `owner` names who declares it (a scene or a term). Registering the same spec again
    is a no-op; another spec under a taken name is refused."""
    if not isinstance(spec, Observable):
        raise ValueError(
            f"{owner}: an observable is declared as an Observable (elastoactive.core.observables), got {spec!r}"
        )
    known = _TABLE.get(spec.name)
    if known is not None and known[0] != spec:
        raise ValueError(f"an observable named {spec.name!r} is already declared by {known[1]}")
    _TABLE[spec.name] = (spec, known[1] if known else owner)
    return spec


def unregister(name: str, owner: str | None = None) -> None:
    """Remove a spec (only if `owner` declared it, when given): a plug-in scene or term that leaves takes its own."""
    table = _read()
    if name in table and (owner is None or table[name][1] == owner) and table[name][1] != "every run":
        del table[name]


def get(name: str) -> Observable:
    """The spec called `name` (KeyError if nothing declares it)."""
    return _read()[name][0]


def spec_or_default(name: str) -> Observable:
    """The spec called `name`, or for a value nothing declares the spec it is treated by: no units, no long name,
    compared relatively by validate (Observable's defaults)."""
    known = _read().get(name)
    return Observable(name, "", "") if known is None else known[0]


def find(name: str) -> Observable | None:
    """The spec called `name`, or None if nothing declares it (an undeclared value a plug-in measures)."""
    known = _read().get(name)
    return None if known is None else known[0]


def owner(name: str) -> str:
    """Who declared the observable `name`."""
    return _read()[name][1]


def known(name: str) -> bool:
    return name in _read()


def names() -> tuple[str, ...]:
    """Every declared observable, in declaration order."""
    return tuple(_read())


def declare(declared: Iterable[Observable | str], owner: str) -> tuple[str, ...]:
    """Register the specs in `declared` (a scene's or a term's `observables`: specs it declares, or names) for
    `owner`; returns their names. A name is a spec declared elsewhere (the ring names the rotating pin's
    rotation_rate), or a value nothing declares (a plug-in written before specs): it is reported as measured, in
    summary.json and as a sweep variable without units or long name, and validate compares it relatively
    (`spec_or_default`).
    A spec under a name another spec holds is refused before any is registered."""
    declared = tuple(declared)
    specs = {item.name: item for item in declared if not isinstance(item, str)}
    for item in declared:
        if not isinstance(item, (str, Observable)):
            raise ValueError(
                f"{owner}: an observable is an elastoactive.core.observables.Observable or a name, got {item!r}"
            )
        known = _TABLE.get(getattr(item, "name", None))
        if isinstance(item, Observable) and known is not None and known[0] != item:
            raise ValueError(f"an observable named {item.name!r} is already declared by {known[1]}")
    for spec in specs.values():
        register(spec, owner)
    return names_of(declared)


def withdraw(declared: Iterable[Observable | str], owner: str) -> None:
    """Remove the specs `owner` declared among `declared` (the reverse of `declare`)."""
    for item in declared:
        if isinstance(item, Observable):
            unregister(item.name, owner)


def names_of(declared: Iterable[Observable | str]) -> tuple[str, ...]:
    """The names in a scene's or a term's `observables` (specs or names)."""
    return tuple(item if isinstance(item, str) else item.name for item in declared)


for _spec in BEAT:
    register(_spec, "every run")

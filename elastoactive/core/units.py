"""Each scene's units: what its numbers are measured in, and the words its labels use.

Every scene declares its `Units` (Scene.units): a chain scene the paper's (CHAIN: l = C1 = gamma = 1, times in
tau = gamma l^2 / C1, sigma = F_a l / C1), a network scene the active solid's (NETWORK: k = gamma = a = 1, times in
gamma / k, sigma = F_a / (k a)). The specs that scenes and terms declare (parameters.Parameter,
observables.Observable) write their units in the chain's symbols ("l", "tau", "rad/tau", "1/tau"), and, where a
scene of other units calls the quantity something else, its words there (`Worded`); `Units.of` and `Units.words`
put a units string and a free text in a scene's own symbols. A scene's beat (amplitude, frequency, ...) is measured
on its `Signal` (Scene.beat_signal): Theta = theta_N - theta_1 (rad) on a chain, a length or a rate on a network.

Everything a user reads about a scene (the CLI's help for it, summary.json's units, a sweep's netCDF attributes,
Trajectory.to_xarray, ea.plot's labels) goes through here, so that a network never speaks the chain's language
(tests/test_scene_units.py holds every registered scene and term to it).

A leaf module: it imports nothing of the package.
"""

from __future__ import annotations

import re
from dataclasses import dataclass


@dataclass(frozen=True)
class Units:
    """A system of units: its symbols, and how a units string or a text written in the chain's symbols reads in it.

    name        the system's key ("chain", "spring network"; not a scene's name): Worded entries name it
    length      the length unit ("l": the link length; "a": the springs' rest length)
    time        the time unit as a fraction (numerator factors, denominator factors): (("tau",), ()) or
                (("gamma",), ("k",))
    basis       what is set to 1, in one line
    time_text   what the time unit is
    sigma       what sigma, the elasto-active number, is in these units
    symbols     the quantities only this system's labels name (a scene of other units must not name them)
    """

    name: str
    length: str
    time: tuple[tuple[str, ...], tuple[str, ...]]
    basis: str
    time_text: str
    sigma: str
    symbols: tuple[str, ...]

    @property
    def time_units(self) -> str:
        """The time unit as a units string: 'tau', 'gamma/k'."""
        return self.of("tau")

    @property
    def rate_units(self) -> str:
        """A frequency's or a rate's units: '1/tau', 'k/gamma'."""
        return self.of("1/tau")

    @property
    def text(self) -> str:
        """The units in one sentence (the CLI's help, summary.json, the netCDF's `units` attribute)."""
        return (
            f"Units: {self.basis}, so times are in {self.time_text}, frequencies in {self.rate_units} and "
            f"sigma = {self.sigma}."
        )

    def of(self, units: str) -> str:
        """`units` (written in the chain's symbols: 'l', 'rad/tau', '1/tau', 'a/tau', 'l^2') in this system's:
        the length symbol l becomes this system's length, tau its time unit (on either side of the '/'). A units
        string with more than one '/' or none of these symbols is returned as it is."""
        if self.name == CHAIN_NAME or not units or units.count("/") > 1:
            return units
        top, _, bottom = units.partition("/")
        numerator, denominator = [], []
        for factors, same, other in ((top.split(), numerator, denominator), (bottom.split(), denominator, numerator)):
            for factor in factors:
                base, caret, power = factor.partition("^")
                if base == "tau":
                    same.extend(f + caret + power for f in self.time[0])
                    other.extend(f + caret + power for f in self.time[1])
                elif base == "l":
                    same.append(self.length + caret + power)
                elif base != "1":
                    same.append(factor)
        if not numerator and not denominator:
            return "1"
        text = " ".join(numerator) or "1"
        if denominator:
            text += "/" + (denominator[0] if len(denominator) == 1 else f"({' '.join(denominator)})")
        return text

    def words(self, text: str) -> str:
        """A free text written in the chain's symbols (a help line: 'MuJoCo timestep in tau') in this system's: each
        units string with a '/' and tau ('rad/tau') rewritten by `of`, then each other tau."""
        if self.name == CHAIN_NAME:
            return text
        text = re.sub(r"(?<![\w^/])[\w^]+/tau(?![\w^])", lambda m: self.of(m.group(0)), text)
        return re.sub(r"(?<![\w^/])tau(?![\w^])", self.time_units, text)


@dataclass(frozen=True)
class Worded:
    """What a spec (a parameter's help, an observable's long name) says in a scene of the units `units` (a
    Units.name), where the chain's words do not fit: sigma is 'F_a / (k a)' on a network, not 'F_a l / C1'."""

    units: str
    text: str


def worded(default: str, entries: tuple[Worded, ...], units: Units) -> str:
    """The text of `entries` for `units` (Worded.units), else `default` put in its symbols (Units.words)."""
    for entry in entries:
        if entry.units == units.name:
            return entry.text
    return units.words(default)


@dataclass(frozen=True)
class Signal:
    """What a scene's beat is measured on (Scene.beat_signal): the amplitude, frequency, period spread and harmonics
    of every run are those of this scalar.

    symbol  its name in labels: 'Theta', 'x'
    text    what it is, in one line: 'Theta = theta_N - theta_1'
    units   its units, in the chain's symbols as specs write them ('rad', 'a', 'rad/tau'); Units.of puts them in a
            scene's
    """

    symbol: str
    text: str
    units: str


CHAIN_NAME = "chain"
CHAIN = Units(
    name=CHAIN_NAME,
    length="l",
    time=(("tau",), ()),
    basis="l = C1 = gamma = 1 (link length l, joint stiffness C1, transverse drag gamma)",
    time_text="tau = gamma l^2 / C1",
    sigma="F_a l / C1",
    symbols=("l", "C1", "tau", "Theta", "theta_N", "theta_1", "N"),
)
"""The paper's units, every chain scene's."""
NETWORK = Units(
    name="spring network",
    length="a",
    time=(("gamma",), ("k",)),
    basis="k = gamma = a = 1 (bond stiffness k, drag gamma, lattice spacing a)",
    time_text="gamma/k",
    sigma="F_a / (k a)",
    symbols=("gamma/k", "k/gamma", "k a", "l_e", "Pi"),
)
"""The active solid's units, every network scene's (docs/network.md)."""
SYSTEMS = (CHAIN, NETWORK)
"""The systems of units the package knows (a plug-in scene may declare its own)."""

THETA = Signal("Theta", "Theta = theta_N - theta_1", "rad")
"""A chain's beat signal: the angle between its last and first links."""


def scene_units(scene) -> Units:
    """The units a scene declares (Scene.units: a chain scene's CHAIN, a network scene's NETWORK)."""
    return scene.units


def beat_signal(physics) -> Signal:
    """What a physics' beat is measured on (Scene.beat_signal(physics): a chain's Theta, a network's own signal)."""
    return physics.scene_def.beat_signal(physics)

"""What a user reads about a scene, in the scene's own units: its parameters' help, its numerical settings' help, its
observables' units and long names, the units record of its summary.json.

The one place that puts the specs (elastoactive.parameters, elastoactive.observables, Numerics' fields) in a scene's
units (elastoactive.units: Scene.units, Scene.beat_signal); the CLI's help for a scene, summary.json, a sweep's
netCDF attributes, Trajectory.to_xarray and ea.plot's labels all read it, so that a network scene never speaks the
chain's language (tests/test_scene_units.py holds every registered scene and term to it).
"""

from __future__ import annotations

from dataclasses import Field

from . import observables
from .observables import Observable
from .parameters import Parameter
from .parameters import get as parameter_spec
from .params import Physics, has_coupling
from .registry import get as scene_named
from .units import Signal, Units, beat_signal, scene_units, worded

__all__ = [
    "Signal",
    "Units",
    "beat_signal",
    "coupling_text",
    "field_help",
    "observable",
    "parameter_help",
    "scene_units",
    "summary_units",
    "units_of",
]


def units_of(scene: str) -> Units:
    """The units of the scene called `scene`."""
    return scene_units(scene_named(scene))


def parameter_help(spec: Parameter, scene: str) -> str:
    """A physics parameter's help on `scene`, in its units (Parameter.help_in)."""
    return spec.help_in(units_of(scene))


def field_help(field: Field, units: Units) -> str:
    """A numerical setting's help (a Numerics field's metadata) in `units`: its `worded` entry for them, else its help
    in their symbols."""
    return worded(field.metadata["help"], field.metadata.get("worded", ()), units)


def observable(name: str, physics: Physics) -> Observable:
    """The observable `name` as `physics` reports it: units and long name in its scene's units, a beat observable's
    about its beat signal (observables.described); a value nothing declares, without units or long name."""
    return observables.described(
        observables.spec_or_default(name), scene_units(physics.scene_def), beat_signal(physics)
    )


def coupling_text(physics: Physics) -> str:
    """'Pi = σ / l_a = 1.5' for a scene that has the coupling Pi (Scene.coupling), else ''."""
    definition = physics.scene_def
    if not has_coupling(definition):
        return ""
    return f"Pi = {definition.coupling_formula} = {definition.coupling(physics):.6g}"


def summary_units(physics: Physics, results: dict) -> dict:
    """summary.json's `units`: the scene's system of units in words, its beat signal, the units of each parameter
    it records and each result that has some (a dimensionless one is left out), and the coupling Pi of a scene that
    has one (its value and formula: Pi is given in place of sigma, which the parameters record)."""
    units = scene_units(physics.scene_def)
    signal = beat_signal(physics)
    parameters = {name: parameter_spec(name).units_in(units) for name in physics.relevant() if name != "scene"}
    measured = {name: observable(name, physics).units for name in results if observables.known(name)}
    out = {
        "system": units.name,
        "text": units.text,
        "length": units.length,
        "time": units.time_units,
        "sigma": units.sigma,
        "beat_signal": f"{signal.text} ({units.of(signal.units)})",
        "parameters": {k: v for k, v in parameters.items() if v not in ("", "1")},
        "results": {k: v for k, v in measured.items() if v not in ("", "1")},
    }
    if has_coupling(physics.scene_def):
        out["coupling"] = {"Pi": physics.Pi, "formula": f"Pi = {physics.scene_def.coupling_formula}"}
    return out

"""What a user reads about a scene's specs, in the scene's own units: its numerical settings' help, its observables'
units and long names (a beat observable's about the scene's beat signal), the units record of its summary.json.

Where the specs (elastoactive.core.observables, Numerics' fields) meet a scene's units (elastoactive.core.units:
Scene.units, Scene.beat_signal; a parameter's own: Parameter.help_in, units_in). The CLI's help for a scene,
summary.json and a sweep's netCDF attributes read it; ea.plot's labels and Trajectory.to_xarray read the scene's units
directly. So a network scene never speaks the chain's language (tests/test_scene_units.py holds every registered scene
and term to it)."""

from __future__ import annotations

from dataclasses import Field

from .core import observables
from .core.observables import Observable
from .core.parameters import get as parameter_spec
from .core.params import Physics, has_coupling
from .core.units import Units, beat_signal, scene_units, worded

__all__ = ["field_help", "observable", "summary_units"]


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

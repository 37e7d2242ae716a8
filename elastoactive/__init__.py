"""elastoactive: elasto-active chains in MuJoCo, checked against the reduced overdamped model.

Reproduces Zheng et al., "Self-oscillation and synchronisation transitions in elasto-active
structures" (PRL 2023, arXiv 2106.05721) in the paper's dimensionless numbers (units l = C1 =
gamma = 1, so times are in tau = gamma l^2 / C1 and frequencies are f tau).

    import elastoactive as ea

    traj = ea.simulate(ea.Physics(n=7, sigma=0.8), duration=600)   # one pinned end (the default scene)
    res = ea.measure(traj)
    res.amplitude, res.frequency          # the paper's flagellar beat
    traj.positions(), traj.tip()          # every particle's (x, y), the tips
    ea.plot.limit_cycle(traj)             # Theta against dTheta/dt
    ea.load("out/run"), ea.load("sweep.nc")   # a run's Trajectory, a sweep's xarray Dataset
    ea.scenes.names()                     # the registered scenes

Front door
----------
Physics, Numerics        parameters of a run (elastoactive.core.params; help(ea.Physics) lists every parameter)
simulate, measure        run a scene in either engine; measure the result (elastoactive.api)
save, load, load_sweep   a run's folder written and read back, a sweep's netCDF read (elastoactive.api)
sweep, ramp              a grid of runs, a ramp up and down, as labelled xarray Datasets (elastoactive.explore)
stability, Stability     the linear stability of a scene's base state, without simulating (elastoactive.explore)
Trajectory, Results      what they return
plot                     figures of a run or a sweep on matplotlib Axes (elastoactive.plot, imported when used)
scenes, terms            the scene and term registries (elastoactive.scenes, elastoactive.terms)
ParameterError, SimulationDiverged
"""

import importlib
from typing import TYPE_CHECKING

from . import _moved
from .core.errors import ParameterError, SimulationDiverged
from .core.table import entry_points_ready

_moved.install()  # old module paths keep working for one release
entry_points_ready()  # the entry points' scenes, terms and studies load when a registry is first listed

if TYPE_CHECKING:  # what the lazy names are, for type checkers and the API reference (read without importing)
    from . import scenes, terms
    from .api import load, load_sweep, measure, save, simulate
    from .core.params import Numerics, Physics
    from .core.trajectory import Trajectory
    from .results import Results

_LAZY = {
    "Physics": "core.physics_doc",
    "Numerics": "core.params",
    "Trajectory": "core.trajectory",
    "simulate": "api",
    "measure": "api",
    "load": "api",
    "load_sweep": "api",
    "save": "api",
    "ramp": "explore",
    "stability": "explore",
    "Stability": "explore",
    "Results": "results",
}
"""Names of the front door imported when first used, and their modules: the records load numpy, running and measuring
the engines and the outputs' writers, which the command line's --help does not need. The registries load the
package's own scenes and terms when first read (elastoactive.core.table.load_built_ins)."""


def __getattr__(name: str):
    """The front door's running names (`ea.simulate`, ...), `ea.plot` (matplotlib) and any sub-module (`ea.results`,
    `ea.sweep`), each imported when first used."""
    if name in _LAZY:
        module = importlib.import_module(f".{_LAZY[name]}", __name__)
        value = getattr(module, name)
        if name == "Physics":
            module.document_physics()  # help(ea.Physics): every registered parameter, with units
        globals()[name] = value
        return value
    if name.startswith("_"):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    try:
        return importlib.import_module(f".{name}", __name__)
    except ModuleNotFoundError as err:
        if err.name != f"{__name__}.{name}":
            raise
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None


def __dir__() -> list[str]:
    """The front door's names and the sub-modules already imported (not the module's own helpers)."""
    public = {name for name in globals() if not name.startswith("_")} - {"TYPE_CHECKING", "importlib"}
    return sorted(public | set(_LAZY) | {"plot"})


__all__ = [
    "Numerics",
    "ParameterError",
    "Physics",
    "Results",
    "SimulationDiverged",
    "Stability",
    "Trajectory",
    "load",
    "load_sweep",
    "measure",
    "plot",
    "ramp",
    "save",
    "scenes",
    "simulate",
    "stability",
    "sweep",
    "terms",
]

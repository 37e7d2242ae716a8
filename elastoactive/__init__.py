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
load, load_sweep         a run or a sweep written by the command line (elastoactive.api)
Trajectory, Results      what they return
plot                     figures of a run or a sweep on matplotlib Axes (elastoactive.plot, imported when used)
scenes, terms            the scene and term registries (elastoactive.scenes, elastoactive.terms)
ParameterError, SimulationDiverged
"""

import importlib

from . import _moved, scenes, terms  # scenes first: registers the built-in scenes that Physics looks up
from .api import document_physics, load, load_sweep, measure, simulate
from .core import registry
from .core.errors import ParameterError, SimulationDiverged
from .core.params import Numerics, Physics
from .core.trajectory import Trajectory
from .results import Results

_moved.install()  # old module paths keep working for one release
registry.entry_points_ready()  # the entry points' scenes, terms and studies load when a registry is first listed
document_physics()  # help(ea.Physics): every registered parameter, with units


def __getattr__(name: str):
    """`ea.plot`, imported when first used (it loads matplotlib)."""
    if name == "plot":
        return importlib.import_module(".plot", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "Numerics",
    "ParameterError",
    "Physics",
    "Results",
    "SimulationDiverged",
    "Trajectory",
    "load",
    "load_sweep",
    "measure",
    "plot",
    "scenes",
    "simulate",
    "terms",
]

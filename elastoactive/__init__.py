"""elastoactive: elasto-active chains in MuJoCo, checked against the reduced overdamped model.

Reproduces Zheng et al., "Self-oscillation and synchronisation transitions in elasto-active
structures" (PRL 2023, arXiv 2106.05721) in the paper's dimensionless numbers (units l = C1 =
gamma = 1, so times are in tau = gamma l^2 / C1 and frequencies are f tau).

    import elastoactive as ea

    traj = ea.simulate(ea.Physics(n=7, sigma=0.8), duration=600)   # one pinned end (the default scene)
    res = ea.measure(traj)
    res.amplitude, res.frequency          # the paper's flagellar beat
    ea.scenes.names()                     # the registered scenes

Front door
----------
Physics, Numerics        parameters of a run (elastoactive.params)
simulate, measure        run a scene in either engine; measure the result (elastoactive.api)
Trajectory, Results      what they return
scenes                   the scene registry (elastoactive.scenes)
ParameterError, SimulationDiverged
"""

from . import _moved, registry, scenes  # scenes first: registers the built-in scenes that Physics looks up
from .api import measure, simulate
from .errors import ParameterError, SimulationDiverged
from .params import Numerics, Physics
from .results import Results
from .trajectory import Trajectory

_moved.install()  # old module paths keep working for one release
registry.entry_points_ready()  # the entry points' scenes, terms and studies load when a registry is first listed

__all__ = [
    "Numerics",
    "ParameterError",
    "Physics",
    "Results",
    "SimulationDiverged",
    "Trajectory",
    "measure",
    "scenes",
    "simulate",
]

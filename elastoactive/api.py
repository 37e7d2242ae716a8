"""The front door's two verbs: simulate a scene, measure a trajectory."""

from __future__ import annotations

import sys

from .engines import check_engine, run_engine
from .params import Numerics, Physics
from .results import Results
from .results import measure as _measure
from .trajectory import Trajectory

LONG_CHAIN = 60
"""Angles from which the pre-flight check takes long enough (a second or more) to announce itself."""


def simulate(
    physics: Physics,
    numerics: Numerics | None = None,
    *,
    duration: float,
    engine: str = "mujoco",
    check: bool = True,
    progress: bool = False,
    theta0=None,
) -> Trajectory:
    """Simulate a scene.

    Parameters
    ----------
    physics : Physics
        The scene (``scene=``, a name from ``ea.scenes.names()``) and its dimensionless parameters.
    numerics : Numerics, optional
        Timestep, particle mass ratio, integrator, seed, sampling interval; default ``Numerics()``
        (every validate error below 1%).
    duration : float
        Simulated time in units of tau = gamma l^2 / C1.
    engine : {"mujoco", "reduced"}
        MuJoCo (the scene's MJCF model with the compiled follower-force callback) or the reduced
        overdamped pendulum ODE.
    check : bool
        Before a MuJoCo run, refuse settings beyond the integrator's stability limit or known to be
        inaccurate (``diagnose.check_timestep``). Pass False only to provoke a divergence on purpose.
    progress : bool
        Show a progress bar (MuJoCo engine).
    theta0 : array_like, optional
        Initial absolute angles (chain 1 then chain 2); default: the scene's seeded initial state.

    Returns
    -------
    Trajectory
        Sample times ``t`` (tau) and absolute angles ``theta`` (one column per particle), the engine's
        wall time and solver information.

    Raises
    ------
    ParameterError
        An invalid or refused parameter; the message names it.
    SimulationDiverged
        A MuJoCo run whose state blew up or left its pin; the message names the likely cause.
    """
    numerics = Numerics() if numerics is None else numerics
    duration = numerics.check_duration(duration)
    options = {"theta0": theta0}
    if check_engine(engine) == "mujoco":
        if check:
            from .diagnose import check_timestep  # start-up time: diagnose builds MuJoCo models

            if progress and physics.n_angles >= LONG_CHAIN:  # the check linearises the model: seconds at N ~ 200
                print(f"elastoactive: checking dt against the stability limits of the N = {physics.n} model...",
                      file=sys.stderr, flush=True)
            check_timestep(physics, numerics)
        options["progress"] = progress
    return run_engine(engine, physics, numerics, duration, **options)


def measure(trajectory: Trajectory, transient: float | None = None) -> Results:
    """Measure a trajectory after its transient.

    Parameters
    ----------
    trajectory : Trajectory
        From ``simulate`` (either engine) or ``results.load_trajectory``.
    transient : float, optional
        Time (tau) discarded before measuring; default: half the run.

    Returns
    -------
    Results
        ``amplitude`` (half the peak-to-peak of Theta = theta_N - theta_1, rad) and ``frequency``
        (f tau of Theta), one per chain for the coupled pair, plus the scene's own observables
        (``snap_amplitude``, ``rotation_rate``, ``frequency_mismatch``; None where not reported).
        ``.as_dict()`` gives them as summary.json writes them.
    """
    return _measure(trajectory, transient)

"""The front door's two verbs: simulate a scene, measure a trajectory.

Arguments are taken in their obvious forms (a scene name or a dict of fields for the physics, a preset name or a
dict of settings for the numerics); anything else is a TypeError naming the argument, a bad value a ParameterError
naming the parameter.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .engines import run_engine
from .errors import ParameterError
from .gate import preflight
from .params import Numerics, Physics, parameter_fields
from .results import Results, check_measurable, check_transient
from .results import measure as _measure
from .trajectory import Trajectory


def _field_names(cls) -> tuple[str, ...]:
    """The keyword arguments a Physics (scene and its parameters) or a Numerics takes."""
    names = tuple(f.name for f in parameter_fields(cls))
    return ("scene", *names) if cls is Physics else names


def _record(cls, value, argument: str, name_kind: str, from_name):
    """value as a `cls` record: the record itself, a name (from_name(name)) or a dict of its fields."""
    if isinstance(value, cls):
        return value
    if isinstance(value, str):
        return from_name(value)
    if isinstance(value, Mapping):
        known = _field_names(cls)
        unknown = [k for k in value if not isinstance(k, str) or k not in known]
        if unknown:
            raise TypeError(
                f"{argument}: {unknown[0]!r} is not a field of ea.{cls.__name__} (fields: {', '.join(known)})"
            )
        return cls(**value)
    raise TypeError(
        f"{argument} must be an ea.{cls.__name__}, {name_kind} or a dict of its fields; got {type(value).__name__}"
    )


def as_physics(physics) -> Physics:
    """An ea.Physics from a Physics, a scene name (the scene with its default parameters) or a dict of fields."""
    return _record(Physics, physics, "physics", "a scene name", lambda name: Physics(scene=name))


def as_numerics(numerics) -> Numerics:
    """An ea.Numerics from None (the defaults), a Numerics, a preset name ("fast") or a dict of settings."""
    if numerics is None:
        return Numerics()
    return _record(Numerics, numerics, "numerics", "a preset name", Numerics.preset)


def simulate(
    physics: Physics | str | Mapping,
    numerics: Numerics | str | Mapping | None = None,
    *,
    duration: float,
    engine: str = "mujoco",
    check: bool = True,
    progress: bool = False,
    theta0=None,
    method: str | None = None,
) -> Trajectory:
    """Simulate a scene.

    Parameters
    ----------
    physics : Physics, str or dict
        The scene (``scene=``, a name from ``ea.scenes.names()``) and its dimensionless parameters; a scene name
        alone means its default parameters, a dict gives Physics' fields.
    numerics : Numerics, str or dict, optional
        Timestep, particle mass ratio, integrator, seed, sampling interval; default ``Numerics()``
        (every validate error below 1%); a preset name ("accurate", "fast") or a dict of Numerics' fields.
    duration : float
        Simulated time in units of tau = gamma l^2 / C1.
    engine : {"mujoco", "reduced"}
        MuJoCo (the scene's MJCF model with the compiled follower-force callback) or the reduced
        overdamped pendulum ODE.
    check : bool
        Before a MuJoCo run, refuse settings beyond the integrator's stability limit or known to be
        inaccurate (``engines.timestep.check_timestep``). Pass False only to provoke a divergence on purpose; every
        other check of the pre-flight gate (``gate.preflight``) runs either way.
    progress : bool
        Show a progress bar (MuJoCo engine).
    theta0 : array_like, optional
        Initial absolute angles (chain 1 then chain 2); default: the scene's seeded initial state.
    method : str, optional
        Reduced engine only: the ODE method ("numba-DOP853", "LSODA", "Radau", ...); default: chosen from the
        stiffness of the linearisation at the start (trajectory.info["method"] says which ran).

    Returns
    -------
    Trajectory
        Sample times ``t`` (tau) and absolute angles ``theta`` (one column per particle), the engine's
        wall time and solver information.

    Raises
    ------
    TypeError
        An argument of the wrong kind; the message names it.
    ParameterError
        An invalid or refused parameter, or a scene whose observables the chain is too short to measure (checked
        before simulating); the message names it.
    SimulationDiverged
        A MuJoCo run whose state blew up or left its pin; the message names the likely cause.
    """
    physics, numerics = as_physics(physics), as_numerics(numerics)
    run = preflight(physics, numerics, duration, engine, method=method, timestep=check, announce=progress)
    options = {"theta0": theta0}
    if run.engine == "mujoco":
        options["progress"] = progress
    elif method is not None:  # the reduced engine's ODE method (None: its automatic choice)
        options["method"] = method
    return run_engine(run.engine, run.physics, run.numerics, run.duration, **options)


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

    Raises
    ------
    TypeError
        ``trajectory`` is not a Trajectory.
    ParameterError
        A transient outside the record, or one that leaves too few samples to measure.
    """
    if not isinstance(trajectory, Trajectory):
        raise TypeError(
            f"trajectory must be an ea.Trajectory (from ea.simulate or elastoactive.results.load_trajectory); "
            f"got {type(trajectory).__name__}"
        )
    check_measurable(trajectory.physics)
    t = np.asarray(trajectory.t, dtype=float)
    if transient is not None:
        try:
            transient = float(transient)
        except (TypeError, ValueError):
            raise ParameterError(f"transient must be a time in tau, got {transient!r}") from None
    check_transient(float(t[-1] - t[0]) if t.size else 0.0, transient, t - t[0] if t.size else t)
    return _measure(trajectory, transient)

"""The front door's verbs: simulate a scene, measure a trajectory, load a run or a sweep from disk.

Arguments are taken in their obvious forms (a scene name or a dict of fields for the physics, a preset name or a
dict of settings for the numerics); anything else is a TypeError naming the argument, a bad value a ParameterError
naming the parameter. Physics' docstring and signature are generated here from the parameter table (every scene's
and term's parameters, with units), so that ``help(ea.Physics)`` and an editor show what is registered.

xarray is imported inside load_sweep, the sweep reader's boundary: it loads pandas (about half a second), which
`import elastoactive` does not pay.
"""

from __future__ import annotations

import warnings
import weakref
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from . import plugins
from .core.errors import ParameterError
from .core.params import Numerics, Physics, parameter_fields
from .core.trajectory import Trajectory
from .engines import run_engine
from .gate import preflight
from .io.outputs import check_folder, check_space, folder_lock
from .records import RecordWarning, load_trajectory, read_summary
from .results import Results, check_measurable, check_transient
from .results import measure as _measure
from .saving import RunSettings, check_destination, trajectory_bytes, write_folder
from .starts import Start, as_start, finite_angles


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
    start=None,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
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
    start : Trajectory, path, NetworkState, (positions, polarity) or array_like, optional
        The state to start from instead of the scene's: a trajectory's last sample, a saved run's (its folder), a
        network's node positions and unit polarities, or a chain's angles (``elastoactive.starts``); checked against
        the scene: a run of another scene (or of another shape: N, chains, nodes), a state of the wrong kind or size,
        or one off the scene's pin is refused in one line naming ``start`` and both scenes. Not with ``theta0``.
    method : str, optional
        Reduced engine only: the ODE method ("numba-DOP853", "LSODA", "Radau", ...); default: chosen from the
        stiffness of the linearisation at the start (trajectory.info["method"] says which ran).
    rtol, atol : float, optional
        Reduced engine only: the adaptive solver's relative and absolute tolerances (atol default rtol / 100); default
        the scene kind's (a chain's 1e-9, a network's 1e-9 up to ~750 free nodes, 1e-6 above:
        ``Scene.reduced_tolerances``; trajectory.info["rtol"] and ["atol"] say which ran).

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
    start_path = str(Path(start).expanduser().resolve()) if isinstance(start, (str, Path)) else None
    start = None if start is None else as_start(start).checked(physics)  # before the gate: it may take seconds
    run = preflight(physics, numerics, duration, engine, method=method, timestep=check, announce=progress)
    for name, value in (("rtol", rtol), ("atol", atol)):
        if value is not None and (run.engine != "reduced" or not 0 < value < 1):
            raise ParameterError(
                f"{name} = {value:g}: the adaptive solver's tolerances apply to engine='reduced', in (0, 1)"
            )
    if atol is not None and rtol is None:
        raise ParameterError("atol: give rtol with it (the scene's automatic tolerances come as a pair)")
    options = {"theta0": None if theta0 is None else finite_angles(theta0, "theta0")}
    if start is not None:
        if theta0 is not None:
            raise ParameterError("start: give start or theta0, not both")
        options = start.engine_options()
    elif theta0 is not None:  # the angles it started from: a start state, as the record keeps one
        start = Start(theta=options["theta0"], source="theta0")
    options["progress"] = progress  # MuJoCo's steps, or the reduced engine's time where its solver is slow
    if run.engine == "reduced" and method is not None:  # the reduced engine's ODE method (None: its automatic choice)
        options["method"] = method
    if rtol is not None:
        options.update(rtol=rtol, atol=rtol / 100 if atol is None else atol)
    trajectory = run_engine(run.engine, run.physics, run.numerics, run.duration, **options)
    _remember(trajectory, RunSettings(run.numerics, run.duration, start, start_path))
    return trajectory


_RUNS: dict[int, tuple[weakref.ref, RunSettings]] = {}
"""How each live trajectory `simulate` returned was run (by id, with a reference that tells a reused id apart): what
`save` records of it."""


def _remember(trajectory: Trajectory, settings: RunSettings) -> None:
    key = id(trajectory)
    _RUNS[key] = (weakref.ref(trajectory), settings)
    weakref.finalize(trajectory, _RUNS.pop, key, None)


def run_settings(trajectory: Trajectory) -> RunSettings | None:
    """How `trajectory` was run: as `simulate` ran it, or as the summary of the run it was loaded from records it
    (None for a trajectory made otherwise)."""
    ref, settings = _RUNS.get(id(trajectory), (None, None))
    if ref is not None and ref() is trajectory:
        return settings
    recorded = trajectory.info.get("summary") if isinstance(trajectory.info, Mapping) else None
    numerics = (recorded or {}).get("numerics")
    if not isinstance(numerics, Mapping) or numerics.get("duration") is None:
        return None
    settings = {k: v for k, v in numerics.items() if k not in ("duration", "transient")}
    return RunSettings(Numerics(**settings), float(numerics["duration"]))


def measure(trajectory: Trajectory, transient: float | None = None) -> Results:
    """Measure a trajectory after its transient.

    Parameters
    ----------
    trajectory : Trajectory
        From ``simulate`` (either engine) or ``records.load_trajectory``.
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
            f"trajectory must be an ea.Trajectory (from ea.simulate or elastoactive.records.load_trajectory); "
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


def save(
    trajectory: Trajectory,
    path,
    numerics: Numerics | str | Mapping | None = None,
    *,
    duration: float | None = None,
    transient: float | None = None,
    force: bool = False,
) -> Path:
    """Write a run's folder, as ``elastoactive run --out`` does: ``summary.json`` (settings, results, units, solver,
    provenance, the run's inputs and the checksums that tie it to its trajectory) and ``trajectory.npz``, with copies
    of the inputs it read (its network file, plug-in files, start state). ``load``, ``run --from`` and ``render`` read
    it.

    Parameters
    ----------
    trajectory : Trajectory
        From ``simulate`` (its numerics, duration and start are known) or ``load`` (its summary's).
    path : str or pathlib.Path
        The run's folder, created if need be; a folder holding a run with other settings is refused unless ``force``.
    numerics : Numerics, str or dict, optional
        The numerics it ran with; needed only for a trajectory that neither ``simulate`` nor ``load`` made.
    duration : float, optional
        Its simulated time, likewise (default: as run).
    transient : float, optional
        Time discarded before measuring; default: half the run.
    force : bool
        Replace a run with other settings already in ``path``.

    Returns
    -------
    pathlib.Path
        The run's folder. Where measuring failed, summary.json records why (``measure_error``), the trajectory is
        kept, and a RecordWarning says so.

    Raises
    ------
    TypeError
        ``trajectory`` is not a Trajectory, or ``path`` not a path.
    ParameterError
        Unknown numerics, a folder that cannot be written or holds another run, a transient outside the run.
    OSError
        A file could not be written (a full disk): the message names it.
    """
    if not isinstance(trajectory, Trajectory):
        raise TypeError(
            f"trajectory must be an ea.Trajectory (from ea.simulate or ea.load); got {type(trajectory).__name__}"
        )
    if not isinstance(path, (str, Path)):
        raise TypeError(f"path must be a str or a pathlib.Path, got {type(path).__name__}")
    settings = run_settings(trajectory)
    if numerics is not None or duration is not None or settings is None:
        if settings is None and (numerics is None or duration is None):
            raise ParameterError(
                "numerics, duration: give the Numerics and duration this trajectory was run with (it comes from "
                "neither ea.simulate nor ea.load)"
            )
        numerics = as_numerics(numerics) if numerics is not None else settings.numerics
        duration = float(duration) if duration is not None else settings.duration
        settings = RunSettings(numerics, duration, *(() if settings is None else (settings.start, settings.start_path)))
    physics = trajectory.physics
    transient = check_transient(settings.duration, transient, np.asarray(trajectory.t) - trajectory.t[0])
    out = check_folder(Path(path).expanduser(), "path")
    with folder_lock(out, "path"):
        check_destination(
            out, physics, settings.numerics, trajectory.engine, settings.duration, transient, force, "path"
        )
        check_space(out, trajectory_bytes(physics, trajectory.t.size), "trajectory.npz", "path")
        written = write_folder(out, trajectory, settings, transient)
    if written.write_error is not None:
        raise written.write_error
    if written.measure_error is not None:
        warnings.warn(
            f"measuring the run failed ({written.measure_error}); {out / 'summary.json'} records the error and "
            f"{out / 'trajectory.npz'} keeps the trajectory",
            RecordWarning,
            stacklevel=2,
        )
    return out


RUN_FILES = ("summary.json", "trajectory.npz")
"""What a run's folder (`elastoactive run --out`) holds."""
SWEEP_SUFFIX = ".nc"
"""The suffix of a sweep's netCDF file (`elastoactive sweep --out`)."""


def load(path):
    """Load a run or a sweep written by the command line.

    Parameters
    ----------
    path : str or pathlib.Path
        A run's folder (``elastoactive run --out``), its ``summary.json`` or its ``trajectory.npz``; or a sweep's
        netCDF file (``.nc``, as `load_sweep`). The plug-ins the run's summary records are loaded first.

    Returns
    -------
    Trajectory or xarray.Dataset
        A run's Trajectory (its summary.json in ``info["summary"]``); a sweep's Dataset.

    Raises
    ------
    ParameterError
        A path that is none of these, or files that are not what the run wrote (checksums); the message names it.
    """
    path = _path(path)
    if path.suffix == SWEEP_SUFFIX:
        return load_sweep(path)
    folder = path if path.is_dir() else path.parent
    if path.is_file() and path.name not in RUN_FILES:
        raise ParameterError(
            f"path: {path} is neither a run (its folder, summary.json or trajectory.npz) nor a sweep (.nc)"
        )
    if not (folder / "summary.json").is_file():
        raise ParameterError(
            f"path: {folder} holds no summary.json (give a folder written by `elastoactive run --out`)"
        )
    for spec in plugins.recorded(folder):
        plugins.load(spec)
    trajectory = load_trajectory(folder / "trajectory.npz")
    trajectory.info.setdefault("summary", read_summary(folder))
    return trajectory


def load_sweep(path):
    """Open a sweep's netCDF file as an xarray Dataset, read into memory (the file is closed again).

    Parameters
    ----------
    path : str or pathlib.Path
        A netCDF file written by ``elastoactive sweep --out`` or ``elastoactive.sweep.run_sweep``.

    Returns
    -------
    xarray.Dataset
        One coordinate per swept parameter and one variable per observable, each with ``units`` and ``long_name``
        attributes; points not run or failed are NaN.

    Raises
    ------
    ParameterError
        A file that is not there or not a netCDF file; the message names it.
    """
    import xarray as xr  # start-up time: xarray loads pandas

    path = _path(path)
    if not path.is_file():
        raise ParameterError(f"path: {path} not found (give a sweep's netCDF file)")
    try:
        with xr.open_dataset(path) as dataset:
            return dataset.load()
    except (OSError, ValueError) as err:
        raise ParameterError(f"path: {path} is not a readable netCDF file ({err})") from None


def _path(path) -> Path:
    if not isinstance(path, (str, Path)):
        raise TypeError(f"path must be a str or a pathlib.Path, got {type(path).__name__}")
    path = Path(path).expanduser()
    if not path.exists():
        raise ParameterError(f"path: {path} not found")
    return path

"""The sweep's verb: a scene at every point of a parameter grid, measured, as the command `elastoactive sweep` runs it
and `ea.sweep(...)` (this package, called) returns it: the labelled xarray Dataset of its netCDF file.

The runners (elastoactive.sweep's run_sweep, run_sweep_outcome) are imported inside `sweep_outcome` and MuJoCo inside
`_import_mujoco_headless`, the engines' boundary: the command line imports this module to build its parser. The front
door's conversions (elastoactive.api: a scene name or a dict into a Physics, a preset name or a dict into a Numerics)
are imported only for an argument that is not already the record, since the front door loads the single run's
records, saving and starts, which a sweep given its records (the command line) does not need.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping
from pathlib import Path

from ..core.errors import ParameterError
from ..core.parameters import get as parameter_spec
from ..core.parameters import known, stochastic
from ..core.params import PRESETS, Numerics, Physics, option
from ..io.outputs import check_file

DEFAULT_DURATION = 300.0
"""Simulated time of each point of a sweep and each step of a ramp, when not given (the commands' default)."""
DEFAULT_PRESET = "accurate"
"""A sweep's numerical settings when not given (Numerics.preset)."""


def _sweep_settings(physics, grid: Mapping, numerics, engine: str) -> tuple[str, dict, dict, Numerics]:
    """(scene, the fixed physics, the grid as arrays, the numerics) of a sweep, refused in one line where the same
    parameter is both fixed by name and on the grid."""
    from . import MUJOCO_ONLY, check_engine_numerics, normalize_grid  # the package's names, once it is loaded

    if not isinstance(grid, Mapping):
        raise TypeError(f"grid must be a dict of parameter name -> values, got {type(grid).__name__}")
    axes = normalize_grid(grid)
    if isinstance(physics, Mapping):  # fields named by the caller: one on the grid too is a contradiction
        fixed = {k: v for k, v in physics.items() if k != "scene"}
        both = [k for k in axes if k in fixed]
        if both:
            raise ParameterError(f"{', '.join(option(k) for k in both)} given both fixed and on the grid")
    if not isinstance(physics, Physics):
        from ..api import as_physics  # the front door's conversion (module docstring)

        physics = as_physics(physics)
    replaced = (set(axes) | {parameter_spec(k).instead_of for k in axes if known(k)}) - {None}
    fixed = {
        k: v
        for k, v in physics.relevant().items()
        if k != "scene" and k not in replaced and not (known(k) and parameter_spec(k).instead_of in replaced)
    }
    if numerics is None:
        numerics = Numerics.preset(DEFAULT_PRESET)
    elif isinstance(numerics, str) and numerics in PRESETS:
        numerics = Numerics.preset(numerics)
    else:
        if isinstance(numerics, Mapping):  # settings named by the caller: refused where they change nothing
            both = [k for k in axes if k in numerics]
            if both:
                raise ParameterError(f"{', '.join(option(k) for k in both)} given both fixed and on the grid")
            noisy = stochastic(physics, axes)
            check_engine_numerics(engine, [k for k in numerics if k in MUJOCO_ONLY], noisy)
        if not isinstance(numerics, Numerics):
            from ..api import as_numerics  # the front door's conversion (module docstring)

            numerics = as_numerics(numerics)
    return physics.scene, fixed, axes, numerics


def sweep_outcome(
    physics,
    grid: Mapping,
    numerics=None,
    *,
    duration: float = DEFAULT_DURATION,
    engine: str = "mujoco",
    transient: float | None = None,
    out=None,
    workers: int | None = None,
    scheduler=None,
    batch_size: int | None = None,
    retry_errors: bool = False,
    check: bool = True,
    progress: bool = False,
    dataset: bool = True,
):
    """`sweep` (same arguments); with dataset=False its outcome without the Dataset (the points' status and error
    texts: sweep.SweepOutcome, what the command reports, without loading xarray).

    Returns
    -------
    xarray.Dataset or elastoactive.sweep.SweepOutcome
        As `sweep`, or the outcome.
    """
    from . import run_sweep, run_sweep_outcome  # the runners: the engines' boundary (module docstring)

    scene, fixed, axes, numerics = _sweep_settings(physics, grid, numerics, engine)
    if out is not None:
        out = check_file(Path(out).expanduser(), option("out"), ())  # a writable place, not under a file
    if engine == "mujoco":
        _import_mujoco_headless()
    run = run_sweep if dataset else run_sweep_outcome
    return run(
        scene,
        axes,
        fixed=fixed,
        numerics=numerics,
        duration=duration,
        engine=engine,
        transient=transient,
        out=out,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
        retry_errors=retry_errors,
        timestep_check=check,
        batch_size=batch_size,
    )


def sweep(
    physics,
    grid: Mapping,
    numerics=None,
    *,
    duration: float = DEFAULT_DURATION,
    engine: str = "mujoco",
    transient: float | None = None,
    out=None,
    workers: int | None = None,
    scheduler=None,
    batch_size: int | None = None,
    retry_errors: bool = False,
    check: bool = True,
    progress: bool = False,
):
    """Run a scene at every point of a parameter grid and measure each, as ``elastoactive sweep`` does.

    Parameters
    ----------
    physics : Physics, str or dict
        The scene and its fixed physics (off the grid): a Physics (its values off the grid are kept), a scene name
        (its defaults) or a dict of Physics' fields (one also on the grid is refused).
    grid : dict
        Parameter name -> values: a sequence, or a string as ``--grid`` takes it (``"0.2:1.0:9"``, ``"0.5,1,2"``);
        names from ``elastoactive.sweep.grid_keys()`` (physics parameters, ``seed``, ``dt``, ...). The Dataset's
        dimensions follow its order.
    numerics : Numerics, str or dict, optional
        A preset name ("accurate", the default; "fast"), a Numerics or a dict of its fields.
    duration : float
        Simulated time of each point (default 300, as the command's).
    engine : {"mujoco", "reduced"}
        The engine every point runs.
    transient : float, optional
        Time discarded before measuring; default: half of each run.
    out : str or pathlib.Path, optional
        A netCDF file written point by point; a re-run with the same arguments resumes it, with other arguments it is
        refused (elastoactive.sweep.SweepMismatch).
    workers : int, optional
        Local threads (MuJoCo: mujoco.batch) or processes (the reduced engine), >= 1; default: every core.
    scheduler : str or dask.distributed.Client, optional
        A Dask scheduler's address or a Client to run the points on (``workers`` is then unused).
    batch_size : int, optional
        Most MuJoCo points stepped together in one batch (default: 8 per thread).
    retry_errors : bool
        When resuming, run the failed points again.
    check : bool
        Refuse MuJoCo points whose timestep is beyond the integrator's limits (as ``simulate``'s ``check``); when
        every point is refused, a ParameterError names a setting that passes before any runs.
    progress : bool
        Show a progress bar.

    Returns
    -------
    xarray.Dataset
        One coordinate per grid parameter (plus ``chain`` for two chains), one variable per observable with
        ``units`` and ``long_name``, ``status`` ("ok", "error") and ``error`` per point; a failed point's
        measurements are NaN. The same Dataset ``out`` holds.

    Raises
    ------
    TypeError
        An argument of the wrong kind; the message names it.
    ParameterError
        An invalid parameter or grid, a setting refused at every point, or an ``out`` that cannot be written or holds
        another sweep; the message names it.
    """
    return sweep_outcome(
        physics,
        grid,
        numerics,
        duration=duration,
        engine=engine,
        transient=transient,
        out=out,
        workers=workers,
        scheduler=scheduler,
        batch_size=batch_size,
        retry_errors=retry_errors,
        check=check,
        progress=progress,
    )


def _import_mujoco_headless() -> None:
    """Import MuJoCo without its GL back end: a sweep renders nothing, and loading glfw costs a child Python that
    probes the library (~0.07 s, before any point can start). MUJOCO_GL is set only for the import and only if the
    user has not set it; elastoactive.render switches back ends if asked later."""
    if "mujoco" in sys.modules or os.environ.get("MUJOCO_GL"):
        return
    os.environ["MUJOCO_GL"] = "disable"
    try:
        import mujoco  # noqa: F401 (start-up time: the engine's boundary, see the docstring)
    finally:
        os.environ.pop("MUJOCO_GL", None)


# ------------------------------------------------------------------------------------------------ ramp

"""The front door's verbs over many runs, or none: a grid of runs (`sweep`), a ramp up and down (`ramp`), the linear
stability of a scene's base state (`stability`).

Each is what its command does (`elastoactive sweep`, `ramp`, `stability`), with the command's defaults and checks:
the commands parse their options and call these. A sweep and a ramp come back as the labelled xarray Dataset their
netCDF file holds (one coordinate per swept parameter, units and long names in the attributes); given `out`, that file
is written as they go and a re-run with the same arguments resumes it.

A package above the sweep's: the grid of runs is the sweep package's own verb (elastoactive.sweep.verb: the package,
called, runs it), taken here beside the ramp and the stability. The ramp's runner is imported inside `ramp_outcome`,
the engines' boundary: `import elastoactive` loads neither.
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from ..api import as_physics, load_sweep
from ..core.errors import ParameterError
from ..core.parameters import get as parameter_spec
from ..core.parameters import known
from ..core.params import Physics, option
from ..reduced.blas import one_blas_thread
from ..sweep.verb import DEFAULT_DURATION, DEFAULT_PRESET, sweep, sweep_outcome

__all__ = [
    "DEFAULT_DURATION",
    "DEFAULT_PRESET",
    "Stability",
    "ramp",
    "ramp_outcome",
    "stability",
    "sweep",
    "sweep_outcome",
]

RAMP_ENGINE = "reduced"
"""The engine a ramp runs when not told (its steps are long runs of large networks)."""


def ramp_outcome(
    physics,
    parameter: str,
    values,
    numerics=None,
    *,
    seeds: Sequence[int] = (0,),
    duration: float = DEFAULT_DURATION,
    transient: float | None = None,
    engine: str = RAMP_ENGINE,
    start=None,
    out,
    workers: int | None = None,
    progress: bool = False,
):
    """`ramp` into the netCDF file `out`, returning what it did (protocols.RampOutcome: the file, the steps run and
    kept, the steps not measured), as the command reports it.

    Returns
    -------
    elastoactive.protocols.RampOutcome
        The file written, the steps run and those its journal held, the wall time, the measuring errors.
    """
    from .. import protocols  # the ramp's boundary: its runner and process pool (module docstring)
    from ..sweep.grid import parse_values  # the sweep's boundary: the grid's value syntax

    if not isinstance(parameter, str):
        raise TypeError(f"parameter must be a parameter's name, got {type(parameter).__name__}")
    if isinstance(values, str):
        values = parse_values(parameter, values)
    values = sorted(float(v) for v in values)
    if isinstance(physics, Mapping) and parameter in physics:
        raise ParameterError(f"{option(parameter)}: {parameter} is ramped; do not fix it too")
    if isinstance(numerics, Mapping) and "seed" in numerics:
        raise ParameterError(f"{option('seed')}: a ramp's seeds are {option('seeds')}")
    if known(parameter) and parameter_spec(parameter).kind is float and values and isinstance(physics, Mapping):
        as_physics({**physics, parameter: values[0]})  # beside the fixed ones, as `simulate` checks it: Pi and sigma
    physics = as_physics(physics)
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ParameterError(f"{option('workers')} must be an integer >= 1, got {workers!r}")
    plan = protocols.make_ramp(
        physics,
        parameter,
        values,
        numerics=numerics,
        seeds=seeds,
        duration=duration,
        transient=transient,
        engine=engine,
        start=start,
    )
    return protocols.run_ramp(plan, out, workers=workers, progress=progress)


def ramp(
    physics,
    parameter: str,
    values,
    numerics=None,
    *,
    seeds: Sequence[int] = (0,),
    duration: float = DEFAULT_DURATION,
    transient: float | None = None,
    engine: str = RAMP_ENGINE,
    start=None,
    out=None,
    workers: int | None = None,
    progress: bool = False,
):
    """Ramp one parameter up and then down in steps, each step starting from the previous step's end, for several
    seeds, as ``elastoactive ramp`` does (the hysteresis loop as data).

    Parameters
    ----------
    physics : Physics, str or dict
        The scene and its fixed physics.
    parameter : str
        The real-valued physics parameter ramped (``"Pi"``, the coupling, on a network; ``"sigma"``).
    values : sequence of float or str
        Its values upward, two or more, increasing; or a string as ``--ramp`` takes it (``"0.6:0.8:5"``).
    numerics : Numerics, str or dict, optional
        Numerical settings (default ``Numerics()``); the seed is each of ``seeds``.
    seeds : sequence of int
        Seeds of each first step's initial state (default ``(0,)``).
    duration : float
        Simulated time of each step (default 300).
    transient : float, optional
        Time discarded before measuring each step; default: half.
    engine : {"reduced", "mujoco"}
        The engine (default "reduced", as the command's).
    start : Trajectory, path or state, optional
        Start every seed's first step from this state (a saved run's folder: its last state; ``elastoactive.starts``).
    out : str or pathlib.Path, optional
        The netCDF file (``.nc``), resumed from its journal by a re-run with the same arguments; default: a temporary
        file, removed once read.
    workers : int, optional
        Processes, one seed each (default: every core).
    progress : bool
        Say when each seed is done.

    Returns
    -------
    xarray.Dataset
        Dimensions seed, direction ("up", "down") and the ramped parameter; one variable per observable, ``order``
        (when each step ran) and, where a step's measuring failed, ``error``.

    Raises
    ------
    TypeError
        An argument of the wrong kind; the message names it.
    ParameterError
        An invalid parameter, values, seeds or start, or an ``out`` that holds another ramp; the message names it.
    SimulationDiverged
        A step diverged (a re-run with the same ``out`` resumes from the last finished step).
    """
    arguments = dict(
        seeds=seeds,
        duration=duration,
        transient=transient,
        engine=engine,
        start=start,
        workers=workers,
        progress=progress,
    )
    if out is not None:
        return load_sweep(ramp_outcome(physics, parameter, values, numerics, out=out, **arguments).path)
    with tempfile.TemporaryDirectory(prefix="elastoactive-ramp-") as folder:
        outcome = ramp_outcome(physics, parameter, values, numerics, out=Path(folder) / "ramp.nc", **arguments)
        return load_sweep(outcome.path)


# ------------------------------------------------------------------------------------------------ stability


@dataclass(frozen=True)
class Stability:
    """The linear stability of a scene's base state (its straight chain, a network's rest states): where it is lost
    (``sigma_c``) and how (``omega_c``, rad per time unit, 0 through a real eigenvalue; ``kind`` in words), and at a
    given ``sigma`` the least stable mode's ``growth`` rate and angular ``frequency`` (None without a sigma).
    ``str()`` gives the lines ``elastoactive stability`` prints.

    sigma_c is inf where the base state stays stable over the range searched. Where the base states form a family (a
    network's fixed points), sigma_c is where the first loses stability, ``sigma_all`` how far one found stays stable
    and ``sigma_ceiling`` above which none is (else None).
    """

    physics: Physics
    sigma_c: float
    omega_c: float
    kind: str
    sigma: float | None = None
    growth: float | None = None
    frequency: float | None = None
    sigma_all: float | None = None
    sigma_ceiling: float | None = None
    report: tuple[str, ...] = ()

    @property
    def unstable(self) -> bool | None:
        """Whether the base state is unstable at ``sigma`` (its least stable mode grows); None without a sigma."""
        return None if self.growth is None else self.growth > 0

    @property
    def f_c(self) -> float:
        """The onset's frequency omega_c / 2 pi (f tau for a chain)."""
        return self.omega_c / (2 * math.pi)

    def __str__(self) -> str:
        return "\n".join(self.report)


def with_operator() -> tuple[str, ...]:
    """The registered scenes with a linear operator about their base state (Scene.no_linear_operator empty)."""
    from ..core import registry  # the registry: its scenes load when first listed

    return tuple(s.name for s in registry.scenes() if not s.no_linear_operator)


def stability(physics, sigma: float | None = None) -> Stability:
    """The linear stability of a scene's base state, without simulating, as ``elastoactive stability`` computes it.

    Parameters
    ----------
    physics : Physics, str or dict
        The scene (one with a linear operator: ``with_operator()``) and its parameters (its own sigma aside: the
        onset is over sigma).
    sigma : float, optional
        Also the least stable mode's growth rate and frequency at this sigma.

    Returns
    -------
    Stability
        sigma_c, omega_c and kind of the onset; growth and frequency at ``sigma``; ``str()`` the command's lines.

    Raises
    ------
    TypeError
        ``physics`` of the wrong kind.
    ParameterError
        A scene without a linear operator, or an invalid parameter; the message names it.
    """
    physics = as_physics(physics)
    scene = physics.scene_def
    if scene.no_linear_operator:
        raise ParameterError(
            f"stability: {physics.scene} has no linear operator here ({scene.no_linear_operator}); "
            f"scenes: {', '.join(with_operator())}"
        )
    if sigma is not None:
        try:
            sigma = float(sigma)
        except (TypeError, ValueError):
            raise ParameterError(f"sigma must be a number, got {sigma!r}") from None
        if not math.isfinite(sigma):
            raise ParameterError(f"sigma must be finite, got {sigma}")
    with one_blas_thread():
        onset = scene.onset(physics)
        eigenvalue = None if sigma is None else complex(scene.leading_eigenvalue(physics, sigma))
        lines = scene.stability_report(physics, sigma, onset=onset, eigenvalue=eigenvalue)
    return Stability(
        physics=physics,
        sigma_c=float(onset.sigma_c),
        omega_c=float(onset.omega_c),
        kind=onset.kind,
        sigma=sigma,
        growth=None if eigenvalue is None else eigenvalue.real,
        frequency=None if eigenvalue is None else abs(eigenvalue.imag),
        sigma_all=onset.sigma_all,
        sigma_ceiling=onset.sigma_ceiling,
        report=tuple(lines),
    )

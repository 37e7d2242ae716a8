"""The two engines that integrate a scene: MuJoCo (`engines.mujoco`) and the reduced pendulum ODE
(`engines.reduced`). Both take (physics, numerics, duration) and return a Trajectory sampled on
numerics.sample_times(duration), from the same initial state (Scene.initial_angles)."""

from __future__ import annotations

from ..core import parameters as _parameters
from ..core.errors import ParameterError
from ..core.params import Numerics, Physics, check_start
from ..core.surface import option
from ..core.trajectory import Trajectory

ENGINES = ("mujoco", "reduced")
MAX_STEPS = 1_000_000_000
"""Steps one MuJoCo run may take: ~1 h at N = 7, far more for long chains."""


def check_steps(numerics: Numerics, duration: float) -> int:
    """The MuJoCo steps of a run (numerics as they run: a long chain's automatic ones), refused beyond MAX_STEPS."""
    steps = (numerics.sample_count(duration) - 1) * numerics.steps_per_sample
    if steps > MAX_STEPS:
        raise ParameterError(
            f"dt = {numerics.dt:g} over duration = {duration:g} tau is {steps:.2g} MuJoCo steps (limit "
            f"{MAX_STEPS:.0e}, hours of computing); raise {option('numerics.dt')} or shorten {option('duration')}"
        )
    return steps


MUJOCO_ONLY = ("dt", "integrator")
"""Numerical settings only the MuJoCo engine reads (the reduced engine uses dt only in a stochastic run,
core.parameters.stochastic; it does use mass_ratio, which decides whether a run is overdamped or inertial:
docs/mujoco.md section 5)."""


def check_engine_numerics(engine: str, names, noisy: bool, label=None) -> None:
    """Refuse MuJoCo-only numerical settings (`names`: those a user gave, or swept) with the reduced engine, where
    they change nothing: integrator always, dt unless the run (some point of a sweep) is stochastic (`noisy`:
    core.parameters.stochastic; dt is then the noise step). `label(name)` is how the message names the setting
    (default: as the caller's surface spells a Numerics field, core.surface.option). The one rule for run, sweep and
    the API."""
    if engine != "reduced":
        return
    label = label or (lambda name: option(f"numerics.{name}"))
    for name in names:
        if name not in MUJOCO_ONLY or (name == "dt" and noisy):
            continue
        why = (
            " (the reduced engine integrates noise-free runs adaptively; it uses dt only when "
            + " or ".join(f"{name} > 0" for name in _parameters.stochastic_names())
            + ")"
            if name == "dt"
            else ""
        )
        raise ParameterError(
            f"{label(name)}: {name} only affects the MuJoCo engine and changes nothing with "
            f"engine reduced{why}; remove it or use engine mujoco"
        )


def check_engine(engine: str) -> str:
    if engine not in ENGINES:
        raise ParameterError(f"engine must be one of {', '.join(ENGINES)}, got {engine!r}")
    return engine


def run_engine(engine: str, physics: Physics, numerics: Numerics, duration: float, **options) -> Trajectory:
    """Simulate with the named engine; options go to simulate_mujoco or simulate_reduced. Every engine path reports
    through engines.runner (its cost, a refusal past its step limit, its progress): the progress option holds for
    the whole run (runner.shown), whichever path the scene takes."""
    from .runner import shown  # engine boundary: the runner loads the cost model (MuJoCo) with it

    check_start(physics, numerics)  # perturbation 0 on an unstable base state, refused alike by both engines
    with shown(options.get("progress", False)):
        if check_engine(engine) == "mujoco":
            from .mujoco import simulate_mujoco  # start-up time: load only the engine in use (mujoco)

            return simulate_mujoco(physics, numerics, duration, **options)
        from .reduced import simulate_reduced  # start-up time: load only the engine in use (numba, ~0.3 s)

        return simulate_reduced(physics, numerics, duration, **options)

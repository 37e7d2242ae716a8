"""The two engines that integrate a scene: MuJoCo (`engines.mujoco`) and the reduced pendulum ODE
(`engines.reduced`). Both take (physics, numerics, duration) and return a Trajectory sampled on
numerics.sample_times(duration), from the same initial state (Scene.initial_angles)."""

from __future__ import annotations

from ..errors import ParameterError
from ..params import Numerics, Physics
from ..trajectory import Trajectory

ENGINES = ("mujoco", "reduced")


def check_engine(engine: str) -> str:
    if engine not in ENGINES:
        raise ParameterError(f"engine must be one of {', '.join(ENGINES)}, got {engine!r}")
    return engine


def run_engine(engine: str, physics: Physics, numerics: Numerics, duration: float, **options) -> Trajectory:
    """Simulate with the named engine; options go to simulate_mujoco or simulate_reduced."""
    if check_engine(engine) == "mujoco":
        from .mujoco import simulate_mujoco  # start-up time: load only the engine in use (mujoco)

        return simulate_mujoco(physics, numerics, duration, **options)
    from .reduced import simulate_reduced  # start-up time: load only the engine in use (numba, ~0.3 s)

    return simulate_reduced(physics, numerics, duration, **options)

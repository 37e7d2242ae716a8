"""The one pre-flight gate: every run passes `preflight` before an engine steps it.

`preflight(physics, numerics, duration, engine)` resolves the numerics once (a long run's automatic sample_dt,
Numerics.for_duration) and runs every check that can refuse a run before it starts, once, in this order:

  1. the engine's name, and the ODE method (the reduced engine's only)
  2. the run's length: a finite duration the engines can record with at least MIN_SAMPLES samples
  3. the scene's observables: a chain long enough to measure each (results.check_measurable)
  4. the numerical settings the engine reads: MuJoCo-only settings a user gave refused with the reduced engine
     (given=True; a batch's cases share numerics across engines, which each engine reads its own part of)
  5. MuJoCo's step count (engines.check_steps, with a long chain's automatic numerics) and its timestep against
     the integrator's stability and accuracy limits and every term's own rate (engines.timestep.check_timestep),
     computed once per distinct model of a batch (`TimestepChecks`)

It returns a `Checked` run: what the engine is then given. `ea.simulate`, the batch every study uses
(batch.run_case / run_cases), a sweep's points, `validate` and `run --from` all pass through it; the sweep defers
step 5 to a thread of its own while its batch steps (timestep=False here, then its `TimestepChecks`), so that a
refused point is dropped from its batch as if it had never run.

engines.cost and engines.timestep are imported inside TimestepChecks.refusal, the MuJoCo engine's boundary: they
build MuJoCo models, which a reduced-engine run never loads.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

from .core.errors import ParameterError
from .core.params import Numerics, Physics
from .engines import check_engine, check_engine_numerics, check_steps
from .io import progress
from .results import check_measurable


@dataclass(frozen=True)
class Checked:
    """A run that passed the gate: the physics, the numerics as resolved for its duration, the duration, the engine
    and the reduced engine's ODE method (None: its automatic choice)."""

    physics: Physics
    numerics: Numerics
    duration: float
    engine: str
    method: str | None = None


class TimestepChecks:
    """engines.timestep.check_timestep per run, computed once per distinct model: its outcome depends on the
    physics, dt, mass_ratio and integrator, on the seed only with noise (the linearisation sees the first step's
    noise draw) and on the initial state only for integrator discrete (its probe run). Thread-safe: a check another
    thread is computing is waited for, not computed again."""

    def __init__(self):
        self._cache: dict = {}
        self._running: dict = {}  # key -> Event set when that check is done
        self._models: dict = {}  # key -> the run's compiled model, offered by a batch (offer)
        self._lock = threading.Lock()

    def offer(self, physics: Physics, numerics: Numerics, model) -> None:
        """The compiled model of a run (as its batch builds it), for its check to use instead of building it again
        (~1.5 ms at N = 7). Kept only until the check is done."""
        key = self.key(physics, numerics)
        with self._lock:
            if key not in self._cache:
                self._models.setdefault(key, model)

    @staticmethod
    def key(physics: Physics, numerics: Numerics) -> tuple:
        seed = numerics.seed if physics.stochastic or numerics.integrator == "discrete" else None
        perturbation = numerics.perturbation if numerics.integrator == "discrete" else None
        return (physics, numerics.dt, numerics.mass_ratio, numerics.integrator, seed, perturbation)

    def known_refusal(self, physics: Physics, numerics: Numerics) -> Exception | None:
        """The check's refusal if it is done and refused the run, else None (nothing is computed)."""
        key = self.key(physics, numerics)
        with self._lock:
            return self._cache.get(key)

    def refusal(self, physics: Physics, numerics: Numerics, announce: bool = False) -> Exception | None:
        """The check's refusal (a ParameterError, or whatever else it raised), or None if the run may go."""
        key = self.key(physics, numerics)
        while True:
            with self._lock:
                if key in self._cache:
                    return self._cache[key]
                running = self._running.get(key)
                if running is None:
                    running = self._running[key] = threading.Event()
                    break
            running.wait()  # another thread computes it
        from .engines.cost import check_announcement  # engine boundary: the cost model loads MuJoCo
        from .engines.timestep import check_timestep  # engine boundary: the check builds MuJoCo models

        announcement = check_announcement(physics) if announce else None  # its time grows like the angles cubed
        if announcement:
            progress.announce(announcement)
        error = None
        with self._lock:
            model = self._models.get(key)
        try:
            check_timestep(physics, numerics, model=model)
        except Exception as err:  # refused (ParameterError) or failed: the run's error either way
            error = err
        except BaseException:  # interrupted: nothing is known
            with self._lock:
                del self._running[key]
            running.set()
            raise
        with self._lock:
            self._cache[key] = error
            self._models.pop(key, None)
            del self._running[key]
        running.set()
        return error

    def __call__(self, physics: Physics, numerics: Numerics, announce: bool = False) -> None:
        error = self.refusal(physics, numerics, announce)
        if error is not None:
            raise error


def preflight(
    physics: Physics,
    numerics: Numerics,
    duration: float,
    engine: str = "mujoco",
    *,
    method: str | None = None,
    timestep: bool = True,
    checks: TimestepChecks | None = None,
    given: bool = True,
    announce: bool = False,
) -> Checked:
    """The gate (module docstring): the run as its engine will be given it, or a ParameterError naming the parameter.

    checks: the TimestepChecks of a batch, so that its runs of one model are checked once (default: a check of
    this run alone). timestep=False leaves out MuJoCo's timestep check (step 5's second half): for a caller that
    runs it itself through its `checks` (the sweep, beside its batch), or that provokes a divergence on purpose.
    given=False: the numerics are a batch's, not a user's (step 4 does not refuse them).
    announce prints a line before a timestep check that takes seconds (the CLI's and the API's progress)."""
    check_engine(engine)
    if method is not None and engine == "mujoco":
        raise ParameterError(f"method = {method}: the ODE method applies to the reduced engine (engine='reduced')")
    # a large network's and a long run's automatic sample_dt
    numerics = physics.scene_def.record_numerics(physics, numerics, duration).for_duration(duration)
    duration = numerics.check_duration(duration)
    check_measurable(physics)
    if given:
        check_engine_numerics(engine, numerics.given(), physics.stochastic)
    if engine == "mujoco":
        check_steps(numerics.for_physics(physics), duration)  # before the timestep check's linearisation
        if timestep:
            (checks if checks is not None else TimestepChecks())(physics, numerics, announce)
    return Checked(physics, numerics, duration, engine, method)

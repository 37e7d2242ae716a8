"""What every engine path does around its loop: its cost before it steps, a refusal past the limit, and its progress.

Every engine path (MuJoCo's planar chain, 3D chain and network loops; the reduced engine's compiled DOP853, scipy's
solvers, its 3D chain's DOP853, the network's DOP853 and every Euler-Maruyama loop) goes through this module, so that
a new scene's engine adapter gets all three by calling it rather than writing them:

  before it steps   `refuse_steps`: its steps (exact at a fixed step, the fewest an adaptive solver can take at the
                    model's fastest rate: `fewest_steps`) refused past MAX_STEPS (steps of a compiled loop; a step
                    that runs Python counts PYTHON_STEP steps) in one line that names the parameter behind them
                    ("sigma = 1e+06: ...") and gives the --duration that passes, and what else does
  its cost          `Meter.announce`: a line through io.progress.announce before a run estimated at ANNOUNCE_SECONDS
                    or more (MuJoCo's from a few timed samples, engines.cost); a run whose cost is not known before
                    it starts (an adaptive solver) is announced by its meter from its own pace over PACE_SECONDS of
                    wall time from its first report (set-up and compiling left out), when that projects
                    ANNOUNCE_SECONDS or more
  while it runs     `Meter.at(t)` with the simulated time reached: every PROGRESS_EVERY seconds of wall time at most
                    the bar (io.progress.progress_bar, in whole time units) is updated; a loop calls it at least every
                    few tenths of a second (a compiled loop in calls of a bounded number of steps, MuJoCo's steps
                    through `mj_steps` in chunks of about PROGRESS_EVERY), so an update is never more than about
                    half a second apart. Whatever an observer of the updates raises propagates: the run stops there,
                    with nothing written.

A meter that is not shown (progress=False) costs one comparison per call: no clock is read.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar

from ..core.errors import ParameterError
from ..core.params import option  # a setting as the caller's surface names it (--dt, numerics.dt)
from ..io.progress import announce, progress_bar
from . import MAX_STEPS

PROGRESS_EVERY = 0.25
"""Seconds of wall time between two progress updates of a run (a long chain's sample can take seconds)."""

ANNOUNCE_SECONDS = 10.0
"""A run estimated to take this long or longer is announced with its estimate before (or, from its pace, while) it
runs."""
PACE_SECONDS = 0.4
"""Wall time over which a meter measures a run's pace before projecting its cost (a run whose cost was not estimated
before it started)."""
PYTHON_STEP = 100
"""How many compiled steps one step that runs Python (scipy's solve_ivp, the noisy network's kicks) counts as against
MAX_STEPS: such a step costs ~100 times a compiled one."""
EXPLICIT_REACH = 10.0
"""Largest h x |lambda| an explicit Runge-Kutta step stays stable at (DOP853's stability region reaches about 6 along
the negative real axis, RK45's about 3): an explicit solver takes at least duration x spectral radius / EXPLICIT_REACH
steps."""
RESOLVED_TURN = 1.0
"""Largest angle (rad) any solver turns a motion it follows (a growing or oscillating mode, a moving clamp) by in one
step: every solver takes at least duration x rate / RESOLVED_TURN steps (DOP853 at rtol 1e-9 takes ~0.3 rad; Radau
and LSODA at their default tolerances less)."""
DEFAULT_DURATION = 300.0
"""The run length `elastoactive run` takes by default: steps that stay within MAX_STEPS over it are blamed on
--duration, not on the rate."""


def _round_down(x: float) -> float:
    """x rounded down to two significant digits (a setting that passes, stated as one would type it)."""
    if x <= 0 or not math.isfinite(x):
        return 0.0
    scale = 10.0 ** (math.floor(math.log10(x)) - 1)
    return math.floor(x / scale) * scale


def fewest_steps(duration: float, rate: float, explicit: bool) -> float:
    """The fewest steps a solver can take over `duration` at the fastest rate `rate` it must follow (1/time): an
    explicit one duration x rate / EXPLICIT_REACH (its stability), any duration x rate / RESOLVED_TURN (accuracy)."""
    return duration * rate / (EXPLICIT_REACH if explicit else RESOLVED_TURN)


def refuse_steps(
    steps: float,
    *,
    what: str,
    duration: float,
    units: str = "tau",
    cause: str = "",
    value: float | None = None,
    python: bool = False,
    at_least: bool = False,
    advice: str = "",
) -> None:
    """Refuse, in one line, a run of `steps` steps past MAX_STEPS (divided by PYTHON_STEP for steps that run Python).

    what: the engine path ("MuJoCo", "the reduced engine's numba-DOP853"); cause: the parameter whose value sets the
    step (e.g. "sigma", "clamp_frequency", "dt"), named first where a run of DEFAULT_DURATION would still pass the
    limit, --duration otherwise; at_least: `steps` is a lower bound (an adaptive solver's fewest_steps); advice: what
    else passes ("a smaller --sigma"). The line always gives the --duration that passes."""
    limit = MAX_STEPS / (PYTHON_STEP if python else 1)
    if not steps > limit:
        return
    shorter = _round_down(duration * limit / steps)
    blamed = "duration" if not cause or steps * DEFAULT_DURATION / duration <= limit else cause
    shown = duration if blamed == "duration" else value
    head = f"{blamed} = {shown:g}: " if shown is not None else f"{blamed}: "
    where = f"over {duration:g} {units}"
    alternative = f" or {advice}" if advice else ""
    raise ParameterError(
        f"{head}{what} takes {'at least ' if at_least else ''}{steps:.2g} steps {where} (limit {limit:.0e}, hours "
        f"of computing); use {option('duration')} {shorter:g}{alternative}"
    )


def duration_text(seconds: float) -> str:
    """A wall time in words: seconds, minutes, hours or days."""
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.3g} days"


_SHOWN: ContextVar[bool] = ContextVar("progress shown", default=False)


@contextmanager
def shown(progress: bool) -> Iterator[None]:
    """Inside the block (this thread), a Meter given no `show` shows progress when `progress`: engines.run_engine
    sets it from its progress option, so that an engine path a scene reaches without being handed the option (a
    scene's hook that does not pass it on) still reports."""
    token = _SHOWN.set(bool(progress))
    try:
        yield
    finally:
        _SHOWN.reset(token)


class Meter:
    """A run's progress in simulated time (`duration` in `units`), shown as a bar when `show`.

    at(t): the loop has reached simulated time t; announce(text): the run's estimated cost, said once before it starts
    (the meter then projects nothing of its own); close(): the end (also on an error: the bar is closed, nothing more
    is said). `what` names the run ("mujoco one-pinned"). The bar appears at the first update, after any
    announcement. show None: as run_engine's progress option says (`shown`)."""

    def __init__(self, duration: float, what: str, show: bool | None = None, units: str = "tau"):
        show = _SHOWN.get() if show is None else show
        self.duration, self.what, self.units, self.shows = float(duration), what, units, bool(show)
        self.total = max(1, math.ceil(self.duration))
        self.bar = None
        self.said = False
        self.shown = 0
        self.start = self.last = time.perf_counter() if show else 0.0
        self.pace: tuple[float, float] | None = None  # (wall clock, simulated time) of the first report

    def announce(self, text: str | None) -> None:
        """Say the run's estimated cost (one line; None: nothing to say) and project nothing more from its pace."""
        self.said = True
        if text and self.shows:
            announce(text)

    def at(self, t: float) -> None:
        """The loop reached simulated time t: update the bar when PROGRESS_EVERY has passed since the last update."""
        if not self.shows:
            return
        now = time.perf_counter()
        if self.pace is None:  # the first report: the pace is measured from here (set-up and compiling left out)
            self.pace = (now, t)
            self._update(t, now)
        elif now - self.last >= PROGRESS_EVERY:
            self._update(t, now)

    def _update(self, t: float, now: float) -> None:
        since, t0 = self.pace
        if not self.said and now - since >= PACE_SECONDS and t > t0:
            self.said = True
            projected = now - self.start + (now - since) * (self.duration - t) / (t - t0)
            if projected >= ANNOUNCE_SECONDS:
                announce(
                    f"note: this {self.what} run will take about {duration_text(projected)} at its pace so far "
                    f"({t:.3g} of {self.duration:g} {self.units} in {now - self.start:.1f} s)"
                )
        if self.bar is None:
            self.bar = progress_bar(self.total, self.what, self.units)
        reached = min(self.total, int(t))
        self.last = now
        self.bar.update(reached - self.shown)
        self.shown = reached

    def close(self, finished: bool = True) -> None:
        """Close the bar (shown by then if the run took PROGRESS_EVERY or more); finished: the run reached its end
        (the bar is completed first)."""
        bar, self.bar = self.bar, None
        if bar is None:
            return
        if finished and self.shown < self.total:
            bar.update(self.total - self.shown)
        bar.close()

    def __enter__(self) -> Meter:
        return self

    def __exit__(self, kind, error, trace) -> None:
        self.close(finished=kind is None)


class StepChunks:
    """MuJoCo's steps in chunks of about PROGRESS_EVERY of wall time, the meter told data.time after each: `(model,
    data, nstep)` runs `nstep` steps through `step(model, data, k)` (mujoco.mj_step, or a noisy loop) in calls of
    `chunk` steps, which adapts to the measured step cost. The state is the same, bit for bit, as from one call
    (mj_step's nstep loops over mj_step in C). Without a shown meter the steps run in one call."""

    def __init__(self, meter: Meter, step: Callable, chunk: int = 256):
        self.meter, self.step, self.chunk = meter, step, max(1, int(chunk))

    def __call__(self, model, data, nstep: int) -> None:
        if not self.meter.shows or nstep <= self.chunk:
            self.step(model, data, nstep)
            return
        left = int(nstep)
        while left > 0:
            count = min(left, self.chunk)
            start = time.perf_counter()
            self.step(model, data, count)
            took = time.perf_counter() - start
            left -= count
            self.meter.at(float(data.time))
            if count == self.chunk:  # aim at PROGRESS_EVERY per call
                self.chunk = max(1, int(self.chunk * min(4.0, max(0.25, PROGRESS_EVERY / max(took, 1e-6)))))


def reporting(fun: Callable, on_time: Callable[[float], None] | None) -> Callable:
    """The right-hand side fun(t, y) of a solver that runs Python per evaluation (scipy's solve_ivp), telling
    on_time(t) first (the same values: nothing that is computed changes); fun itself when on_time is None."""
    if on_time is None:
        return fun

    def told(t, y):
        on_time(t)
        return fun(t, y)

    return told


def resume(call: Callable[[int], int], paused: int, reached: Callable[[], float], meter: Meter, steps: int) -> int:
    """Run a resumable compiled loop to its end: call(k) takes at most k steps and returns `paused` while unfinished
    (any other status ends it, and is returned); the meter is told reached() after every call. Without a shown meter
    every call takes `steps` steps (the loop's own budget); with one, the count adapts to about PROGRESS_EVERY of wall
    time a call, from a few hundred steps, since a step's cost varies by orders of magnitude with the model and its
    state. A resumable loop takes the same steps, bit for bit, however its calls are cut."""
    if not meter.shows:
        status = paused
        while status == paused:
            status = call(steps)
        return status
    count, status = min(steps, 256), paused
    while status == paused:
        start = time.perf_counter()
        status = call(count)
        took = time.perf_counter() - start
        meter.at(reached())
        count = max(1, int(count * min(4.0, max(0.25, PROGRESS_EVERY / max(took, 1e-6)))))
    return status


EXPLICIT_METHODS = ("numba-DOP853", "DOP853", "RK45", "RK23")
"""The explicit ones among the adaptive methods (reduced.settings.METHODS, the network's and the 3D chain's DOP853):
the spectral radius bounds their steps (fewest_steps)."""
COMPILED_METHODS = ("numba-DOP853",)
"""The methods whose steps run no Python (the others count PYTHON_STEP steps each)."""


def refuse_rate(
    physics,
    duration: float,
    rate: float,
    *,
    method: str,
    what: str,
    units: str = "tau",
    python: bool | None = None,
    blame: Callable[[], tuple[str, float, str]] | None = None,
) -> None:
    """Refuse, before it steps, an adaptive solver's run whose fewest steps (fewest_steps) pass the limit: at `rate`,
    the model's fastest rate (1/time) for `method` (the spectral radius for an explicit method, the fastest mode that
    does not decay for an implicit one: `motion_rate`), blamed on sigma (or on what blame() returns: (parameter,
    value, advice), asked only when refusing); or at its fastest term's (terms.base.fastest_term: a moving clamp's
    frequency), blamed on that term's parameter. python: whether a step runs Python (default: unless the method is
    compiled)."""
    from ..terms.base import fastest_term  # the terms' table: loaded with the physics already

    explicit = method in EXPLICIT_METHODS
    python = method not in COMPILED_METHODS if python is None else python
    steps = fewest_steps(duration, rate, explicit)
    if not max(steps, fewest_steps(duration, fastest_term(physics)[0], False)) > MAX_STEPS / (
        PYTHON_STEP if python else 1
    ):
        return
    cause, value, advice = blame() if blame is not None else ("sigma", physics.sigma, f"a smaller {option('sigma')}")
    term_rate, term = fastest_term(physics)
    term_steps = fewest_steps(duration, term_rate, False)
    if term is not None and term_steps > steps:
        steps = term_steps
        limit = MAX_STEPS / (PYTHON_STEP if python else 1)
        slower = str(term.slower(physics, term_rate * limit / steps) or "").strip()
        name = slower.split()[0] if slower else ""
        if name not in {p.name for p in term.parameters}:
            name = term.parameters[0].name if term.parameters else "duration"
        cause, value = name, getattr(physics, name, None)
        advice = option(name) + slower[len(name) :] if slower.startswith(name) else slower
    refuse_steps(
        steps,
        what=f"{what} {method}",
        duration=duration,
        units=units,
        cause=cause,
        value=value,
        python=python,
        at_least=True,
        advice=advice,
    )


def motion_rate(eig, explicit: bool) -> float:
    """The rate (1/time) that bounds an adaptive method's steps, from the eigenvalues of the Jacobian at the start:
    the spectral radius for an explicit method (its stability), the fastest mode that does not decay for an implicit
    one (what it must follow: growing or oscillating modes; 0 when every mode decays)."""
    import numpy as np  # start-up time: numpy is loaded with any solver that hands eigenvalues here

    eig = np.asarray(eig, dtype=complex).reshape(-1)
    if eig.size == 0:
        return 0.0
    size = np.abs(eig)
    if explicit:
        return float(size.max())
    moving = size[eig.real >= -1e-9 * size]
    return float(moving.max(initial=0.0))


START_FACTOR = 10.0
"""A model whose fastest rate at its start is this many times its rate at its base state is slow because of where it
starts (an absurd --perturbation), not because of its parameters: a refusal names the start."""


def solver_budget(
    physics,
    duration: float,
    what: str,
    units: str = "tau",
    start: tuple[str, float] | None = None,
    base_rate: Callable[[], float] | None = None,
):
    """budget(method, eig) for reduced.solve.solve_ode and solve_inertial: refuse_rate at motion_rate(eig) (0 where
    the method was given and eig is None: the terms' rates alone). start: (parameter, value) of the initial state
    (("perturbation", 0.01)), blamed where the rate at the start is START_FACTOR times base_rate(), the model's
    fastest rate at its base state, or more."""

    def budget(method: str, eig) -> None:
        explicit = method in EXPLICIT_METHODS
        rate = 0.0 if eig is None else motion_rate(eig, explicit)

        def blame() -> tuple[str, float, str]:
            if start is not None and base_rate is not None and rate > START_FACTOR * base_rate():
                return start[0], start[1], f"a smaller {option(start[0])}"
            return "sigma", physics.sigma, f"a smaller {option('sigma')}"

        refuse_rate(physics, duration, rate, method=method, what=what, units=units, blame=blame)

    return budget


def fixed_step_budget(physics, duration: float, dt: float, what: str, units: str = "tau"):
    """budget(steps, substeps) for reduced.solve.solve_sde: refuse_steps at steps x substeps, blamed on dt (or, where
    the inertial model's stiffness takes substeps, on sigma)."""

    def budget(steps: int, substeps: int) -> None:
        if substeps > 1:
            advice = f"a smaller {option('sigma')}, or a larger {option('mass_ratio')}"
            cause, value = "sigma", physics.sigma
        else:
            cause, value, advice = "dt", dt, f"a larger {option('dt')}"
        refuse_steps(
            steps * substeps, what=f"{what} at dt = {dt:g}", duration=duration, units=units, cause=cause,
            value=value, advice=advice,
        )  # fmt: skip

    return budget

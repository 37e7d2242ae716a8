"""What a run will cost before it runs: MuJoCo's wall time from its step cost, the reduced engine's from a pilot.

MuJoCo's cost is close to linear in the number of steps: `sample_cost` times a few recorded samples of the
compiled model (the follower-force callback on, as in the run) on a copy of the run's state, so the run itself is
untouched (bit-identical). The reduced engine's cost depends on the adaptive solver's steps, which follow the
dynamics rather than a fixed dt: `reduced_cost` times a pilot that grows from a short span until one run takes
PILOT_SECONDS (a large model's stiff solve costs seconds per tau: its pilot stays short). MuJoCo's pre-flight
stability check is dense in the model's angles: `check_seconds` estimates it from their number, and
`check_announcement` words it before a large model's check starts. A MuJoCo run of NOTE_SECONDS or more is
announced with its estimate (`cost_note`), and where the reduced engine would give the same observables far sooner
the line says so too; the run still goes.
"""

from __future__ import annotations

import copy
import dataclasses
import time
from typing import NamedTuple

import mujoco
import numpy as np

from ..controllers import follower_forces
from ..core.errors import ParameterError
from ..core.params import Numerics, Physics
from .runner import ANNOUNCE_SECONDS, Meter, duration_text

PROBE_SECONDS = 0.02
"""Wall time spent timing MuJoCo's samples (at least PROBE_MIN_SAMPLES samples)."""
PROBE_MIN_SAMPLES = 2
PROBE_SHARE = 0.05
"""Most of a run's samples the probe steps (a short run is not made much longer by its own estimate)."""
NOTE_SECONDS = 60.0
"""A MuJoCo run estimated to take longer than this is compared with the reduced engine (a shorter one of
runner.ANNOUNCE_SECONDS or more is announced with its own estimate alone)."""
FAR_BEYOND = 10.0
"""The note is shown when the MuJoCo estimate is more than this many times the reduced engine's."""
PILOT_SHARE = 0.02
"""Share of the run's duration the reduced engine's pilot simulates (at least PILOT_MIN_TAU)."""
PILOT_MIN_TAU = 5.0
PILOT_SECONDS = 0.5
"""Wall time the reduced engine's pilot may take: it starts over PILOT_FIRST_TAU and doubles its span until one run
takes this long or covers its share, so a large model's stiff solve (seconds per tau) is timed over a short span."""
PILOT_FIRST_TAU = 0.01


class MujocoCost(NamedTuple):
    """A MuJoCo run's estimated wall time and what it comes from."""

    wall_s: float
    steps: int
    us_per_step: float
    probed_samples: int


def sample_cost(model: mujoco.MjModel, data: mujoco.MjData, steps_per_sample: int, samples: int) -> tuple[float, int]:
    """(seconds per recorded sample, samples timed): a few samples of the run, stepped on a copy of its state; where
    one sample takes longer than the probe's budget (a long chain's slow steps), single steps (samples timed 0)."""
    probe = copy.copy(data)
    record = np.empty(model.nq)  # each sample is copied out, as the run records it
    limit = max(PROBE_MIN_SAMPLES, min(samples, int(PROBE_SHARE * samples)))
    timed = 0
    with follower_forces():
        mujoco.mj_step(model, probe, nstep=1)  # the first step pays one-off costs (caches, the callback's set-up)
        start = time.perf_counter()
        mujoco.mj_step(model, probe, nstep=1)
        step = time.perf_counter() - start
        if step * steps_per_sample * PROBE_MIN_SAMPLES > PROBE_SECONDS:  # slow steps (long chains): time steps alone
            count = 1
            while time.perf_counter() - start < PROBE_SECONDS:
                mujoco.mj_step(model, probe, nstep=1)
                count += 1
            return (time.perf_counter() - start) / count * steps_per_sample, 0
        start = time.perf_counter()
        while timed < limit and (timed < PROBE_MIN_SAMPLES or time.perf_counter() - start < PROBE_SECONDS):
            mujoco.mj_step(model, probe, nstep=steps_per_sample)
            record[:] = probe.qpos
            timed += 1
        elapsed = time.perf_counter() - start
    return elapsed / max(timed, 1), timed


def mujoco_cost(model: mujoco.MjModel, data: mujoco.MjData, numerics: Numerics, samples: int) -> MujocoCost:
    """Estimated wall time of `samples` recorded samples (numerics.steps_per_sample steps each) of this model."""
    per_sample, timed = sample_cost(model, data, numerics.steps_per_sample, samples)
    steps = samples * numerics.steps_per_sample
    return MujocoCost(per_sample * samples, steps, 1e6 * per_sample / numerics.steps_per_sample, timed)


def reduced_cost(physics: Physics, numerics: Numerics, duration: float) -> float | None:
    """Estimated wall time (s) of the reduced engine over `duration`, from a pilot of a few percent of it that stops
    growing once a run takes PILOT_SECONDS (the first run, which may compile the kernels, counts only when it alone
    takes that long). A stiff model's start costs most, so a short pilot overestimates it: the note that names the
    reduced engine as the quicker one errs on the side of silence. None when the reduced engine cannot run this case."""
    from .reduced import simulate_reduced  # start-up time: numba's kernels load only when a pilot runs

    pilot = min(duration, max(PILOT_MIN_TAU, PILOT_SHARE * duration))
    span = min(pilot, max(PILOT_FIRST_TAU, 4 * numerics.dt))
    numerics = dataclasses.replace(numerics, sample_dt=numerics.dt)  # a short span still records a few samples
    timed = False
    try:
        while True:
            start = time.perf_counter()
            simulate_reduced(physics, numerics, span)
            took = time.perf_counter() - start
            if took >= PILOT_SECONDS or (timed and span >= pilot):
                break
            span = min(pilot, 2 * span) if timed else span
            timed = True
    except (ParameterError, RuntimeError):
        return None
    return took * duration / span


CHECK_SECONDS_PER_ANGLE3 = 2e-7
"""Wall time of MuJoCo's pre-flight stability check (diagnose.check_timestep) per angle cubed: its linearisation
and the eigenvalues of its matrices are dense in the angles (2 N forward passes of O(N^2) each): the one-pinned
chain's took 8 s of CPU time at N = 400 and 173 s at N = 1000 (1.7e-7 N^3; 340 s of wall time on the shared
machine)."""
ANNOUNCED_CHECK_SECONDS = 1.0
"""A pre-flight check estimated to take at least this long is announced, with its estimate, before it starts."""


def check_seconds(n_angles: int) -> float:
    """Estimated wall time (s) of MuJoCo's pre-flight stability check of a model with this many angles."""
    return CHECK_SECONDS_PER_ANGLE3 * float(n_angles) ** 3


def check_announcement(physics: Physics) -> str | None:
    """The line that announces a long pre-flight check (ANNOUNCED_CHECK_SECONDS or more) with its estimated time,
    None for a quick one."""
    seconds = check_seconds(physics.n_angles)
    if seconds < ANNOUNCED_CHECK_SECONDS:
        return None
    return (
        f"checking dt against the stability limits of the N = {physics.n} model (about "
        f"{duration_text(max(seconds, 1.0))})..."
    )


def cost_note(mujoco_estimate: MujocoCost, reduced_s: float | None) -> str | None:
    """One line before a MuJoCo run of NOTE_SECONDS or more (None for a shorter one): its estimated wall time, and the
    reduced engine's where that is more than FAR_BEYOND times quicker."""
    if mujoco_estimate.wall_s < NOTE_SECONDS:
        return None
    line = short_note(mujoco_estimate)
    if reduced_s is None or mujoco_estimate.wall_s < FAR_BEYOND * reduced_s:
        return line
    return (
        f"{line}; the reduced engine gives the same observables in about {duration_text(reduced_s)} "
        "(--engine reduced, or engine='reduced'). Running it anyway"
    )


def announce_cost(
    meter: Meter, model: mujoco.MjModel, data: mujoco.MjData, numerics: Numerics, samples: int, reduced_seconds
) -> MujocoCost | None:
    """A shown MuJoCo run's estimate (mujoco_cost; None when the meter is not shown), said through the meter before the
    run: from runner.ANNOUNCE_SECONDS on with its estimated time, from NOTE_SECONDS on with the reduced engine's too
    where far quicker (cost_note; reduced_seconds(): the reduced engine's estimate, a pilot run only then)."""
    if not meter.shows:
        return None
    estimate = mujoco_cost(model, data, numerics, samples)
    note = None
    if estimate.wall_s >= NOTE_SECONDS:
        note = cost_note(estimate, reduced_seconds())
    elif estimate.wall_s >= ANNOUNCE_SECONDS:
        note = short_note(estimate)
    meter.announce(f"note: {note}" if note else None)
    return estimate


def short_note(estimate: MujocoCost) -> str:
    """The line before a MuJoCo run of ANNOUNCE_SECONDS or more: its estimated wall time and steps."""
    return (
        f"this MuJoCo run will take about {duration_text(estimate.wall_s)} ({estimate.steps:.3g} "
        f"steps at {estimate.us_per_step:.3g} us)"
    )

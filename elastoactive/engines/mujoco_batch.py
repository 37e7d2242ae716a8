"""Many MuJoCo runs at once: `mujoco.batch` steps the simulations of one model on C threads.

`simulate_mujoco_batch(runs, threads=...)` gives, for every run, exactly what
`engines.mujoco.simulate_mujoco` gives (the same Trajectory, bit for bit, or the same
SimulationDiverged), but runs them together:

* Runs are grouped into batches that share one compiled model. Each run's own model is compiled
  (`model.prepare`, as simulate_mujoco does) and compared with the batch's: the fields that differ
  must be ones mujoco.batch can expand per simulation (`mujoco.batch.MODEL_FIELDS`: site_user for
  sigma, numeric_data for noise and seed, tendon_stiffness for kappa, the actuator gains for the
  drag ratio, the pin's site_pos and the keyframe for delta, opt.timestep and eq_solref for dt, ...),
  and they are expanded with that run's values, so every simulation runs on a model equal to its
  own in every field the physics reads. Runs that differ in anything else (N, the sizes, the mass
  ratio through stat.meaninertia, the sampling) go to separate batches (`signature`).
* Each simulation starts from its own initial state (its mjSTATE_INTEGRATION row, taken from the
  MjData that `prepare` made: the seeded initial angles), and the batch steps all of them on C
  threads with the compiled follower-force callback; no Python runs per step.
* Stepping is `Batch.rollout` in chunks of many samples (one call per chunk, the GIL released), which
  records every substep; the samples are every steps_per_sample-th record. The divergence checks
  of simulate_mujoco (bad-state warnings, a non-finite state or a step that moves it farther than an
  accurate run does, every CHECK_EVERY samples; the pin drift at every sample of a pinned scene) are
  done on the records, per simulation: a diverged simulation is that run's SimulationDiverged and
  stops; the others go on.
* rollout stops a simulation whose warning counters rise; simulate_mujoco does not stop there. Such
  a simulation's chunk is replayed from the chunk's start, sample by sample with Batch.step (which
  is mj_step), with simulate_mujoco's checks in its order, so that the outcome is still its outcome.

The runs are split into chunks, each group of runs that likely share a model into at least one chunk per
thread (`plan`), and the chunks run on the threads, the costliest first (`run_chunks`, by `run_weight`: a
thread that finishes a cheap group takes a share of a costly one rather than waiting while a single thread
runs it); a chunk runs its batches one after another on the threads it was given. wall_time_s of a batched run
is its share of its batch's wall time (batch wall x threads / simulations); info["batch"] has the batch's size, threads
and wall time.
"""

from __future__ import annotations

import math
import os
import queue
import threading
import time
from collections import defaultdict, deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np
from mujoco import batch as mjbatch

from ..controllers import follower_forces
from ..core.errors import ParameterError, SimulationDiverged
from ..core.params import Numerics, Physics, check_start
from ..core.trajectory import Trajectory
from ..mjcf.chain import prepare, state_of
from ..terms import polarity_addresses
from .monitor import is_check, runaway
from .mujoco import BAD_STATE_WARNINGS, CHECK_EVERY, PIN_DRIFT_LIMIT, numerics_info, pin_drift_message, pin_violation
from .timestep import divergence_cause

RECORD_BYTES = 32 << 20
"""Bytes of records one rollout call of a batch may fill, in buffers reused from call to call. It sets
the chunk length (about 1600 samples for 16 runs at N = 7 and 20 steps per sample): the threads of a
batch wait for each other at the end of each call, so fewer calls lose less; a call is also the
granularity of cancelling."""
MAX_CHUNK_SAMPLES = 5000
"""Most samples one rollout call runs."""
_BAD = np.array([int(w) for w in BAD_STATE_WARNINGS])
_INTEGRATION = mujoco.mjtState.mjSTATE_INTEGRATION
_TIME = mujoco.mjtState.mjSTATE_TIME


class Cancelled(Exception):
    """A batch stopped because its `cancel` event was set; its unfinished runs have no outcome."""


@dataclass(frozen=True)
class Run:
    """One simulation: what simulate_mujoco(physics, numerics, duration) takes."""

    physics: Physics
    numerics: Numerics = field(default_factory=Numerics)
    duration: float = 200.0

    @property
    def used(self) -> Numerics:
        """The numerics the run uses: numerics.for_physics(physics), as simulate_mujoco resolves them."""
        return self.numerics.for_physics(self.physics)


def as_runs(runs, numerics: Numerics | None = None, duration: float | None = None) -> list[Run]:
    """Runs from Run or Case objects (anything with physics, numerics, duration), (physics, numerics,
    duration) tuples, or Physics objects with the shared `numerics` and `duration`."""
    out = []
    for run in runs:
        if isinstance(run, Physics):
            if duration is None:
                raise ParameterError("simulate_mujoco_batch: give a duration with a list of Physics")
            out.append(Run(run, numerics if numerics is not None else Numerics(), duration))
        elif isinstance(run, tuple):
            out.append(Run(*run))
        else:
            out.append(Run(run.physics, run.numerics, run.duration))
    return out


# ----------------------------------------------------------------------------- grouping

_FIELDS: tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]] | None = None
"""MjModel's array fields, size fields and option fields (read from the first model seen)."""
PHYSICS_STAT = ("meaninertia", "meanmass", "meansize")
"""mjStatistic fields the simulation may read (the constraint solver scales by meaninertia); center
and extent only place the camera."""


def _fields(model: mujoco.MjModel) -> tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    global _FIELDS
    if _FIELDS is None:
        names = [n for n in dir(model) if not n.startswith("_")]
        arrays = tuple(n for n in names if isinstance(getattr(model, n, None), np.ndarray))
        sizes = tuple(n for n in names if isinstance(getattr(model, n, None), int))
        options = tuple(n for n in dir(model.opt) if not n.startswith("_") and not callable(getattr(model.opt, n)))
        _FIELDS = (arrays, sizes, options)  # one assignment: other threads see all three or none
    return _FIELDS


def _opt_value(model: mujoco.MjModel, name: str) -> np.ndarray:
    return np.asarray(getattr(model.opt, name))


def signature(model: mujoco.MjModel) -> bytes:
    """Everything of a compiled model that mujoco.batch cannot give a simulation of its own: sizes,
    non-expandable arrays (structure, names, assets), non-expandable options and the statistics the
    physics reads. Models with equal signatures can run in one batch, the rest of their fields
    expanded per simulation."""
    arrays, sizes, options = _fields(model)
    parts = [repr([getattr(model, n) for n in sizes]).encode()]
    parts += [getattr(model, n).tobytes() for n in arrays if n not in mjbatch.MODEL_FIELDS]
    parts += [_opt_value(model, n).tobytes() for n in options if f"opt.{n}" not in mjbatch.MODEL_FIELDS]
    parts += [np.asarray(getattr(model.stat, n)).tobytes() for n in PHYSICS_STAT]
    for name in ("names", "paths", "text_data"):
        value = getattr(model, name, b"")
        parts.append(value if isinstance(value, bytes) else repr(value).encode())
    return b"\x00|".join(parts)


def _expanded_fields(models: Sequence[mujoco.MjModel]) -> list[str]:
    """The expandable fields (batch.expand names) in which the models differ from the first."""
    ref = models[0]
    arrays, _, options = _fields(ref)
    out = []
    for name in arrays:
        if name in mjbatch.MODEL_FIELDS:
            first = getattr(ref, name).tobytes()
            if any(getattr(m, name).tobytes() != first for m in models[1:]):
                out.append(name)
    for name in options:
        key = f"opt.{name}"
        if key in mjbatch.MODEL_FIELDS:
            first = _opt_value(ref, name).tobytes()
            if any(_opt_value(m, name).tobytes() != first for m in models[1:]):
                out.append(key)
    return out


def _field_value(model: mujoco.MjModel, name: str) -> np.ndarray:
    return _opt_value(model, name[4:]) if name.startswith("opt.") else getattr(model, name)


def batch_key(run: Run) -> tuple:
    """A cheap key (no compiling) under which runs are likely to share a model: scene, N, the mass
    ratio (stat.meaninertia), the integrator and the sampling, of the numerics the run uses (Run.used).
    `signature` decides. `run`: a Run or anything with physics, numerics and duration (batch.Case)."""
    num = run.numerics.for_physics(run.physics)
    return (
        run.physics.scene,
        run.physics.n,
        num.mass_ratio,
        num.integrator,
        num.steps_per_sample,
        num.sample_count(run.duration),
    )


def run_weight(run: Run) -> float:
    """A run's relative cost, for ordering chunks without compiling: steps x N (the step cost of the chains
    grows about linearly with N); 1 for a run this cannot size (an invalid run fails at once)."""
    try:
        num = run.numerics.for_physics(run.physics)
        return float(num.sample_count(run.duration) * num.steps_per_sample * max(1, int(run.physics.n)))
    except Exception:  # noqa: BLE001 (an invalid run: preparing it records the error)
        return 1.0


def plan(runs: Sequence[Run], max_points: int | None = None, min_chunks: int = 1) -> list[list[int]]:
    """Indices of `runs` in chunks that likely share a model (batch_key, in input order), each of at
    most `max_points` runs, a group split into near-equal chunks (at least `min_chunks` when it has
    that many runs, e.g. one per Dask thread)."""
    groups: dict[tuple, list[int]] = defaultdict(list)
    for i, run in enumerate(runs):
        try:
            key = batch_key(run)
        except Exception:  # an invalid run: its own chunk, where preparing it records the error
            key = ("invalid", i)
        groups[key].append(i)
    chunks = []
    for members in groups.values():
        count = max(1, min(len(members), min_chunks))
        if max_points:
            count = max(count, math.ceil(len(members) / max_points))
        size = math.ceil(len(members) / count)
        chunks += [members[k : k + size] for k in range(0, len(members), size)]
    return chunks


# ----------------------------------------------------------------------------- one batch


@dataclass
class _Sim:
    index: int  # in the caller's list
    run: Run
    t: np.ndarray
    model: mujoco.MjModel
    data: mujoco.MjData
    violation: float
    qpos: np.ndarray = None  # (T, nq)
    polarity: np.ndarray = None  # (T, units): self-aligning units' activations (mjData.act)


class _Warnings:
    """Stand-in for MjData in divergence_cause, which reads data.warning[w].number."""

    def __init__(self, counts: np.ndarray):
        self.warning = _Counts(np.array(counts))


class _Counts:
    def __init__(self, counts: np.ndarray):
        self._counts = counts

    def __getitem__(self, w) -> _Count:
        return _Count(int(self._counts[int(w)]))


@dataclass
class _Count:
    number: int


def _prepare(index: int, run: Run) -> _Sim:
    if not run.duration > 0:
        raise ParameterError(f"duration (in tau) must be a positive number, got {run.duration}")
    check_start(run.physics, run.used)  # as run_engine: perturbation 0 on an unstable base state
    t = run.used.sample_times(run.duration)
    model, data = prepare(run.physics, run.used)
    violation = pin_violation(model, data) if run.physics.scene_def.pinned else 0.0
    return _Sim(index, run, t, model, data, violation)


def run_batch(
    sims: Sequence[_Sim],
    threads: int,
    on_done: Callable[[int, Any], None],
    cancel: threading.Event | None = None,
    on_start: Callable[[], None] | None = None,
    drop: Callable[[int], BaseException | None] | None = None,
) -> None:
    """Run simulations whose models share a signature in one mujoco.batch on `threads` threads; each
    outcome (Trajectory or exception) goes to on_done(index, outcome) as soon as it is known. The
    follower callback must be installed (follower_forces) by the caller, for the whole call.
    on_start() is called as the stepping starts (from then on the GIL is free most of the time).
    drop(index), asked before each chunk of samples, may return an exception that ends that
    simulation at once, as its outcome (e.g. a pre-flight check that failed meanwhile)."""
    ref = sims[0]
    model, nsim = ref.model, len(sims)
    nstep, samples = ref.run.used.steps_per_sample, ref.t.size
    nq = model.nq
    pinned = ref.run.physics.scene_def.pinned
    start = time.perf_counter()
    b = mjbatch.Batch(model, nsim, threads)
    for name in _expanded_fields([s.model for s in sims]):
        values = b.expand(name)
        for k, s in enumerate(sims):
            values[k] = _field_value(s.model, name)
    units = polarity_addresses(model) if model.na else None  # self-aligning units' polarity psi (mjData.act)
    for k, s in enumerate(sims):
        mujoco.mj_getState(s.model, s.data, b.state[k], _INTEGRATION)
        s.qpos = np.empty((samples, nq))
        s.qpos[0] = s.data.qpos
        if units is not None:
            s.polarity = np.empty((samples, units.size))
            s.polarity[0] = s.data.act[units]
        s.model = s.data = None  # the batch holds what it needs
    ends = (int(model.eq_obj1id[0]), int(model.eq_obj2id[0])) if pinned else None
    violation = np.array([s.violation for s in sims])
    active = np.ones(nsim, bool)
    done = [False] * nsim
    nsite = model.nsite

    def finish(k: int, outcome) -> None:
        active[k] = False
        done[k] = True
        on_done(sims[k].index, outcome)

    per_step = nq * 8 + 8 + (nsite * 24 if pinned else 0)
    chunk = int(max(1, min(MAX_CHUNK_SAMPLES, RECORD_BYTES // max(1, nsim * nstep * per_step))))
    record = ["qpos", _TIME] + (["site_xpos"] if pinned else []) + (["act"] if units is not None else [])
    # one buffer per recorded field, for the largest call, reused by every call (fresh arrays would
    # cost their page faults and zeroing at every call, ~2% of the stepping)
    shapes = {
        "qpos": (nq,),
        _TIME: (1,),
        **({"site_xpos": (nsite, 3)} if pinned else {}),
        **({"act": (model.na,)} if units is not None else {}),
    }
    buffers = {
        name: (np.empty(nsim * chunk * nstep * math.prod(shape)), math.prod(shape), shape)
        for name, shape in shapes.items()
    }
    k0 = 1  # the first sample of the chunk
    while k0 < samples and active.any():
        if cancel is not None and cancel.is_set():
            raise Cancelled
        if drop is not None:
            for k in np.flatnonzero(active):
                reason = drop(sims[k].index)
                if reason is not None:
                    finish(int(k), reason)
            if not active.any():
                break
        count = min(chunk, samples - k0)
        ids = np.flatnonzero(active)
        n = ids.size
        saved_state = b.state[ids].copy()
        saved_warning = b.warning[ids].copy()
        out = {
            name: buffer[: n * count * nstep * size].reshape(n, count * nstep, *shape)
            for name, (buffer, size, shape) in buffers.items()
        }
        failed: dict[int, str] = {}
        if on_start is not None and k0 == 1:
            on_start()
        try:
            b.rollout(count * nstep, record=record, ids=None if n == nsim else ids, out=out)
        except mjbatch.SimulationError as err:
            failed = {int(i): b.error(int(i)) or str(err) for i in err.ids}
        rose = (b.warning[ids, :, 1] != saved_warning[:, :, 1]).any(axis=1)
        for j, k in enumerate(ids):
            k = int(k)
            if k in failed:
                finish(k, mujoco.FatalError(f"MuJoCo error: {failed[k]}"))
                continue
            if rose[j]:  # rollout stopped it: redo this chunk as simulate_mujoco steps
                b.state[k] = saved_state[j]
                b.warning[k] = saved_warning[j]
                outcome = _replay(b, k, sims[k], k0, count, nstep, ends, violation, units)
                if outcome is not None:
                    finish(k, outcome)
                continue
            q = out["qpos"][j, nstep - 1 :: nstep]
            sample_ks = np.arange(k0, k0 + count)
            sims[k].qpos[k0 : k0 + count] = q
            if units is not None:
                sims[k].polarity[k0 : k0 + count] = out["act"][j, nstep - 1 :: nstep][:, units]
            event = None  # (sample offset, message)
            checks = np.flatnonzero((sample_ks % CHECK_EVERY == 0) | (sample_ks == samples - 1))
            bad_before = bool(saved_warning[j][_BAD, 1].any())
            for s in checks:  # simulate_mujoco's checks, in its order: a bad state, then a runaway step
                s = int(s)
                t_s = float(out[_TIME][j, s * nstep + nstep - 1, 0])
                if bad_before or not np.isfinite(q[s]).all():
                    event = (
                        s,
                        divergence_cause(
                            sims[k].run.physics, sims[k].run.used, t_s, None, _Warnings(b.warning[k, :, 1])
                        ),
                    )
                    break
                before = out["qpos"][j, s * nstep + nstep - 2] if nstep > 1 else sims[k].qpos[k0 + s - 1]
                change = runaway(sims[k].qpos, k0 + s, nstep, before)
                if change is not None:
                    event = (
                        s,
                        divergence_cause(
                            sims[k].run.physics,
                            sims[k].run.used,
                            t_s,
                            None,
                            _Warnings(b.warning[k, :, 1]),
                            step_change=change,
                        ),
                    )
                    break
            if pinned:
                drift = _pin_drift(out["site_xpos"][j, nstep - 1 :: nstep], ends, violation, k)
                if drift is not None and (event is None or drift < event[0]):
                    t_s = float(out[_TIME][j, drift * nstep + nstep - 1, 0])
                    event = (drift, pin_drift_message(violation[k], t_s, sims[k].run.used))
            if event is not None:
                finish(k, SimulationDiverged(event[1]))
        k0 += count

    wall = time.perf_counter() - start
    share = wall * min(threads, nsim) / nsim
    for k, s in enumerate(sims):
        if done[k]:
            continue
        physics, numerics = s.run.physics, s.run.used
        steps = int((samples - 1) * nstep)
        info = {
            "steps": steps,
            "integrator": numerics.integrator,
            "us_per_step": 1e6 * share / max(steps, 1),
            "batch": {"size": nsim, "threads": min(threads, nsim), "wall_s": wall},
        }
        if pinned:
            info["constraint_violation"] = float(violation[k])
        info.update(numerics_info(s.run.numerics, numerics))
        theta, head = state_of(physics, s.qpos)
        s.qpos = None
        done[k] = True
        on_done(
            s.index,
            Trajectory(
                t=s.t,
                theta=theta,
                physics=physics,
                engine="mujoco",
                wall_time_s=share,
                info=info,
                head=head,
                polarity=s.polarity,
            ),
        )


def _pin_drift(xpos: np.ndarray, ends: tuple[int, int], violation: np.ndarray, k: int) -> int | None:
    """Update simulation k's largest pin violation over these samples' site positions (S, nsite, 3),
    exactly as pin_violation computes it; return the first sample where it exceeds the limit."""
    diff = xpos[:, ends[0]] - xpos[:, ends[1]]
    approx = np.sqrt(np.einsum("ij,ij->i", diff, diff))
    running = float(violation[k])
    # a sample whose (rounded differently) estimate is below the running maximum cannot raise it:
    # only the others are measured as pin_violation measures them (np.linalg.norm)
    for s in np.flatnonzero(approx >= running * (1 - 1e-9)):
        if approx[s] < running * (1 - 1e-9):
            continue
        running = max(running, float(np.linalg.norm(diff[s])))
        if running > PIN_DRIFT_LIMIT:
            violation[k] = running
            return int(s)
    violation[k] = running
    return None


def _replay(
    b: mjbatch.Batch,
    k: int,
    sim: _Sim,
    k0: int,
    count: int,
    nstep: int,
    ends,
    violation: np.ndarray,
    units: np.ndarray | None = None,
):
    """Step simulation k sample by sample over samples k0 .. k0 + count - 1 with simulate_mujoco's
    checks; returns its SimulationDiverged, or None if it went through."""
    ids = np.array([k], np.int32)
    samples = sim.t.size
    physics, numerics = sim.run.physics, sim.run.used
    xpos = b.bind("site_xpos") if ends is not None else None
    for kk in range(k0, k0 + count):
        check = is_check(kk, samples)
        try:
            if check and nstep > 1:  # the last step apart, as simulate_mujoco steps it (monitor.step_last_apart)
                b.step(ids, nstep=nstep - 1)
            before = b.qpos[k].copy()
            b.step(ids, nstep=1 if check else nstep)
        except mjbatch.SimulationError as err:
            return mujoco.FatalError(f"MuJoCo error: {b.error(k) or err}")
        qpos = b.qpos[k]
        sim.qpos[kk] = qpos
        if units is not None:
            sim.polarity[kk] = b.act[k][units]
        if check:
            counts = b.warning[k, :, 1]
            if counts[_BAD].any() or not np.all(np.isfinite(qpos)):
                return SimulationDiverged(
                    divergence_cause(physics, numerics, float(b.time[k]), None, _Warnings(counts))
                )
            change = runaway(sim.qpos, kk, nstep, before)
            if change is not None:
                return SimulationDiverged(
                    divergence_cause(physics, numerics, float(b.time[k]), None, _Warnings(counts), step_change=change)
                )
        if ends is not None:
            value = float(np.linalg.norm(xpos[k, ends[0]] - xpos[k, ends[1]]))
            violation[k] = max(violation[k], value)
            if violation[k] > PIN_DRIFT_LIMIT:
                return SimulationDiverged(pin_drift_message(violation[k], float(b.time[k]), numerics))
    return None


def run_chunk(
    runs: Sequence[Run],
    indices: Sequence[int],
    threads: int,
    on_done: Callable[[int, Any], None],
    cancel: threading.Event | None = None,
    on_start: Callable[[], None] | None = None,
    drop: Callable[[int], BaseException | None] | None = None,
    on_prepared: Callable[[int, mujoco.MjModel], None] | None = None,
    on_batch_end: Callable[[], None] | None = None,
) -> None:
    """Prepare runs[i] for i in indices, group them by signature and run each group as one batch on
    `threads` threads; outcomes go to on_done(i, Trajectory | exception). The caller installs the
    follower callback. on_prepared(i, model) is given each run's compiled model (model.prepare's, built for
    runs[i].used), e.g. for a pre-flight check that would otherwise build it again; it must only read it.
    on_batch_end() is called after each batch (or run alone) has given all its outcomes (e.g. to save them together)."""
    groups: dict[bytes, list[_Sim]] = {}
    for i in indices:
        if runs_alone(runs[i]):  # a scene of a kind the batch does not run: its own engine, alone on this thread
            if on_start is not None:
                on_start()
            on_done(i, _alone_outcome(runs[i]))
            if on_batch_end is not None:
                on_batch_end()
            continue
        try:
            sim = _prepare(i, runs[i])
        except Exception as err:  # as simulate_mujoco would raise it
            on_done(i, err)
            continue
        if on_prepared is not None:
            on_prepared(i, sim.model)
        groups.setdefault(signature(sim.model), []).append(sim)
    for sims in groups.values():
        run_batch(sims, threads, on_done, cancel, on_start, drop)
        if on_batch_end is not None:
            on_batch_end()


def runs_alone(run: Run) -> bool:
    """Whether a run's scene is of a kind that the batched engine does not run (Scene.mujoco_batched: a network's
    engine runs it alone on one thread of its chunk)."""
    try:
        return not run.physics.scene_def.mujoco_batched
    except Exception:  # noqa: BLE001 (an invalid run: preparing it records the error)
        return False


def _alone_outcome(run: Run):
    """The outcome of a run that runs alone (runs_alone), as simulate_mujoco gives it (its scene's run_mujoco; the
    caller has installed the callbacks)."""
    try:
        return run.physics.scene_def.run_mujoco(run.physics, run.used, run.duration, install_callbacks=False)
    except Exception as err:  # noqa: BLE001 (as simulate_mujoco would raise it)
        return err


# ----------------------------------------------------------------------------- scheduling

_SENTINEL = object()


def run_chunks(
    chunks: Sequence[Sequence],
    threads: int,
    task: Callable[[Sequence, int, Callable[[Any], None], threading.Event], Any],
    cancel: threading.Event | None = None,
    idle: Any = None,
    weight: Callable[[Sequence], float] = len,
) -> Iterator[Any]:
    """Run task(chunk, k, emit, cancel) for every chunk on worker threads, k C threads each and
    `threads` in all, with the follower callback installed; yields, in the caller's thread, every
    item a task passes to emit(item), as soon as it does. A task's exception is raised here.

    Chunks run largest first (by `weight`, default their length). A chunk takes every free thread up to its
    size (one batch on all threads is balanced within each call), but only one when other chunks wait and its size is
    not a multiple of the free threads (two batches of 3 on 2 threads run side by side, rather than
    one after the other at 3/4 of the speed). Closing the generator sets `cancel` and waits for the
    running tasks (a batch stops at its next chunk of samples, raising Cancelled). With `idle` given,
    it is yielded whenever no item is waiting (e.g. to write out several items at once)."""
    order = deque(sorted(range(len(chunks)), key=lambda c: -weight(chunks[c])))
    messages: queue.Queue = queue.Queue()
    cancel = cancel if cancel is not None else threading.Event()
    free = max(1, int(threads))
    running = 0
    workers: list[threading.Thread] = []
    pending_items = False  # items were yielded since the last `idle`

    def work(c: int, k: int) -> None:
        error = None
        try:
            task(chunks[c], k, lambda item: messages.put((_SENTINEL, item)), cancel)
        except BaseException as err:  # noqa: BLE001 (handed to the caller's thread)
            error = err
        messages.put((c, (k, error)))

    # the passive callback is global to the process: installed here, in the caller's thread, for
    # as long as any worker runs (a worker must not install and restore it under another's feet)
    with follower_forces():
        try:
            while order or running:
                while order and free > 0:
                    c = order[0]
                    size = max(1, len(chunks[c]))
                    k = min(free, size)
                    if len(order) > 1 and k > 1 and size % k:
                        k = 1
                    order.popleft()
                    free -= k
                    running += 1
                    worker = threading.Thread(target=work, args=(c, k), name=f"elastoactive-batch-{c}", daemon=True)
                    workers.append(worker)
                    worker.start()
                if idle is not None and messages.empty() and pending_items:
                    pending_items = False
                    yield idle
                try:
                    tag, value = messages.get(timeout=0.5)
                except queue.Empty:  # wake up now and then: a Ctrl-C is delivered between waits
                    continue
                if tag is _SENTINEL:
                    pending_items = True
                    yield value
                    continue
                k, error = value
                running -= 1
                free += k
                if error is not None:
                    raise error
            if idle is not None and pending_items:
                yield idle
        finally:
            cancel.set()
            for worker in workers:
                worker.join()


def simulate_mujoco_batch(
    runs: Iterable,
    numerics: Numerics | None = None,
    duration: float | None = None,
    *,
    threads: int | None = None,
    max_points: int | None = None,
    on_done: Callable[[int, Any], None] | None = None,
) -> list[Trajectory | Exception]:
    """Simulate many runs with mujoco.batch on `threads` C threads (default: every core); returns,
    in input order, each run's Trajectory or the exception simulate_mujoco would have raised for it
    (SimulationDiverged, ParameterError, ...): bit for bit what simulate_mujoco gives.

    runs: Run or batch.Case objects, (physics, numerics, duration) tuples, or Physics objects with
    the shared `numerics` and `duration`. max_points: most runs per batch (default: no limit).
    on_done(i, outcome) is called in this thread as each run finishes."""
    runs = as_runs(runs, numerics, duration)
    outcomes: list[Any] = [None] * len(runs)
    for i, outcome in iter_mujoco_batch(runs, threads=threads, max_points=max_points):
        outcomes[i] = outcome
        if on_done is not None:
            on_done(i, outcome)
    return outcomes


def iter_mujoco_batch(
    runs: Sequence[Run], *, threads: int | None = None, max_points: int | None = None
) -> Iterator[tuple[int, Trajectory | Exception]]:
    """(index, outcome) of every run as it finishes (simulate_mujoco_batch, one at a time)."""
    runs = as_runs(runs)
    if threads is None:
        threads = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if isinstance(threads, bool) or int(threads) < 1:
        raise ParameterError(f"threads must be an integer >= 1, got {threads!r}")

    def task(chunk, k, emit, cancel):
        run_chunk(runs, chunk, k, lambda i, outcome: emit((i, outcome)), cancel)

    weights = [run_weight(run) for run in runs]
    # a group per thread at least: one batch on all threads would leave a thread idle once a cheaper group
    # beside it has finished (a batch's threads are fixed when it starts)
    chunks = plan(runs, max_points, min_chunks=int(threads))
    yield from run_chunks(chunks, int(threads), task, weight=lambda chunk: sum(weights[i] for i in chunk))


__all__ = [
    "simulate_mujoco_batch",
    "iter_mujoco_batch",
    "Run",
    "plan",
    "run_weight",
    "run_chunk",
    "run_chunks",
    "signature",
    "Cancelled",
]

"""What every MuJoCo run loop checks while it runs (the chains' simulate_mujoco and its batch, the networks'
simulate_network_mujoco): which MuJoCo warnings mean a bad state, how far one step may move the state, and how often
the loop looks."""

from __future__ import annotations

import mujoco
import numpy as np

from .runner import PROGRESS_EVERY  # noqa: F401 (the run loops import it here)

CHECK_EVERY = 100  # samples between divergence checks

BAD_STATE_WARNINGS = (
    mujoco.mjtWarning.mjWARN_BADQPOS,
    mujoco.mjtWarning.mjWARN_BADQVEL,
    mujoco.mjtWarning.mjWARN_BADQACC,
    # the implicit solve failed (seen with `discrete` on long chains): the state goes on, wrong
    mujoco.mjtWarning.mjWARN_INERTIA,
)

MAX_STEP_CHANGE = 1.0
"""Largest change of any coordinate of qpos in one step (rad for an angle, l for a position) that a run can make and
still be accurate: the pre-flight check holds dt x (fastest rate) <= params.RESOLUTION = 0.2, so a step that turns a
segment by a radian resolves nothing. A state moving this fast has diverged even while it stays finite (e.g. a term's
force stiffer than dt resolves, which the linearised pre-flight check cannot see: a force away from the base state or
outside MuJoCo's passive forces). It is read from the state itself, whatever the terms declare."""


def bad_state(data: mujoco.MjData) -> bool:
    """Whether MuJoCo flagged a bad state or the positions are no longer finite (auto-reset is off: it stays so)."""
    return any(data.warning[w].number for w in BAD_STATE_WARNINGS) or not np.all(np.isfinite(data.qpos))


def is_check(k: int, samples: int) -> bool:
    """Whether the run loop checks the state at sample k (of `samples`): every CHECK_EVERY samples and the last."""
    return k % CHECK_EVERY == 0 or k == samples - 1


def step_last_apart(model: mujoco.MjModel, data: mujoco.MjData, nstep: int, steps=None) -> np.ndarray:
    """Step `nstep` steps, the last one on its own (mj_step's nstep loops over mj_step in C: the state is bit for bit
    that of one call), and return qpos one step before the end. steps(model, data, k): how the first nstep - 1 are
    stepped (runner.StepChunks: in chunks that report progress), default one mj_step call."""
    if nstep > 1:
        if steps is None:
            mujoco.mj_step(model, data, nstep=nstep - 1)
        else:
            steps(model, data, nstep - 1)
    before = data.qpos.copy()
    mujoco.mj_step(model, data)
    return before


def step_change(qpos: np.ndarray, k: int, nstep: int, before: np.ndarray) -> float:
    """The largest change of a coordinate per step that the check at sample k sees: the last step's (qpos[k] less
    `before`, the state one step earlier) and, a lower bound for every step since the previous check, each sample's
    change over its nstep steps (qpos: the samples recorded so far, (T, nq))."""
    previous = ((k - 1) // CHECK_EVERY) * CHECK_EVERY
    spread = np.abs(np.diff(qpos[previous : k + 1], axis=0))
    last = float(np.max(np.abs(qpos[k] - before), initial=0.0))
    return max(last, float(np.max(spread, initial=0.0)) / nstep)


def runaway(qpos: np.ndarray, k: int, nstep: int, before: np.ndarray) -> float | None:
    """step_change when it exceeds MAX_STEP_CHANGE (the run has diverged), else None."""
    change = step_change(qpos, k, nstep, before)
    return change if change > MAX_STEP_CHANGE else None

"""What every MuJoCo run loop checks while it runs (the chains' simulate_mujoco and its batch, the networks'
simulate_network_mujoco): which MuJoCo warnings mean a bad state, and how often the loop looks."""

from __future__ import annotations

import mujoco
import numpy as np

CHECK_EVERY = 100  # samples between divergence checks
PROGRESS_EVERY = 0.25  # seconds between progress updates (a long chain's sample can take seconds)

BAD_STATE_WARNINGS = (
    mujoco.mjtWarning.mjWARN_BADQPOS,
    mujoco.mjtWarning.mjWARN_BADQVEL,
    mujoco.mjtWarning.mjWARN_BADQACC,
    # the implicit solve failed (seen with `discrete` on long chains): the state goes on, wrong
    mujoco.mjtWarning.mjWARN_INERTIA,
)


def bad_state(data: mujoco.MjData) -> bool:
    """Whether MuJoCo flagged a bad state or the positions are no longer finite (auto-reset is off: it stays so)."""
    return any(data.warning[w].number for w in BAD_STATE_WARNINGS) or not np.all(np.isfinite(data.qpos))

"""Readable Python version of the follower-force callback (slow: about ten times the step).

Kept as the specification the compiled callback is tested against. For every site s with
user value F: force f = -F (1 + eta) x_s at the site, added to qfrc_passive as J_s^T f.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ..noise import force_factor


def reference_passive(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    marker = model.numeric("elastoactive_follower") if _has_marker(model) else None
    if marker is None or model.nuser_site < 1:
        return
    noise_amplitude, seed = marker.data[0], int(marker.data[1])
    magnitudes = model.site_user[:, 0]
    active = np.flatnonzero(magnitudes)
    factor = np.ones(active.size)
    if noise_amplitude > 0:
        step = int(round(data.time / model.opt.timestep))
        factor = force_factor(seed, step, active.size, noise_amplitude, model.opt.timestep)[0]
    jacp = np.zeros((3, model.nv))
    for k, s in enumerate(active):
        force = -magnitudes[s] * factor[k] * data.site_xmat[s].reshape(3, 3)[:, 0]
        mujoco.mj_jacSite(model, data, jacp, None, s)
        data.qfrc_passive += jacp.T @ force


def _has_marker(model: mujoco.MjModel) -> bool:
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, "elastoactive_follower") >= 0

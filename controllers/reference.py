"""Readable Python version of the follower-force callback (slow: about ten times the step).

Kept as the specification the compiled callback is tested against. For every site s with
user value F: force f = -F (1 + eta) x_s at the site, added to qfrc_passive as J_s^T f.
Coloured noise (the marker's third entry tau_c > 0): eta held in data.userdata and advanced exactly as
follower.c does (see there and elastoactive.controllers.noise.ColouredNoise). The tip drive (numeric
elastoactive_drive = (A, omega, d_x, d_y)): the force A sin(omega t) (d_x, d_y, 0) on every site whose second user value
is non-zero.
"""

from __future__ import annotations

import mujoco
import numpy as np

from .noise import INITIAL_STEP, force_factor, ou_constants, standard_normal


def reference_passive(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    marker = model.numeric("elastoactive_follower") if _has_marker(model) else None
    if marker is None or model.nuser_site < 1:
        return
    noise_amplitude, seed = marker.data[0], int(marker.data[1])
    magnitudes = model.site_user[:, 0]
    active = np.flatnonzero(magnitudes)
    factor = np.ones(active.size)
    tau_c = marker.data[2] if marker.data.size >= 3 else 0.0
    if noise_amplitude > 0 and tau_c > 0:
        if model.nuserdata >= 1 + active.size:
            factor = 1.0 + coloured_noise(model, data, noise_amplitude, seed, tau_c, active.size)
    elif noise_amplitude > 0:
        step = int(round(data.time / model.opt.timestep))
        factor = force_factor(seed, step, active.size, noise_amplitude, model.opt.timestep)[0]
    jacp = np.zeros((3, model.nv))
    for k, s in enumerate(active):
        force = -magnitudes[s] * factor[k] * data.site_xmat[s].reshape(3, 3)[:, 0]
        mujoco.mj_jacSite(model, data, jacp, None, s)
        data.qfrc_passive += jacp.T @ force
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, "elastoactive_drive") >= 0 and model.nuser_site >= 2:
        amplitude, omega, dx, dy = model.numeric("elastoactive_drive").data[:4]
        force = amplitude * np.sin(omega * data.time) * np.array([dx, dy, 0.0])
        for s in np.flatnonzero(model.site_user[:, 1]):
            mujoco.mj_jacSite(model, data, jacp, None, s)
            data.qfrc_passive += jacp.T @ force


def _has_marker(model: mujoco.MjModel) -> bool:
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, "elastoactive_follower") >= 0


def coloured_noise(
    model: mujoco.MjModel, data: mujoco.MjData, amplitude: float, seed: int, tau_c: float, count: int
) -> np.ndarray:
    """eta of the current step from data.userdata (userdata[0] = held step + 1, userdata[1:1+count] = eta),
    advanced there to the step floor(time / dt + 1e-6): follower.c's coloured_noise, number for number."""
    dt = model.opt.timestep
    std, decay, kick = ou_constants(float(amplitude), float(tau_c), dt)
    step = max(0, int(np.floor(data.time / dt + 1e-6)))
    held = int(data.userdata[0]) - 1
    eta = data.userdata[1 : 1 + count].copy()
    if held < 0 or step < held:
        eta = std * standard_normal(seed, INITIAL_STEP, count)[0]
        held = 0
    for k in range(held, step):
        eta = decay * eta + kick * standard_normal(seed, k, count)[0]
    data.userdata[0] = step + 1.0
    data.userdata[1 : 1 + count] = eta
    return eta

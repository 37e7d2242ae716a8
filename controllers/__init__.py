"""Per-step follower forces: the compiled callback used for real runs, and its Python twin.

MuJoCo's passive callback is global to the process. `follower_forces()` installs the compiled
C callback (controllers/follower.c) for the duration of a `with` block; it acts only on models
built by elastoactive (they carry the numeric `elastoactive_follower`), executes no Python per
step, and runs in parallel inside mujoco.rollout threads.
"""

from __future__ import annotations

import contextlib
import ctypes

import mujoco

from ..core.jit_cache import use_keyed_cache

use_keyed_cache()  # before any kernel module (hydro): numba reads its cache folder when first imported

from . import _follower  # noqa: E402
from .reference import reference_passive  # noqa: E402

_CALLBACK_TYPE = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)
_ACT_DYN_TYPE = ctypes.CFUNCTYPE(ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int)


def _check_version() -> None:
    built, running = _follower.header_version(), mujoco.mj_version()
    if built != running:
        raise RuntimeError(
            f"elastoactive's follower callback was compiled against MuJoCo {built} but MuJoCo {running} "
            "is running; reinstall elastoactive (pip install --force-reinstall --no-deps -e .)"
        )


_check_version()
compiled_passive = _CALLBACK_TYPE(_follower.passive_address())
"""The compiled passive callback, as a ctypes function pointer MuJoCo accepts."""
compiled_act_dyn = _ACT_DYN_TYPE(_follower.act_dyn_address())
"""The compiled activation dynamics of self-aligning units (dpsi/dt of each marked actuator: follower.c)."""


@contextlib.contextmanager
def follower_forces(callback=compiled_passive):
    """Install a passive callback (default: the compiled one) and the compiled act_dyn callback of self-aligning
    units, and restore the previous ones after."""
    previous, previous_act = mujoco.get_mjcb_passive(), mujoco.get_mjcb_act_dyn()
    mujoco.set_mjcb_passive(callback)
    mujoco.set_mjcb_act_dyn(compiled_act_dyn)
    try:
        yield
    finally:
        mujoco.set_mjcb_passive(previous)
        mujoco.set_mjcb_act_dyn(previous_act)


__all__ = ["compiled_act_dyn", "compiled_passive", "follower_forces", "reference_passive"]

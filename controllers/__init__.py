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

from . import _follower
from .reference import reference_passive

_CALLBACK_TYPE = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)


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


@contextlib.contextmanager
def follower_forces(callback=compiled_passive):
    """Install a passive callback (default: the compiled one) and restore the previous one after."""
    previous = mujoco.get_mjcb_passive()
    mujoco.set_mjcb_passive(callback)
    try:
        yield
    finally:
        mujoco.set_mjcb_passive(previous)


__all__ = ["compiled_passive", "follower_forces", "reference_passive"]

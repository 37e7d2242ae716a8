"""One BLAS thread while the implicit solvers run (plain ctypes; no numba, no scipy).

The implicit methods (scipy's Radau, BDF, LSODA) factorise an N x N matrix every few steps. At the sizes of the
reduced model (N <= 1000) a multi-threaded OpenBLAS gains little on an idle machine and loses badly on a busy
one: its threads spin while they wait for a core, and on 2 shared cores one LU of a 160 x 160 matrix was
measured at 13 ms instead of 0.2 ms (a whole beat of the N = 160 filament 2.7 s instead of 0.34 s).
`one_blas_thread` sets every OpenBLAS loaded in the process (numpy's and scipy's) to one thread and restores
the previous count afterwards. Where no OpenBLAS is found (another BLAS, or no /proc) it does nothing.

Finding the OpenBLAS libraries reads /proc/self/maps and opens each (a few ms); their controls are kept per process
and looked up again only when a module has been imported or removed since (`len(sys.modules)` changed): an OpenBLAS
is mapped by importing the extension module that links it (numpy, scipy.linalg), so the controls found hold until the
next import. A library loaded by other means (ctypes, with no import) is found at the next import.
"""

from __future__ import annotations

import ctypes
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import NamedTuple

__all__ = ["one_blas_thread"]

_PREFIXES = ("scipy_openblas", "openblas")
_SUFFIXES = ("64_", "")


class _Found(NamedTuple):
    """The OpenBLAS controls found, and the number of modules loaded when they were looked up."""

    modules: int
    controls: tuple[tuple[object, object], ...]


_found: list[_Found] = []
"""The last lookup of this process (empty: none yet)."""


def _mapped_openblas() -> list[str]:
    """Paths of the OpenBLAS libraries mapped into this process (none where /proc cannot be read)."""
    try:
        maps = Path("/proc/self/maps").read_text().splitlines()
    except OSError:
        return []
    return sorted({line.split()[-1] for line in maps if "openblas" in line.rsplit("/", 1)[-1].lower()})


def _find_controls() -> tuple[tuple[object, object], ...]:
    """(set_num_threads, get_num_threads) of every OpenBLAS mapped into this process, looked up now."""
    controls = []
    for path in _mapped_openblas():
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for prefix in _PREFIXES:
            for suffix in _SUFFIXES:
                setter = getattr(lib, f"{prefix}_set_num_threads{suffix}", None)
                getter = getattr(lib, f"{prefix}_get_num_threads{suffix}", None)
                if setter is not None and getter is not None:
                    setter.argtypes, getter.restype = [ctypes.c_int], ctypes.c_int
                    controls.append((setter, getter))
                    break
            else:
                continue
            break
    return tuple(controls)


def _openblas_controls() -> tuple[tuple[object, object], ...]:
    """(set_num_threads, get_num_threads) of every OpenBLAS mapped into this process: those found by the last lookup
    while no module has been imported or removed since, else looked up again (module docstring)."""
    modules = len(sys.modules)
    if not _found or _found[0].modules != modules:
        _found[:] = [_Found(modules, _find_controls())]
    return _found[0].controls


@contextmanager
def one_blas_thread():
    """Run the block with every OpenBLAS of the process on one thread; the previous counts come back after."""
    controls = _openblas_controls()
    before = [getter() for _, getter in controls]
    for setter, _ in controls:
        setter(1)
    try:
        yield
    finally:
        for (setter, _), count in zip(controls, before):
            setter(count)

"""Where numba keeps the compiled kernels: a cache folder keyed by the sources of every compiled module.

The kernels are compiled with cache=True. numba invalidates a cached function when its own file changes, but not
when a function it calls, in another file, changes: after an edit of elastoactive/reduced/kernels_extended.py, a cached
kernels.eval_rhs (which inlines it) would keep running the old code, silently; nor when the function comes from
another package (the fluid's kernel compiles in elastoactive.hydro's mobilities). So the cache lives in a folder
named by a digest of all the sources numba compiles (the packages of COMPILED_PACKAGES): any edit, upgrade or
checkout of another commit starts a fresh folder, and nothing stale is ever loaded.

`use_keyed_cache` runs when any package of COMPILED_PACKAGES is imported, before its kernel modules are (it imports
nothing heavy: numba reads NUMBA_CACHE_DIR when it is first imported, and the worker processes inherit it). A folder
given in NUMBA_CACHE_DIR by the user is kept as the base; the default base is the user's cache folder
($XDG_CACHE_HOME or ~/.cache)/elastoactive.
"""

from __future__ import annotations

import functools
import hashlib
import os
import sys
import tempfile
from pathlib import Path

ENV = "NUMBA_CACHE_DIR"
BASE_ENV = "ELASTOACTIVE_NUMBA_BASE"
"""The base folder chosen once per process tree (children see NUMBA_CACHE_DIR already keyed)."""


def source_digest(folders: list[Path]) -> str:
    """A digest of the contents of every .py file under the folders (sorted by path, so the same tree gives the
    same digest on every machine)."""
    digest = hashlib.sha256()
    for folder in folders:
        for path in sorted(folder.rglob("*.py")):
            digest.update(path.relative_to(folder).as_posix().encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


COMPILED_PACKAGES = ("reduced", "hydro", "controllers")
"""The packages of elastoactive that hold numba kernels; each calls use_keyed_cache in its __init__."""


def _compiled_sources() -> list[Path]:
    """The folders holding every module numba compiles: the packages of COMPILED_PACKAGES."""
    package = Path(__file__).resolve().parents[1]
    return [(package / name).resolve() for name in COMPILED_PACKAGES]


def default_base() -> Path:
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "elastoactive"


@functools.cache
def use_keyed_cache() -> Path:
    """Point numba's cache at base/numba-<digest of the compiled sources>; returns the folder (once per process:
    every package of COMPILED_PACKAGES calls it on import)."""
    base = Path(os.environ.get(BASE_ENV) or os.environ.get(ENV) or default_base())
    folder = base / f"numba-{source_digest(_compiled_sources())}"
    try:  # numba raises at a kernel's definition when it cannot create its cache folder
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:  # an unwritable home: a private folder under the temporary one
        base = Path(tempfile.gettempdir()) / f"elastoactive-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
        folder = base / folder.name
        folder.mkdir(parents=True, exist_ok=True)
    os.environ[BASE_ENV] = str(base)
    os.environ[ENV] = str(folder)
    config = sys.modules.get("numba.core.config")
    if config is not None:  # numba already imported (by the user): set its live setting too
        config.CACHE_DIR = str(folder)
    return folder

"""numba's on-disk cache is keyed by the compiled sources, so an edited kernel is never loaded stale."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from elastoactive.core import jit_cache


def test_the_digest_changes_with_any_source_and_only_with_them(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    (a / "sub").mkdir(parents=True)
    b.mkdir()
    (a / "sub" / "kernels.py").write_text("x = 1\n")
    (b / "callers.py").write_text("y = 2\n")
    (b / "notes.txt").write_text("not a source")
    first = jit_cache.source_digest([a, b])
    assert jit_cache.source_digest([a, b]) == first  # deterministic
    (b / "notes.txt").write_text("edited, still not a source")
    assert jit_cache.source_digest([a, b]) == first
    (a / "sub" / "kernels.py").write_text("x = 3\n")  # a callee in another file than its caller
    assert jit_cache.source_digest([a, b]) != first


def test_numba_caches_in_the_folder_of_the_current_sources(tmp_path):
    """In a fresh process, once a compiled package is imported (the mobilities here): numba's live setting and the
    workers' environment name the keyed folder, under the base the user gave."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    env.pop(jit_cache.BASE_ENV, None)
    code = (
        "import os, elastoactive.hydro, numba.core.config as c; from elastoactive.core import jit_cache as j;"
        "print(c.CACHE_DIR); print(os.environ['NUMBA_CACHE_DIR']); print(j.source_digest(j._compiled_sources()))"
    )
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    live, inherited, digest = out.stdout.split()
    assert live == inherited == str(tmp_path / f"numba-{digest}")
    assert Path(live).is_dir()
    assert {p.name for p in jit_cache._compiled_sources()} == set(jit_cache.COMPILED_PACKAGES)


def test_every_compiled_kernel_lives_in_the_keyed_folder():
    """The cache is keyed by the packages of COMPILED_PACKAGES alone: a numba kernel anywhere else would be cached
    unkeyed, and each of them sets the keyed folder when it is imported."""
    root = Path(jit_cache.__file__).resolve().parents[2]
    keyed = jit_cache._compiled_sources()
    outside = [
        str(path.relative_to(root))
        for folder in ("elastoactive", "analysis", "mjcf", "controllers")
        for path in (root / folder).rglob("*.py")
        if "from numba import" in path.read_text() and not any(path.resolve().is_relative_to(k) for k in keyed)
    ]
    assert not outside, outside
    for folder in keyed:
        assert "use_keyed_cache()" in (folder / "__init__.py").read_text(), folder

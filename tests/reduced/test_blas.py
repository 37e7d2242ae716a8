"""reduced.blas: the OpenBLAS controls are looked up once per process and again only after an import, which is what
maps a new OpenBLAS (scipy's beside numpy's)."""

from __future__ import annotations

import subprocess
import sys
import types

from elastoactive.reduced import blas


def test_the_controls_are_kept_until_a_module_is_imported(monkeypatch):
    reads = []
    found = blas._mapped_openblas

    def counted():
        reads.append(1)
        return found()

    monkeypatch.setattr(blas, "_mapped_openblas", counted)
    monkeypatch.setattr(blas, "_found", [])
    first = blas._openblas_controls()
    with blas.one_blas_thread():
        pass
    assert blas._openblas_controls() is first and len(reads) == 1
    monkeypatch.setitem(sys.modules, "elastoactive_test_blas_new_module", types.ModuleType("new"))
    assert len(blas._openblas_controls()) == len(first) and len(reads) == 2  # read again


SCRIPT = """
import sys
from elastoactive.reduced import blas
import numpy  # numpy's OpenBLAS
numpy_only = blas._openblas_controls()
import scipy.linalg  # scipy's own OpenBLAS, mapped by this import
both = blas._openblas_controls()
with blas.one_blas_thread():
    inside = [get() for _, get in both]
print(len(numpy_only), len(both), *inside)
"""


def test_an_openblas_loaded_later_is_set_to_one_thread():
    done = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    numpy_only, both, *inside = (int(word) for word in done.stdout.split())
    assert both == numpy_only + 1 and inside == [1] * both, done.stdout

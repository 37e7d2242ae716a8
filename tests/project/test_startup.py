"""What a whole process imports: a reduced run loads numpy and numba (whose kernel registry brings scipy.linalg in, for
its BLAS check) and nothing heavier; a MuJoCo sweep loads numpy, mujoco and the netCDF writer (h5netcdf, h5py) and
neither the reduced engine's packages nor the single run's front door; `elastoactive --help` loads no third-party
package at all.

Counted on the import tree of `python -X importtime` (each module under the module that imported it), so a failure
names who brought the module in. The figures of time are scripts/benchmark.py's (section B), not a test's.
"""

from __future__ import annotations

import os
import subprocess
import sys
from typing import NamedTuple

REDUCED_RUN = ("run", "one-pinned", "--engine", "reduced", "--duration", "50", "--quiet")
OWN_THIRD_PARTY = {"numpy", "numba"}
"""The third-party packages the package's own modules import during a reduced run."""
NEVER = ("mujoco", "glfw", "matplotlib", "PIL", "pandas", "xarray", "netCDF4", "h5py", "IPython")
"""Packages a reduced run never needs."""
SCIPY_BY_NUMBA = ("scipy.linalg",)
"""scipy's parts that numba's registry (numba.np.arraymath's BLAS check) imports when its first kernel loads."""


class Imported(NamedTuple):
    name: str
    importers: tuple[str, ...]
    """The chain of modules that imported it, innermost first (empty: imported at the top, by running code)."""


def _imports(args: tuple[str, ...], cwd) -> list[Imported]:
    """Every module `python -X importtime -m elastoactive args` imports, in order, with its importers, from the
    package's first on (the interpreter's start-up before it, site and its .pth hooks, is not the package's)."""
    done = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "elastoactive", *args],
        cwd=cwd,
        env={**os.environ, "MUJOCO_GL": "egl"},  # set, as a user's shell may: its check must not load MuJoCo
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    rows = []
    for line in done.stderr.splitlines():
        if line.startswith("import time:") and "|" in line and "cumulative" not in line:
            field = line.split("|")[2]
            rows.append((field.strip(), (len(field) - len(field.lstrip(" ")) - 1) // 2))
    assert len(rows) > 50, done.stderr[-2000:]
    out = []
    for i, (name, depth) in enumerate(rows):  # a module's line follows those of the modules it imported
        chain = []
        for later, level in rows[i + 1 :]:
            if level < depth:
                chain.append(later)
                depth = level
        out.append(Imported(name, tuple(chain)))
    first = next(i for i, m in enumerate(out) if any(_top(n) == "elastoactive" for n in (m.name, *m.importers)))
    return out[first:]


def _top(name: str) -> str:
    return name.split(".")[0]


def _third_party(name: str) -> bool:
    return _top(name) not in sys.stdlib_module_names and _top(name) not in ("elastoactive", "sitecustomize", "org")


def test_a_reduced_run_imports_numpy_and_numba_only(tmp_path):
    imported = _imports(REDUCED_RUN, tmp_path)
    names = {m.name for m in imported}
    assert "elastoactive.engines.reduced" in names and "numba" in names
    entries = [m for m in imported if _top(m.name) in NEVER and not (m.importers and _top(m.importers[0]) in NEVER)]
    assert not entries, "a reduced run imports " + "; ".join(f"{m.name} <- {' <- '.join(m.importers)}" for m in entries)
    own = {
        _top(m.name): m.importers[0]
        for m in imported
        if _third_party(m.name) and m.importers and m.importers[0].startswith("elastoactive")
    }
    assert set(own) <= OWN_THIRD_PARTY, f"the package imports {own} (package: importer)"
    for m in imported:  # scipy comes in through numba alone
        if _top(m.name) == "scipy" and not (m.importers and _top(m.importers[0]) == "scipy"):
            assert m.importers and _top(m.importers[0]) == "numba", f"{m.name} <- {' <- '.join(m.importers)}"
    parts = {".".join(n.split(".")[:2]) for n in names if n.startswith("scipy.") and n.split(".")[1][0] != "_"}
    assert parts <= {"scipy.version", *SCIPY_BY_NUMBA}, sorted(parts)


MUJOCO_SWEEP = ("sweep", "one-pinned", "--grid", "sigma=0.3:1.0:4", "--duration", "5", "--quiet")
SWEEP_OWN_THIRD_PARTY = {"numpy", "mujoco", "h5netcdf"}
"""The third-party packages the package's own modules import during a MuJoCo sweep: the engine and the netCDF file's
writer (what these import in turn is theirs, SWEEP_NEVER aside)."""
SWEEP_NEVER = ("scipy", "numba", "xarray", "pandas", "netCDF4", "matplotlib", "PIL", "glfw", "IPython", "dask")
"""Packages a MuJoCo sweep never needs: the reduced engine's (numba, scipy), the Dataset's (xarray, pandas: the command
reports from the points' status, not a Dataset), another writer, plotting, a cluster's scheduler."""
SWEEP_NOT_OWN = ("api", "explore", "records", "saving", "starts", "plugins", "engines.reduced", "reduced.solve")
"""The package's modules a command-line MuJoCo sweep does not load: the single run's front door (ea.simulate's
conversions, records, folders, starts), the plug-ins' recording, the reduced engine and its solvers. The whole process
is held (what comes before the first step is a part of it)."""


def _loaded_at_exit(args: tuple[str, ...], cwd) -> set[str]:
    """Every module in sys.modules once `elastoactive args` has run in a fresh process: what the import tree misses too
    (a submodule imported by `from package import module` or importlib.import_module is not timed by -X importtime)."""
    script = f"import sys\nfrom elastoactive.cli import main\nassert main({list(args)!r}) == 0\nprint(*sys.modules)"
    done = subprocess.run([sys.executable, "-c", script], cwd=cwd, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return set(done.stdout.split())


def test_a_mujoco_sweep_imports_the_engine_and_the_writer_only(tmp_path):
    imported = _imports((*MUJOCO_SWEEP, "--out", str(tmp_path / "tree.nc")), tmp_path)
    assert {"mujoco", "elastoactive.engines.mujoco_batch", "h5netcdf"} <= {m.name for m in imported}
    entries = [m for m in imported if _top(m.name) in SWEEP_NEVER]
    assert not entries, "a sweep imports " + "; ".join(f"{m.name} <- {' <- '.join(m.importers)}" for m in entries[:5])
    own = {
        _top(m.name): m.importers[0]
        for m in imported
        if _third_party(m.name) and m.importers and m.importers[0].startswith("elastoactive")
    }
    assert set(own) <= SWEEP_OWN_THIRD_PARTY, f"the package imports {own} (package: importer)"
    loaded = _loaded_at_exit((*MUJOCO_SWEEP, "--out", str(tmp_path / "all.nc")), tmp_path)  # untimed imports too
    assert "elastoactive.engines.mujoco_batch" in loaded
    assert not sorted(n for n in loaded if _top(n) in SWEEP_NEVER)
    assert not sorted(n for n in loaded if n.removeprefix("elastoactive.") in SWEEP_NOT_OWN)


def test_help_imports_no_third_party_package(tmp_path):
    imported = _imports(("--help",), tmp_path)
    assert not sorted({_top(m.name) for m in imported if _third_party(m.name)})

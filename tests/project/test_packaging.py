"""The package installs the way users install packages: a built wheel, non-editable, in a fresh environment.

pyproject.toml finds the packages (`[tool.setuptools.packages.find]`: every folder with an __init__.py under
elastoactive/, the design's top-level folders mjcf/, controllers/ and analysis/ through the links elastoactive/mjcf ->
../mjcf and so on); the checks here hold what discovery finds to the tree and install the wheel into a new virtual
environment that sees none of the checkout, then run the command and the import from outside it.
"""

from __future__ import annotations

import os
import subprocess
import sys
import sysconfig
import tomllib
from pathlib import Path

import pytest
from setuptools import find_packages

ROOT = Path(__file__).resolve().parents[2]
CONFIG = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]


DESIGN = ("mjcf", "controllers", "analysis")
"""The design's top-level folders, each a sub-package of elastoactive."""


def _tree_packages() -> set[str]:
    """Package names of every folder holding an __init__.py under elastoactive/, its links followed."""
    found = set()
    for folder, dirs, files in os.walk(ROOT / "elastoactive", followlinks=True):
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        if "__init__.py" in files:
            found.add(".".join(Path(folder).relative_to(ROOT).parts))
    return found


def test_discovery_finds_the_tree():
    """pyproject's package discovery (no hand list) finds every package of the tree, the design's folders among them."""
    found = set(find_packages(str(ROOT), include=CONFIG["packages"]["find"]["include"]))
    assert found == _tree_packages(), found ^ _tree_packages()
    assert {f"elastoactive.{name}" for name in DESIGN} | {"elastoactive.analysis.network", "elastoactive.core"} <= found


@pytest.mark.parametrize("name", DESIGN)
def test_the_design_folders_are_linked_into_the_package(name):
    """mjcf/, controllers/ and analysis/ stay at the top level, where the design puts them; elastoactive/<name> is a
    relative link to each, so that a checkout moved elsewhere still imports them."""
    link = ROOT / "elastoactive" / name
    assert link.is_symlink() and not Path(os.readlink(link)).is_absolute(), f"elastoactive/{name} is not a link"
    assert link.resolve() == (ROOT / name).resolve()


@pytest.mark.slow
def test_wheel_installs_and_runs_outside_the_checkout(tmp_path):
    """Build the wheel as `pip wheel .` does, install it non-editable into a fresh venv (its dependencies taken
    from this environment's site-packages, without this environment's editable install), then run `elastoactive
    run` and `import elastoactive` from a folder outside the checkout."""
    wheels = tmp_path / "wheels"
    build = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", str(ROOT), "--no-deps", "-q", "-w", str(wheels)],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert build.returncode == 0, build.stdout + build.stderr
    (wheel,) = wheels.glob("elastoactive-*.whl")

    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=120)
    python = venv / "bin" / "python"
    purelib = Path(
        subprocess.run(
            [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    )
    # the dependencies (numpy, mujoco, ...) from this environment: a plain path entry, so that its .pth files
    # (among them the editable install's finder) are not run
    (purelib / "_deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    install = subprocess.run(
        [sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps", "-q", str(wheel)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert install.returncode == 0, install.stdout + install.stderr

    outside = tmp_path / "elsewhere"
    outside.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    where = subprocess.run(
        [
            str(python),
            "-c",
            "import elastoactive as ea, elastoactive.engines, elastoactive.cli; "
            "print(ea.__file__); print(ea.scenes.names())",
        ],
        cwd=outside,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert where.returncode == 0, where.stderr
    location = Path(where.stdout.splitlines()[0]).resolve()
    assert location.is_relative_to(venv.resolve()), f"imported from {location}, not from the installed wheel"
    assert ROOT not in location.parents
    # typed (PEP 561) and licensed: the marker is installed beside the package, the license in its metadata
    assert (location.parent / "py.typed").is_file()
    (dist_info,) = location.parent.parent.glob("elastoactive-*.dist-info")
    assert "MIT License" in next(dist_info.rglob("LICENSE")).read_text()

    run = subprocess.run(
        [str(venv / "bin" / "elastoactive"), "run", "one-pinned", "--duration", "2", "--out", "beat"],
        cwd=outside,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert (outside / "beat" / "summary.json").is_file()

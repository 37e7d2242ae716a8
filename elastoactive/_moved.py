"""Old import paths of modules that moved into sub-packages: they keep working, with a warning, through the 0.1
releases (REMOVED_IN: they go in 0.2.0; docs/changelog.md lists them).

`MOVED` maps each old dotted name to its new one. `install` puts a finder on sys.meta_path that answers an import
of an old name with the new module itself (the same module object, so its private names, monkeypatching and
identity checks all behave as before) and emits a DeprecationWarning naming the new path.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings

REMOVED_IN = "0.2.0"
"""The release that drops the old names: they work, with a DeprecationWarning, in every 0.1 release."""

MOVED = {
    "elastoactive.sweep_grid": "elastoactive.sweep.grid",
    "elastoactive.sweep_netcdf": "elastoactive.sweep.netcdf",
    "elastoactive.sweep_points": "elastoactive.sweep.points",
    "elastoactive.sweep_runners": "elastoactive.sweep.runners",
    "elastoactive.sweep_store": "elastoactive.sweep.store",
    "elastoactive.render_gl": "elastoactive.render.gl",
    "elastoactive.render_network": "elastoactive.render.network",
    "elastoactive.validate": "elastoactive.checks.validate",
    "elastoactive.accuracy": "elastoactive.checks.accuracy",
    "elastoactive.extremes": "elastoactive.checks.extremes",
    "elastoactive.reproduce": "elastoactive.report.reproduce",
    "elastoactive.claims": "elastoactive.report.claims",
    "elastoactive.paper": "elastoactive.studies.paper",
    "elastoactive.report.paper": "elastoactive.studies.paper",
    "elastoactive.outputs": "elastoactive.io.outputs",
    "elastoactive.jsonio": "elastoactive.io.jsonio",
    "elastoactive.executor": "elastoactive.io.executor",
    "elastoactive.progress": "elastoactive.io.progress",
    "elastoactive.warm": "elastoactive.cli.warm",
    "elastoactive.diagnose": "elastoactive.engines.timestep",
    "elastoactive.regime": "elastoactive.engines.regime",
    "elastoactive.noise": "elastoactive.controllers.noise",
    "elastoactive.model": "elastoactive.mjcf.chain",
    "elastoactive.network_model": "elastoactive.mjcf.network",
    "elastoactive.engines.node_kernels": "elastoactive.reduced.node_kernels",
    "elastoactive.analysis.jit_cache": "elastoactive.core.jit_cache",
    "elastoactive.reduced.jit_cache": "elastoactive.core.jit_cache",
    "elastoactive.analysis.network.model": "elastoactive.reduced.network",
    "elastoactive.analysis.network.geometry": "elastoactive.networks.geometry",
    "elastoactive.analysis.network.initial": "elastoactive.networks.state",
    "elastoactive.analysis.reduced": "elastoactive.reduced",
    "elastoactive.errors": "elastoactive.core.errors",
    "elastoactive.constants": "elastoactive.core.constants",
    "elastoactive.table": "elastoactive.core.table",
    "elastoactive.units": "elastoactive.core.units",
    "elastoactive.parameters": "elastoactive.core.parameters",
    "elastoactive.observables": "elastoactive.core.observables",
    "elastoactive.registry": "elastoactive.core.registry",
    "elastoactive.cases": "elastoactive.core.cases",
    "elastoactive.trajectory": "elastoactive.core.trajectory",
    "elastoactive.params": "elastoactive.core.params",
    "elastoactive.initial": "elastoactive.reduced.initial",
}
"""Old module name -> new module name (a moved package's sub-modules follow it: analysis.reduced.x -> reduced.x)."""


def new_name(old: str) -> str | None:
    """Where the module once called `old` lives now (None: it did not move)."""
    for moved, new in MOVED.items():
        if old == moved or old.startswith(moved + "."):
            return new + old[len(moved) :]
    return None


class _Alias(importlib.abc.Loader):
    def __init__(self, new: str):
        self.new = new

    def create_module(self, spec):
        return importlib.import_module(self.new)

    def exec_module(self, module):
        """The module is the new one, already executed."""


class MovedFinder(importlib.abc.MetaPathFinder):
    """Imports of an old name load the new module (with a DeprecationWarning)."""

    def find_spec(self, fullname, path=None, target=None):
        new = new_name(fullname)
        if new is None:
            return None
        warnings.warn(
            f"{fullname} has moved to {new}; the old name works in 0.1.x and is removed in elastoactive {REMOVED_IN}",
            DeprecationWarning,
            stacklevel=3,
        )
        module = importlib.import_module(new)
        return importlib.machinery.ModuleSpec(fullname, _Alias(new), is_package=hasattr(module, "__path__"))


def install() -> None:
    """Put the finder first on sys.meta_path, once: it answers old names only, which no module of the new tree has (a
    left-over folder of compiled files under an old path would otherwise be found as an empty namespace package)."""
    if not any(isinstance(f, MovedFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, MovedFinder())

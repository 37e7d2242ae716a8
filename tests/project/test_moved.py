"""Modules that moved into sub-packages keep their old import paths for one release, with a DeprecationWarning."""

from __future__ import annotations

import importlib
import sys
import warnings

import pytest

from elastoactive import _moved


@pytest.mark.parametrize("old", sorted(_moved.MOVED))
def test_an_old_path_gives_the_new_module_with_a_warning(old):
    sys.modules.pop(old, None)
    with pytest.warns(DeprecationWarning, match=_moved.MOVED[old].replace(".", r"\.")):
        module = importlib.import_module(old)
    assert module is importlib.import_module(_moved.MOVED[old])


def test_a_sub_module_of_a_moved_package_follows_it():
    sys.modules.pop("elastoactive.analysis.reduced.kernels", None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        from elastoactive.analysis.reduced import kernels
    assert kernels is importlib.import_module("elastoactive.reduced.kernels")


def test_the_new_tree_never_imports_an_old_path():
    """Nothing of the package itself goes through the aliases: importing every new module warns about none."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        for name in (
            "elastoactive",
            "elastoactive.cli",
            "elastoactive.sweep",
            "elastoactive.render",
            "elastoactive.checks.validate",
            "elastoactive.report.reproduce",
            "elastoactive.cli.warm",
        ):
            importlib.import_module(name)

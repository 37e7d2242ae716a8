"""The fluid studies' test modules import their study inside a fixture and leave the study registry as they found it:
a study module that is not yet one of the built-ins (studies/__init__.py) registers itself on import, and its budget
would then count in every test of the same process that sums the registered budgets (tests/studies/test_registry.py).
Once it is a built-in it was registered before the fixture ran, and stays."""

from __future__ import annotations

import importlib
from collections.abc import Iterator
from types import ModuleType

from elastoactive.studies import registry


def study_module(name: str) -> Iterator[ModuleType]:
    """elastoactive.studies.<name>, its registration undone afterwards unless it was registered before."""
    before = name in registry.names()
    module = importlib.import_module(f"elastoactive.studies.{name}")
    if name not in registry.names():  # imported, then unregistered, by an earlier module of this process
        module = importlib.reload(module)
    try:
        yield module
    finally:
        if not before:
            registry.STUDIES.unregister(name)

"""The scene registry: every scene is one module here, registered under its name.

    import elastoactive as ea
    ea.scenes.names()                 # ('one-pinned', 'two-pinned', 'rotating-pin', ...): every registered scene
    scene = ea.scenes.get("two-pinned")
    scene.parameters, scene.observables, scene.validation_cases()

A new scene is a subclass of a kind of scene, `ChainScene` or `NetworkScene` (the contract: elastoactive.scenes.base),
registered with `register`;
the CLI, sweeps, validate, render, accuracy and the stability grid then offer it. See
docs/scenes.md for the contract and the diff a new scene needs.
"""

import importlib

from ..core.registry import UnknownScene, get, names, register, scenes, unregister
from .base import Scene, ValidationCase
from .chain_kind import ChainScene
from .network_kind import NetworkScene

BUILT_IN = (
    "one_pinned",
    "two_pinned",
    "rotating_pin",
    "coupled_pair",
    "paraboloid",
    "ring",
    "lattice",
    "trap",
    "star",
    "network",
    "clamped3d",
    "pivot3d",
    "cilium",
    "cilia_pair",
    "cilia_row",
)
"""The package's own scenes: the modules whose `SCENE` registers, in the paper's order, then ours. The command line's
--help reads this list and the scenes' names and summaries from source (elastoactive.cli.catalogue)."""

_modules = [importlib.import_module(f".{name}", __name__) for name in BUILT_IN]
for _module in _modules:  # once all are imported: the scenes' own specs follow the chain's and the terms'
    register(_module.SCENE)

__all__ = [
    "ChainScene",
    "NetworkScene",
    "Scene",
    "UnknownScene",
    "ValidationCase",
    "get",
    "names",
    "register",
    "scenes",
    "unregister",
]

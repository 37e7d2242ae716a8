"""The scene registry's table: scene name -> Scene object (a `Registry`, elastoactive.core.table: the one registry type
that parameters, scenes, terms and studies share).

A leaf module but for the parameter and observable tables, where a scene's specs are registered with it, so that
`params` can look a scene up while the scene modules themselves import `params`. Scenes enter the table through
`register`; the built-in ones when `elastoactive.scenes` is imported, which `import elastoactive` does first; those of
the `elastoactive.scenes` entry points when the table is first listed (elastoactive.core.table.load_entry_points).
`elastoactive.scenes` is the public face of this table.
"""

from __future__ import annotations

from typing import Protocol

from . import observables as _observables
from . import parameters as _parameters
from .table import ENTRY_POINT_GROUPS, Registry, UnknownName, entry_points_ready, load_entry_points


class Scene(Protocol):
    """What the table needs of a scene: its name and its kind (the full contract: elastoactive.scenes.base.Scene)."""

    name: str
    kind: str


class UnknownScene(UnknownName):
    """Raised by `get` for a name that no scene registered (params turns it into a ParameterError)."""

    kind, kinds = "scene", "scenes"


def _adopt(scene: Scene) -> None:
    """Register an entry point's scene unless it registered itself on import; refuse what is not a scene."""
    if not callable(getattr(scene, "run_mujoco", None)):
        raise TypeError(f"{type(scene).__name__} is not a scene (elastoactive.scenes.Scene)")
    if getattr(scene, "name", None) not in SCENES:
        register(scene)


SCENES: Registry[Scene] = Registry("scene", error=UnknownScene, group="scenes", adopt=_adopt, built_ins=True)
"""The scenes, in registration order."""


def register(scene: Scene, *, replace: bool = False) -> Scene:
    """Add a scene to the registry under `scene.name`, with the parameter and observable specs it declares; returns it
    (usable as a decorator on instances). A scene of no kind (a direct subclass of Scene) is refused in one line."""
    name = SCENES.admit(scene, replace=replace)
    if not getattr(scene, "kind", ""):
        raise TypeError(
            f"scene {name!r} is of no kind: subclass elastoactive.scenes.ChainScene (chains) or NetworkScene (an "
            "elastic network), not Scene"
        )
    for spec in getattr(scene, "parameters", ()):  # the scene's own parameter specs (names refer to declared ones)
        if isinstance(spec, _parameters.Parameter):
            _parameters.register(spec, f"scene {name}")
        elif not _parameters.known(spec):
            raise ValueError(
                f"scene {name!r} names the parameter {spec!r}, which nothing declares "
                "(declare it as an elastoactive.core.parameters.Parameter in the scene's parameters)"
            )
    declared = (*getattr(scene, "observables", ()), *getattr(scene, "occasional_observables", ()))
    _observables.declare(declared, f"scene {name}")  # its specs, or names of declared ones
    return SCENES.register(scene, owner=f"scene {name}", replace=True)


def unregister(name: str) -> None:
    """Remove a scene and the parameter and observable specs it declared (a test's toy scene cleans up with this)."""
    scene = SCENES.unregister(name)
    for spec in getattr(scene, "parameters", ()):
        if (
            isinstance(spec, _parameters.Parameter)
            and _parameters.known(spec.name)
            and _parameters.owner(spec.name) == f"scene {name}"
        ):
            _parameters.unregister(spec.name)
    declared = (*getattr(scene, "observables", ()), *getattr(scene, "occasional_observables", ()))
    _observables.withdraw(declared, f"scene {name}")


def get(name: str) -> Scene:
    """The registered scene called `name` (the entry points' scenes included)."""
    return SCENES.get(name)


def names() -> tuple[str, ...]:
    """Names of the registered scenes (the entry points' included), in registration order."""
    return SCENES.names()


def scenes() -> tuple[Scene, ...]:
    """The registered scenes (the entry points' included), in registration order."""
    return SCENES.entries()


__all__ = [
    "ENTRY_POINT_GROUPS",
    "SCENES",
    "Scene",
    "UnknownName",
    "UnknownScene",
    "entry_points_ready",
    "get",
    "load_entry_points",
    "names",
    "register",
    "scenes",
    "unregister",
]


def initial_angles(physics, numerics):
    """Absolute angles theta_i at t = 0 of a scene (chain 1 then chain 2 for the pair): its choice
    (Scene.initial_angles, from the start shapes of elastoactive.reduced.initial)."""
    return get(physics.scene).initial_angles(physics, numerics)

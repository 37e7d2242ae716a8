"""The scene registry's table: scene name -> Scene object (and UnknownName, what every registry raises for a name
it does not hold).

A leaf module (it imports nothing of the package but the parameter and observable tables, where a scene's specs are
registered with it), so that `params` can look a scene up while the scene modules themselves import `params`. Scenes
enter the table through `register`; the built-in ones when `elastoactive.scenes` is imported, which `import
elastoactive` does first; those of the `elastoactive.scenes` entry points when the table is first listed
(`load_entry_points`, which the term and study registries share).
`elastoactive.scenes` is the public face of this table.
"""

from __future__ import annotations

import importlib.metadata
import types
import warnings
from typing import Protocol

from . import observables as _observables
from . import parameters as _parameters


class Scene(Protocol):
    """What the table needs of a scene: its name (the full contract: elastoactive.scenes.base.Scene)."""

    name: str


_SCENES: dict[str, Scene] = {}


ENTRY_POINT_GROUPS = {"scenes": "elastoactive.scenes", "terms": "elastoactive.terms", "studies": "elastoactive.studies"}
"""The entry-point group of each registry: a distribution's entry point names a module (importing it registers what
it defines) or a Scene or Term (an instance, or a class to instantiate), which its registry registers."""
_entry_points = {"ready": False, "loaded": set()}
"""Whether `import elastoactive` has finished (a plug-in imports the package itself), and the groups loaded."""


def entry_points_ready() -> None:
    """Let the entry points load from now on (`import elastoactive` calls this once the package is whole)."""
    _entry_points["ready"] = True


def load_entry_points(kind: str, register_object=None) -> None:
    """Load the entry points of registry `kind` ("scenes", "terms" or "studies"), once, when the package is whole;
    `register_object(obj)` registers what an entry point names unless it is a module. A plug-in that fails to load
    is skipped with a RuntimeWarning naming it (a broken third-party package does not stop the others)."""
    if not _entry_points["ready"] or kind in _entry_points["loaded"]:
        return
    _entry_points["loaded"].add(kind)  # before loading: a plug-in that lists the registry does not load it again
    for point in importlib.metadata.entry_points(group=ENTRY_POINT_GROUPS[kind]):
        try:
            obj = point.load()
            if register_object is not None and not isinstance(obj, types.ModuleType):
                register_object(obj() if isinstance(obj, type) else obj)
        except Exception as err:  # noqa: BLE001  (any plug-in's failure is reported, not raised)
            warnings.warn(
                f"elastoactive: the {ENTRY_POINT_GROUPS[kind]} entry point {point.name!r} ({point.value}) did not "
                f"load: {err}",
                RuntimeWarning,
                stacklevel=3,
            )


class UnknownName(KeyError):
    """A name that no entry of a registry (scenes, terms, studies) holds; its message lists the names that are, as
    registered when it was raised. A KeyError (a registry is a table); the name is its argument."""

    kind, kinds = "entry", "entries"

    def __init__(self, name, names: tuple[str, ...] = ()):
        super().__init__(name)
        self.name, self.names = name, tuple(names)

    def __str__(self) -> str:
        listed = ", ".join(self.names) if self.names else "none"
        return f"no {self.kind} called {self.name!r}; the registered {self.kinds}: {listed}"


class UnknownScene(UnknownName):
    """Raised by `get` for a name that no scene registered (params turns it into a ParameterError)."""

    kind, kinds = "scene", "scenes"


def register(scene: Scene, *, replace: bool = False) -> Scene:
    """Add a scene to the registry under `scene.name`; returns it (usable as a decorator on instances)."""
    name = getattr(scene, "name", None)
    if not isinstance(name, str) or not name:
        raise ValueError(f"a scene needs a non-empty string `name`, got {name!r}")
    if name in _SCENES and not replace and _SCENES[name] is not scene:
        raise ValueError(f"a scene named {name!r} is already registered (pass replace=True to replace it)")
    for spec in getattr(scene, "parameters", ()):  # the scene's own parameter specs (names refer to declared ones)
        if isinstance(spec, _parameters.Parameter):
            _parameters.register(spec, f"scene {name}")
        elif not _parameters.known(spec):
            raise ValueError(
                f"scene {name!r} names the parameter {spec!r}, which nothing declares "
                "(declare it as an elastoactive.parameters.Parameter in the scene's parameters)"
            )
    declared = (*getattr(scene, "observables", ()), *getattr(scene, "occasional_observables", ()))
    _observables.declare(declared, f"scene {name}")  # its specs, or names of declared ones
    _SCENES[name] = scene
    return scene


def unregister(name: str) -> None:
    """Remove a scene and the parameter and observable specs it declared (a test's toy scene cleans up with this)."""
    scene = _SCENES.pop(name, None)
    for spec in getattr(scene, "parameters", ()):
        if (
            isinstance(spec, _parameters.Parameter)
            and _parameters.known(spec.name)
            and _parameters.owner(spec.name) == f"scene {name}"
        ):
            _parameters.unregister(spec.name)
    declared = (*getattr(scene, "observables", ()), *getattr(scene, "occasional_observables", ()))
    _observables.withdraw(declared, f"scene {name}")


def _register_new(scene: Scene) -> None:
    """Register an entry point's scene unless it registered itself on import; refuse what is not a scene."""
    if not callable(getattr(scene, "chain_count", None)):
        raise TypeError(f"{type(scene).__name__} is not a scene (elastoactive.scenes.Scene)")
    if getattr(scene, "name", None) not in _SCENES:
        register(scene)


def _plugins() -> None:
    """The scenes of the `elastoactive.scenes` entry points, loaded the first time the registry is listed."""
    load_entry_points("scenes", _register_new)


def get(name: str) -> Scene:
    """The registered scene called `name` (the entry points' scenes included)."""
    try:
        return _SCENES[name]
    except (KeyError, TypeError):
        pass
    _plugins()
    try:
        return _SCENES[name]
    except (KeyError, TypeError):
        raise UnknownScene(name, names()) from None


def names() -> tuple[str, ...]:
    """Names of the registered scenes (the entry points' included), in registration order."""
    _plugins()
    return tuple(_SCENES)


def scenes() -> tuple[Scene, ...]:
    """The registered scenes (the entry points' included), in registration order."""
    _plugins()
    return tuple(_SCENES.values())

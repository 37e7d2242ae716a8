"""One registry type: a table of named entries with one way to register, look up, list and refuse an unknown name.

The package's four registries are instances of `Registry`: the parameter specs (elastoactive.core.parameters), the
scenes (elastoactive.core.registry), the terms (elastoactive.core.term_registry) and the studies
(elastoactive.studies.registry). Each entry is kept with its owner (who declared it: 'term contact', 'scene ring');
registering the same entry again is a no-op, another entry under a taken name is refused unless replace=True; an unknown
name raises the registry's UnknownName (a KeyError) whose message is one line listing the names that are. A registry
with an entry-point group loads the plug-ins of that group (`load_entry_points`) the first time it is asked for a name
it does not hold or listed. The package's own entries (its scenes and terms, with their parameters and observables)
join when a registry is first read (`load_built_ins`): `import elastoactive` imports neither, so that what needs no
scene (the command line's --help, a script that reads one record) does not load numpy and the engines.

A leaf module: it imports nothing of the package, so that every registry can use it.
"""

from __future__ import annotations

import importlib
import os
import re
import sys
import types
import warnings
from collections.abc import Callable, Iterator
from typing import Generic, TypeVar

T = TypeVar("T")

ENTRY_POINT_GROUPS = {"scenes": "elastoactive.scenes", "terms": "elastoactive.terms", "studies": "elastoactive.studies"}
"""The entry-point group of each registry: a distribution's entry point names a module (importing it registers what
it defines) or a Scene or Term (an instance, or a class to instantiate), which its registry registers."""
BUILT_INS = {"terms": "elastoactive.terms", "scenes": "elastoactive.scenes"}
"""The package's own entries: the module whose import registers its terms, and its scenes (each with the parameter and
observable specs it declares), imported in this order: the chain's specs, the terms', the scenes'."""
_built_ins = {"loaded": False}
"""Whether the package's own entries are registered, or registering (load_built_ins)."""
_entry_points = {"ready": False, "loaded": set()}
"""Whether `import elastoactive` has finished (a plug-in imports the package itself), and the groups loaded."""


def entry_points_ready() -> None:
    """Let the entry points load from now on (`import elastoactive` calls this once the package is whole)."""
    _entry_points["ready"] = True


def load_built_ins() -> None:
    """Import the package's own scenes and terms (BUILT_INS), once: what a registry's first read needs. Marked before
    the import, so that a read while they import (a scene module looking up a parameter) sees what is registered so
    far and does not start it again; the order of registration is that of the imports, whichever registry is read
    first. An import that fails is raised, and the next read tries again (never a table silently short)."""
    if not _built_ins["loaded"]:
        _built_ins["loaded"] = True
        try:
            for module in BUILT_INS.values():
                importlib.import_module(module)
        except BaseException:
            _built_ins["loaded"] = False
            raise


def built_ins_loaded() -> bool:
    """Whether the package's own scenes and terms are registered, or registering (load_built_ins)."""
    return _built_ins["loaded"]


_PATH_FINDERS = ("_frozen_importlib_external.PathFinder", "importlib_metadata.MetadataPathFinder")
"""The finders of distributions that look where declares_entry_points looks (the folders of sys.path): Python's own,
and the importlib_metadata backport's, which a dependency may have installed."""


def declares_entry_points(kind: str) -> bool:
    """Whether an installed distribution may declare entry points of registry `kind`, answered in a few milliseconds
    without importlib.metadata (which takes ~40 ms to import): False only when no distribution folder (*.dist-info,
    *.egg-info) in a folder of sys.path names the group in its entry_points.txt, no entry of sys.path is an archive
    and no import finder but those of _PATH_FINDERS finds distributions; True otherwise (load_entry_points then reads
    them)."""
    header = re.compile(rf"^\s*\[\s*{re.escape(ENTRY_POINT_GROUPS[kind])}\s*\]", re.MULTILINE)
    for finder in sys.meta_path:
        cls = finder if isinstance(finder, type) else type(finder)
        if hasattr(finder, "find_distributions") and f"{cls.__module__}.{cls.__qualname__}" not in _PATH_FINDERS:
            return True
    for entry in sys.path:
        if os.path.isfile(entry):
            return True
        try:
            folders = [e.path for e in os.scandir(entry or ".") if e.name.endswith((".dist-info", ".egg-info"))]
        except OSError:
            continue
        for folder in folders:
            try:
                with open(os.path.join(folder, "entry_points.txt"), encoding="utf-8", errors="replace") as text:
                    if header.search(text.read()):
                        return True
            except OSError:
                continue
    return False


def load_entry_points(kind: str, register_object=None) -> None:
    """Load the entry points of registry `kind` ("scenes", "terms" or "studies"), once, when the package is whole;
    `register_object(obj)` registers what an entry point names unless it is a module. A plug-in that fails to load
    is skipped with a RuntimeWarning naming it (a broken third-party package does not stop the others)."""
    if not _entry_points["ready"] or kind in _entry_points["loaded"]:
        return
    _entry_points["loaded"].add(kind)  # before loading: a plug-in that lists the registry does not load it again
    import importlib.metadata  # the plug-in boundary: reading the installed distributions' metadata costs ~40 ms

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
    """A name that no entry of a registry holds; its message lists the names that are, as registered when it was
    raised. A KeyError (a registry is a table); the name is its argument."""

    kind, kinds = "entry", "entries"

    def __init__(self, name, names: tuple[str, ...] = ()):
        super().__init__(name)
        self.name, self.names = name, tuple(names)

    def __str__(self) -> str:
        listed = ", ".join(self.names) if self.names else "none"
        return f"no {self.kind} called {self.name!r}; the registered {self.kinds}: {listed}"


class Registry(Generic[T]):
    """A table of named entries (module docstring).

    kind, kinds   what an entry is called in messages ('scene', 'scenes')
    error         the UnknownName subclass `get` raises (default: one made for `kind`)
    group         the entry-point group whose plug-ins join on first need ("scenes", ...), or None
    built_ins     whether the package's own scenes and terms hold or declare entries of this registry: they are
                  imported before its first read (load_built_ins; registering is no read: their modules register)
    adopt         adopt(obj): registers what an entry point names (a Scene, a Term); checks it is one
    order         key of `entries` and `names` (default: registration order)
    same          same(known, entry): whether registering `entry` under a name `known` holds is the same entry again
                  (a no-op; default: the same object, or an equal one)
    replaceable   whether its register takes replace=True (a refusal says so)
    """

    def __init__(
        self,
        kind: str,
        kinds: str | None = None,
        *,
        error: type[UnknownName] | None = None,
        group: str | None = None,
        adopt: Callable[[object], None] | None = None,
        order: Callable[[T], float] | None = None,
        same: Callable[[T, T], bool] = lambda known, entry: known is entry or known == entry,
        replaceable: bool = True,
        built_ins: bool = False,
    ):
        self.kind, self.kinds = kind, kinds or f"{kind}s"
        self.error = error or type(f"Unknown{kind.title()}", (UnknownName,), {"kind": kind, "kinds": self.kinds})
        self.group, self.adopt, self.order, self.same, self.replaceable = group, adopt, order, same, replaceable
        self.built_ins = built_ins
        self._table: dict[str, tuple[T, str]] = {}

    @property
    def _read(self) -> dict[str, tuple[T, str]]:
        """The table, once the package's own entries are in it (load_built_ins)."""
        if self.built_ins:
            load_built_ins()
        return self._table

    # ------------------------------------------------------------------ register
    def admit(self, entry: T, name: str | None = None, replace: bool = False) -> str:
        """The name `entry` would be registered under (default entry.name), or a ValueError saying why it cannot be: no
        name, or a name another entry holds (unless replace=True). Registers nothing."""
        name = getattr(entry, "name", None) if name is None else name
        if not isinstance(name, str) or not name:
            raise ValueError(f"a {self.kind} needs a non-empty string `name`, got {name!r}")
        known = self._table.get(name)
        if known is not None and not replace and not self.same(known[0], entry):
            by = f"declared by {known[1]}" if known[1] else "registered"
            hint = " (pass replace=True to replace it)" if self.replaceable else ""
            raise ValueError(f"a {self.kind} named {name!r} is already {by}{hint}")
        return name

    def register(self, entry: T, *, name: str | None = None, owner: str = "", replace: bool = False) -> T:
        """Add `entry` under `name` (default entry.name), declared by `owner`; returns it. The same entry again is a
        no-op (its first owner kept); another entry under a taken name is refused unless replace=True (admit)."""
        name = self.admit(entry, name, replace)
        if name not in self._table or replace:
            self._table[name] = (entry, owner)
        return entry

    def unregister(self, name: str) -> T | None:
        """Remove the entry called `name` (a test's toy cleans up with this); returns it, or None if there was none."""
        known = self._read.pop(name, None)
        return None if known is None else known[0]

    # ------------------------------------------------------------------ look up
    def _plugins(self) -> None:
        if self.built_ins:  # the package's own first: a plug-in may replace one of them
            load_built_ins()
        if self.group is not None:
            load_entry_points(self.group, self.adopt)

    def find(self, name: str) -> T | None:
        """The entry called `name` (the entry points' included), or None."""
        known = self._read.get(name) if isinstance(name, str) else None
        if known is None and self.group is not None:
            self._plugins()
            known = self._table.get(name) if isinstance(name, str) else None
        return None if known is None else known[0]

    def get(self, name: str) -> T:
        """The entry called `name`; an unknown name raises `error` (one line listing the registered names)."""
        found = self.find(name)
        if found is None:
            raise self.error(name, self.names())
        return found

    def known(self, name: str) -> bool:
        """Whether an entry is called `name` (without loading plug-ins)."""
        return name in self._read

    def owner(self, name: str) -> str:
        """Who declared the entry called `name`."""
        if name not in self._read:
            raise self.error(name, tuple(self._table))
        return self._table[name][1]

    # ------------------------------------------------------------------ list
    def entries(self) -> tuple[T, ...]:
        """Every entry (the entry points' included), in `order` (default: registration order)."""
        self._plugins()
        values = [entry for entry, _ in self._read.values()]
        return tuple(sorted(values, key=self.order) if self.order is not None else values)

    def names(self) -> tuple[str, ...]:
        """The entries' names, in the order of `entries`."""
        if self.order is None:
            self._plugins()
            return tuple(self._read)
        order = {id(entry): i for i, entry in enumerate(self.entries())}
        return tuple(sorted(self._table, key=lambda n: order[id(self._table[n][0])]))

    def __contains__(self, name: object) -> bool:
        return name in self._read

    def __iter__(self) -> Iterator[str]:
        return iter(self._read)

    def __len__(self) -> int:
        return len(self._read)

"""One registry type: a table of named entries with one way to register, look up, list and refuse an unknown name.

The package's four registries are instances of `Registry`: the parameter specs (elastoactive.core.parameters), the
scenes (elastoactive.core.registry), the terms (elastoactive.core.term_registry) and the studies
(elastoactive.studies.registry). Each entry is kept with its owner (who declared it: 'term contact', 'scene ring');
registering the same entry again is a no-op, another entry under a taken name is refused unless replace=True; an unknown
name raises the registry's UnknownName (a KeyError) whose message is one line listing the names that are. A registry
with an entry-point group loads the plug-ins of that group (`load_entry_points`) the first time it is asked for a name
it does not hold or listed; the installed distributions are read once per process for every group (and again only if a
distribution is installed or removed on sys.path meanwhile), without importlib.metadata where none declares a group.
The package's own entries (its scenes and terms, with their parameters and observables) join when a registry is first
read (`load_built_ins`): `import elastoactive` imports neither, so that what needs no scene (the command line's --help,
a script that reads one record) does not load numpy and the engines.

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
from typing import Generic, NamedTuple, TypeVar

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
_GROUP_HEADER = re.compile(
    r"^\s*\[\s*(" + "|".join(re.escape(g) for g in ENTRY_POINT_GROUPS.values()) + r")\s*\]", re.MULTILINE
)
"""The header of an entry_points.txt section of one of the package's groups."""


class _Installed(NamedTuple):
    """What the installed distributions declare, as read for one state of the places they are found (`_places`)."""

    places: tuple
    groups: frozenset[str] | None
    """The package's groups that a distribution folder declares; None: not to be ruled out without importlib.metadata
    (another finder of distributions, or an archive on sys.path)."""
    points: dict[str, tuple]
    """Each group's entry points, as importlib.metadata lists them (read once, on first need)."""


_installed: list[_Installed] = []
"""The last reading of this process (empty: none yet)."""


def _places() -> tuple:
    """Where distributions are found, in a state that installing or removing one changes: the finders of
    distributions, and each entry of sys.path with the distribution folders (*.dist-info, *.egg-info) in it (None for an
    archive; an empty tuple for what cannot be listed)."""
    finders = tuple(
        f"{cls.__module__}.{cls.__qualname__}"
        for finder in sys.meta_path
        if hasattr(finder, "find_distributions")
        for cls in (finder if isinstance(finder, type) else type(finder),)
    )
    entries = []
    for entry in sys.path:
        if os.path.isfile(entry):
            entries.append((entry, None))
            continue
        try:
            found = sorted(e.name for e in os.scandir(entry or ".") if e.name.endswith((".dist-info", ".egg-info")))
        except OSError:
            found = []
        entries.append((entry, tuple(found)))
    return finders, tuple(entries)


def _declared_groups(places: tuple) -> frozenset[str] | None:
    """The package's entry-point groups that a distribution folder of `places` names in its entry_points.txt; None
    when no reading of folders can rule a group out: a finder of distributions other than _PATH_FINDERS, or an archive
    on sys.path."""
    finders, entries = places
    if any(name not in _PATH_FINDERS for name in finders) or any(found is None for _, found in entries):
        return None
    groups = set()
    for entry, found in entries:
        for folder in found:
            try:
                path = os.path.join(entry or ".", folder, "entry_points.txt")
                with open(path, encoding="utf-8", errors="replace") as text:
                    groups.update(_GROUP_HEADER.findall(text.read()))
            except OSError:
                continue
    return frozenset(groups)


def _reading() -> _Installed:
    """The installed distributions' declarations, read once per process and again only when the places they are found
    in have changed (_places: an entry of sys.path, a distribution folder or a finder added or removed)."""
    places = _places()
    if not _installed or _installed[0].places != places:
        _installed[:] = [_Installed(places, _declared_groups(places), {})]
    return _installed[0]


def declares_entry_points(kind: str) -> bool:
    """Whether an installed distribution may declare entry points of registry `kind`, answered without
    importlib.metadata (~40 ms to import, ~15 ms to list the entry points of ~240 distributions): False only when no
    distribution folder in a folder of sys.path names the group, no entry of sys.path is an archive and no import
    finder but those of _PATH_FINDERS finds distributions; True otherwise (installed_entry_points then reads them).
    The folders are read once for every group (_reading)."""
    groups = _reading().groups
    return groups is None or ENTRY_POINT_GROUPS[kind] in groups


def installed_entry_points(kind: str) -> tuple:
    """The installed distributions' entry points of registry `kind` (importlib.metadata's EntryPoint objects): none,
    without reading metadata, where no distribution declares the group (declares_entry_points); else those that one
    importlib.metadata scan of the distributions lists for every group, kept while the places they are found in are
    unchanged (_reading)."""
    if not declares_entry_points(kind):
        return ()
    reading = _reading()
    if not reading.points:
        import importlib.metadata  # the plug-in boundary: reading the installed distributions' metadata

        listed = importlib.metadata.entry_points()
        reading.points.update({g: tuple(listed.select(group=g)) for g in ENTRY_POINT_GROUPS.values()})
    return reading.points[ENTRY_POINT_GROUPS[kind]]


def load_entry_points(kind: str, register_object=None) -> None:
    """Load the entry points of registry `kind` ("scenes", "terms" or "studies"), once, when the package is whole;
    `register_object(obj)` registers what an entry point names unless it is a module. A plug-in that fails to load
    is skipped with a RuntimeWarning naming it (a broken third-party package does not stop the others)."""
    if not _entry_points["ready"] or kind in _entry_points["loaded"]:
        return
    _entry_points["loaded"].add(kind)  # before loading: a plug-in that lists the registry does not load it again
    for point in installed_entry_points(kind):
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

"""Plug-ins named by the user: a module or a .py file whose scenes, terms and studies register when it is imported.

`load(spec)` imports one (the CLI's ``--plugin``) and remembers what it registered with its spec, so that a run's
summary.json records the plug-ins it needs (`needed`) and ``run --from`` or ``render`` of that run load them again.
A plug-in file runs from the bytes whose SHA-256 it is recorded with (`loaded_file`); a run keeps a copy of them, and
`recorded` loads that copy when the file has changed since (or is gone).

Installed distributions need no naming: their entry points (groups ``elastoactive.scenes``, ``elastoactive.terms``,
``elastoactive.studies``) load when a registry is first listed (elastoactive.core.registry.load_entry_points). A run
records which distribution and entry point provided each scene and term it used (`entry_point_sources`), and a re-run
where that distribution is not installed is refused naming it (`check_entry_points`).
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import json
import sys
from dataclasses import dataclass
from pathlib import Path

from .core import registry, term_registry
from .core.errors import ParameterError
from .core.table import ENTRY_POINT_GROUPS, installed_entry_points
from .io.jsonio import from_jsonable
from .io.outputs import InputFile

_SOURCES: dict[tuple[str, str], str] = {}
"""(registry, name) -> the spec of the plug-in that registered it (`load`)."""
_LOADED: dict[str, tuple[str, str]] = {}
"""spec as resolved (a module name, or a file's absolute path) -> (the module name it was imported under, the spec a
summary.json records)."""
_FILES: dict[str, tuple[str, bytes]] = {}
"""A plug-in file's recorded spec (its absolute path) -> (the SHA-256 of the bytes it ran, those bytes)."""


def _names() -> dict[str, set[str]]:
    """The names each registry holds now (the studies' only once their registry is imported: not imported, it holds
    none a plug-in registered)."""
    studies = sys.modules.get("elastoactive.studies.registry")
    return {
        "scenes": set(registry.SCENES),
        "terms": set(term_registry.TERMS),
        "studies": set(studies.STUDIES) if studies is not None else set(),
    }


def _resolve(spec: str) -> str:
    """A .py file as its absolute path; a module name as given."""
    if spec.endswith(".py") or "/" in spec or "\\" in spec:
        path = Path(spec).expanduser().resolve()
        if not path.is_file():
            raise ParameterError(f"--plugin: {spec} is not a file (give a module name or a .py file)")
        return str(path)
    return spec


def _import(name: str):
    """(the module `name`, whether it was found in the working folder only): the working folder is searched after
    sys.path, as ``python -m`` would (the console script does not put it on sys.path)."""
    try:
        return importlib.import_module(name), False
    except ModuleNotFoundError as err:
        here = str(Path.cwd())
        if err.name is None or not (name == err.name or name.startswith(err.name + ".")) or here in sys.path:
            raise
    sys.path.append(here)  # kept: forked workers and pickled objects import the module by its name
    try:
        return importlib.import_module(name), True
    except ModuleNotFoundError as err:
        if err.name is not None and (name == err.name or name.startswith(err.name + ".")):
            sys.path.remove(here)
        raise


def load(spec: str) -> str:
    """Import the plug-in `spec` (a module name, or a .py file), which registers its scenes, terms and studies;
    remember which names it registered. Loading a spec twice imports it once. Returns the spec as a summary.json
    records it: a file's absolute path (a module found only in the working folder: its file's), else the module
    name."""
    if not isinstance(spec, str) or not spec.strip():
        raise ParameterError(f"--plugin must name a module or a .py file, got {spec!r}")
    resolved = _resolve(spec.strip())
    if resolved in _LOADED:
        return _LOADED[resolved][1]
    before = _names()
    recorded = resolved
    try:
        if resolved.endswith(".py"):
            path = Path(resolved)
            module_name = f"elastoactive_plugin_{path.stem}_{abs(hash(resolved)):x}"
            found = importlib.util.spec_from_file_location(module_name, path)
            module = importlib.util.module_from_spec(found)
            source = path.read_bytes()  # run from the bytes the record's checksum and copy are of
            sys.modules[module_name] = module  # registered objects' classes stay importable (pickling, workers)
            try:
                exec(compile(source, str(path), "exec"), module.__dict__)  # noqa: S102 (the user's plug-in)
            except BaseException:
                sys.modules.pop(module_name, None)
                raise
            _FILES[resolved] = (hashlib.sha256(source).hexdigest(), source)
        else:
            module, here = _import(resolved)
            module_name = module.__name__
            file = getattr(module, "__file__", None) or ""
            if here and file.endswith(".py") and Path(file).name != "__init__.py":
                recorded = str(Path(file).resolve())  # a re-run from another folder finds it by its path
    except ModuleNotFoundError as err:
        if err.name and (resolved == err.name or resolved.startswith(err.name + ".")):
            raise ParameterError(f"--plugin: no module named {resolved!r} (give a module name or a .py file)") from None
        raise ParameterError(f"--plugin {spec}: it did not load (ModuleNotFoundError: {err})") from None
    except ParameterError:
        raise
    except Exception as err:  # noqa: BLE001  (whatever the plug-in's code raised: one line naming it)
        raise ParameterError(f"--plugin {spec}: it did not load ({type(err).__name__}: {err})") from None
    added = {kind: names - before[kind] for kind, names in _names().items()}
    if not any(added.values()) and not _registered_from(module_name):
        raise ParameterError(
            f"--plugin {spec}: it loaded and registered no scene, term or study (a plug-in calls "
            "elastoactive.scenes.register, elastoactive.terms.register or registers a study when imported)"
        )
    _LOADED[resolved] = _LOADED[recorded] = (module_name, recorded)
    for kind, names in added.items():
        for name in names:
            _SOURCES[(kind, name)] = recorded
    return recorded


def _registered_from(module_name: str) -> bool:
    """Whether a registered scene, term or study is defined in the module `module_name` (or below it): a plug-in
    imported before it was named registered then."""
    studies = sys.modules.get("elastoactive.studies.registry")
    found = [*registry.SCENES.entries(), *term_registry.TERMS.entries()]
    found += list(studies.STUDIES.entries()) if studies is not None else []
    homes = {getattr(type(item), "__module__", "") for item in found}
    homes |= {getattr(getattr(item, "run", None), "__module__", "") for item in found}
    return any(home == module_name or home.startswith(module_name + ".") for home in homes)


def source(kind: str, name: str) -> str | None:
    """The spec of the plug-in (`load`) that registered `name` in registry `kind`; None for the package's own and
    for entry points (found again without being named)."""
    return _SOURCES.get((kind, name))


def needed(physics) -> list[str]:
    """The plug-ins (`load` specs) a run of `physics` needs to be re-created: its scene's, and those of the terms
    that act in it or whose parameters it records."""
    specs = [source(kind, name) for kind, name, _ in _used(physics)]
    return list(dict.fromkeys(s for s in specs if s))


def loaded_file(spec: str) -> tuple[str, bytes] | None:
    """(SHA-256, bytes) of the plug-in file `spec` (as `load` returned it) as it was loaded; None for a module."""
    return _FILES.get(spec)


def _record(path) -> tuple[Path, dict] | None:
    """(the run's folder, its summary.json parsed) of a run's record (a run folder, its summary.json or its
    trajectory.npz); None for a path that is not one."""
    path = Path(path)
    summary = path / "summary.json" if path.is_dir() else path.with_name("summary.json")
    if path.is_file() and path.suffix not in (".json", ".npz"):
        return None
    try:
        record = json.loads(summary.read_text())
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    return (summary.parent, record) if isinstance(record, dict) else None


def _inputs(record: dict, key: str, tp) -> list:
    """The records of `key` in a summary's `inputs` block as `tp` (malformed ones left out)."""
    inputs = record.get("inputs")
    values = inputs.get(key) if isinstance(inputs, dict) else None
    out = []
    for value in values if isinstance(values, list) else ():
        try:
            out.append(from_jsonable(tp, value))
        except (TypeError, KeyError, ValueError, AttributeError):
            continue
    return out


def plugin_files(record: dict) -> dict[str, InputFile]:
    """The plug-in files a summary records in its inputs, by spec (their path)."""
    return {f.path: f for f in _inputs(record, "plugin_files", InputFile)}


def _located(folder: Path, record: dict) -> list[tuple[str, str | None]]:
    """(the spec to load, a note or None) for each plug-in the record lists: a file that changed since the run (or is
    gone) is loaded from the run's copy when it holds the bytes the run ran."""
    specs = record.get("plugins")
    files = plugin_files(record)
    out = []
    for spec in specs if isinstance(specs, list) else ():
        if not isinstance(spec, str):
            continue
        if spec not in files:
            out.append((spec, None))
            continue
        where, note = files[spec].locate(folder, "plug-in file")
        if where is None:
            note += "; loading it as it is now"
        out.append((str(where) if where is not None else spec, note))
    return out


def recorded(path) -> list[str]:
    """The plug-ins a run's record (a run folder, its summary.json or its trajectory.npz) lists, each as the spec to
    load: a plug-in file as the run recorded it, or the run's copy of it when the file has changed since or is gone;
    none for a path that is not a record."""
    found = _record(path)
    return [] if found is None else [spec for spec, _ in _located(*found)]


def file_notes(folder, record: dict) -> list[str]:
    """One line for each plug-in file of a run's record that changed since the run or is gone (`recorded`)."""
    return [note for _, note in _located(Path(folder), record) if note]


# ------------------------------------------------------------------------------------------------ entry points

_KINDS = {"scenes": ("scene", registry.SCENES), "terms": ("term", term_registry.TERMS)}
"""The registries a run's record names entries of: (what one entry is called, the registry)."""


@dataclass(frozen=True)
class EntryPointSource:
    """Where an installed distribution's entry point provided a registered scene or term: `kind` the registry
    ("scenes", "terms"), `name` the entry's, `group` and `entry_point` ("name = module:object") the entry point's,
    `distribution` and `version` the distribution's (None when its metadata does not say)."""

    kind: str
    name: str
    group: str
    entry_point: str
    distribution: str | None = None
    version: str | None = None

    def package(self) -> str:
        return " ".join(p for p in (self.distribution, self.version) if p) or "an unnamed distribution"

    def describe(self) -> str:
        return (
            f"the {_KINDS[self.kind][0]} {self.name!r} came from the package '{self.package()}' (entry point "
            f"{self.entry_point} in {self.group})"
        )


def _module(obj) -> str:
    return getattr(type(obj), "__module__", "") or ""


def _own(obj) -> bool:
    """Whether a scene or term is the package's own (or a --plugin's: recorded by `source`)."""
    return _module(obj).split(".")[0] == "elastoactive"


def _rank(point, module: str, name: str) -> int | None:
    """How well the entry point `point` accounts for an entry of `module` called `name` (0 best; None: not at all)."""
    if point.module == module:
        return 0
    if module.startswith(point.module + "."):
        return 1
    if module.split(".")[0] == point.module.split(".")[0]:
        return 2
    return 3 if point.name == name else None


def _entry_point(kind: str, name: str, obj) -> EntryPointSource | None:
    """The installed entry point that provided `obj` (registered as `name` in registry `kind`), or None."""
    group = ENTRY_POINT_GROUPS[kind]
    module = _module(obj)
    ranked = [(r, p) for p in installed_entry_points(kind) if (r := _rank(p, module, name)) is not None]
    if not ranked:
        return None
    point = min(ranked, key=lambda rp: rp[0])[1]
    dist = getattr(point, "dist", None)
    meta = dist.metadata if dist is not None else None
    return EntryPointSource(
        kind,
        name,
        group,
        f"{point.name} = {point.value}",
        meta["Name"] if meta is not None and meta["Name"] else None,
        dist.version if dist is not None else None,
    )


def _used(physics) -> list[tuple[str, str, object]]:
    """(registry, name, entry) of the scene of `physics` and the terms that act in it or whose parameters it
    records (`needed`'s selection)."""
    recorded_names = set(physics.relevant())
    used = [("scenes", physics.scene, registry.get(physics.scene))]
    for term in term_registry.terms():
        if term.active(physics) or any(p.name in recorded_names for p in term.parameters):
            used.append(("terms", term.name, term))
    return used


def entry_point_sources(physics) -> list[EntryPointSource]:
    """The entry points of installed distributions that provided the scene and terms a run of `physics` uses (none
    for the package's own and for --plugin's)."""
    out = []
    for kind, name, obj in _used(physics):
        if _own(obj) or source(kind, name) is not None:
            continue
        found = _entry_point(kind, name, obj)
        if found is not None:
            out.append(found)
    return out


def entry_points(record: dict) -> list[EntryPointSource]:
    """The entry-point sources a run's summary records in its inputs."""
    return [e for e in _inputs(record, "entry_points", EntryPointSource) if e.kind in _KINDS]


def check_entry_points(record: dict, what: str) -> list[str]:
    """Refuse (ParameterError, one line starting with `what`) a record whose scene or term came from an installed
    distribution's entry point that provides nothing here; one note for each that another version provides now."""
    notes = []
    for recorded_source in entry_points(record):
        _, table = _KINDS[recorded_source.kind]
        obj = table.find(recorded_source.name)  # the entry points load on this look-up
        if obj is None:
            wanted = recorded_source.distribution
            fix = f"pip install {wanted}" + (f"=={recorded_source.version}" if recorded_source.version else "")
            raise ParameterError(
                f"{what}: {recorded_source.describe()}, which is not installed here; "
                + (fix if wanted else "install it")
            )
        here = _entry_point(recorded_source.kind, recorded_source.name, obj)
        if here is not None and (here.distribution, here.version) != (
            recorded_source.distribution,
            recorded_source.version,
        ):
            notes.append(f"{recorded_source.describe()}; here '{here.package()}' provides it")
    return notes

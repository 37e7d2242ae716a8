"""Plug-ins named by the user: a module or a .py file whose scenes, terms and studies register when it is imported.

`load(spec)` imports one (the CLI's ``--plugin``) and remembers what it registered with its spec, so that a run's
summary.json records the plug-ins it needs (`needed`) and ``run --from`` or ``render`` of that run load them again.
Installed distributions need no naming: their entry points (groups ``elastoactive.scenes``, ``elastoactive.terms``,
``elastoactive.studies``) load when a registry is first listed (elastoactive.core.registry.load_entry_points).
"""

from __future__ import annotations

import importlib
import importlib.util
import json
import sys
from pathlib import Path

from .core import registry, term_registry
from .core.errors import ParameterError

_SOURCES: dict[tuple[str, str], str] = {}
"""(registry, name) -> the spec of the plug-in that registered it (`load`)."""
_LOADED: dict[str, tuple[str, str]] = {}
"""spec as resolved (a module name, or a file's absolute path) -> (the module name it was imported under, the spec a
summary.json records)."""


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
            sys.modules[module_name] = module  # registered objects' classes stay importable (pickling, workers)
            try:
                found.loader.exec_module(module)
            except BaseException:
                sys.modules.pop(module_name, None)
                raise
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
    _LOADED[resolved] = _LOADED[recorded] = (module_name, recorded)
    for kind, names in _names().items():
        for name in names - before[kind]:
            _SOURCES[(kind, name)] = recorded
    return recorded


def source(kind: str, name: str) -> str | None:
    """The spec of the plug-in (`load`) that registered `name` in registry `kind`; None for the package's own and
    for entry points (found again without being named)."""
    return _SOURCES.get((kind, name))


def needed(physics) -> list[str]:
    """The plug-ins (`load` specs) a run of `physics` needs to be re-created: its scene's, and those of the terms
    that act in it or whose parameters it records."""
    recorded = set(physics.relevant())
    specs = [source("scenes", physics.scene)]
    for term in term_registry.terms():
        if term.active(physics) or any(p.name in recorded for p in term.parameters):
            specs.append(source("terms", term.name))
    return list(dict.fromkeys(s for s in specs if s))


def recorded(path) -> list[str]:
    """The plug-ins a run's record (a run folder, its summary.json or its trajectory.npz) lists; none for a path
    that is not one."""
    path = Path(path)
    summary = path / "summary.json" if path.is_dir() else path.with_name("summary.json")
    if path.is_file() and path.suffix not in (".json", ".npz"):
        return []
    try:
        record = json.loads(summary.read_text())
    except (OSError, UnicodeDecodeError, ValueError):
        return []
    specs = record.get("plugins") if isinstance(record, dict) else None
    return [s for s in specs if isinstance(s, str)] if isinstance(specs, list) else []

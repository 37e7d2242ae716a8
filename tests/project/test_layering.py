"""The package's layering, checked on its source: no import cycles, scenes are plug-ins, analysis is pure.

These read the code with `ast` (nothing is imported), so they name the offending file and line.
"""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

import pytest

import elastoactive as ea

ROOT = Path(__file__).resolve().parents[2]


def _modules() -> dict[str, Path]:
    """Module name -> file, from pyproject's package-dir mapping (the top-level folders are sub-packages)."""
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    mapping = cfg.get("package-dir", {})
    out = {}
    for package in cfg["packages"]:
        folder = ROOT / mapping.get(package, package.replace(".", "/"))
        for f in folder.glob("*.py"):
            out[package if f.name == "__init__.py" else f"{package}.{f.stem}"] = f
    return out


MODULES = _modules()


def _imports(name: str, path: Path):
    """(target module, line, inside a function or class, under `if TYPE_CHECKING`) for every import."""
    tree = ast.parse(path.read_text(), str(path))
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    nested: set[int] = set()
    typing_only: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            nested |= {id(n) for n in ast.walk(node) if n is not node}
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            typing_only |= {id(n) for n in ast.walk(node) if n is not node}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            targets = [base] + [f"{base}.{a.name}" for a in node.names]
        else:
            continue
        for target in targets:
            yield target, node.lineno, id(node) in nested, id(node) in typing_only


def test_no_import_cycles_between_modules():
    """Imports inside functions count; importing a sub-module imports its package, so edges into a
    package's __init__ are not counted (as in the team's import_cycles tool)."""
    graph = {m: set() for m in MODULES}
    for name, path in MODULES.items():
        for target, *_ in _imports(name, path):
            if target in MODULES and target != name and MODULES[target].name != "__init__.py":
                graph[name].add(target)
    cycles, state = [], {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                cycles.append(stack[stack.index(nxt) :] + [nxt])
            elif nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = "done"

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])
    assert not cycles, "import cycles: " + "; ".join(" -> ".join(c) for c in cycles)


def _continues_imports(text: str) -> bool:
    """Whether a line belongs to an import statement: its first line, or a line of a parenthesised name list."""
    stripped = text.strip()
    return (
        stripped.startswith(("import ", "from "))
        or stripped == ")"
        or (
            stripped.endswith(",")
            and stripped.replace(",", "").replace(" as ", " ").replace("_", "").replace(" ", "").isalnum()
        )
    )


def test_function_level_imports_say_why():
    """An import inside a function needs a comment on its line or the line above (start-up time, an
    optional dependency, ...)."""
    missing = []
    for name, path in MODULES.items():
        lines = path.read_text().splitlines()
        for _, line, nested, typing_only in _imports(name, path):
            if not nested or typing_only:
                continue
            first = line  # the block of consecutive import statements this one belongs to, and the line above it
            while first >= 2 and _continues_imports(lines[first - 2]):
                first -= 1
            if not any("#" in lines[i - 1] for i in range(max(first - 1, 1), line + 1)):
                missing.append(f"{path.relative_to(ROOT)}:{line}")
    assert not missing, "imports inside functions without a reason: " + ", ".join(sorted(set(missing)))


def test_scene_names_only_in_scene_modules():
    """Outside elastoactive/scenes/ no code names a scene, but for the one default (params.DEFAULT_SCENE)."""
    hits = []
    for name, path in MODULES.items():
        if name.startswith("elastoactive.scenes"):
            continue
        for lineno, line in enumerate(path.read_text().splitlines(), 1):
            for scene in ea.scenes.names():
                if f'"{scene}"' in line or f"'{scene}'" in line:
                    hits.append(f"{path.relative_to(ROOT)}:{lineno}: {line.strip()}")
    assert len(hits) == 1 and "DEFAULT_SCENE" in hits[0], hits


@pytest.mark.parametrize("name", sorted(m for m in MODULES if m.startswith("elastoactive.analysis")))
def test_analysis_is_pure(name):
    """analysis/ is mathematics: it imports nothing of the package outside itself but the reduced engine's mathematics,
    the network records, the error types and the models' constants (leaves)."""
    outside = [
        f"line {line}: {target}"
        for target, line, *_ in _imports(name, MODULES[name])
        if target.startswith("elastoactive")
        and not target.startswith(PURE + ("elastoactive.analysis",))
        and target != "elastoactive"
    ]
    assert not outside, f"{name} imports {outside}"


PURE = ("elastoactive.reduced", "elastoactive.networks", "elastoactive.errors", "elastoactive.constants")
"""The packages and leaves below the scenes: the reduced engine's mathematics, the network records, errors,
constants."""


@pytest.mark.parametrize("name", sorted(m for m in MODULES if m.startswith(PURE[:2])))
def test_reduced_engine_and_network_records_stand_alone(name):
    """The reduced engine (elastoactive/reduced/) and the network records know no scene, term, Physics or engine:
    arrays and records in, arrays out."""
    outside = [
        f"line {line}: {target}"
        for target, line, *_ in _imports(name, MODULES[name])
        if target.startswith("elastoactive") and not target.startswith(PURE) and target != "elastoactive"
    ]
    assert not outside, f"{name} imports {outside}"


def test_tests_mirror_the_packages():
    """tests/ holds one folder per sub-package (the design's top-level folders among them), named as the package,
    plus docs/ (the README, the site, the notebook) and project/ (packaging, layering); the front door's modules
    are tested in tests/ itself."""
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    packages = {p.split(".")[1] for p in cfg["packages"] if p.count(".") == 1}
    folders = {p.name for p in (ROOT / "tests").iterdir() if p.is_dir() and not p.name.startswith((".", "_"))}
    assert folders - packages <= {"docs", "project"}, folders - packages
    stray = [
        p.name for p in (ROOT / "tests").glob("*.py") if p.name != "conftest.py" and not p.name.startswith("test_")
    ]
    assert not stray, f"helpers belong beside the tests that use them: {stray}"
    names = [p.name for p in (ROOT / "tests").rglob("test_*.py")]
    assert len(names) == len(set(names)), "test files need unique names (pytest imports them by basename)"

"""The package's layering, checked on its source: no import cycles, scenes are plug-ins, analysis is pure.

These read the code with `ast` (nothing is imported), so they name the offending file and line.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path

import pytest

import elastoactive as ea

ROOT = Path(__file__).resolve().parents[2]


def _packages() -> dict[str, Path]:
    """Package name -> folder: every folder holding an __init__.py under elastoactive/, the design's top-level folders
    (mjcf/, controllers/, analysis/) through their links, as pyproject's package discovery finds them."""
    out = {}
    for folder, dirs, files in os.walk(ROOT / "elastoactive", followlinks=True):
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        if "__init__.py" in files:
            out[".".join(Path(folder).relative_to(ROOT).parts)] = Path(folder)
    return out


PACKAGES = _packages()


def _modules() -> dict[str, Path]:
    """Module name -> file, for every module of every package."""
    out = {}
    for package, folder in PACKAGES.items():
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


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The cycles a depth-first search meets in `graph` (node -> what it imports), each closed on its first node."""
    cycles, state = [], {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                cycles.append(stack[stack.index(nxt) :] + [nxt])
            elif nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])
    return cycles


def test_no_import_cycles_between_modules():
    """Imports inside functions count; importing a sub-module imports its package, so edges into a
    package's __init__ are not counted (as in the team's import_cycles tool)."""
    graph = {m: set() for m in MODULES}
    for name, path in MODULES.items():
        for target, *_ in _imports(name, path):
            if target in MODULES and target != name and MODULES[target].name != "__init__.py":
                graph[name].add(target)
    cycles = _cycles(graph)
    assert not cycles, "import cycles: " + "; ".join(" -> ".join(c) for c in cycles)


def _package_of(module: str) -> str:
    """The package a module belongs to: itself for a package's __init__, else the longest package prefixing it."""
    return module if module in PACKAGES else module.rsplit(".", 1)[0]


def _package_graph() -> dict[str, set[str]]:
    """Package -> the packages its modules import, every import counted (inside functions, and the names a package's
    __init__ defines: `from .. import terms` is an edge to elastoactive.terms, `from ..core.params import Physics` to
    elastoactive.core; an attribute of a package, `from elastoactive import simulate`, to that package)."""
    graph = {p: set() for p in PACKAGES}
    for name, path in MODULES.items():
        if name.endswith(".__main__"):
            continue  # `python -m elastoactive`: the command's entry, run and never imported, is above every layer
        source = _package_of(name)
        statements: dict[int, list[str]] = {}
        for target, line, *_ in _imports(name, path):
            statements.setdefault(line, []).append(target)
        for base, *names in statements.values():
            named = [n for n in names if n in MODULES]  # `from ..core import registry`: the module, not its parent
            for target in named or [base]:
                found = target if target in MODULES else target.rsplit(".", 1)[0]
                if found in MODULES:
                    graph[source].add(_package_of(found))
        graph[source].discard(source)
    return graph


def test_no_import_cycles_between_packages():
    """The packages' layers run one way: no package imports, through any of its modules, a package that imports it
    back (the front door, elastoactive/, on top; the shared records, elastoactive.core, at the bottom)."""
    cycles = _cycles(_package_graph())
    assert not cycles, "package cycles: " + "; ".join(" -> ".join(c) for c in cycles)


def test_the_package_cycle_check_finds_a_cycle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}
    assert _cycles(graph) == [["a", "b", "c", "a"]]


def test_the_shared_records_import_nothing_above_them():
    """elastoactive.core is the bottom layer: it imports no other package of elastoactive."""
    assert _package_graph()["elastoactive.core"] <= {"elastoactive"}, _package_graph()["elastoactive.core"]


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


PURE = (
    "elastoactive.reduced",
    "elastoactive.networks",
    "elastoactive.hydro",
    "elastoactive.core.errors",
    "elastoactive.core.constants",
    "elastoactive.core.jit_cache",
)
"""The packages and leaves below the scenes: the reduced engine's mathematics, the network records, the
hydrodynamic mobilities, errors, constants, numba's keyed cache."""


@pytest.mark.parametrize("name", sorted(m for m in MODULES if m.startswith(PURE[:3])))
def test_reduced_engine_and_network_records_stand_alone(name):
    """The reduced engine (elastoactive/reduced/), the network records and the mobilities (elastoactive/hydro/) know
    no scene, term, Physics or engine: arrays and records in, arrays out."""
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
    packages = {p.split(".")[1] for p in PACKAGES if p.count(".") == 1}
    folders = {p.name for p in (ROOT / "tests").iterdir() if p.is_dir() and not p.name.startswith((".", "_"))}
    assert folders - packages <= {"docs", "project"}, folders - packages
    stray = [
        p.name for p in (ROOT / "tests").glob("*.py") if p.name != "conftest.py" and not p.name.startswith("test_")
    ]
    assert not stray, f"helpers belong beside the tests that use them: {stray}"
    names = [p.name for p in (ROOT / "tests").rglob("test_*.py")]
    assert len(names) == len(set(names)), "test files need unique names (pytest imports them by basename)"


KIND_TESTS = ("is_network", "is_chain")
"""Names that would ask a scene's kind outside the kinds (a helper or property answering "is this a network?")."""
KINDS = ("ChainScene", "NetworkScene", "network_kind", "chain_kind")
KIND_PARTS = ("network", "initial_network", "chain_prefixes", "reduced_system", "initial_angles")
"""Hooks of one kind only (a network's, a chain's): probing a scene for them asks which kind it is."""
KIND_WORDS = {scene.kind for scene in ea.scenes.scenes()}
"""The registered scenes' kinds, as Scene.kind names them ('chain', 'network')."""


def _kind_branches(path: Path) -> list[int]:
    """Lines that ask which kind a scene is: `x.network(...) is (not) None`, a name `is_network`, isinstance against
    a kind class, a comparison of `.kind` with a kind's word, or hasattr/getattr probing for one kind's hook."""
    hits = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            calls_network = any(
                isinstance(s, ast.Call) and isinstance(s.func, ast.Attribute) and s.func.attr == "network"
                for s in sides
            )
            against_none = any(isinstance(s, ast.Constant) and s.value is None for s in sides)
            kind_word = any(isinstance(s, ast.Attribute) and s.attr == "kind" for s in sides) and any(
                isinstance(s, ast.Constant) and s.value in KIND_WORDS for s in sides
            )
            if (calls_network and against_none) or kind_word:
                hits.append(node.lineno)
        elif isinstance(node, (ast.Name, ast.Attribute)):
            if (node.id if isinstance(node, ast.Name) else node.attr) in KIND_TESTS:
                hits.append(node.lineno)
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "isinstance":
            if any(k in ast.unparse(node) for k in KINDS):
                hits.append(node.lineno)
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("hasattr", "getattr"):
            if len(node.args) > 1 and isinstance(node.args[1], ast.Constant) and node.args[1].value in KIND_PARTS:
                hits.append(node.lineno)  # probing for one kind's part: whether the scene has a network, or chains
    return hits


def test_no_module_outside_the_scene_kinds_asks_which_kind_a_scene_is():
    """A chain and a network are two kinds of scene (elastoactive.scenes.base): whatever differs between them is a
    hook of the kind (its engines, builder, painter, positions, stability report), so that a third kind needs no
    edit outside scenes/. No module outside elastoactive/scenes/ branches on the kind."""
    hits = [
        f"{path.relative_to(ROOT)}:{line}"
        for name, path in MODULES.items()
        if not name.startswith("elastoactive.scenes")
        for line in _kind_branches(path)
    ]
    assert not hits, "branches on a scene's kind outside the scene kinds: " + ", ".join(hits)


def test_the_kind_branch_check_finds_a_branch(tmp_path):
    """The check above can fail: it finds each form of the branch in a file written to fail it."""
    source = tmp_path / "branches.py"
    source.write_text(
        "if scene.network(physics) is not None:\n    pass\n"
        "ok = traj.is_network\n"
        "chain = isinstance(scene, ChainScene)\n"
        "net = scene.kind == 'network'\n"
        "probe = getattr(scene, 'network', None)\n"
        "fine = scene.positions(traj)\n"
    )
    assert sorted(_kind_branches(source)) == [1, 3, 4, 5, 6]


TERM_CONTRACT = ("elastoactive.terms.base",)
"""The term package's contract (the Term class and its records), which any module may import; a term module is not."""
TERM_READERS = ("elastoactive.terms", "elastoactive.studies")
"""Where a term module may be imported by name: the term package itself, and a study of one term (the self-aligning
study, the moving clamp's tongue), which is about that term."""


def _term_modules() -> set[str]:
    """The modules that define a registered term (a helper module of the term package that is no term, such as the
    network units' noise parameters, is not one)."""
    return {type(term).__module__ for term in ea.terms.terms()} - set(TERM_CONTRACT)


def _terms_imported_by_name(name: str, path: Path) -> list[str]:
    terms = _term_modules()
    return [f"line {line}: {target}" for target, line, *_ in _imports(name, path) if target in terms]


def test_no_engine_builder_or_scene_imports_a_term_by_name():
    """The engines, builders, scenes and records reach a term through the term registry and the hooks of the term
    contract (elastoactive.terms: polarity_term, polarity_addresses, turning_rate, Term.load_mask, ...), so that a
    second term of the same role plugs in the same way."""
    hits = {
        name: found
        for name, path in MODULES.items()
        if not name.startswith(TERM_READERS)
        for found in [_terms_imported_by_name(name, path)]
        if found
    }
    assert not hits, f"term modules imported by name: {hits}"


def test_the_term_import_check_finds_an_import(tmp_path):
    source = tmp_path / "engine.py"
    source.write_text("from ..terms.self_aligning import turning_rate\nfrom ..terms import polarity_term\n")
    assert _terms_imported_by_name("elastoactive.engines.engine", source) == [
        "line 1: elastoactive.terms.self_aligning"
    ]

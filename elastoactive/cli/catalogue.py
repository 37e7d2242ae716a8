"""The scenes the top-level help lists, without importing a scene: `elastoactive --help` answers in a tenth of a second.

A scene module imports numpy and the engines' records, half a second before the first line of help. Until something
has read the scene registry, the package's own scenes are read from their source instead: the module list
`elastoactive.scenes.BUILT_IN` and, in each module, the literal `name` and `summary` of the class that its `SCENE`
instantiates (as setuptools reads a version without importing its module). Anything else (a scene that a plug-in or
an entry point adds, a registry already read, a summary that is not a literal) is listed from the registry itself,
which imports them. tests/cli/test_catalogue.py holds the source reading to the registry for every built-in scene.
"""

from __future__ import annotations

import ast
import importlib.util
import re
import sys
from pathlib import Path

from ..core.table import BUILT_INS, built_ins_loaded, declares_entry_points

_SCENE = re.compile(r"^SCENE = (\w+)\(\)$", re.MULTILINE)
"""A scene module's registered instance: `SCENE = ClassName()`."""
_ENDS_HEAD = re.compile(r"[^\s#]|\s+(def |async def |@)")
"""A line that ends a class's head: unindented (the class is over), or a method or decorator in its body."""


class NotLiteral(LookupError):
    """The source does not declare what the catalogue reads as literals (it is then read from the registry)."""


def _literal(tree: ast.Module, name: str):
    """The literal value assigned to `name` at the top of `tree` (a module or a class body)."""
    for node in tree.body:
        if isinstance(node, ast.Assign) and [getattr(t, "id", None) for t in node.targets] == [name]:
            try:
                return ast.literal_eval(node.value)
            except ValueError:
                break
    raise NotLiteral(name)


def _class_head(source: str, cls: str) -> ast.Module:
    """The statements of the top-level class `cls` in `source` before its first method: its lines from `class` up to
    the first `def` or decorator in its body, or the next unindented line, parsed (a class states its name and
    summary first; reading no method keeps --help quick)."""
    lines = source.splitlines()
    head = next((i for i, line in enumerate(lines) if re.match(rf"class {cls}\b", line)), None)
    if head is None:
        raise NotLiteral(cls)
    end = next((i for i in range(head + 1, len(lines)) if _ENDS_HEAD.match(lines[i])), len(lines))
    try:
        tree = ast.parse("\n".join(lines[head:end]))
    except SyntaxError:
        raise NotLiteral(cls) from None
    if not (tree.body and isinstance(tree.body[0], ast.ClassDef)):
        raise NotLiteral(cls)
    return ast.Module(body=tree.body[0].body, type_ignores=[])


def from_source() -> tuple[tuple[str, str], ...]:
    """(name, summary) of each of the package's own scenes, in registration order, read from source; NotLiteral (or
    OSError) where the source does not hold them as literals."""
    spec = importlib.util.find_spec(BUILT_INS["scenes"])  # the package's location, without running its __init__
    if spec is None or spec.origin is None:
        raise NotLiteral(BUILT_INS["scenes"])
    folder = Path(spec.origin).parent
    listed = []
    for module in _literal(ast.parse(Path(spec.origin).read_text()), "BUILT_IN"):
        source = (folder / f"{module}.py").read_text()
        instance = _SCENE.search(source)
        if instance is None:
            raise NotLiteral(module)
        body = _class_head(source, instance.group(1))
        listed.append((_literal(body, "name"), _literal(body, "summary")))
    return tuple(listed)


def scenes() -> tuple[tuple[str, str], ...]:
    """(name, summary) of every registered scene, in registration order: from source while nothing but the package's
    own can be registered (module docstring), else from the registry."""
    untouched = not built_ins_loaded() and BUILT_INS["scenes"] not in sys.modules
    if untouched and not declares_entry_points("scenes"):  # an installed distribution's scenes: the registry loads them
        try:
            return from_source()
        except (NotLiteral, OSError):
            pass
    from ..core import registry  # the registry's first read: every scene, its terms and numpy load past here

    return tuple((s.name, s.summary) for s in registry.scenes())

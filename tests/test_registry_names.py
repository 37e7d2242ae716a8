"""Every registry (scenes, terms, studies) names what it holds: an unknown name is refused with the registered names,
and the docs' examples of `names()` quote the registry as it is."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

import elastoactive as ea
from elastoactive import studies

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize(
    "kind, get, names",
    [
        ("scene", ea.scenes.get, ea.scenes.names),
        ("term", ea.terms.get, ea.terms.names),
        ("study", studies.registry.get, studies.registry.names),
        ("study", studies.STUDIES.__getitem__, studies.registry.names),
    ],
)
@pytest.mark.parametrize("name", ["nope", "", None, 3])
def test_an_unknown_name_lists_the_registered_ones(kind, get, names, name):
    with pytest.raises(KeyError) as info:
        get(name)
    message = str(info.value)
    assert message.startswith(f"no {kind} called {name!r}; the registered ")
    assert all(registered in message for registered in names()) and len(names()) >= 3


def _quoted_names():
    """Every `ea.<registry>.names()  # (...)` example in the docs and the docstrings: (where, registry, the tuple
    quoted, whether it ends in '...')."""
    pattern = re.compile(r"ea\.(scenes|terms)\.names\(\)\s*#\s*(\(.*?\))")
    files = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")), *sorted((ROOT / "elastoactive").rglob("*.py"))]
    for path in files:
        for number, line in enumerate(path.read_text().splitlines(), 1):
            match = pattern.search(line)
            if match:
                text = match.group(2)
                partial = "..." in text
                quoted = ast.literal_eval(text.replace(", ...", "").replace("...", ""))
                yield f"{path.relative_to(ROOT)}:{number}", match.group(1), tuple(quoted), partial


def test_the_docs_quote_the_registries_as_they_are():
    """A quoted tuple of names is the registry's (or, ending in '...', its first names): no count goes stale."""
    quoted = list(_quoted_names())
    assert {registry for _, registry, _, _ in quoted} == {"scenes", "terms"}
    for where, registry, names, partial in quoted:
        registered = getattr(ea, registry).names()
        assert (registered[: len(names)] if partial else registered) == names, (where, names, registered)

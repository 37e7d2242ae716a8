"""The one registry type (elastoactive.core.table.Registry) behind parameters, scenes, terms and studies: one way to
register, look up, list and refuse an unknown name."""

from __future__ import annotations

import json
import subprocess
import sys
from typing import NamedTuple

import pytest

import elastoactive as ea
from elastoactive import terms
from elastoactive.core import parameters, registry, table
from elastoactive.studies import registry as studies


class Entry(NamedTuple):
    name: str
    rank: float = 0.0


def test_the_four_registries_are_one_type():
    tables = (parameters._TABLE, registry.SCENES, terms.TERMS, studies.STUDIES)
    assert all(isinstance(t, table.Registry) for t in tables)
    assert [t.kind for t in tables] == ["parameter", "scene", "term", "study"]
    assert all(issubclass(t.error, table.UnknownName) and issubclass(t.error, KeyError) for t in tables)


def test_register_look_up_and_list():
    table_ = table.Registry("widget")
    a, b = Entry("a", 2.0), Entry("b", 1.0)
    assert table_.register(a, owner="test") is a and table_.register(b) is b
    assert table_.names() == ("a", "b") and table_.entries() == (a, b) and table_.get("a") is a
    assert table_.find("c") is None and table_.known("a") and table_.owner("a") == "test"
    assert table_.register(Entry("a", 2.0)) == a  # the same entry again: a no-op, its owner kept
    assert table_.owner("a") == "test"
    ordered = table.Registry("widget", order=lambda e: e.rank)
    ordered.register(a), ordered.register(b)
    assert ordered.names() == ("b", "a") and ordered.entries() == (b, a)
    assert table_.unregister("a") is a and table_.names() == ("b",) and table_.unregister("a") is None


def test_a_taken_name_and_an_unknown_name_are_refused_in_one_line():
    table_ = table.Registry("widget")
    table_.register(Entry("a"), owner="scene x")
    with pytest.raises(ValueError, match=r"^a widget named 'a' is already declared by scene x \(pass replace=True"):
        table_.register(Entry("a", 1.0))
    assert table_.register(Entry("a", 1.0), replace=True).rank == 1.0
    with pytest.raises(KeyError) as err:
        table_.get("nope")
    assert str(err.value) == "no widget called 'nope'; the registered widgets: a" and isinstance(err.value, KeyError)
    with pytest.raises(ValueError, match="needs a non-empty string `name`"):
        table_.register(Entry(""))


def test_each_registry_refuses_an_unknown_name_its_own_way():
    for get, kind in ((parameters.get, "parameter"), (ea.scenes.get, "scene"), (ea.terms.get, "term")):
        with pytest.raises(KeyError, match=f"no {kind} called 'nope'; the registered {kind}s: "):
            get("nope")
    with pytest.raises(KeyError, match="no study called 'nope'; the registered studies: "):
        studies.get("nope")


_ORDER = """
import importlib, json, sys
importlib.import_module(sys.argv[1])
from elastoactive.core import observables, parameters, registry, term_registry
print(json.dumps([parameters.names(), observables.names(), term_registry.names(), registry.names()]))
"""


def _tables(first: str) -> list:
    """The parameter, observable, term and scene tables' names in a fresh process that imports `first` first."""
    out = subprocess.run([sys.executable, "-c", _ORDER, first], capture_output=True, text=True, timeout=120, check=True)
    return json.loads(out.stdout)


@pytest.mark.parametrize(
    "first", ["elastoactive.terms.noise", "elastoactive.scenes.ring", "elastoactive.core.params", "elastoactive.api"]
)
def test_the_registries_hold_the_same_order_whatever_is_imported_first(first):
    """The package's own scenes and terms join on a registry's first read, or on their import (a module that imports
    one first): the chain's parameters lead, then the terms', then the scenes', and every table is in one order,
    whichever module a fresh process imports first (the order of options, of help(ea.Physics), of a summary's
    parameters)."""
    tables = _tables(first)
    assert tables == _tables("elastoactive")
    names = tables[0]
    assert names[:2] == ["n", "Pi"]
    assert names.index("drag_ratio") < names.index("delta")  # a term's before a scene's


def test_a_registry_read_loads_the_package_s_own_first():
    """In a fresh process nothing is registered beyond the chain's parameters and the beat observables until a
    registry is read; the first read (any registry) registers every built-in scene and term."""
    probe = (
        "import sys\n"
        "from elastoactive.core import parameters, table\n"
        "print(table.built_ins_loaded(), 'elastoactive.scenes' in sys.modules, len(parameters._TABLE._table))\n"
        "from elastoactive.core import term_registry\n"
        "print('drag' in term_registry.TERMS, table.built_ins_loaded(), 'elastoactive.scenes' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, check=True)
    assert out.stdout.split("\n")[:2] == ["False False 2", "True True True"], out.stdout


def test_a_built_in_that_fails_to_import_is_raised_at_every_read():
    """In a fresh process whose scenes cannot import (numpy made unimportable): the first read raises the import's
    error, and so does the next; no read returns a table without the package's own."""
    probe = (
        "import sys\n"
        "sys.modules['numpy'] = None\n"
        "from elastoactive.core import registry\n"
        "for _ in range(2):\n"
        "    try:\n"
        "        registry.names()\n"
        "        print('listed')\n"
        "    except ImportError as err:\n"
        "        print(type(err).__name__)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, check=True)
    assert out.stdout.split() == ["ModuleNotFoundError", "ModuleNotFoundError"], out.stdout + out.stderr

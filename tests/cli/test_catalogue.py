"""The scenes the top-level help lists, read from source without importing a scene (elastoactive.cli.catalogue):
the same names and summaries, in the same order, as the registry holds for every one of the package's own scenes, and
the registry's own list wherever the source cannot say (a plug-in's scene, a summary that is not a literal)."""

from __future__ import annotations

import ast

import pytest

import elastoactive as ea
from elastoactive.cli import catalogue
from elastoactive.cli.options import scene_help
from elastoactive.core import table


def test_the_source_lists_what_the_registry_holds():
    """Every built-in scene, by name and summary, in registration order (the registry's first entries)."""
    listed = catalogue.from_source()
    registered = tuple((s.name, s.summary) for s in ea.scenes.scenes())
    assert len(listed) == len(ea.scenes.BUILT_IN) >= 12
    assert listed == registered[: len(listed)]


def test_the_help_lists_every_registered_scene():
    """Once the registry is read (as here), the epilog is the registry's: every scene, a plug-in's too."""
    assert table.built_ins_loaded()
    assert catalogue.scenes() == tuple((s.name, s.summary) for s in ea.scenes.scenes())
    for scene in ea.scenes.scenes():
        assert f"  {scene.name:<13} {scene.summary}" in scene_help()


def test_a_plugin_scene_is_listed(toy_scene):
    """A scene registered beside the package's own is in the top-level help (read from the registry)."""
    assert toy_scene.name in scene_help()


@pytest.fixture
def toy_scene():
    class Toy(ea.scenes.ChainScene):
        name = "toy-catalogue"
        summary = "a toy scene of the catalogue's test"

    scene = ea.scenes.register(Toy())
    yield scene
    ea.scenes.unregister(scene.name)


@pytest.mark.parametrize(
    "source",
    [
        'class Toy(ChainScene):\n    name = "toy"\n    summary = "chain " + SUFFIX\n',  # computed: not a literal
        'class Toy(ChainScene):\n    name = "toy"\n\n    def run(self):\n        pass\n    summary = "late"\n',
        'class Other(ChainScene):\n    name = "toy"\n    summary = "s"\n',  # no class of SCENE's
        "class Toy(ChainScene:\n    name = 'toy'\n",  # not Python
    ],
)
def test_a_source_that_does_not_say_is_not_read(source):
    """A summary that is computed, stated after a method, or a class that cannot be found or parsed: NotLiteral, and
    the help then asks the registry (catalogue.scenes)."""
    with pytest.raises(catalogue.NotLiteral):
        head = catalogue._class_head(source + "\nSCENE = Toy()\n", "Toy")
        catalogue._literal(head, "name"), catalogue._literal(head, "summary")


def test_a_class_head_ends_at_its_first_method():
    source = (
        'class Toy(ChainScene):\n    name = "toy"\n    # a note\n\n    summary = (\n        "two "\n        "lines"\n'
        "    )\n\n    @property\n    def x(self):\n        return 1\n"
    )
    head = catalogue._class_head(source, "Toy")
    assert [type(node) for node in head.body] == [ast.Assign, ast.Assign]
    assert catalogue._literal(head, "summary") == "two lines"

"""Every registered scene and term passes the conformance kit (elastoactive.testing), check by check, so that a
scene or term added to the package cannot land without its promises."""

import pytest

import elastoactive as ea
from elastoactive import testing

SCENES = ea.scenes.names()
TERMS = ea.terms.names()


@pytest.mark.parametrize("check", [c.name for c in testing.SCENE_CHECKS])
@pytest.mark.parametrize("scene", SCENES)
def test_scene_keeps_its_promise(scene, check):
    assert testing.check_scene(scene, only=check) == [check]


@pytest.mark.parametrize("check", [c.name for c in testing.TERM_CHECKS])
@pytest.mark.parametrize("term", TERMS)
def test_term_keeps_its_promise(term, check):
    assert testing.check_term(term, only=check) == [check]

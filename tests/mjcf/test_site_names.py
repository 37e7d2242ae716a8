"""The docs call MuJoCo's elements by the names the built model has: every element name docs/mujoco.md quotes (a
concrete one, `particle_0`, or a template in the paper's 1-based i, `particle_{i-1}`) is a name of a compiled model,
and a template over i = 1..N gives exactly the model's elements of that kind (the sites start at particle_0)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import elastoactive as ea
from elastoactive.mjcf.chain import build_model

ROOT = Path(__file__).resolve().parents[2]
PAGES = ("docs/mujoco.md", "README.md")
N = 4
SCENES = ("one-pinned", "two-pinned", "coupled-pair", "paraboloid")
"""The chain scenes whose elements the page names (the pin, the pair's tendon, the dish's head)."""
ELEMENT = re.compile(r"`((?:chain[12]_)?(?:particle|segment|hinge|head)(?:_[xy]|_\d+|_\{[^}`]+\})?)`")
"""A quoted element name: particle_0, chain1_hinge_0, head_x, or a template particle_{i-1}."""


def _names(model) -> set[str]:
    kinds = ("site", "body", "joint", "tendon", "actuator")
    return {
        getattr(model, kind)(k).name
        for kind in kinds
        for k in range(getattr(model, f"n{kind}" if kind != "joint" else "njnt"))
    }


@pytest.fixture(scope="module")
def models() -> dict[str, set[str]]:
    return {scene: _names(build_model(ea.Physics(scene, n=N))) for scene in SCENES}


def _quoted() -> list[tuple[str, str]]:
    return [(page, name) for page in PAGES for name in ELEMENT.findall((ROOT / page).read_text())]


def test_the_pages_quote_element_names():
    assert {name for _, name in _quoted()} >= {"particle_0", "particle_{i-1}", "segment_{i-1}", "hinge_{i-1}"}


@pytest.mark.parametrize("page, name", sorted(set(_quoted())))
def test_a_quoted_name_is_the_models(page, name, models):
    every = set().union(*models.values())
    template = re.fullmatch(r"(.*)_\{([^}]+)\}", name)
    if template is None:
        assert name in every, f"{page} quotes `{name}`, which no compiled model has"
        return
    prefix, expression = template.groups()
    if "i" in expression:  # over the paper's i = 1..N: exactly the model's elements of that kind
        names = {f"{prefix}_{eval(expression, {'i': i, 'N': N})}" for i in range(1, N + 1)}  # noqa: S307
        model = models["one-pinned"]
        kind = {n for n in model if re.fullmatch(rf"{re.escape(prefix)}_\d+", n)}
        assert names == kind, f"{page}: `{name}` over i = 1..{N} gives {sorted(names)}; the model has {sorted(kind)}"
    else:
        assert f"{prefix}_{eval(expression, {'N': N})}" in every, f"{page}: `{name}` at N = {N}"  # noqa: S307

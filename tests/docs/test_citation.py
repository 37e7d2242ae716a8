"""CITATION.cff is valid YAML with the keys Citation File Format 1.2.0 requires, and agrees with pyproject."""

import re
import tomllib
from pathlib import Path

import pytest

yaml = pytest.importorskip("yaml")

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def cff():
    data = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    return data


def _names(authors):
    return [a.get("family-names") or a.get("name") for a in authors]


def test_required_keys(cff):
    for key in ("cff-version", "message", "title", "authors"):
        assert cff.get(key), f"CITATION.cff lacks {key!r}"
    assert cff["cff-version"] == "1.2.0"
    assert cff["title"] == "elastoactive"
    assert all(isinstance(a, dict) and (a.get("name") or a.get("family-names")) for a in cff["authors"])


def test_agrees_with_pyproject(cff):
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert str(cff["version"]) == project["version"]
    assert cff["license"] == project["license"] == "MIT"


def test_cites_the_paper_and_its_data(cff):
    paper = cff["preferred-citation"]
    assert paper["type"] == "article"
    assert paper["title"].lower() == "self-oscillation and synchronisation transitions in elasto-active structures"
    assert _names(paper["authors"]) == ["Zheng", "Brandenbourger", "Robinet", "Schall", "Lerner", "Coulais"]
    assert "2106.05721" in paper["url"]
    data = [r for r in cff.get("references", []) if r.get("doi") == "10.5281/zenodo.6549887"]
    assert len(data) == 1 and data[0]["type"] == "data" and data[0]["authors"]
    for ref in [paper, *cff.get("references", [])]:  # CFF: every reference has a type, a title and authors
        assert ref.get("type") and ref.get("title") and ref.get("authors")
        if "doi" in ref:
            assert re.fullmatch(r"10\.\d{4,9}/[-._;()/:A-Za-z0-9]+", ref["doi"])

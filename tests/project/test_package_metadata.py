"""The package's metadata says what it is: its license is the MIT text shipped beside it, it is typed (PEP 561's
py.typed, installed with the package), and pyproject.toml carries classifiers and project URLs that lead somewhere.
tests/project/test_packaging.py checks that the built wheel carries py.typed and the license."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_the_license_file_is_the_license_pyproject_names():
    project = PROJECT["project"]
    assert project["license"] == "MIT"
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License") and "the elastoactive authors" in text
    assert "Permission is hereby granted, free of charge" in text
    assert project.get("license-files", ["LICENSE"]) == ["LICENSE"]
    # an SPDX license expression excludes license classifiers (setuptools refuses both)
    assert not [c for c in project["classifiers"] if c.startswith("License ::")]


def test_the_package_is_typed_and_ships_its_marker():
    assert (ROOT / "elastoactive" / "py.typed").is_file()
    assert "py.typed" in PROJECT["tool"]["setuptools"]["package-data"]["elastoactive"]
    assert "Typing :: Typed" in PROJECT["project"]["classifiers"]


def test_classifiers_and_urls():
    """Classifiers name the Python versions requires-python allows and the field; every URL is a web address or a
    path of the source tree that exists (there is no hosted documentation)."""
    project = PROJECT["project"]
    classifiers = project["classifiers"]
    assert "Programming Language :: Python :: 3.11" in classifiers  # requires-python = ">=3.11"
    assert project["requires-python"] == ">=3.11"
    assert "Topic :: Scientific/Engineering :: Physics" in classifiers
    urls = project["urls"]
    assert "Documentation" in urls
    for name, url in urls.items():
        assert url.startswith("https://") or (ROOT / url).exists(), (name, url)

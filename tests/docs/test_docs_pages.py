"""The documentation's pages, read as files (no build): the generated pages committed in docs/ are what the code
writes today, every relative link in README.md and docs/ leads to a file of the repository, the citation page agrees
with CITATION.cff, the changelog names every deprecated module path and the release that removes it, and the gallery
shows beside every figure the command that made it."""

from __future__ import annotations

import importlib.util
import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"

LINK = re.compile(r"\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)|(?:src|href|poster)=\"([^\"]+)\"")
"""A Markdown link or image's target, or an HTML attribute's that names a file."""


@pytest.fixture(scope="module")
def hooks():
    """scripts/docs_hooks.py as a module (it needs MkDocs: the docs extra)."""
    pytest.importorskip("mkdocs", reason="the docs extra is not installed: run bash scripts/docs_setup.sh")
    spec = importlib.util.spec_from_file_location("docs_hooks_under_test", ROOT / "scripts" / "docs_hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_generated_pages_are_up_to_date(hooks):
    """docs/cli.md and docs/api/parameters.md are what the parser and the parameter table give today (rewrite them
    with `bash scripts/docs.sh generate`)."""
    stale = hooks.write_pages(check=True)
    assert not stale, f"out of date: {', '.join('docs/' + p for p in stale)}; run bash scripts/docs.sh generate"


def test_the_parameters_page_lists_every_parameter_and_setting(hooks):
    """Every registered parameter has a row (with its default, range and scenes), every Numerics setting one with its
    default as a value, not the name of a constant."""
    import dataclasses

    from elastoactive.core import parameters
    from elastoactive.core.params import Numerics
    from elastoactive.core.physics_doc import physics_doc

    page = hooks.parameters_reference()
    for name in parameters.names():
        row = re.search(rf"^\| `{name}` \|.*$", page, re.M)
        assert row, name
        assert f"\n{name} : " in "\n" + physics_doc(), name  # the same table as help(ea.Physics)
        spec = parameters.get(name)
        if spec.instead_of is None:
            assert f"`{hooks._value(spec.default)}`" in row.group(0), name
    for field in dataclasses.fields(Numerics):
        row = re.search(rf"^\| `{field.name}` \|.*$", page, re.M)
        assert row and f"`{hooks._value(field.default)}`" in row.group(0), field.name
    assert "DEFAULT_" not in page


def _markdown_files() -> list[Path]:
    return [ROOT / "README.md", *sorted(DOCS.rglob("*.md"))]


def _relative_links(path: Path) -> list[str]:
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)  # code blocks are code, not links
    targets = [m.group(1) or m.group(2) for m in LINK.finditer(text)]
    return [t for t in targets if not re.match(r"[a-zA-Z][\w+.-]*:", t) and not t.startswith("#")]


def test_every_relative_link_leads_to_a_file():
    """A relative link in README.md or any page of docs/ names a file or folder of the repository, so that it works
    where the Markdown is read as it is (the code host) as well as in the built site."""
    broken = []
    for path in _markdown_files():
        for target in _relative_links(path):
            file = target.split("#")[0].split("?")[0]
            if file and not (path.parent / file).exists():
                broken.append(f"{path.relative_to(ROOT)}: {target}")
    assert not broken, "links to no file:\n" + "\n".join(broken)
    assert "cli.md" in {t.split("#")[0] for t in _relative_links(DOCS / "run.md")}


def _fields(body: str) -> dict[str, str]:
    """{field: value} of one BibTeX entry's body (`name = {value}, ...`; values may hold braces and span lines), each
    value with its outer braces, any inner ones and repeated whitespace dropped."""
    fields, i = {}, 0
    while match := re.compile(r"\s*(\w+)\s*=\s*\{").match(body, i):
        depth, j = 1, match.end()
        while depth:
            depth += {"{": 1, "}": -1}.get(body[j], 0)
            j += 1
        value = body[match.end() : j - 1].replace("{", "").replace("}", "")
        fields[match.group(1).lower()] = " ".join(value.split())
        i = body.find(",", j) + 1 if "," in body[j : j + 2] else len(body)
    return fields


def _bibtex(text: str) -> dict[str, dict[str, str]]:
    """key -> {"type": entry type, field: value} of every entry in the page's bibtex blocks."""
    entries = {}
    for block in re.findall(r"```bibtex\n(.*?)```", text, re.S):
        head = re.match(r"\s*@(\w+)\{([^,]+),", block)
        entries[head.group(2)] = {"type": head.group(1), **_fields(block[head.end() : block.rindex("}")])}
    return entries


def test_the_citation_page_agrees_with_citation_cff():
    """docs/citing.md's BibTeX holds what CITATION.cff says: the software's title, version and licence, the paper's
    title, authors and arXiv number, and the data's DOI."""
    yaml = pytest.importorskip("yaml")
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    entries = _bibtex((DOCS / "citing.md").read_text())
    software = next(e for e in entries.values() if e["type"] == "software")
    assert software["title"] == cff["title"] and software["version"] == str(cff["version"])
    assert software["license"] == cff["license"]
    assert all(a["name"] in software["author"] for a in cff["authors"])
    paper = cff["preferred-citation"]
    cited = next(e for e in entries.values() if e.get("eprint"))
    assert cited["title"].lower() == paper["title"].lower()
    assert cited["eprint"] in paper["url"]
    authors = [a.strip() for a in cited["author"].split(" and ")]
    assert authors == [f"{a['family-names']}, {a['given-names']}" for a in paper["authors"]]
    dois = {e.get("doi") for e in entries.values()}
    assert {r["doi"] for r in cff.get("references", []) if "doi" in r} <= dois


def test_the_changelog_names_the_deprecated_paths_and_their_release():
    """Every old module path that still imports (elastoactive._moved) is in the changelog with its new path, and the
    release that removes them, which the warning names too, comes after the current version."""
    from elastoactive import _moved

    changelog = (DOCS / "changelog.md").read_text()
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert f"## {version}" in changelog
    for old, new in _moved.MOVED.items():
        assert f"| `{old}` | `{new}` |" in changelog, old
    assert f"removed in {_moved.REMOVED_IN}" in changelog
    release = tuple(int(p) for p in _moved.REMOVED_IN.split("."))
    assert release > tuple(int(p) for p in version.split(".")), (_moved.REMOVED_IN, version)
    with pytest.warns(DeprecationWarning, match=re.escape(_moved.REMOVED_IN)):
        finder = _moved.MovedFinder()
        finder.find_spec("elastoactive.params")


def _figures() -> list[tuple[str, str]]:
    """(figure, its caption) of every figure on the gallery page."""
    gallery = (DOCS / "gallery.md").read_text()
    out = []
    for block in re.findall(r"<figure.*?</figure>", gallery, re.S):
        figure = re.search(r"(?:\]\(|poster=\")((?:img|reproduction)/[\w.-]+\.png)", block).group(1)
        out.append((figure, re.search(r"<figcaption>(.*?)</figcaption>", block, re.S).group(1)))
    return out


def test_the_gallery_shows_the_command_behind_every_figure():
    """Each figure's caption ends with the command that made it: the reproduction's figures `reproduce --only` the
    study that draws them (report.md's list of figures), the scenes' stills and videos scripts/make_readme_images.py
    with their name, the rest the command or script that writes them."""
    report = (DOCS / "reproduction" / "report.md").read_text()
    study = dict(re.findall(r"^- `([\w.]+\.png)` \((\w+)\)$", report, re.M))
    images = (ROOT / "scripts" / "make_readme_images.py").read_text()
    made = set(re.findall(r'^\s+\("([\w-]+)", ea\.Physics', images, re.M))
    from elastoactive.core import registry

    made |= set(registry.names())
    figures = _figures()
    assert len(figures) >= 40
    for figure, caption in figures:
        command = re.search(r"`([^`]+)`$", caption.strip())
        assert command, f"{figure}: no command in its caption"
        command = command.group(1)
        folder, name = figure.split("/")
        if folder == "reproduction":
            assert command == f"elastoactive reproduce --only {study[name]} --out docs/reproduction", figure
        elif command.startswith(".venv/bin/python scripts/make_readme_images.py"):
            assert command.endswith(f"--only {name.removesuffix('.png')}") and name.removesuffix(".png") in made
        elif command.startswith("elastoactive reproduce --only "):  # a study's figure, copied into docs/img
            assert study.get(name) == command.split()[3], figure
        elif command.startswith("elastoactive accuracy "):  # the study's outputs (checks.accuracy.OUTPUTS)
            assert f'"{name}"' in (ROOT / "elastoactive" / "checks" / "accuracy.py").read_text(), figure
        else:
            script = re.fullmatch(r"\.venv/bin/python (scripts/\S+\.py)", command)
            assert script and name in (ROOT / script.group(1)).read_text(), f"{figure}: {command}"

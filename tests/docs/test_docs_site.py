"""The documentation site (mkdocs.yml) builds offline with warnings as errors, broken links and anchors among them, its
search index finds every public name and every parameter, and it renders in a real browser: headless Chromium opens
the home page, the API pages, the gallery and the other pages of the nav, served from the built site, and every image
on them loads and decodes. scripts/docs_setup.sh installs what this needs (the `docs` extra and
Debian's chromium); without chromium the browser checks skip only where it cannot be installed (not root with apt)."""

from __future__ import annotations

import argparse
import functools
import http.server
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

OFFLINE = {"HTTP_PROXY": "http://127.0.0.1:9", "HTTPS_PROXY": "http://127.0.0.1:9", "NO_PROXY": "", "no_proxy": ""}
"""Any request the build tried to send over the network would fail through this proxy (nothing listens on port 9)."""

OTHER_PAGES = (
    "installation",
    "faq",
    "contributing",
    "changelog",
    "citing",
    "cli",
    "api/parameters",
    "api/plot",
    "api/scenes",
    "api/terms",
    "api/testing",
)
"""Pages of the nav opened in the browser besides the three screenshotted below (their DOM only: a launch each)."""

MARK_IMAGES = b"""<script>
addEventListener("DOMContentLoaded", () => {
  const images = [...document.images];
  images.forEach((img) => { img.loading = "eager"; });
  const settled = (img) => img.complete ? Promise.resolve()
    : new Promise((done) => { img.addEventListener("load", done); img.addEventListener("error", done); });
  Promise.all(images.map(settled)).then(() => {
    images.forEach((img) => { img.dataset.rendered = img.complete && img.naturalWidth > 0 ? "yes" : "no"; });
    document.body.dataset.imagesChecked = String(images.length);
  });
});
</script>"""
"""Put into every page the test serves: once every image has loaded or failed, each is marked with whether it decoded
to a picture (lazy images are loaded at once: the page is read without scrolling)."""


def _mkdocs_ready() -> None:
    try:
        import material  # noqa: F401
        import mkdocs  # noqa: F401
        import mkdocstrings  # noqa: F401
    except ImportError as err:
        pytest.fail(f"the docs extra is not installed ({err}): run bash scripts/docs_setup.sh")


def _build(config: Path, site: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, **OFFLINE, "NO_MKDOCS_2_WARNING": "1"}
    return subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file", str(config), "--site-dir", str(site)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    _mkdocs_ready()
    out = tmp_path_factory.mktemp("site")
    result = _build(ROOT / "mkdocs.yml", out)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return out


def test_the_site_builds_offline_with_warnings_as_errors(site):
    """The strict, offline build gives every page of the nav, the command-line page written from the parser (every
    subcommand and every option of `run`) and the API pages written from the docstrings."""
    from elastoactive.cli import build_parser

    for page in (
        "index",
        "getting-started",
        "run",
        "sweep",
        "reproduce",
        "cli",
        "api/index",
        "api/analysis",
        "gallery",
        "reproduction/report",
        "model",
        "errata",
        "performance",
        *OTHER_PAGES,
    ):
        assert (site / f"{page}.html").is_file(), page
    cli = (site / "cli.html").read_text()
    parser = build_parser()
    commands = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction").choices
    for name in commands:
        assert f'id="elastoactive-{name}"' in cli, name
    for action in commands["run"]._actions:
        if isinstance(action, argparse._HelpAction) or action.help == argparse.SUPPRESS:
            continue  # --help is every command's, and a suppressed option is not for users
        for option in action.option_strings:
            assert f"<code>{option}</code>" in cli, option
    api = (site / "api" / "index.html").read_text()
    for name in ("elastoactive.simulate", "elastoactive.measure", "elastoactive.Physics", "elastoactive.Numerics"):
        assert f'id="{name}"' in api, name
    assert (site / "assets" / "mathjax" / "tex-svg.js").is_file()


def _search_index(site: Path) -> dict[str, str]:
    """location -> text of every entry of the built site's search index."""
    import json

    docs = json.loads((site / "search" / "search_index.json").read_text())["docs"]
    return {doc["location"]: doc["title"] + " " + doc["text"] for doc in docs}


def _lent(module, name: str) -> str | None:
    """The sub-module a lazily imported front-door function or class is defined in, None for the others."""
    value = getattr(module, name)
    home = getattr(value, "__module__", None)
    lent = isinstance(home, str) and home.startswith("elastoactive.explore") and callable(value)
    return home if lent else None


def test_the_search_index_finds_every_public_name_and_parameter(site):
    """Every name of the front door (ea.__all__), every function of ea.plot and every name of the conformance kit has
    its own entry in the search index (a heading of the API reference), and every parameter of ea.Physics and every
    setting of ea.Numerics is found on the parameters' page."""
    import dataclasses

    import elastoactive as ea
    import elastoactive.plot
    import elastoactive.testing
    from elastoactive.core import parameters
    from elastoactive.core.params import Numerics

    index = _search_index(site)
    anchors = {location.split("#", 1)[1] for location in index if "#" in location}
    # a name the front door lends from a sub-package is found under its own module's name (ea.ramp: explore's)
    public = [f"elastoactive.{name}" for name in ea.__all__ if _lent(ea, name) is None]
    public += [f"{_lent(ea, name)}.{name}" for name in ea.__all__ if _lent(ea, name) is not None]
    public += [f"elastoactive.plot.{name}" for name in elastoactive.plot.__all__]
    public += [f"elastoactive.testing.{name}" for name in elastoactive.testing.__all__]
    assert not [name for name in public if name not in anchors], "not in the search index"
    text = " ".join(t for location, t in index.items() if location.startswith("api/parameters.html"))
    names = [*parameters.names(), *(f.name for f in dataclasses.fields(Numerics))]
    missing = [name for name in names if not re.search(rf"<code>{re.escape(name)}</code> (float|int|str|bool) ", text)]
    assert not missing, f"not on the parameters' page of the search index: {missing}"


def test_the_records_show_their_defaults_as_values(site):
    """ea.Numerics' defaults and ea.Physics' scene read as values (0.0025, 'one-pinned'), not as the constants that
    hold them."""
    api = (site / "api" / "index.html").read_text()
    assert not re.search(r'<span class="n">DEFAULT_', api), "a signature shows a constant's name"  # prose may name one
    assert '<span class="mf">0.0025</span>' in api and "one-pinned" in api


def test_a_broken_link_or_anchor_fails_the_build(tmp_path):
    """A page linking to a page that does not exist, or to a heading that does not, stops the build, naming both."""
    _mkdocs_ready()
    docs = tmp_path / "docs"
    shutil.copytree(ROOT / "docs", docs, ignore=shutil.ignore_patterns("reproduction", "generated", "img", "api"))
    for folder in ("reproduction", "generated", "img"):
        (docs / folder).symlink_to(ROOT / "docs" / folder)
    (docs / "api").mkdir()
    for page in (ROOT / "docs" / "api").glob("*.md"):
        (docs / "api" / page.name).write_text(f"# {page.stem}\n")  # the docstrings are not what is tested here
    with (docs / "getting-started.md").open("a") as page:
        page.write("\n[gone](no-such-page.md) and [nowhere](model.md#no-such-heading)\n")
    config = tmp_path / "mkdocs.yml"
    text = (ROOT / "mkdocs.yml").read_text().replace("docs_dir: docs", f"docs_dir: {docs}")
    config.write_text(text.replace("scripts/docs_hooks.py", str(ROOT / "scripts" / "docs_hooks.py")))
    result = _build(config, tmp_path / "site")
    assert result.returncode != 0
    assert "no-such-page.md" in result.stderr and "no-such-heading" in result.stderr, result.stderr[-3000:]


def test_the_docs_extra_is_what_the_site_needs():
    """The site's build (mkdocs.yml) needs MkDocs, its theme, mkdocstrings' Python handler and MathJax: the `docs`
    extra installs each, and scripts/docs_setup.sh installs that extra."""
    extra = " ".join(tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]["docs"])
    for package in ("mkdocs>", "mkdocs-material", "mkdocstrings[python]", "django-static-mathjax"):
        assert package in extra, package
    assert '["optional-dependencies"]["docs"]' in (ROOT / "scripts" / "docs_setup.sh").read_text()


def _chromium() -> str:
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    if found:
        return found
    installable = shutil.which("apt-get") and os.geteuid() == 0
    if installable or os.environ.get("CI"):
        pytest.fail("chromium is not installed: run bash scripts/docs_setup.sh (it installs Debian's chromium as root)")
    pytest.skip("chromium is not installed and cannot be here (not root with apt-get): the browser checks need it")


class _Handler(http.server.SimpleHTTPRequestHandler):
    """The built site, each HTML page with MARK_IMAGES; every path asked for that does not exist is recorded."""

    missing: list[str]

    def send_head(self):
        path = Path(self.translate_path(self.path))
        if path.is_dir():
            path = path / "index.html"
        if path.suffix == ".html" and path.is_file():
            body = path.read_bytes().replace(b"</body>", MARK_IMAGES + b"</body>", 1)
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            import io

            return io.BytesIO(body)
        if not path.exists():
            self.missing.append(self.path)
        return super().send_head()

    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def served(site):
    chromium = _chromium()
    handler = type("Handler", (_Handler,), {"missing": []})
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(handler, directory=str(site)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield chromium, f"http://127.0.0.1:{server.server_address[1]}", handler.missing
    finally:
        server.shutdown()
        server.server_close()


def _open(chromium: str, url: str, *, dump: bool, screenshot: Path | None = None) -> str:
    what = ["--dump-dom"] if dump else [f"--screenshot={screenshot}", "--window-size=1280,1600", "--hide-scrollbars"]
    with tempfile.TemporaryDirectory(prefix="chromium-") as profile:  # its own profile: browsers may run side by side
        result = subprocess.run(
            [
                chromium,
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                f"--user-data-dir={profile}",
                "--virtual-time-budget=5000",
                *what,
                url,
            ],
            capture_output=True,
            text=True,
            timeout=120,
        )
    assert result.returncode == 0, result.stderr[-2000:]
    return result.stdout


def _rendered_images(dom: str) -> tuple[int, list[str]]:
    """How many images the page has, once all settled, and the sources of those that did not decode."""
    checked = re.search(r'data-images-checked="(\d+)"', dom)
    assert checked, "the page's images never settled"
    failed = re.findall(r'<img[^>]*src="([^"]*)"[^>]*data-rendered="no"', dom)
    failed += re.findall(r'<img[^>]*data-rendered="no"[^>]*src="([^"]*)"', dom)
    return int(checked.group(1)), failed


def _assert_painted(png: Path) -> None:
    """The screenshot shows a page, not a blank window: many colours, text and pictures."""
    import matplotlib.image
    import numpy as np

    pixels = matplotlib.image.imread(png)[..., :3]
    colours = np.unique((pixels * 255).astype(np.uint8).reshape(-1, 3), axis=0)
    assert len(colours) > 200, f"{png.name}: {len(colours)} colours"


def _gallery_images() -> int:
    return len(re.findall(r"!\[[^\]]*\]\([^)]*\.png\)", (ROOT / "docs" / "gallery.md").read_text()))


def test_the_gallery_shows_every_figure_and_video():
    """Every PNG and MP4 in docs/img and docs/reproduction is on the gallery page (a still or a video's poster)."""
    gallery = (ROOT / "docs" / "gallery.md").read_text()
    shown = set(re.findall(r"(?:\(|\")((?:img|reproduction)/[\w.-]+\.(?:png|mp4))", gallery))
    made = {
        f"{folder}/{p.name}"
        for folder in ("img", "reproduction")
        for p in (ROOT / "docs" / folder).iterdir()
        if p.suffix in (".png", ".mp4")
    }
    assert not made - shown, f"not in docs/gallery.md: {sorted(made - shown)}"
    assert not shown - made, f"docs/gallery.md shows files that do not exist: {sorted(shown - made)}"


@pytest.mark.parametrize(
    ("page", "at_least"), [("index.html", 6), ("gallery.html", _gallery_images()), ("api/index.html", 0)]
)
def test_pages_render_in_a_real_browser(served, tmp_path, page, at_least):
    """Chromium renders the page: every image on it decodes (the home page's stills, every figure of the gallery),
    nothing it asks for is missing (a video, a script, MathJax), and the screenshot is a painted page."""
    chromium, base, missing = served
    missing.clear()
    dom = _open(chromium, f"{base}/{page}", dump=True)
    count, failed = _rendered_images(dom)
    assert count >= at_least and not failed, (page, count, failed)
    assert not missing, (page, missing)
    if page == "api/index.html":  # the docstrings, rendered: a function's parameters and what it returns
        assert 'id="elastoactive.simulate"' in dom and "Parameters" in dom
    shot = tmp_path / (page.replace("/", "_") + ".png")
    _open(chromium, f"{base}/{page}", dump=False, screenshot=shot)
    _assert_painted(shot)


@pytest.mark.parametrize("page", OTHER_PAGES)
def test_every_page_renders_in_a_real_browser(served, page):
    """Chromium renders the page: its heading is there, every image on it decodes and nothing it asks for is
    missing."""
    chromium, base, missing = served
    missing.clear()
    dom = _open(chromium, f"{base}/{page}.html", dump=True)
    _, failed = _rendered_images(dom)
    assert not failed and not missing, (page, failed, missing)
    assert re.search(r"<h1[^>]*>", dom) and "md-content" in dom, page


def test_maths_is_typeset_offline(served):
    """The model's $...$ come out as MathJax's SVG, from the copy in the site (nothing fetched from elsewhere)."""
    chromium, base, missing = served
    dom = _open(chromium, f"{base}/model.html", dump=True)
    assert dom.count("<mjx-container") > 50 and "<svg" in dom
    assert not re.search(r'<span class="arithmatex">\\\(', dom), "a formula was left as TeX"

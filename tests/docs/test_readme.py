"""The README is the front page (short: what it is, the pictures, the two commands, ten lines of Python, what it
reproduces, the code map, links into the site), and every command and code block in it and in the site's guides runs,
so a documented command can never fail unseen: the README's commands as written, through a shell, from a folder whose
.venv is the set-up's and with no `elastoactive` on PATH (as a reader has them right after the set-up command); the
guides' (which activate the venv first) at a small size. The README's own set-up commands (scripts/setup.sh,
scripts/test.sh) are what CI runs, so they are not run again here."""

from __future__ import annotations

import functools
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()

GUIDES = ("getting-started", "run", "sweep", "reproduce", "beyond")
"""The site's guide pages (docs/<name>.md) whose code blocks run here, beside the README's: the front page's
sections moved there."""

PAGES = {"README.md": README, **{f"docs/{name}.md": (ROOT / "docs" / f"{name}.md").read_text() for name in GUIDES}}

SHORT = 20.0
"""tau: the longest run a documented command makes here (its files and messages are what is checked, not its physics,
which the physics tests check)."""
LADDERS = {"filament": "10,20", "whirl": "8,10,14"}
"""The continuum commands' ladders of N in the guide tests: the same code as the default ladders, without their longest
chains (the default filament ladder reaches N = 160)."""

FRONT_PAGE_LINES = 150
"""The README is a front page: at most this many lines, the rest is on the site."""


def _blocks(language: str) -> list[tuple[str, str]]:
    """(page, code) of every fenced block in the language, page by page."""
    return [
        (page, code) for page, text in PAGES.items() for code in re.findall(rf"```{language}\n(.*?)```", text, re.S)
    ]


def _readme_lines() -> list[str]:
    """The README's `elastoactive` command lines, exactly as written (their comments included)."""
    return [
        line.strip()
        for page, block in _blocks("bash")
        if page == "README.md"
        for line in block.splitlines()
        if line.strip().startswith(("elastoactive ", ".venv/bin/elastoactive "))
    ]


def _without_elastoactive(path: str) -> str:
    """PATH without the folders that hold an `elastoactive` command (an activated venv's bin)."""
    return os.pathsep.join(d for d in path.split(os.pathsep) if d and not (Path(d) / "elastoactive").exists())


def _commands() -> list[tuple[str, list[str]]]:
    """(page, argv) of the `elastoactive ...` lines of the bash blocks, comments dropped, in order."""
    out = []
    for page, block in _blocks("bash"):
        for line in block.splitlines():
            line = line.split("  #")[0].strip()
            if line.startswith(("elastoactive ", ".venv/bin/elastoactive ")):
                out.append((page, shlex.split(line)[1:]))
    return out


def _shrink(argv: list[str], scheduler=None) -> list[str]:
    """The same command at a small size: shorter runs, two grid values, the tiny reproduction, one scene's
    validation."""
    argv = list(argv)
    for i, arg in enumerate(argv[:-1]):
        nxt = argv[i + 1]
        if arg == "--duration":
            argv[i + 1] = str(min(float(nxt), SHORT))
        elif arg == "--grid":
            name, values = nxt.split("=", 1)
            if ":" in values:
                a, b, _ = values.split(":")
                values = f"{a}:{b}:2"
            else:
                values = ",".join(values.split(",")[:2])
            argv[i + 1] = f"{name}={values}"
        elif arg == "--time":
            argv[i + 1] = str(min(float(nxt), SHORT / 2))
        elif arg == "--scheduler":
            argv[i + 1] = scheduler()
    if argv[0] == "run" and "--duration" not in argv and "--help" not in argv and "--from" not in argv:
        argv += ["--duration", str(SHORT)]
    if argv[0] == "sweep" and "--duration" not in argv:
        argv += ["--duration", str(SHORT)]
    if argv[0] == "reproduce":
        argv += ["--tiny", "--workers", "1"]
    if argv[0] in LADDERS and "--ns" not in argv:
        argv += ["--ns", LADDERS[argv[0]]]
    if argv[0] == "validate" and (len(argv) == 1 or argv[1].startswith("-")):
        # every scene's cases (or convergence ladders) take minutes: one scene's go through the same code (the
        # convergence ladder's nine MuJoCo runs: the single trapped unit's take 7 s, a chain's 38)
        argv.insert(1, "trapped-unit" if "--convergence" in argv else "two-pinned")
    return argv


CODE_SHORT = 150.0
"""tau: the longest run a documented Python block makes here, long enough for the numbers it prints to be measured
(a beat's amplitude and frequency over the second half)."""


def _shrink_code(code: str) -> str:
    """A Python block at a small size: every `duration=` capped at CODE_SHORT (what is checked is that the documented
    code runs and prints, not its physics)."""
    return re.sub(r"duration=(\d+(?:\.\d*)?)", lambda m: f"duration={min(float(m[1]), CODE_SHORT):g}", code)


@functools.cache
def _gl_works() -> bool:
    from elastoactive.render import RenderError, gl_backend  # importing render is slow: only here

    try:
        gl_backend()
    except RenderError:
        return False
    return True


def test_readme_has_the_two_commands():
    section = README[README.index("## Two commands") :]
    section = section[: section.index("\n## ", 1)]
    assert "bash scripts/setup.sh && .venv/bin/elastoactive reproduce" in section
    assert "bash scripts/test.sh" in section


def test_readme_is_a_front_page():
    """Under FRONT_PAGE_LINES lines with the front page's sections, no generated block (those live on the site's
    pages), and every link into docs/ names a file there (or the page the site writes from the parser)."""
    lines = README.splitlines()
    assert len(lines) < FRONT_PAGE_LINES, f"README.md has {len(lines)} lines: move the details to docs/"
    headings = re.findall(r"^## (.*)$", README, re.M)
    assert headings[:1] == ["Two commands"] and {"Ten lines of Python", "What it reproduces", "Code map"} <= set(
        headings
    )
    assert "<!-- generated:" not in README
    python = [code for page, code in _blocks("python") if page == "README.md"]
    assert len(python) == 1 and len([line for line in python[0].splitlines() if line.strip()]) <= 10
    assert "docs/reproduction/report.md" in README[README.index("## What it reproduces") :]
    for target in re.findall(r"\]\((docs/[^)#\s]+)", README):
        assert (ROOT / target).exists(), target


COMMAND_PAGES = sorted({page for page, _ in _commands()})
"""The pages with commands: each page's commands run in order in a folder of their own, as a reader follows one page
(one test per page, so that the pages run side by side on the suite's workers)."""


@pytest.fixture(scope="module")
def scheduler():
    """address() -> a local Dask scheduler's address, the cluster started when a command first asks for one."""
    clusters = []

    def address() -> str:
        if not clusters:
            from distributed import LocalCluster  # optional dependency, used here only for the sweep's Dask line

            clusters.append(
                LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp", dashboard_address=None)
            )
        return clusters[0].scheduler_address

    yield address
    for cluster in clusters:
        cluster.close()


def test_the_pages_document_commands_and_code():
    commands, blocks = _commands(), _blocks("python")
    assert len(commands) >= 10 and "README.md" in COMMAND_PAGES
    assert {page for page, _ in blocks} >= {"README.md", "docs/run.md", "docs/getting-started.md"}
    assert all(_shrink_code(code) != code for _, code in blocks if "duration=" in code)


def test_the_readme_commands_need_nothing_but_the_set_up():
    """Right after `bash scripts/setup.sh` the command is .venv/bin/elastoactive: a bare `elastoactive` is not on PATH
    until the venv is activated, which the README does not do."""
    lines = _readme_lines()
    assert len(lines) >= 4 and all(line.startswith(".venv/bin/elastoactive ") for line in lines), lines


@pytest.mark.slow
def test_the_readme_commands_run_as_written(tmp_path):
    """Each README command line, verbatim, through bash, in a folder whose .venv is the set-up's and with no other
    `elastoactive` on PATH: it exits 0, and its sweep measures every point (no NaN frequency or periodicity)."""
    venv = ROOT / ".venv"
    if not (venv / "bin" / "elastoactive").exists():
        pytest.skip("no set-up here: bash scripts/setup.sh makes .venv/bin/elastoactive")
    (tmp_path / ".venv").symlink_to(venv)
    env = {**os.environ, "PYTHONWARNINGS": "ignore", "PATH": _without_elastoactive(os.environ.get("PATH", ""))}
    for line in _readme_lines():
        if "--video" in line and not _gl_works():
            continue  # no GL here for videos
        result = subprocess.run(
            ["bash", "-c", line], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=1200
        )
        assert result.returncode == 0, f"{line}\n{result.stderr[-2000:]}"
    import xarray as xr  # start-up time: only this test reads a netCDF

    with xr.open_dataset(tmp_path / "results" / "onset.nc") as onset:
        assert onset["frequency"].notnull().all() and onset["periodic"].notnull().all()


@pytest.mark.slow
@pytest.mark.parametrize("page", [page for page in COMMAND_PAGES if page != "README.md"])
def test_every_guide_command_runs(page, tmp_path, scheduler):
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    for argv in (argv for where, argv in _commands() if where == page):
        if argv[0] == "reproduce" or ("--video" in argv or "-o" in argv or "--still" in argv) and not _gl_works():
            continue  # reproduce is the main job (test_reproduce runs it tiny); no GL here for videos
        small = _shrink(argv, scheduler)
        result = subprocess.run(
            [sys.executable, "-m", "elastoactive", *small],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert result.returncode == 0, f"elastoactive {' '.join(small)}\n{result.stderr[-2000:]}"


@pytest.mark.parametrize(
    "page, code", _blocks("python"), ids=[f"{page}:{i}" for i, (page, _) in enumerate(_blocks("python"))]
)
def test_every_readme_python_block_runs(page, code, tmp_path):
    code = _shrink_code(code)
    result = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, f"{page}:\n{code}\n{result.stderr[-2000:]}"


def test_generated_tables_come_from_the_committed_reports():
    """The claims table of docs/reproduce.md and the validate and convergence tables of docs/accuracy.md equal the
    committed report files."""
    result = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "update_readme.py"), "--check"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 0, result.stderr


def test_committed_report_matches_the_code():
    """docs/reproduction/report.md was written by today's code: its claims and sigma_c tables equal those
    the code builds from the committed study data (so a change of wording or of a number shows here)."""
    from elastoactive.report import claims
    from elastoactive.studies import STUDIES, load_study

    folder = ROOT / "docs" / "reproduction"
    studies = {name: load_study(folder, name) for name in STUDIES}
    report = (folder / "report.md").read_text()
    assert claims.claims_table(claims.build_claims(studies)) in report
    stability = studies["stability"]
    assert claims.sigma_c_table(stability, every=1 if stability.summary.n_max <= 20 else 4) in report

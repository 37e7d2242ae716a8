"""Every command and code block in the README runs (at a small size), so a documented command can
never fail unseen. The README's own set-up commands (scripts/setup.sh, scripts/test.sh) are what CI
runs, so they are not run again here."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def _blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", README, re.S)


def _commands() -> list[list[str]]:
    """The `elastoactive ...` lines of the bash blocks, comments dropped, in order."""
    out = []
    for block in _blocks("bash"):
        for line in block.splitlines():
            line = line.split("  #")[0].strip()
            if line.startswith(("elastoactive ", ".venv/bin/elastoactive ")):
                out.append(shlex.split(line)[1:])
    return out


def _shrink(argv: list[str], scheduler: str | None) -> list[str]:
    """The same command at a small size: shorter runs, two grid values, the tiny reproduction."""
    argv = list(argv)
    for i, arg in enumerate(argv[:-1]):
        nxt = argv[i + 1]
        if arg == "--duration":
            argv[i + 1] = str(min(float(nxt), 60.0))
        elif arg == "--grid":
            name, values = nxt.split("=", 1)
            if ":" in values:
                a, b, _ = values.split(":")
                values = f"{a}:{b}:2"
            else:
                values = ",".join(values.split(",")[:2])
            argv[i + 1] = f"{name}={values}"
        elif arg == "--time":
            argv[i + 1] = "50"
        elif arg == "--scheduler":
            argv[i + 1] = scheduler
    if argv[0] == "run" and "--duration" not in argv and "--help" not in argv and "--from" not in argv:
        argv += ["--duration", "60"]
    if argv[0] == "sweep" and "--duration" not in argv:
        argv += ["--duration", "30"]
    if argv[0] == "reproduce":
        argv += ["--tiny", "--workers", "1"]
    return argv


def _gl_works() -> bool:
    from elastoactive.render import RenderError, gl_backend  # importing render is slow: only here

    try:
        gl_backend()
    except RenderError:
        return False
    return True


def test_readme_has_the_two_commands():
    assert "bash scripts/setup.sh && .venv/bin/elastoactive reproduce" in README
    assert "bash scripts/test.sh" in README


@pytest.mark.slow
def test_every_readme_command_runs(tmp_path):
    from distributed import LocalCluster  # optional dependency, used here only for the README's Dask line

    commands = _commands()
    assert len(commands) >= 10
    gl = _gl_works()
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, protocol="tcp", dashboard_address=None
    ) as cluster:
        for argv in commands:
            if argv[0] == "reproduce" or ("--video" in argv or "-o" in argv or "--still" in argv) and not gl:
                continue  # reproduce is the main job (test_reproduce runs it tiny); no GL here for videos
            small = _shrink(argv, cluster.scheduler_address)
            result = subprocess.run(
                [sys.executable, "-m", "elastoactive", *small],
                cwd=tmp_path,
                env=env,
                capture_output=True,
                text=True,
                timeout=600,
            )
            assert result.returncode == 0, f"elastoactive {' '.join(small)}\n{result.stderr[-2000:]}"


def test_every_readme_python_block_runs(tmp_path):
    blocks = _blocks("python")
    assert blocks
    for code in blocks:
        result = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=600)
        assert result.returncode == 0, f"{code}\n{result.stderr[-2000:]}"


def test_readme_tables_come_from_the_committed_reports():
    """The README's claims, validate and convergence tables equal the committed report files."""
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

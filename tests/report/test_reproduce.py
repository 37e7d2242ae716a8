"""`elastoactive reproduce --tiny` and the scenario scripts at their tiny size."""

from __future__ import annotations

import os
import re
import runpy
import subprocess
import sys
from pathlib import Path

import pytest

import elastoactive.studies
from elastoactive.cli import main
from elastoactive.io.progress import LOG_INTERVAL, LineProgress
from elastoactive.report.reproduce import reproduce
from elastoactive.studies import STUDIES, SUMMARIES, load_study

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = {
    "flagellar_hopf.py": ["fig3ab_hopf.png", "fig3cd_eigenvalues.png", "figA_size_effect.png", "normal_form_n2.png"],
    "self_snapping.py": ["fig4cd_snapping.png", "figA_snapping_map.png"],
    "rotating_pin.py": ["figA_rotating_pin.png"],
    "synchronisation.py": ["fig5ef_sync.png", "fig5f_tongue.png", "sync_n2_kappa_c.png"],
    "noise_anisotropy.py": ["figA_noise.png", "figA_anisotropy.png"],
}


def _png(path: Path) -> bool:
    return path.exists() and path.stat().st_size > 5000 and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


REPRODUCED = (
    "stability",
    "growth",
    "hopf",
    "normal_form",
    "snapping",
    "rotation",
    "sync",
    "tongue",
    "sync_n2",
    "noise",
    "anisotropy",
    "self_aligning",
    "star",
)
"""The studies `reproduce --tiny` runs here: the paper's (the claims and figures checked below, the scenario scripts'
figures) and those that no other test runs at the tiny size (test_every_study_runs_tiny_in_some_test)."""


def test_reproduce_tiny_writes_report_figures_and_data(tmp_path):
    out = tmp_path / "repro"
    argv = ["reproduce", "--tiny", "--only", ",".join(REPRODUCED), "--out", str(out), "--workers", "2", "--quiet"]
    assert main(argv) == 0
    report = (out / "report.md").read_text()
    assert "| # | claim | paper | MuJoCo | reduced model | agree |" in report
    rows = [line for line in report.splitlines() if line.startswith("| ") and line[2].isdigit()]
    assert len(rows) >= 20
    for claim in ("Landau-Stuart", "N^-3", "kappa_c", "Arnold tongue", "constant speed", "delta = 0", "tau_L/tau_T"):
        assert claim in report, claim
    # what the tiny size cannot judge (the onset fit and its exponent, the N^-3 slope, the supplement's Landau
    # coefficient) is said to be so, not judged **no**; no number prints as nan
    unjudged = [row for row in rows if "**not judged at this size**" in row]
    for claim in (
        "N = 7 simulations: onset sigma_c",
        "supercritical Hopf",
        "sigma_c falls as N^-3",
        "Landau-Stuart cubic coefficient (supplement)",
    ):
        assert any(claim in row for row in unjudged), claim
    assert not any("nan" in cell.split() or "^nan" in cell for row in rows for cell in row.split("|")), report
    figures = sorted({f for names in SCRIPTS.values() for f in names})
    for name in figures + ["fig2_limit_cycles.png", "growth_rates.png", "fig4b_snapping_shapes.png"]:
        assert _png(out / name), name
    for name in REPRODUCED:
        summary = load_study(out, name).summary
        assert isinstance(summary, SUMMARIES[name]) and summary.as_dict(), name
    assert (out / "stability_sigma_c.csv").read_text().startswith("N,sigma_c,")


def test_every_study_runs_tiny_in_some_test():
    """Every registered study runs at the tiny size somewhere in the suite: in the reproduction above, or in a test of
    its own (`<name>_study("tiny"`, or a `tiny_studies(...)` fixture call naming it), so that a new study cannot
    go unrun."""
    sources = "\n".join(p.read_text() for p in (ROOT / "tests").rglob("test_*.py"))
    fixture_calls = " ".join(re.findall(r"tiny_studies\(([^)]*)\)", sources))
    unrun = [
        name
        for name in STUDIES
        if name not in REPRODUCED and f'{name}_study("tiny"' not in sources and f'"{name}"' not in fixture_calls
    ]
    assert not unrun, f"studies no test runs at the tiny size: {unrun}"


def test_reproduce_rejects_unknown_study(tmp_path):
    with pytest.raises(ValueError):
        reproduce(tmp_path, "tiny", 1, only=["nonsense"], progress=False, log=lambda *a: None)


@pytest.mark.parametrize("script", sorted(SCRIPTS))
def test_scenario_script_tiny(script, tmp_path, monkeypatch, capsys):
    """Each scenario script, as `python scripts/SCRIPT --tiny --out DIR --workers 2` runs it, writes its figures and
    says so. Its studies are the committed reproduction's (docs/reproduction, read back), handed to the script in
    place of running them again (test_reproduce_tiny_writes_report_figures_and_data runs every study at the tiny
    size); the script's arguments, saving, figures and printout are its own."""
    committed = ROOT / "docs" / "reproduction"
    asked = []
    for name, study in STUDIES.items():

        def ready(size, workers=None, *, name=name):
            assert size == "tiny" and workers in (None, 2), (name, size, workers)
            asked.append(name)
            return load_study(committed, name)

        monkeypatch.setattr(elastoactive.studies, study.__name__, ready)
    monkeypatch.setattr(sys, "argv", [script, "--tiny", "--out", str(tmp_path), "--workers", "2"])
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(ROOT / "scripts" / script), run_name="__main__")
    assert asked, "the script ran none of the studies"
    for name in SCRIPTS[script]:
        assert _png(tmp_path / name), name
    assert "wrote" in capsys.readouterr().out


def test_progress_says_done_only_when_every_item_finished(capsys):
    """close() runs in a `finally` on Ctrl-C too: 30 of 44 cases must not read as 'done'."""
    bar = LineProgress(44, "Hopf N = 7", "case")
    bar.start -= 2 * LOG_INTERVAL  # a long batch: its closing line is due
    bar.n = 30
    bar.close()
    assert "done" not in capsys.readouterr().err
    bar.n = 44
    bar.close()
    assert "Hopf N = 7: done (44 cases" in capsys.readouterr().err


def test_the_claims_block_holds_only_the_claims_table():
    """The generated claims block of docs/reproduce.md is the claims table alone (not report.md's sigma_c(N) table
    nor its run-time table), one row per claim the committed study data make."""
    import importlib.util

    from elastoactive.report import claims
    from elastoactive.studies import load_study, registry

    spec = importlib.util.spec_from_file_location("update_readme", ROOT / "scripts" / "update_readme.py")
    update_readme = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(update_readme)
    block = update_readme.claims_table()
    lines = block.splitlines()
    folder = ROOT / "docs" / "reproduction"
    rows = claims.build_claims(
        {name: load_study(folder, name) for name in registry.names() if (folder / f"{name}.json").exists()}
    )
    assert lines[0] == "| # | claim | paper | MuJoCo | reduced model | agree |" and len(lines) == 2 + len(rows)
    assert all(line.startswith(f"| {i} | ") for i, line in enumerate(lines[2:], 1))
    page = (ROOT / "docs" / "reproduce.md").read_text()
    assert f"<!-- generated: claims -->\n{block}\n<!-- end -->" in page


def test_the_code_digest_covers_every_source_that_makes_results():
    """Resume keeps a study only when the code that made it is today's: the digest must see the reduced engine,
    the MJCF templates and the callback's C source, which a checkout keeps in top-level folders."""
    from elastoactive.report.reproduce import source_digest, source_files

    files = source_files()
    for rel in (
        "reproduce.py",
        "studies/registry.py",
        "reduced/kernels.py",
        "stability.py",
        "common.xml",
        "follower.c",
    ):
        assert any(k.endswith(":" + rel) or k.endswith("/" + rel) for k in files), rel
    inits = {p.parent.name for p in files.values() if p.name == "__init__.py"}
    assert {"elastoactive", "analysis", "reduced", "studies"} <= inits  # same names in different folders all count
    assert len(source_digest()) == 16 and source_digest() == source_digest()


def test_one_reproduce_per_folder_and_a_stale_lock_is_taken_over(tmp_path, capsys):
    """A second reproduce into a folder another one is writing is refused in one line naming --out and the holder,
    before any study runs; the lock file a killed run leaves behind blocks nothing."""
    from conftest import refused

    from elastoactive.io.outputs import lock_file
    from elastoactive.report.reproduce import LOCK

    out = tmp_path / "repro"
    out.mkdir()
    hold = (
        "import sys; from elastoactive.io.outputs import lock_file\n"
        "with lock_file(sys.argv[1], 'reproduce'):\n    print('held', flush=True); sys.stdin.read()"
    )
    holder = subprocess.Popen(
        [sys.executable, "-c", hold, str(out / LOCK)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )
    try:
        assert holder.stdout.readline().strip() == "held"
        line = refused(
            capsys,
            ["reproduce", "--tiny", "--only", "stability", "--out", str(out), "--quiet"],
            "--out",
            "another reproduce is writing into it",
            f"pid {holder.pid}",
        )
        assert "wait for it" in line and sorted(p.name for p in out.iterdir()) == [LOCK]
    finally:
        holder.kill()  # no clean-up: its lock file stays, stale
        holder.wait()
    assert (out / LOCK).exists()
    with lock_file(out / LOCK, "reproduce"):  # taken over at once
        assert f"pid {os.getpid()} " in (out / LOCK).read_text()
    assert not (out / LOCK).exists()

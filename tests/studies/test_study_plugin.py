"""A study is a plug-in: this file alone defines two toy studies (the linear onset of short chains: no
simulation, a fraction of a second), registers them, and `reproduce` runs them into report.md with their
figures and claim rows; a partial run merges with the folder, a rerun resumes, Ctrl-C keeps what finished."""

from __future__ import annotations

import json
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from elastoactive.analysis import stability as stab
from elastoactive.cli import main
from elastoactive.core.errors import ParameterError
from elastoactive.report import reproduce as reproduce_module
from elastoactive.report.reproduce import Interrupted, reproduce
from elastoactive.studies import STUDIES, SUMMARIES, Study, Summary, load_study, registry
from elastoactive.studies import plotting as plots
from elastoactive.studies.claim_rows import Claim, fmt, verdict

CALLS: list[str] = []
"""Names of the toy studies run, in order (the tests read which ran and which were kept)."""
STOP: set[str] = set()
"""Toy studies that act as if Ctrl-C came while they run."""


@dataclass(frozen=True)
class OnsetSummary(Summary):
    sigma_c: list[float]
    exponent: float


def _onset_study(name: str, ns: tuple[int, ...]):
    def run(size: str = "quick", workers=None, progress: bool = True) -> Study:
        start = time.perf_counter()
        CALLS.append(name)
        if name in STOP:
            raise KeyboardInterrupt
        n = np.array(ns)
        sc = np.array([stab.critical_sigma(int(k))[0] for k in n])
        slope = float(np.polyfit(np.log(n), np.log(sc), 1)[0])
        return Study(
            name, size, {"n": n, "sigma_c": sc}, OnsetSummary(list(map(float, sc)), slope), time.perf_counter() - start
        )

    return run


@plots.styled
def _figure(study: Study, out: Path) -> list[Path]:
    fig, ax = plots.pyplot().subplots(figsize=(4, 3))
    ax.loglog(study.data["n"], study.data["sigma_c"], **plots.ENGINE_STYLE["reduced"])
    ax.set_xlabel("N")
    return [plots.save(fig, out, f"{study.name}_onset.png")]


def _claims(study: Study, read: Mapping[str, Study]) -> list[Claim]:
    s = study.summary
    other = read.get("toy_short")
    seen = f"; with toy_short: {fmt(other.summary.exponent, 3)}" if other else ""
    return [
        Claim(
            f"{study.name}: sigma_c falls as N^-3 at small N",
            "N^-3",
            "-",
            f"slope {fmt(s.exponent, 3)}{seen}",
            verdict(-3.5 < s.exponent < -2.0),
            "linear stability of N = 2..4 (toy study of the plug-in test)",
        )
    ]


@pytest.fixture
def toys(monkeypatch):
    """toy_short (N = 2, 3) and toy_long (N = 3, 4; its claims read toy_short), registered for one test; the code
    digest held fixed (the package's sources may change under a test run in a shared checkout)."""
    monkeypatch.setattr(reproduce_module, "source_digest", lambda: "code-1")
    CALLS.clear()
    STOP.clear()
    for name, ns, order, reads in (("toy_short", (2, 3), 1001, ()), ("toy_long", (3, 4), 1002, ("toy_short",))):
        entry = registry.declare(name, summary=OnsetSummary, order=order, budget=60.0, reads=reads)
        entry.run(_onset_study(name, ns))
        entry.figure(_figure)
        entry.claims(_claims)
    yield ("toy_short", "toy_long")
    registry.unregister("toy_short")
    registry.unregister("toy_long")


def _quiet(*_):
    pass


def test_a_study_registered_in_a_test_file_reaches_the_report(toys, tmp_path):
    assert "toy_long" in STUDIES and SUMMARIES["toy_long"] is OnsetSummary
    assert list(STUDIES)[-2:] == ["toy_short", "toy_long"]  # ordered by `order`, after the built-in studies
    result = reproduce(tmp_path, "tiny", 2, only=list(toys), progress=False, log=_quiet)  # figures in their process
    report = result.report.read_text()
    assert "- `toy_short_onset.png` (toy_short)" in report and "- `toy_long_onset.png` (toy_long)" in report
    assert (tmp_path / "toy_long_onset.png").stat().st_size > 5000
    assert "| 1 | toy_short: sigma_c falls as N^-3 at small N |" in report
    assert "| 2 | toy_long: sigma_c falls as N^-3 at small N |" in report and "with toy_short:" in report
    assert "## Claims (2 of 2 agree)" in report
    assert "| study | wall s | figures s | CPU s | budget s |" in report  # each study's time, figures apart, its budget
    assert "| toy_long | " in report and " | 60 |" in report and "(registry.StudyEntry.budget; 120 s" in report
    assert result.timings["toy_long"].budget_s == 60.0 and result.timings["toy_long"].cpu_s > 0
    record = json.loads((tmp_path / "provenance.json").read_text())
    assert record["timings"]["toy_long"]["budget_s"] == 60.0 and len(record["load_average"]) == 3
    assert isinstance(load_study(tmp_path, "toy_long").summary, OnsetSummary)


def test_a_partial_run_merges_and_a_rerun_resumes(toys, tmp_path):
    reproduce(tmp_path, "tiny", 1, only=list(toys), progress=False, log=_quiet)
    assert CALLS == ["toy_short", "toy_long"]
    again = reproduce(tmp_path, "tiny", 1, only=list(toys), progress=False, log=_quiet)
    assert CALLS == ["toy_short", "toy_long"] and again.kept == ["toy_short", "toy_long"]  # same size, same code
    partial = reproduce(tmp_path, "tiny", 1, only=["toy_long"], progress=False, log=_quiet, force=True)
    assert CALLS[-1] == "toy_long" and partial.ran == ["toy_long"] and partial.kept == ["toy_short"]
    report = partial.report.read_text()
    assert "toy_short: sigma_c falls" in report and "toy_long: sigma_c falls" in report  # the report did not shrink
    record = json.loads((tmp_path / "provenance.json").read_text())
    assert record["studies_run"] == ["toy_long"] and record["studies_kept"] == ["toy_short"]


def test_another_size_is_refused_in_one_line(toys, tmp_path, capsys):
    reproduce(tmp_path, "tiny", 1, only=["toy_short"], progress=False, log=_quiet)
    with pytest.raises(ParameterError, match="tiny-size studies"):
        reproduce(tmp_path, "quick", 1, only=["toy_long"], progress=False, log=_quiet)
    assert main(["reproduce", "--only", "toy_long", "--out", str(tmp_path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "--force" in err
    assert CALLS == ["toy_short"]
    forced = reproduce(tmp_path, "quick", 1, only=["toy_long"], progress=False, log=_quiet, force=True)
    assert CALLS == ["toy_short", "toy_long"] and list(forced.studies) == [
        "toy_long"
    ]  # the tiny one left out, and said
    assert "Left out: toy_short, whose data in this folder are of another size." in forced.report.read_text()


def test_ctrl_c_keeps_the_finished_studies_and_a_rerun_resumes(toys, tmp_path, capsys):
    STOP.add("toy_long")
    assert main(["reproduce", "--tiny", "--only", "toy_short,toy_long", "--out", str(tmp_path), "--quiet"]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "interrupted during toy_long" in err[0] and "kept" in err[0] and "toy_short" in err[0]
    assert (tmp_path / "toy_short.json").exists() and not (tmp_path / "toy_long.json").exists()
    with pytest.raises(Interrupted):
        reproduce(tmp_path, "tiny", 1, only=list(toys), progress=False, log=_quiet)
    STOP.clear()
    CALLS.clear()
    result = reproduce(tmp_path, "tiny", 1, only=list(toys), progress=False, log=_quiet)
    assert CALLS == ["toy_long"] and result.kept == ["toy_short"]


def test_data_this_code_cannot_read_are_rerun_or_named(toys, tmp_path):
    reproduce(tmp_path, "tiny", 1, only=list(toys), progress=False, log=_quiet)
    (tmp_path / "toy_short.npz").write_bytes(b"torn")
    lines = []
    partial = reproduce(tmp_path, "tiny", 1, only=["toy_long"], progress=False, log=lines.append)
    assert "toy_short" not in partial.studies and any("left out of the report: toy_short" in x for x in lines)
    assert "Left out: the data of toy_short" in partial.report.read_text()
    CALLS.clear()
    whole = reproduce(tmp_path, "tiny", 1, only=list(toys), progress=False, log=_quiet)
    assert CALLS == ["toy_short"] and whole.kept == ["toy_long"]  # asked for: run again


def test_data_made_by_other_code_are_run_again(toys, tmp_path, monkeypatch):
    reproduce(tmp_path, "tiny", 1, only=list(toys), progress=False, log=_quiet)
    monkeypatch.setattr(reproduce_module, "source_digest", lambda: "code-2")
    lines = []
    result = reproduce(tmp_path, "tiny", 1, only=["toy_short"], progress=False, log=lines.append)
    assert CALLS == ["toy_short", "toy_long", "toy_short"] and result.kept == [
        "toy_long"
    ]  # toy_long merged, as recorded
    assert any("made by other code: toy_short" in x for x in lines)
    assert json.loads((tmp_path / "toy_short.json").read_text())["provenance"]["code"] == "code-2"

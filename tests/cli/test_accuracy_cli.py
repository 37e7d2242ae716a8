"""`elastoactive accuracy`: a folder holding a study's results is replaced only with --force, refused before any
run."""

import pytest

from elastoactive.checks import accuracy
from elastoactive.cli import main


@pytest.fixture
def study(monkeypatch):
    """The study's runs replaced by a record of the sizes asked for (no simulation); its writer kept."""
    asked = []
    row = {"case": "one-pinned", "engine": "reduced", "series": "numba-DOP853", "status": "ok", "wall_s": 0.1}
    meta = {"cases": [("one-pinned", 10.0)], "size": "tiny", "quick": True, "workers": 1, "elapsed_s": 0.1}

    def run_study(size, **kwargs):
        asked.append(size)
        return [row], meta

    monkeypatch.setattr(accuracy, "run_study", run_study)

    def write_outputs(out, rows, meta):
        out.mkdir(parents=True, exist_ok=True)
        (out / "accuracy.md").write_text("new")

    monkeypatch.setattr(accuracy, "write_outputs", write_outputs)
    monkeypatch.setattr(accuracy, "summarise", lambda rows: {})
    monkeypatch.setattr(accuracy, "format_defaults", lambda summary: "")
    monkeypatch.setattr(accuracy, "format_recommendations", lambda *a: "")
    monkeypatch.setattr(accuracy, "recommend", lambda *a, **k: {})
    return asked


@pytest.mark.parametrize("name", accuracy.OUTPUTS)
def test_results_in_the_folder_are_kept_without_force(tmp_path, capsys, study, name):
    (tmp_path / name).write_text("quick results")
    assert main(["accuracy", "--tiny", "--out", str(tmp_path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--out" in err[0] and name in err[0] and "--force" in err[0], err
    assert study == [] and (tmp_path / name).read_text() == "quick results"


def test_force_replaces_them_and_a_fresh_folder_needs_none(tmp_path, capsys, study):
    (tmp_path / "old" / "accuracy.md").parent.mkdir()
    (tmp_path / "old" / "accuracy.md").write_text("quick results")
    assert main(["accuracy", "--tiny", "--out", str(tmp_path / "old"), "--quiet", "--force"]) == 0
    assert (tmp_path / "old" / "accuracy.md").read_text() == "new"
    assert main(["accuracy", "--tiny", "--out", str(tmp_path / "fresh"), "--quiet"]) == 0
    assert study == ["tiny", "tiny"]

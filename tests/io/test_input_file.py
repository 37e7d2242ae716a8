"""InputFile: a file a run read, found again where it still holds the bytes the run read (the original, else the run's
copy), and a record of them refused when malformed."""

import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.io.outputs import InputFile
from elastoactive.records import RunInputs


@pytest.fixture
def recorded(tmp_path):
    original = tmp_path / "nets" / "good.json"
    original.parent.mkdir()
    original.write_text('{"nodes": []}')
    record, data = InputFile.of(tmp_path / "nets" / ".." / "nets" / "good.json", "network.json")
    run = tmp_path / "run"
    run.mkdir()
    (run / "network.json").write_bytes(data)
    return record, original, run


def test_the_original_while_it_holds_the_bytes_read(recorded):
    record, original, run = recorded
    assert record.path == str(original.resolve())
    assert record.locate(run, "network file") == (original, None)


def test_the_runs_copy_once_the_original_changed_or_is_gone(recorded):
    record, original, run = recorded
    original.write_text('{"nodes": [[0, 0]]}')
    found, note = record.locate(run, "network file")
    assert found == (run / "network.json").resolve()
    assert note.startswith(f"network file {original} changed since the run (sha256 {record.sha256[:12]} then, ")
    assert note.endswith("now); using the run's copy network.json")
    original.unlink()
    gone = record.locate(run, "network file")[1]
    assert gone == f"network file {original} is gone; using the run's copy network.json"


def test_neither_holding_the_bytes_read_is_said(recorded):
    record, original, run = recorded
    original.write_text("{}")
    (run / "network.json").write_text("{}")
    found, note = record.locate(run, "network file")
    assert found is None and note.endswith("and the run's copy network.json is missing or changed too")


def test_a_malformed_inputs_record_is_refused_in_one_line():
    expected = r"^RUN/summary.json: its inputs record is not one elastoactive run writes$"
    with pytest.raises(ParameterError, match=expected):
        RunInputs.of({"inputs": {"network_file": {"path": "/x.json"}}}, "RUN/summary.json")
    assert RunInputs.of({}) == RunInputs()

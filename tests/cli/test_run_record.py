"""A run's folder is its whole record: the network file it read (copied, with its SHA-256, named by its absolute path),
the state it started from, and a finished simulation kept even when measuring it fails; `run --from`, `render` and
`ea.load` read the run's own inputs."""

import json
import os

import numpy as np
import pytest
from conftest import refused

import elastoactive as ea
from elastoactive import records
from elastoactive.cli import main
from elastoactive.cli import render as render_cli

NETWORK = {
    "nodes": [[0, 0], [1, 0], [0.5, 0.866], [1.5, 0.866], [1, 1.732]],
    "bonds": [[0, 1], [1, 2], [0, 2], [1, 3], [2, 3], [2, 4], [3, 4]],
    "pinned": [0, 1, 3],
}
"""A five-node network: three nodes pinned, two units."""
NETWORK_RUN = ["--sigma", "0.2", "--alignment-length", "0.1", "--duration", "6", "--engine", "reduced", "--quiet"]


def _summary(folder):
    return json.loads((folder / "summary.json").read_text())


@pytest.fixture
def network_run(tmp_path, monkeypatch, capsys):
    """A network run from ../nets/good.json, typed from a working folder beside it: (the run's folder, the file)."""
    nets, work = tmp_path / "nets", tmp_path / "work"
    nets.mkdir()
    work.mkdir()
    good = nets / "good.json"
    good.write_text(json.dumps(NETWORK))
    monkeypatch.chdir(work)
    assert main(["run", "network", "--geometry", "../nets/good.json", *NETWORK_RUN, "--out", "../run"]) == 0
    capsys.readouterr()
    return tmp_path / "run", good


def test_a_network_run_records_its_file_by_absolute_path_with_a_copy_and_its_checksum(network_run):
    run, good = network_run
    summary = _summary(run)
    assert summary["parameters"]["geometry"] == str(good.resolve())
    recorded = summary["inputs"]["network_file"]
    assert recorded["path"] == str(good.resolve()) and recorded["copy"] == records.NETWORK_COPY
    assert (run / "network.json").read_bytes() == good.read_bytes()
    assert recorded["sha256"] == records.sha256(good)


def test_run_from_an_absolute_path_in_another_folder(network_run, tmp_path, monkeypatch, capsys):
    run, _ = network_run
    elsewhere = tmp_path / "elsewhere" / "deeper"  # where ../nets/good.json is not
    elsewhere.mkdir(parents=True)
    monkeypatch.chdir(elsewhere)
    assert main(["run", "--from", str(run.resolve()), "--quiet", "--out", "again"]) == 0
    assert "network file" not in capsys.readouterr().err  # nothing changed: no note
    again = ea.load(elsewhere / "again")
    np.testing.assert_array_equal(again.nodes, ea.load(run).nodes)


def _unpin_node_3_and_add_a_node(path):
    data = json.loads(path.read_text())
    data["pinned"] = [0, 1]
    data["nodes"].append([2.0, 1.7])
    data["bonds"] += [[3, 5], [4, 5]]
    path.write_text(json.dumps(data))


def test_after_the_network_file_is_edited_run_from_render_and_load_read_the_runs_copy(
    network_run, tmp_path, monkeypatch, capsys
):
    run, good = network_run
    first = ea.load(run)
    _unpin_node_3_and_add_a_node(good)
    assert main(["run", "--from", str(run), "--quiet", "--out", str(tmp_path / "again")]) == 0
    err = capsys.readouterr().err.splitlines()
    changed = [line for line in err if "changed since the run" in line]
    assert changed == [
        f"elastoactive: warning: network file {good.resolve()} changed since the run (sha256 "
        f"{_summary(run)['inputs']['network_file']['sha256'][:12]} then, {records.sha256(good)[:12]} now); using the "
        "run's copy network.json"
    ]
    again = ea.load(tmp_path / "again")
    np.testing.assert_array_equal(again.nodes, first.nodes)  # the recorded network, not the edited one
    assert _summary(tmp_path / "again")["results"]["amplitude"] == _summary(run)["results"]["amplitude"]
    with pytest.warns(records.RecordWarning, match="using the run's copy network.json"):
        loaded = ea.load(run)
    assert ea.measure(loaded).amplitude == pytest.approx(_summary(run)["results"]["amplitude"], rel=1e-12)
    drawn = {}
    monkeypatch.setattr(render_cli, "_render", lambda traj, *args, **kwargs: drawn.setdefault("traj", traj) and 0)
    assert main(["render", str(run), "--still", str(tmp_path / "still.png")]) == 0
    assert drawn["traj"].physics.scene_def.network(drawn["traj"].physics).positions.shape == (5, 2)
    assert "using the run's copy network.json" in capsys.readouterr().err


def test_a_run_whose_network_file_is_gone_still_loads(network_run):
    run, good = network_run
    good.unlink()
    with pytest.warns(records.RecordWarning, match="is gone; using the run's copy"):
        loaded = ea.load(run)
    assert loaded.physics.geometry == str((run / "network.json").resolve())


def test_a_run_whose_network_file_and_copy_changed_is_refused(network_run, capsys):
    run, good = network_run
    _unpin_node_3_and_add_a_node(good)
    (run / "network.json").write_text(good.read_text())
    refused(capsys, ["run", "--from", str(run), "--quiet"], "run --from", "network file", "copy network.json")


def test_a_start_state_is_recorded_and_repeated_by_run_from(tmp_path, monkeypatch, capsys):
    chain = ["--n", "4", "--sigma", "0.8", "--duration", "4", "--engine", "reduced", "--quiet"]
    monkeypatch.chdir(tmp_path)
    assert main(["run", "one-pinned", *chain, "--out", "first"]) == 0
    assert main(["run", "one-pinned", *chain, "--start-from", "first", "--out", "second"]) == 0
    capsys.readouterr()
    start = _summary(tmp_path / "second")["inputs"]["start"]
    assert start["path"] == str((tmp_path / "first").resolve()) and start["copy"] == records.START_COPY
    last = ea.load(tmp_path / "first").theta[-1]
    assert start["state_sha256"] == records.state_digest({"theta": last})
    (tmp_path / "first" / "trajectory.npz").unlink()  # the run's copy of the state is enough
    other = tmp_path.parent / f"{tmp_path.name}-other"
    other.mkdir()
    monkeypatch.chdir(other)
    assert main(["run", "--from", str(tmp_path / "second"), "--quiet", "--out", "third"]) == 0
    np.testing.assert_array_equal(ea.load(other / "third").theta, ea.load(tmp_path / "second").theta)
    (tmp_path / "second" / "start.npz").unlink()  # and without it nor the start run: refused
    refused(capsys, ["run", "--from", str(tmp_path / "second"), "--quiet"], "the state it started from", "start.npz")


def _failing_measure(*args, **kwargs):
    raise IndexError("index 0 is out of bounds for axis 0 with size 0")


def test_a_failure_in_measuring_keeps_the_trajectory_and_records_the_error(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(records, "measure", _failing_measure)
    argv = ["run", "one-pinned", "--n", "4", "--duration", "4", "--engine", "reduced", "--quiet"]
    line = refused(capsys, [*argv, "--out", str(tmp_path / "run")], "measuring the run failed", "IndexError", code=1)
    assert "trajectory is kept" in line
    summary = _summary(tmp_path / "run")
    assert summary["results"] is None
    assert summary["measure_error"] == "IndexError: index 0 is out of bounds for axis 0 with size 0"
    monkeypatch.undo()
    loaded = ea.load(tmp_path / "run")  # the trajectory reads back, checked against its summary
    assert loaded.t.size > 2 and np.all(np.isfinite(loaded.theta))
    assert main(["run", "--from", str(tmp_path / "run"), "--quiet", "--out", str(tmp_path / "again")]) == 0
    np.testing.assert_array_equal(ea.load(tmp_path / "again").theta, loaded.theta)


def test_a_run_killed_while_measuring_leaves_a_trajectory_and_a_summary_saying_so(tmp_path, monkeypatch, capsys):
    """The trajectory is on disk before measuring starts: a process that dies there leaves a readable run."""
    seen = {}

    def dies(traj, *args, **kwargs):
        seen["summary"] = _summary(tmp_path / "run")
        seen["files"] = sorted(os.listdir(tmp_path / "run"))
        raise KeyboardInterrupt

    monkeypatch.setattr(records, "measure", dies)
    argv = ["run", "one-pinned", "--n", "4", "--duration", "4", "--engine", "reduced", "--quiet"]
    assert main([*argv, "--out", str(tmp_path / "run")]) == 130
    assert seen["files"] == ["summary.json", "trajectory.npz"]
    assert seen["summary"]["results"] is None and seen["summary"]["measure_error"] == records.MEASURING
    monkeypatch.undo()
    assert ea.load(tmp_path / "run").t.size > 2

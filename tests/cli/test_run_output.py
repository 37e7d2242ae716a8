"""`elastoactive run` prints its results for a person by default (a table with units, the notes as warnings), one
line with --quiet (nothing else on stdout), the full JSON with --json (stdout holds the JSON alone)."""

import json

import pytest

from elastoactive.cli import main

RUN = ["run", "one-pinned", *"--n 3 --sigma 2 --duration 8 --engine reduced".split()]


@pytest.fixture
def run(tmp_path, capsys):
    def printed(*options: str):
        assert main([*RUN, "--out", str(tmp_path / "run"), "--force", *options]) == 0
        return capsys.readouterr()

    return printed


def test_the_default_is_a_table_with_units(run, tmp_path):
    out = run().out.splitlines()
    assert out[0].startswith("one-pinned, reduced: 8 tau in ")
    assert out[1].split()[0] == "amplitude" and out[1].split()[-1] == "rad"
    assert out[2].split()[0] == "frequency" and out[2].split()[-1] == "1/tau"
    assert not any("harmonics" in line or "{" in line for line in out)
    assert out[-1] == f"wrote {tmp_path / 'run' / 'summary.json'} and {tmp_path / 'run' / 'trajectory.npz'}"


def test_quiet_prints_one_line(run):
    captured = run("--quiet")
    assert len(captured.out.splitlines()) == 1 and captured.out.startswith("amplitude ")
    assert all(line.startswith("elastoactive: warning:") for line in captured.err.splitlines())


def test_json_prints_the_record_alone(run, tmp_path):
    captured = run("--quiet", "--json")
    printed = json.loads(captured.out)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert {k: v for k, v in printed.items() if k != "wall_time_s"} == json.loads(json.dumps(summary["results"]))
    assert "harmonics" in printed and "notes" in printed
    assert "wrote" in run("--json").err  # the folder is said on stderr: stdout stays JSON

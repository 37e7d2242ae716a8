"""A run records the plug-ins it used: a plug-in file by its SHA-256 and a copy in the run's folder (loaded by
`run --from` when the file has changed since), an entry-point plug-in by its distribution, version and entry point
(a re-run where that distribution is missing is refused naming it)."""

import json
import sys

import numpy as np
import pytest
from conftest import refused
from test_plugin_loading import tether_source

import elastoactive as ea
from elastoactive import plugins
from elastoactive.cli import main
from elastoactive.core import table
from elastoactive.io.outputs import sha256
from elastoactive.records import RecordWarning

CHAIN = ["--n", "4", "--sigma", "0.3", "--duration", "4", "--engine", "reduced", "--quiet"]


def _summary(folder):
    return json.loads((folder / "summary.json").read_text())


def _unload(name: str) -> None:
    """Unregister the term `name` and forget every plug-in file that registered it."""
    specs = {spec for (kind, entry), spec in plugins._SOURCES.items() if kind == "terms" and entry == name}
    if name in ea.terms.names():
        ea.terms.unregister(name)
    for key in [k for k, spec in plugins._SOURCES.items() if spec in specs]:
        del plugins._SOURCES[key]
    for key, (module, spec) in list(plugins._LOADED.items()):
        if spec in specs:
            del plugins._LOADED[key]
            sys.modules.pop(module, None)
    for spec in specs:
        plugins._FILES.pop(spec, None)


@pytest.fixture
def plugin_file(tmp_path, monkeypatch):
    path = tmp_path / "rtether.py"
    path.write_text(tether_source("record-tether", "rt"))
    monkeypatch.chdir(tmp_path)
    yield path
    _unload("record-tether")


def test_a_plugin_file_is_recorded_with_its_checksum_and_copied(plugin_file, capsys):
    assert main(["run", "one-pinned", "--plugin", "rtether.py", *CHAIN, "--rt-k", "0.5", "--out", "first"]) == 0
    summary = _summary(plugin_file.parent / "first")
    assert summary["inputs"]["plugin_files"] == [
        {"path": str(plugin_file.resolve()), "sha256": sha256(plugin_file), "copy": "plugin-rtether.py"}
    ]
    assert (plugin_file.parent / "first" / "plugin-rtether.py").read_bytes() == plugin_file.read_bytes()


def test_run_from_loads_the_runs_copy_of_a_plugin_file_that_changed(plugin_file, capsys):
    assert main(["run", "one-pinned", "--plugin", "rtether.py", *CHAIN, "--rt-k", "0.5", "--out", "first"]) == 0
    _unload("record-tether")
    source = plugin_file.read_text()
    plugin_file.write_text(source.replace("= -physics.rt_k *", "= -2 * physics.rt_k *"))  # another force
    capsys.readouterr()
    assert main(["run", "--from", "first", "--out", "again"]) == 0
    err = capsys.readouterr().err
    assert f"plug-in file {plugin_file.resolve()} changed since the run" in err
    assert "using the run's copy plugin-rtether.py" in err
    with pytest.warns(RecordWarning, match="using the run's copy plugin-rtether.py"):
        first = ea.load(plugin_file.parent / "first")
    np.testing.assert_array_equal(ea.load(plugin_file.parent / "again").theta, first.theta)


def _distribution(folder, name: str, version: str, entry: str) -> None:
    info = folder / f"{name.replace('-', '_')}-{version}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: {version}\n")
    (info / "entry_points.txt").write_text(f"[elastoactive.terms]\n{entry}\n")


def test_an_entry_point_term_is_recorded_and_a_rerun_without_its_package_refused(tmp_path, monkeypatch, capsys):
    installed = tmp_path / "site"
    installed.mkdir()
    (installed / "toy_tep.py").write_text(tether_source("tep", "tep"))
    _distribution(installed, "tep-plugin", "1.0", "tep = toy_tep")
    monkeypatch.setitem(table._entry_points, "loaded", set())  # the entry points load again, as in a fresh process
    monkeypatch.syspath_prepend(str(installed))
    try:
        assert main(["run", "one-pinned", *CHAIN, "--tep-k", "0.5", "--out", str(tmp_path / "run")]) == 0
        assert _summary(tmp_path / "run")["inputs"]["entry_points"] == [
            {
                "kind": "terms",
                "name": "tep",
                "group": "elastoactive.terms",
                "entry_point": "tep = toy_tep",
                "distribution": "tep-plugin",
                "version": "1.0",
            }
        ]
    finally:
        ea.terms.unregister("tep")
        sys.modules.pop("toy_tep", None)
    monkeypatch.setattr(sys, "path", [p for p in sys.path if p != str(installed)])  # the package is not installed
    monkeypatch.setitem(table._entry_points, "loaded", set())
    expected = (
        "the term 'tep' came from the package 'tep-plugin 1.0' (entry point tep = toy_tep in elastoactive.terms), "
        "which is not installed here; pip install tep-plugin==1.0"
    )
    line = refused(capsys, ["run", "--from", str(tmp_path / "run"), "--quiet"], expected)
    assert line == f"elastoactive: error: run --from {tmp_path / 'run'}: {expected}"
    with pytest.raises(ea.ParameterError, match="not installed here; pip install tep-plugin==1.0"):
        ea.load(tmp_path / "run")

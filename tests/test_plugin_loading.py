"""Plug-ins from outside the package: a term written in a file of the working folder runs from the command line
(``--plugin``) in both engines, a run records the plug-ins it needs so that ``run --from`` loads them, and terms,
scenes and studies declared as entry points of an installed distribution join the registries when first listed.
"""

import json
import os
import subprocess
import sys
import textwrap

import pytest

import elastoactive as ea
from elastoactive import plugins
from elastoactive.cli import main
from elastoactive.cli.options import preload_plugins
from elastoactive.core import table

TETHER = '''
"""A position-dependent force: the tip pulled toward an anchor by a spring of rest length 0, F = -k (r_tip - a)."""

import numpy as np

import elastoactive as ea
from elastoactive.core.parameters import Parameter
from elastoactive.terms import Term


class Tether(Term):
    name = "NAME"
    summary = "the tip on a spring to an anchor"
    parameters = (
        Parameter("PREFIX_k", 0.0, "the tether's stiffness (C1 / l^2)", low=0.0, quiet_default=True),
        Parameter("PREFIX_x", 3.0, "the anchor's x (l)", quiet_default=True),
        Parameter("PREFIX_y", 2.0, "the anchor's y (l)", quiet_default=True),
    )
    observables = ("PREFIX_tip_y",)

    def build(self, spec, physics, numerics):  # MuJoCo: a spatial tendon of rest length 0, anchor to tip site
        anchor = [physics.PREFIX_x, physics.PREFIX_y, 0.0]
        spec.worldbody.add_site(name="PREFIX_anchor", pos=anchor)
        tendon = spec.add_tendon(name="PREFIX", stiffness=[physics.PREFIX_k, 0, 0], springlength=[0.0, 0.0])
        tendon.wrap_site("PREFIX_anchor")
        tendon.wrap_site(f"particle_{physics.n - 1}")

    def node_forces(self, physics):  # the reduced model: the same force, from the particles' positions
        anchor = np.array([physics.PREFIX_x, physics.PREFIX_y])

        def forces(positions):
            out = np.zeros_like(positions)
            out[physics.n - 1] = -physics.PREFIX_k * (positions[physics.n - 1] - anchor)
            return out

        return forces

    def measure(self, traj, transient):
        keep = traj.t >= transient
        return {"PREFIX_tip_y": float(np.sin(traj.theta[keep, : traj.physics.n]).sum(axis=1).mean())}


ea.terms.register(Tether())
'''


def tether_source(name: str, prefix: str) -> str:
    return TETHER.replace("NAME", name).replace("PREFIX", prefix)


def _forget(spec: str) -> None:
    """Unregister what the plug-in `spec` registered and let it load again."""
    for (kind, name), source in list(plugins._SOURCES.items()):
        if source == spec:
            {"terms": ea.terms.unregister, "scenes": ea.scenes.unregister}[kind](name)
            del plugins._SOURCES[(kind, name)]
    for key, (module, recorded) in list(plugins._LOADED.items()):
        if recorded == spec:
            del plugins._LOADED[key]
            sys.modules.pop(module, None)


@pytest.fixture
def tether_file(tmp_path, monkeypatch):
    """tether.py in a temporary working folder (outside the package), unregistered afterwards."""
    (tmp_path / "tether.py").write_text(tether_source("test-tether", "tether"))
    monkeypatch.chdir(tmp_path)
    yield tmp_path / "tether.py"
    _forget(str((tmp_path / "tether.py").resolve()))


def test_a_term_in_a_file_runs_from_the_cli_in_both_engines(tether_file, capsys):
    """A position-dependent force written outside the package: MuJoCo (a tendon) and the reduced model (node
    forces) bend the chain alike within 1%; the summary records the plug-in, so `run --from` needs no --plugin."""
    tips = {}
    for engine in ("mujoco", "reduced"):
        out = tether_file.parent / engine
        argv = ["run", "one-pinned", "--plugin", "tether.py", "--n", "4", "--sigma", "0.3", "--tether-k", "0.5"]
        assert main([*argv, "--duration", "10", "--engine", engine, "--quiet", "--out", str(out)]) == 0
        summary = json.loads((out / "summary.json").read_text())
        assert summary["plugins"] == [str(tether_file.resolve())]
        assert summary["parameters"]["tether_k"] == 0.5
        tips[engine] = summary["results"]["tether_tip_y"]
    assert tips["reduced"] > 1.0  # the tether pulls the tip up (the chain lies along x without it)
    assert tips["mujoco"] == pytest.approx(tips["reduced"], rel=0.01)
    capsys.readouterr()
    # a fresh process, no --plugin: the record names the file, which --from loads before reading the options
    rerun = subprocess.run(
        [sys.executable, "-m", "elastoactive", "run", "--from", str(tether_file.parent / "reduced"), "--json"],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tether_file.parent.parent,
    )
    assert rerun.returncode == 0, rerun.stderr
    assert json.loads(rerun.stdout)["tether_tip_y"] == pytest.approx(tips["reduced"], rel=1e-6)
    # render (any run named on the command line) loads the plug-ins its record names
    spec = str(tether_file.resolve())
    _forget(spec)
    assert "test-tether" not in ea.terms.names()
    preload_plugins(["render", str(tether_file.parent / "mujoco"), "--still", "tip.png"])
    assert "test-tether" in ea.terms.names() and plugins.source("terms", "test-tether") == spec
    # and so does ea.load of it, in Python
    _forget(spec)
    traj = ea.load(tether_file.parent / "reduced")
    assert traj.physics.tether_k == 0.5 and plugins.source("terms", "test-tether") == spec


def test_a_term_in_a_file_is_swept(tether_file, capsys):
    out = tether_file.parent / "sweep.nc"
    argv = ["sweep", "one-pinned", "--plugin", "tether.py", "--n", "4", "--grid", "tether_k=0.5", "--duration", "10"]
    assert main([*argv, "--engine", "reduced", "--workers", "1", "--quiet", "--out", str(out)]) == 0
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert ds["tether_k"].attrs["long_name"].startswith("the tether's stiffness")
        assert float(ds["amplitude"].values.ravel()[0]) >= 0


def test_plugin_before_the_command_and_its_options_in_help(tether_file, capsys):
    with pytest.raises(SystemExit):
        main(["--plugin=tether.py", "run", "--help"])
    assert "--tether-k" in capsys.readouterr().out


def test_a_plugin_that_is_not_there_is_one_error_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["run", "one-pinned", "--plugin", "absent.py"]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        "elastoactive: error: --plugin: absent.py is not a file (give a module name or a .py file)"
    ]
    assert main(["run", "one-pinned", "--plugin", "no_such_plugin_module"]) == 2
    assert "no module named 'no_such_plugin_module'" in capsys.readouterr().err


def test_a_plugin_that_fails_is_one_error_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "broken.py").write_text("raise RuntimeError('no licence server')\n")
    assert main(["run", "one-pinned", "--plugin", "broken.py"]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        "elastoactive: error: --plugin broken.py: it did not load (RuntimeError: no licence server)"
    ]


def test_a_plugin_that_registers_nothing_is_one_error_line(tmp_path, monkeypatch, capsys):
    """A module that loads but adds no scene, term or study (a typo'd module name, `--plugin os`) is no plug-in: the
    run would go on without what the user meant to add."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "empty_plugin.py").write_text("SCALE = 2.0\n")
    for spec in ("empty_plugin.py", "os"):
        assert main(["run", "one-pinned", "--plugin", spec, "--duration", "1"]) == 2
        lines = capsys.readouterr().err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith(f"elastoactive: error: --plugin {spec}: it loaded and")


def test_a_module_in_the_working_folder_is_found_and_recorded_by_its_file(tether_file, monkeypatch):
    """`--plugin tether` (a module name) finds tether.py in the working folder, which the console script does not put
    on sys.path; the record names the file, so a re-run from elsewhere finds it; importing it again does nothing."""
    monkeypatch.setattr(sys, "path", [p for p in sys.path if p not in ("", ".", str(tether_file.parent))])
    spec = str(tether_file.resolve())
    assert plugins.load("tether") == spec
    assert plugins.needed(ea.Physics(n=5, tether_k=0.1)) == [spec]
    assert plugins.load("tether.py") == spec  # the same file: not imported twice (no 'already registered')
    sys.modules.pop("tether", None)


def test_a_plugin_whose_dependency_is_missing_is_one_error_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "needy.py").write_text("import no_such_dependency_here\n")
    assert main(["run", "one-pinned", "--plugin", "needy.py"]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        "elastoactive: error: --plugin needy.py: it did not load (ModuleNotFoundError: "
        "No module named 'no_such_dependency_here')"
    ]


def test_an_entry_point_that_is_not_a_term_is_refused(tmp_path, monkeypatch, fresh_group):
    (tmp_path / "toy_ep_wrong.py").write_text("class NotATerm:\n    name = 'not-a-term'\n")
    _distribution(tmp_path, "elastoactive.terms", "wrong = toy_ep_wrong:NotATerm")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.warns(RuntimeWarning, match="NotATerm is not a term"):
        assert "not-a-term" not in ea.terms.names()
    sys.modules.pop("toy_ep_wrong", None)


def test_a_run_needs_no_plugin_it_does_not_use(tether_file):
    plugins.load("tether.py")
    assert plugins.needed(ea.Physics(n=5)) == []
    assert plugins.needed(ea.Physics(n=5, tether_k=0.1)) == [str(tether_file.resolve())]


def _distribution(folder, group: str, entry: str) -> None:
    """An installed distribution in `folder` (a .dist-info folder) declaring one entry point of `group`."""
    info = folder / "toy_elastoactive_plugin-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: toy-elastoactive-plugin\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(f"[{group}]\n{entry}\n")


@pytest.fixture
def fresh_group(monkeypatch):
    """The entry points of every registry load again at their next listing (as in a fresh process)."""
    monkeypatch.setitem(table._entry_points, "loaded", set())


def test_an_entry_point_term_is_found(tmp_path, monkeypatch, fresh_group):
    (tmp_path / "toy_ep_tether.py").write_text(tether_source("entry-tether", "ep_tether"))
    _distribution(tmp_path, "elastoactive.terms", "entry-tether = toy_ep_tether")
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        assert "entry-tether" in ea.terms.names()
        assert ea.Physics(n=5, ep_tether_k=0.1).ep_tether_k == 0.1
    finally:
        ea.terms.unregister("entry-tether")
        sys.modules.pop("toy_ep_tether", None)


def test_an_entry_point_object_is_registered(tmp_path, monkeypatch, fresh_group):
    """An entry point naming a Scene (not a module that registers it): registered when the scenes are listed."""
    (tmp_path / "toy_ep_scene.py").write_text(
        textwrap.dedent(
            """
            from elastoactive.scenes.one_pinned import OnePinned

            class Copy(OnePinned):
                name = "entry-copy"
            """
        )
    )
    _distribution(tmp_path, "elastoactive.scenes", "entry-copy = toy_ep_scene:Copy")
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        assert ea.scenes.get("entry-copy").name == "entry-copy"
        assert "entry-copy" in ea.scenes.names()
    finally:
        ea.scenes.unregister("entry-copy")
        sys.modules.pop("toy_ep_scene", None)


def test_a_broken_entry_point_warns_and_the_others_load(tmp_path, monkeypatch, fresh_group):
    _distribution(tmp_path, "elastoactive.studies", "broken = no_such_module_here")
    monkeypatch.syspath_prepend(str(tmp_path))
    from elastoactive.studies import registry as studies

    with pytest.warns(RuntimeWarning, match="'broken'"):
        names = studies.names()
    assert "hopf" in names


def test_an_installed_scene_is_in_the_top_level_help(tmp_path):
    """In a fresh process whose path holds a distribution declaring a scene, `elastoactive --help` lists it (the help
    reads the registry, not the source, once a distribution may add a scene: table.declares_entry_points)."""
    (tmp_path / "toy_ep_help.py").write_text(
        textwrap.dedent(
            """
            from elastoactive.scenes.one_pinned import OnePinned

            class Listed(OnePinned):
                name = "entry-listed"
                summary = "an installed distribution's scene"
            """
        )
    )
    _distribution(tmp_path, "elastoactive.scenes", "entry-listed = toy_ep_help:Listed")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    out = subprocess.run(
        [sys.executable, "-m", "elastoactive", "--help"], env=env, capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 0, out.stderr
    assert "entry-listed" in out.stdout and "an installed distribution's scene" in out.stdout
    assert "one-pinned" in out.stdout


@pytest.mark.parametrize("group", ["elastoactive.scenes", "elastoactive.terms", "elastoactive.studies"])
def test_a_distribution_s_entry_points_are_seen_without_reading_metadata(tmp_path, monkeypatch, group):
    """declares_entry_points answers for the group a distribution on sys.path declares, and only for it."""
    kinds = {v: k for k, v in table.ENTRY_POINT_GROUPS.items()}
    monkeypatch.setattr(sys, "path", [str(tmp_path)])  # only this folder's distributions (none yet)
    assert not any(table.declares_entry_points(kind) for kind in kinds.values())
    _distribution(tmp_path, group, "toy = toy_module")
    assert [table.declares_entry_points(kind) for kind in kinds.values()] == [g == group for g in kinds]


def test_an_unknown_distribution_finder_is_not_ruled_out(monkeypatch):
    """A finder of distributions other than Python's own: the answer is 'maybe' (the registry then reads them)."""

    class Finder:
        def find_spec(self, *args):
            return None

        def find_distributions(self, *args, **kwargs):
            return iter(())

    monkeypatch.setattr(sys, "meta_path", [Finder(), *sys.meta_path])
    assert table.declares_entry_points("scenes")


def test_the_distributions_are_read_once_for_every_group(tmp_path, monkeypatch):
    """One importlib.metadata listing serves every registry's group (none at all while no distribution declares one);
    a distribution installed on sys.path afterwards is read again."""
    import importlib.metadata

    listings = []
    listed = importlib.metadata.entry_points

    def counted(**kwargs):
        listings.append(kwargs)
        return listed(**kwargs)

    monkeypatch.setattr(importlib.metadata, "entry_points", counted)
    monkeypatch.setattr(sys, "path", [str(tmp_path)])
    monkeypatch.setattr(table, "_installed", [])
    assert [table.installed_entry_points(kind) for kind in table.ENTRY_POINT_GROUPS] == [(), (), ()]
    assert listings == []  # nothing declared: no metadata read
    _distribution(tmp_path, "elastoactive.terms", "toy = toy_module")
    points = {kind: table.installed_entry_points(kind) for kind in (*table.ENTRY_POINT_GROUPS, "terms")}
    assert [p.name for p in points["terms"]] == ["toy"] and points["scenes"] == points["studies"] == ()
    assert listings == [{}]  # one listing for every group, read when a group was first declared

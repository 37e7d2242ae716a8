"""The Python front door (`import elastoactive as ea`) and every registered scene in both engines."""

import subprocess
import sys

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.checks.validate import angle_errors, observable_errors


def test_the_tutorial_points_to_every_scene():
    """The notebook's "Where next" names every registered scene (a new one is not left out of the tour)."""
    import json
    from pathlib import Path

    notebook = Path(__file__).resolve().parents[1] / "examples" / "tutorial.ipynb"
    cells = ["".join(c["source"]) for c in json.loads(notebook.read_text())["cells"] if c["cell_type"] == "markdown"]
    where_next = [c for c in cells if c.startswith("## Where next")]
    assert len(where_next) == 1
    missing = [name for name in ea.scenes.names() if name not in where_next[0]]
    assert not missing, missing


def test_front_door_names():
    for name in (
        "Physics",
        "Numerics",
        "simulate",
        "measure",
        "scenes",
        "ParameterError",
        "SimulationDiverged",
        "Trajectory",
        "Results",
        "load",
        "load_sweep",
        "plot",
        "terms",
    ):
        assert hasattr(ea, name), name
        assert name in ea.__all__, name
    for fn in (ea.simulate, ea.measure, ea.load, ea.load_sweep):
        assert "Parameters" in fn.__doc__ and "Returns" in fn.__doc__


def test_paper_beat_through_the_front_door():
    traj = ea.simulate(ea.Physics(scene="one-pinned", n=7, sigma=0.8), duration=600)
    res = ea.measure(traj)
    assert isinstance(res, ea.Results) and traj.engine == "mujoco"
    # the reduced model's beat at the paper's parameters (validate: MuJoCo within 0.1%)
    reference = ea.measure(ea.simulate(ea.Physics(n=7, sigma=0.8), duration=600, engine="reduced"))
    assert res.amplitude == pytest.approx(reference.amplitude, rel=2e-3)
    assert res.frequency == pytest.approx(reference.frequency, rel=2e-3)
    assert 2.5 < res.amplitude < 3.5 and 0.03 < res.frequency < 0.05


def test_front_door_runs_the_preflight_check():
    # dt = 0.05 at sigma = 5 is stable but 11% off: refused unless the caller opts out
    physics, numerics = ea.Physics(sigma=5), ea.Numerics(dt=0.05, sample_dt=0.05)
    with pytest.raises(ea.ParameterError, match="dt"):
        ea.simulate(physics, numerics, duration=5)
    assert ea.simulate(physics, numerics, duration=5, check=False).theta.shape[0] == 101


def test_bad_engine_is_named():
    with pytest.raises(ea.ParameterError, match="engine"):
        ea.simulate(ea.Physics(), duration=1, engine="bogus")


@pytest.mark.parametrize("scene", ea.scenes.names())
def test_every_scene_in_both_engines(scene):
    """The first validation case of each registered scene, 150 tau, in both engines: the same motion."""
    case = ea.scenes.get(scene).validation_cases()[0]
    mj = ea.simulate(case.physics, duration=150.0)
    red = ea.simulate(case.physics, duration=150.0, engine="reduced")
    np.testing.assert_array_equal(mj.t, red.t)
    assert angle_errors(mj, red)["angle"] < 0.01
    errors = observable_errors(case.physics, ea.measure(mj), ea.measure(red))
    assert set(errors) >= set(ea.scenes.get(scene).compared)
    assert max(errors[k] for k in ea.scenes.get(scene).compared) < 0.01, errors


def test_python_dash_m():
    out = subprocess.run([sys.executable, "-m", "elastoactive", "--help"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0 and "reproduce" in out.stdout
    for name in ea.scenes.names():
        assert name in out.stdout


def test_import_leaves_the_running_machinery_to_first_use():
    """`import elastoactive` loads neither numpy nor a scene, a term or an engine: the records load when a front-door
    name is first used, the package's scenes and terms when a registry is first read, the engines and the outputs'
    writers when a running name is; then `ea.simulate` and a sub-module by attribute work, and an unknown name is an
    AttributeError."""
    probe = (
        "import sys, elastoactive as ea\n"
        "late = ('numpy', 'elastoactive.core.params', 'elastoactive.scenes', 'elastoactive.terms', "
        "'elastoactive.api', 'elastoactive.results', 'elastoactive.engines', 'elastoactive.gate')\n"
        "print([m for m in late if m in sys.modules])\n"
        "physics = ea.Physics(scene='ring')\n"
        "print([m for m in late if m in sys.modules])\n"
        "print(len(ea.scenes.names()) > 5, callable(ea.simulate), callable(ea.records.read_summary))\n"
        "print('simulate' in dir(ea), hasattr(ea, 'no_such_name'))\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, check=True)
    lines = out.stdout.split("\n")
    assert lines[0] == "[]", out.stdout + out.stderr
    assert lines[1] == "['numpy', 'elastoactive.core.params', 'elastoactive.scenes', 'elastoactive.terms']", lines[1]
    assert lines[2:4] == ["True True True", "True False"], out.stdout + out.stderr

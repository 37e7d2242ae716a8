"""A physical term is a plug-in: a uniform force field defined in this file alone runs in both engines through run,
validate and sweep.

The field puts the same force (field_x, field_y) on every particle. Its MJCF element is MuJoCo's gravity, set to the
force over the particles' mass (every body of the chain carries one particle's mass); its reduced-model
contribution is the force on each particle (Term.node_forces). No module of the package is edited to add it: its
parameters join Physics, the CLI's options and the sweep's grid through the parameter table.
"""

import json

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.parameters import Parameter
from elastoactive.scenes.base import ValidationCase
from elastoactive.sweep import run_sweep
from elastoactive.terms import Term


class UniformField(Term):
    name = "toy-uniform-field"
    summary = "the same force on every particle (a test's toy term)"
    parameters = (Parameter("field_x", 0.0, "uniform force on every particle, x component (C1 / l)", quiet_default=True),
                  Parameter("field_y", 0.0, "uniform force on every particle, y component (C1 / l)", quiet_default=True))
    observables = ("tip_y",)

    def build(self, spec, physics, numerics):
        import mujoco

        spec.option.gravity = [physics.field_x / numerics.mass_ratio, physics.field_y / numerics.mass_ratio, 0.0]
        spec.option.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_GRAVITY)

    def node_forces(self, physics):
        force = np.array([physics.field_x, physics.field_y])
        return lambda positions: np.broadcast_to(force, positions.shape)

    def measure(self, traj, transient):
        keep = traj.t >= transient
        return {"tip_y": float(np.sin(traj.theta[keep, : traj.physics.n]).sum(axis=1).mean())}

    def validation_cases(self, physics):
        return (ValidationCase(physics(n=5, sigma=0.8, field_x=-0.02, field_y=0.02), 200.0, convergence=False),)


@pytest.fixture
def field():
    term = ea.terms.register(UniformField())
    yield term
    ea.terms.unregister(term.name)


def test_parameters_join_physics_only_while_registered(field):
    p = ea.Physics(n=5, field_y=0.05)
    assert p.field_y == 0.05 and p.relevant()["field_y"] == 0.05 and "field_x" not in p.relevant()
    assert "field_y" not in ea.Physics(n=5).relevant()  # at rest it changes nothing a summary records
    with pytest.raises(ea.ParameterError, match="field_y must be finite"):
        ea.Physics(field_y=float("nan"))


def test_refused_once_unregistered():
    with pytest.raises(ea.ParameterError, match="unknown parameter 'field_y'"):
        ea.Physics(field_y=0.1)


def test_field_bends_the_chain_alike_in_both_engines(field):
    physics = ea.Physics(n=5, sigma=0.3, field_y=0.05)  # below the onset: the chain settles, bent by the field
    runs = {e: ea.simulate(physics, duration=40.0, engine=e) for e in ("mujoco", "reduced")}
    tips = {e: ea.measure(tr).extra["tip_y"] for e, tr in runs.items()}
    assert tips["reduced"] > 0.3  # the field pushes the chain up (it hangs straight along x without it)
    assert tips["mujoco"] == pytest.approx(tips["reduced"], rel=0.01)
    np.testing.assert_allclose(runs["mujoco"].theta, runs["reduced"].theta, atol=0.01 * np.abs(runs["reduced"].theta).max())


def test_field_through_run(field, tmp_path):
    out = tmp_path / "run"
    assert main(["run", "one-pinned", "--n", "5", "--sigma", "0.3", "--field-y", "0.05", "--duration", "20",
                 "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["field_y"] == 0.05
    assert summary["results"]["tip_y"] > 0.3


def test_field_through_validate(field, capsys):
    assert main(["validate", "one-pinned", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "one-pinned N=5 sigma=0.8 field_x=-0.02 field_y=0.02" in out and "PASS" in out


def test_field_through_sweep(field, tmp_path):
    ds = run_sweep("one-pinned", {"field_y": [0.02, 0.05]}, fixed={"n": 5, "sigma": 0.3}, numerics="fast",
                   duration=20.0, out=tmp_path / "field.nc", workers=1, progress=False)
    assert (ds["status"].values == "ok").all()
    tip = ds["tip_y"].values
    assert tip[1] > tip[0] > 0
    assert ds["field_y"].attrs["long_name"].startswith("uniform force on every particle")

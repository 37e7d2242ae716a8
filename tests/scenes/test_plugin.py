"""A scene is a plug-in: a toy scene defined in this file alone runs through run, validate and sweep.

The toy is a new physical system built only from the Scene contract: two chains on freely rotating
pins (no clamp spring), coupled by a spring between their first pendula. No module of the package
is edited to add it; the CLI, validate and sweep find it through the registry.
"""

import json

import numpy as np
import pytest
import xarray as xr

import elastoactive as ea
from elastoactive.checks.validate import observable_errors
from elastoactive.cli import main
from elastoactive.core import observables
from elastoactive.core.observables import Observable
from elastoactive.records import load_trajectory
from elastoactive.results import Results
from elastoactive.scenes import ChainScene
from elastoactive.scenes.base import ValidationCase
from elastoactive.sweep import run_sweep


class FreePair(ChainScene):
    name = "toy-free-pair"
    summary = "two chains on free pins, coupled at their first pendula (a test's toy scene)"
    base_file = "coupled-pair.xml"  # its clamps, markers and defaults fit
    parameters = ("kappa",)
    n_chains = 2
    clamped = False
    observables = ("rotation_rate",)
    compared = ("rotation_rate",)

    def build(self, spec, physics, numerics):
        first, second = (f"{prefix}hinge_0" for prefix in self.chain_prefixes())
        spec.geom("clamp2").pos = [-0.15, self.chain_offset(physics, 1), 0.0]
        tendon = spec.add_tendon(name="coupling", stiffness=[physics.kappa, 0, 0], springlength=[0.0, 0.0])
        tendon.wrap_joint(first, 1.0)
        tendon.wrap_joint(second, -1.0)

    def reduced_system(self, physics):
        return super().reduced_system(physics)._replace(kappa=physics.kappa)

    def measure_extra(self, traj, transient):
        t = traj.t
        keep = t >= transient
        omega = np.gradient(traj.theta[:, 0], t)  # chain 1's first pendulum
        return {"rotation_rate": float(omega[keep].mean())}

    def validation_cases(self):
        return (ValidationCase(self.physics(n=3, sigma=1.5, kappa=1.0), 40.0),)


@pytest.fixture
def toy():
    scene = ea.scenes.register(FreePair())
    yield scene
    ea.scenes.unregister(scene.name)


def test_registry_lists_the_toy_only_while_registered(toy):
    assert toy.name in ea.scenes.names() and ea.scenes.get(toy.name) is toy
    p = ea.Physics(scene=toy.name, n=3, kappa=0.5)
    assert (
        p.n_chains == 2
        and not p.clamped
        and p.relevant() == {"scene": toy.name, "n": 3, "sigma": 0.8, "drag_ratio": 1.0, "noise": 0.0, "kappa": 0.5}
    )


def test_toy_is_refused_once_unregistered():
    with pytest.raises(ea.ParameterError, match="scene must be one of"):
        ea.Physics(scene=FreePair.name)


def test_toy_runs_in_both_engines_and_they_agree(toy):
    physics = toy.validation_cases()[0].physics
    runs = {e: ea.simulate(physics, duration=40.0, engine=e) for e in ("mujoco", "reduced")}
    rates = {e: ea.measure(tr).rotation_rate for e, tr in runs.items()}
    assert abs(rates["reduced"]) > 0.01  # it does rotate
    assert rates["mujoco"] == pytest.approx(rates["reduced"], rel=0.01)
    np.testing.assert_allclose(
        runs["mujoco"].theta, runs["reduced"].theta, atol=0.02 * np.abs(runs["reduced"].theta).max()
    )


def test_toy_through_run(toy, tmp_path):
    out = tmp_path / "run"
    assert (
        main(
            [
                "run",
                toy.name,
                "--n",
                "3",
                "--sigma",
                "1.5",
                "--kappa",
                "1",
                "--duration",
                "20",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["scene"] == toy.name and "rho" not in summary["parameters"]
    assert set(summary["results"]) == {
        "amplitude",
        "frequency",
        "periodic",
        "period_spread",
        "notes",
        "harmonics",
        "rotation_rate",
    }
    assert len(summary["results"]["amplitude"]) == 2


def test_toy_through_validate(toy, capsys):
    assert main(["validate", toy.name, "--quiet"]) == 0
    out = capsys.readouterr().out
    assert f"{toy.name} N=3" in out and "PASS" in out


def test_toy_through_sweep(toy, tmp_path):
    path = tmp_path / "toy.nc"
    ds = run_sweep(
        toy.name,
        {"kappa": [0.5, 2.0]},
        fixed={"n": 3, "sigma": 1.5},
        numerics="fast",
        duration=20.0,
        out=path,
        workers=1,
        progress=False,
    )
    assert (ds["status"].values == "ok").all()
    assert set(ds.data_vars) >= {"amplitude", "frequency", "rotation_rate"}
    assert ds["amplitude"].dims == ("kappa", "chain")
    with xr.open_dataset(path, engine="h5netcdf") as saved:
        np.testing.assert_array_equal(saved["rotation_rate"].values, ds["rotation_rate"].values)


TIP_ANGLE = Observable(
    "toy_tip_angle", "rad", "time mean of the last pendulum's angle theta_N (a test's toy observable)", error="absolute"
)


class TipAngle(ChainScene):
    """A clamped chain (ChainScene's defaults) that reports an observable it declares itself."""

    name = "toy-tip-angle"
    summary = "a clamped chain reporting the mean angle of its last pendulum (a test's toy scene)"
    base_file = "one-pinned.xml"
    observables = (TIP_ANGLE,)

    def measure_extra(self, traj, transient):
        keep = traj.t >= transient
        return {"toy_tip_angle": float(traj.theta[keep, traj.physics.n - 1].mean())}


@pytest.fixture
def tip_scene():
    scene = ea.scenes.register(TipAngle())
    yield scene
    ea.scenes.unregister(scene.name)


def test_own_observable_through_run(tip_scene, tmp_path):
    out = tmp_path / "run"
    args = ["run", tip_scene.name, "--n", "3", "--sigma", "0.5", "--duration", "10", "--engine", "reduced"]
    assert main([*args, "--out", str(out), "--quiet"]) == 0
    results = json.loads((out / "summary.json").read_text())["results"]
    assert list(results)[-1] == "toy_tip_angle" and abs(results["toy_tip_angle"]) < 1.0
    measured = ea.measure(load_trajectory(out))
    assert measured.toy_tip_angle == measured.value("toy_tip_angle") == measured.extra["toy_tip_angle"]


def test_own_observable_through_sweep(tip_scene, tmp_path):
    path = tmp_path / "tip.nc"
    ds = run_sweep(
        tip_scene.name,
        {"sigma": [0.3, 0.5]},
        fixed={"n": 3},
        engine="reduced",
        duration=10.0,
        out=path,
        workers=1,
        progress=False,
    )
    assert (ds["status"].values == "ok").all() and np.isfinite(ds["toy_tip_angle"].values).all()
    with xr.open_dataset(path, engine="h5netcdf") as saved:
        assert saved["toy_tip_angle"].attrs == {"units": "rad", "long_name": TIP_ANGLE.long_name}


def test_own_observable_compared_by_its_spec(tip_scene):
    """validate compares a plug-in's observable as its spec says (here absolutely: NAME_abs)."""
    physics = ea.Physics(scene=tip_scene.name, n=3)
    a, b = (Results(0.1, 0.2, True, extra={"toy_tip_angle": v}) for v in (0.25, 0.5))
    assert observable_errors(physics, a, b)["toy_tip_angle_abs"] == pytest.approx(0.25)


def test_own_observable_withdrawn_with_its_scene():
    scene = ea.scenes.register(TipAngle())
    assert observables.get("toy_tip_angle") is TIP_ANGLE and observables.owner("toy_tip_angle") == f"scene {scene.name}"
    ea.scenes.unregister(scene.name)
    assert not observables.known("toy_tip_angle") and observables.known("rotation_rate")  # named, not owned, by toys


def test_an_undeclared_observable_is_reported_as_measured_and_compared_relatively():
    """A plug-in written before specs names its observables only: they are reported as before (no units), and
    validate compares them relatively (the spec's defaults)."""

    class Vague(TipAngle):
        name = "toy-vague"
        observables = ("toy_vague_value",)

    scene = ea.scenes.register(Vague())
    try:
        assert not observables.known("toy_vague_value") and scene.observable_names() == ("toy_vague_value",)
        physics = ea.Physics(scene=scene.name, n=3)
        a, b = (Results(0.1, 0.2, True, extra={"toy_vague_value": v}) for v in (1.0, 1.5))
        assert observable_errors(physics, a, b)["toy_vague_value"] == pytest.approx(1 / 3)
    finally:
        ea.scenes.unregister(scene.name)


def test_a_taken_observable_name_is_refused():
    class Clash(TipAngle):
        name = "toy-clash"
        observables = (Observable("rotation_rate", "rad", "not the rotating pin's"),)

    with pytest.raises(ValueError, match="observable named 'rotation_rate' is already declared by scene rotating-pin"):
        ea.scenes.register(Clash())
    assert observables.get("rotation_rate").units == "rad/tau"

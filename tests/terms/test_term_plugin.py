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
import xarray as xr

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.core import observables
from elastoactive.core.observables import Observable
from elastoactive.core.parameters import Parameter
from elastoactive.scenes.base import ValidationCase
from elastoactive.sweep import run_sweep
from elastoactive.terms import Term


class UniformField(Term):
    name = "toy-uniform-field"
    summary = "the same force on every particle (a test's toy term)"
    parameters = (
        Parameter("field_x", 0.0, "uniform force on every particle, x component (C1 / l)", quiet_default=True),
        Parameter("field_y", 0.0, "uniform force on every particle, y component (C1 / l)", quiet_default=True),
    )
    observables = (
        Observable("tip_y", "l", "mean height of the chain's tip above the clamp (a test's toy observable)"),
    )

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
    np.testing.assert_allclose(
        runs["mujoco"].theta, runs["reduced"].theta, atol=0.01 * np.abs(runs["reduced"].theta).max()
    )


def test_field_through_run(field, tmp_path):
    out = tmp_path / "run"
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--n",
                "5",
                "--sigma",
                "0.3",
                "--field-y",
                "0.05",
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
    assert summary["parameters"]["field_y"] == 0.05
    assert summary["results"]["tip_y"] > 0.3


def test_field_through_validate(field, capsys):
    assert main(["validate", "one-pinned", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "one-pinned N=5 sigma=0.8 field_x=-0.02 field_y=0.02" in out and "PASS" in out


def test_field_through_sweep(field, tmp_path):
    ds = run_sweep(
        "one-pinned",
        {"field_y": [0.02, 0.05]},
        fixed={"n": 5, "sigma": 0.3},
        numerics="fast",
        duration=20.0,
        out=tmp_path / "field.nc",
        workers=1,
        progress=False,
    )
    assert (ds["status"].values == "ok").all()
    tip = ds["tip_y"].values
    assert tip[1] > tip[0] > 0
    assert ds["field_y"].attrs["long_name"].startswith("uniform force on every particle")
    assert ds["tip_y"].attrs == {"units": "l", "long_name": UniformField.observables[0].long_name}
    with xr.open_dataset(tmp_path / "field.nc", engine="h5netcdf") as saved:  # the file, not only the Dataset
        assert saved["tip_y"].attrs["units"] == "l" and saved["tip_y"].attrs["long_name"].startswith("mean height")


def test_observable_declared_only_while_registered(field):
    assert (
        observables.get("tip_y") is UniformField.observables[0] and observables.owner("tip_y") == f"term {field.name}"
    )
    tr = ea.simulate(ea.Physics(n=3, sigma=0.3, field_y=0.05), duration=5.0, engine="reduced")
    assert ea.measure(tr).tip_y == ea.measure(tr).value("tip_y") == ea.measure(tr).as_dict()["tip_y"]


def test_observable_withdrawn_with_its_term():
    term = ea.terms.register(UniformField())
    assert observables.known("tip_y")
    ea.terms.unregister(term.name)
    assert not observables.known("tip_y") and observables.known("contact_fraction")
    res = ea.measure(ea.simulate(ea.Physics(n=3), duration=2.0, engine="reduced"))
    with pytest.raises(AttributeError, match="tip_y"):
        res.tip_y  # noqa: B018  (the attribute access is what is tested)
    assert res.contact_fraction is None  # declared, not measured without contact


def test_a_term_cannot_redeclare_a_taken_observable():
    class Clash(Term):
        name = "toy-clash"
        observables = (Observable("contact_fraction", "%", "not self-contact's"),)

    with pytest.raises(ValueError, match="observable named 'contact_fraction' is already declared by term contact"):
        ea.terms.register(Clash())
    assert "toy-clash" not in ea.terms.names() and observables.get("contact_fraction").units == "1"


class StiffTether(Term):
    """Every particle pulled toward its rest point on the x axis by a force k d, capped at tether_cap: a stiff
    position-dependent force that MuJoCo applies through actuators (not its passive forces, which the pre-flight
    check linearises) and that declares no rate. At k = 2000 and dt = 0.0025 MuJoCo's explicit step is unstable, yet
    the capped force keeps the state finite: the chain's angles run to tens of radians."""

    name = "toy-stiff-tether"
    summary = "a capped stiff spring from every particle to its rest point (a test's toy term)"
    parameters = (
        Parameter("tether_k", 0.0, "tether stiffness (C1 / l^2)", low=0.0, quiet_default=True),
        Parameter("tether_cap", 1e9, "largest tether force (C1 / l)", low=0.0, quiet_default=True),
    )

    def build(self, spec, physics, numerics):
        import mujoco

        for i in range(physics.n):
            spec.worldbody.add_site(name=f"tether_anchor_{i}", pos=[i + 1.0, 0.0, 0.0])
            tendon = spec.add_tendon(name=f"tether_{i}")
            tendon.wrap_site(f"particle_{i}")
            tendon.wrap_site(f"tether_anchor_{i}")
            actuator = spec.add_actuator(
                name=f"tether_pull_{i}", target=f"tether_{i}", trntype=mujoco.mjtTrn.mjTRN_TENDON
            )
            actuator.gainprm[0] = 0.0
            actuator.biastype = mujoco.mjtBias.mjBIAS_AFFINE
            actuator.biasprm[:3] = [0.0, -physics.tether_k, 0.0]
            actuator.forcelimited = 1
            actuator.forcerange = [-physics.tether_cap, physics.tether_cap]

    def node_forces(self, physics):
        k, cap = physics.tether_k, physics.tether_cap

        def law(positions):
            d = positions - np.stack([np.arange(1.0, len(positions) + 1.0), np.zeros(len(positions))], axis=1)
            r = np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
            return -np.minimum(k * r, cap) * d / r

        return law


@pytest.fixture
def tether():
    term = ea.terms.register(StiffTether())
    yield term
    ea.terms.unregister(term.name)


def test_a_finite_runaway_state_is_a_divergence(tether):
    """The state itself tells a diverged run, whatever the terms declare: one step moving it by more than
    monitor.MAX_STEP_CHANGE is SimulationDiverged (a single run and a batched one alike), not 70 rad of angles."""
    from elastoactive.engines.mujoco_batch import simulate_mujoco_batch

    physics = ea.Physics(n=5, sigma=0.8, tether_k=2000.0, tether_cap=2000.0)
    with pytest.raises(ea.SimulationDiverged, match="one step moved the state by .* an accurate run moves less") as err:
        ea.simulate(physics, duration=5.0, engine="mujoco")
    assert "Term.rate" in str(err.value) and "reduce dt" in str(err.value)
    batched = simulate_mujoco_batch(
        [physics, ea.Physics(n=5, sigma=0.8, tether_k=1.0, tether_cap=2000.0)], ea.Numerics(), 5.0, threads=1
    )
    assert isinstance(batched[0], ea.SimulationDiverged) and str(batched[0]) == str(err.value)
    assert np.abs(batched[1].theta).max() < 0.05  # a soft tether runs: the check reads the state, not the term


def test_a_network_run_is_checked_for_runaway_steps(monkeypatch):
    """The network engine applies the same state check (here with a threshold that any motion exceeds)."""
    from elastoactive.engines import monitor

    monkeypatch.setattr(monitor, "MAX_STEP_CHANGE", 1e-12)
    with pytest.raises(ea.SimulationDiverged, match="nodes moved .* in one step"):
        ea.simulate(ea.Physics(scene="trapped-unit"), duration=1.0, engine="mujoco")


class Declared(Term):
    """A plug-in term that declares a fast rate and leaves every other hook at its default."""

    name = "toy-declared-rate"
    parameters = (Parameter("declared_rate", 0.0, "a rate the term imposes (1 / tau)", low=0.0, quiet_default=True),)

    def rate(self, physics):
        return physics.declared_rate


def test_a_term_rate_refusal_reads_well_for_every_term():
    from elastoactive.terms.base import slower_advice

    term = ea.terms.register(Declared())
    try:
        with pytest.raises(ea.ParameterError) as err:
            ea.simulate(ea.Physics(n=5, declared_rate=5000.0), duration=1.0, engine="mujoco")
        message = str(err.value)
        assert "toy-declared-rate term" in message and "  " not in message and "or (" not in message
        assert "declared_rate" in message.split("Use dt <=")[1]
        for name in ea.terms.names():
            advice = slower_advice(ea.terms.get(name), ea.Physics(), 10.0)
            assert advice.startswith(" or ") and advice[4:].strip() == advice[4:] and len(advice) > 8, name
            assert "  " not in advice and "()" not in advice, name
    finally:
        ea.terms.unregister(term.name)

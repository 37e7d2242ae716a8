"""One rule for run, sweep and the API: a value given where it does not act is refused in one line naming it.

A parameter the scene does not have (delta on one-pinned), one whose switch is off (contact_radius without
contact, noise_correlation without noise), and a MuJoCo-only numerical setting with the reduced engine (integrator;
dt without noise). Every parameter is declared once (elastoactive.core.parameters), so the rule is checked for every
scene and every parameter, not for a list of commands.
"""

import json

import numpy as np
import pytest
from conftest import refused

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.core import parameters, registry
from elastoactive.core.params import Numerics, scene_parameters
from elastoactive.sweep import make_sweep, parse_grid


def _foreign():
    """(scene, parameter) pairs where the scene does not have the parameter."""
    return [(s, p) for s in registry.names() for p in parameters.names() if p not in scene_parameters(registry.get(s))]


@pytest.mark.parametrize("scene, name", _foreign())
def test_a_parameter_the_scene_does_not_have_is_refused_everywhere(scene, name, capsys):
    spec = parameters.get(name)
    value = spec.default if spec.instead_of is None else 1.0  # the coupling Pi has no default of its own
    message = f"{name} has no effect on scene {scene}"
    with pytest.raises(ea.ParameterError, match=message):
        ea.Physics(scene=scene, **{name: value})
    with pytest.raises(ea.ParameterError, match=message):
        make_sweep(
            scene, {"sigma": [0.5, 0.8]}, fixed={name: value}, numerics=Numerics(), duration=10.0, engine="mujoco"
        )
    option = parameters.get(name).option
    args = [option] if isinstance(value, bool) else [option, str(value)]
    assert main(["run", scene, *args, "--duration", "5", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


@pytest.mark.parametrize(
    "name, value, switch",
    [
        ("contact_radius", 0.2, "contact"),
        ("contact_friction", 0.3, "contact"),
        ("noise_correlation", 1.0, "noise"),
        ("noise_calculus", "stratonovich", "noise"),
    ],
)
def test_a_value_whose_switch_is_off_is_refused(name, value, switch, capsys):
    with pytest.raises(ea.ParameterError, match=f"{name} has no effect without {switch}"):
        ea.Physics(**{name: value})
    assert ea.Physics(**{name: parameters.get(name).default}).relevant() == ea.Physics().relevant()  # the default: fine
    assert main(["run", "one-pinned", parameters.get(name).option, str(value), "--duration", "5", "--quiet"]) == 2
    assert f"{name} has no effect without {switch}" in capsys.readouterr().err


def test_turning_a_switch_off_drops_what_it_carried():
    p = ea.Physics(contact=True, contact_radius=0.2).replace(contact=False)
    assert p == ea.Physics() and p.contact_radius == parameters.get("contact_radius").default


@pytest.mark.parametrize("numerics", [Numerics(integrator="RK4"), Numerics(dt=0.05)])
def test_mujoco_only_numerics_are_refused_with_the_reduced_engine(numerics):
    with pytest.raises(ea.ParameterError, match="only affects the MuJoCo engine"):
        ea.simulate(ea.Physics(n=3), numerics, duration=5.0, engine="reduced")


def test_dt_is_the_noise_step_of_the_reduced_engine():
    traj = ea.simulate(ea.Physics(n=2, noise=0.1), Numerics(dt=0.01), duration=1.0, engine="reduced")
    assert traj.t.size == 21


STOCHASTIC = [name for name in parameters.names() if parameters.get(name).stochastic]


def _scene_with(name: str) -> str:
    """A scene on which the parameter acts (the first registered)."""
    return next(s for s in registry.names() if name in scene_parameters(registry.get(s)))


def test_the_stochastic_parameters_are_declared():
    assert {"noise", "rotational_diffusion", "translational_diffusion"} <= set(STOCHASTIC)


@pytest.mark.parametrize("name", STOCHASTIC)
def test_dt_acts_on_the_reduced_engine_exactly_when_a_stochastic_parameter_is_on(name, tmp_path):
    """Whichever parameter makes a run stochastic, the one rule (core.parameters.stochastic) lets dt through to the
    reduced engine, records it, and refuses it without: in a run, in a sweep's fixed numerics and on its grid."""
    scene = _scene_with(name)
    on = ea.Physics(scene=scene, **{name: 0.01})
    assert on.stochastic and not on.replace(**{name: 0.0}).stochastic
    assert parameters.stochastic({}, {name: [0.0, 0.01]}) and not parameters.stochastic({name: 0.01}, {name: [0.0]})
    run = ["run", scene, "--engine", "reduced", "--dt", "0.01", "--duration", "2", "--quiet"]
    assert main([*run, parameters.get(name).option, "0.01", "--out", str(tmp_path / "on")]) == 0
    assert json.loads((tmp_path / "on" / "summary.json").read_text())["numerics"]["dt"] == 0.01
    assert main([*run, "--out", str(tmp_path / "off")]) == 2
    sweep = ["sweep", scene, "--engine", "reduced", "--dt", "0.01", "--duration", "2", "--quiet"]
    assert main([*sweep, "--grid", f"{name}=0,0.01", "--out", str(tmp_path / "on.nc")]) == 0
    assert main([*sweep, "--grid", f"{name}=0", "--out", str(tmp_path / "off.nc")]) == 2


def test_numpy_numbers_are_numbers():
    p = ea.Physics(n=np.int64(7), sigma=np.float32(0.5), contact=np.bool_(True))
    assert p.n == 7 and type(p.n) is int and p.contact is True
    with pytest.raises(ea.ParameterError, match="must be an integer"):
        ea.Physics(n=7.5)


def test_only_numbers_are_swept():
    for name in ("loaded", "contact", "noise_calculus"):
        with pytest.raises(ea.ParameterError, match=f"{name} is not a number and cannot be swept"):
            parse_grid([f"{name}=1"])
    # a text value is given as a fixed value, on every scene that has it
    sweep = make_sweep(
        "one-pinned",
        {"sigma": [0.5, 0.8]},
        fixed={"loaded": "tip"},
        numerics=Numerics(),
        duration=10.0,
        engine="mujoco",
    )
    assert sweep.case(0).physics.loaded == "tip"


@pytest.mark.parametrize(
    "argv",
    [
        ["star", "--hub", "clamped", "--hub-stiffness", "1"],
        ["one-pinned", "--alignment-length", "1"],
        ["one-pinned", "--clamp-frequency", "0.01"],
        ["one-pinned", "--drive-direction", "transverse"],
        ["one-pinned", "--contact-radius", "0.1"],
    ],
)
def test_an_option_typed_where_it_does_not_act_is_refused_even_at_its_default(argv, capsys, no_simulation):
    """The API lets a switch-dependent value equal to its default through (the physics takes it anyway), but a value
    typed on the command line is meant to act: run refuses it in one line naming its switch (it had been dropped)."""
    refused(capsys, ["run", *argv, "--duration", "2"], f"{argv[-2][2:].replace('-', '_')} has no effect without")


def test_stability_refuses_n_on_a_network(capsys):
    refused(capsys, ["stability", "lattice", "--n", "5"], "n has no effect on scene lattice")
    assert main(["stability", "one-pinned"]) == 0  # a chain's N still defaults to 7
    assert "N = 7" in capsys.readouterr().out


@pytest.mark.parametrize(
    "scene",
    [s for s in registry.names() if registry.get(s).pinned and "drive_amplitude" in scene_parameters(registry.get(s))],
)
def test_a_tip_drive_on_a_pinned_tip_is_refused_in_both_engines(scene):
    """The tip drive pushes chain 1's last particle; a scene that holds it on a pin would take the force on the pin
    (the reduced engine refused it, MuJoCo ran it with an effect of 3e-5 rad): refused by the physics itself."""
    with pytest.raises(ea.ParameterError, match=f"drive_amplitude: .* scene {scene} holds on a pin"):
        ea.Physics(scene=scene, drive_amplitude=0.1)
    assert ea.Physics(drive_amplitude=0.1).drive_amplitude == 0.1  # a free tip takes it


def test_the_calculus_of_coloured_noise_is_refused(capsys, no_simulation):
    """Coloured noise is a smooth random force: the calculus, which reads white noise, changes nothing there."""
    with pytest.raises(ea.ParameterError, match="noise_calculus has no effect with noise_correlation = 0.5"):
        ea.Physics(noise=0.1, noise_correlation=0.5, noise_calculus="stratonovich")
    white = ea.Physics(noise=0.1, noise_calculus="stratonovich")
    coloured = white.replace(noise_correlation=0.5)  # the switch turned on drops what it leaves unused
    assert "noise_calculus" not in coloured.relevant() and coloured.noise_correlation == 0.5
    refused(
        capsys,
        [
            "run",
            "one-pinned",
            "--noise",
            "0.1",
            "--noise-correlation",
            "0.5",
            "--noise-calculus",
            "ito",
            "--duration",
            "2",
        ],
        "noise_calculus has no effect with noise_correlation",
    )


@pytest.mark.parametrize("engine", ["mujoco", "reduced"])
def test_no_perturbation_on_an_unstable_base_state_is_refused(engine):
    """perturbation = 0 above onset sits on the unstable base state (reported as a beat); below onset it is a run
    at rest."""
    with pytest.raises(ea.ParameterError, match=r"perturbation = 0 .* unstable .*numerics\.perturbation > 0"):
        ea.simulate(ea.Physics(n=3, sigma=3.0), Numerics(perturbation=0.0), duration=1.0, engine=engine)
    traj = ea.simulate(ea.Physics(n=3, sigma=0.5), Numerics(perturbation=0.0), duration=1.0, engine=engine)
    assert np.abs(traj.theta).max() == 0.0


def test_no_perturbation_is_refused_in_a_mujoco_batch():
    from elastoactive.engines.mujoco_batch import simulate_mujoco_batch

    outcomes = simulate_mujoco_batch(
        [ea.Physics(n=3, sigma=3.0), ea.Physics(n=3, sigma=0.5)], Numerics(perturbation=0.0), 1.0, threads=1
    )
    assert isinstance(outcomes[0], ea.ParameterError) and "perturbation = 0" in str(outcomes[0])
    assert not isinstance(outcomes[1], Exception)


@pytest.mark.parametrize(
    "switch, setting", [("clamp_amplitude", "clamp_frequency"), ("drive_amplitude", "drive_frequency")]
)
def test_a_sweep_holds_the_undriven_baseline(switch, setting):
    """A fixed value whose switch is swept acts at the grid's points where the switch is on and is dropped where it is
    off (the undriven baseline is a grid point); it is refused only when the switch is never on."""
    sweep = make_sweep(
        "one-pinned", {switch: [0.0, 0.1]}, fixed={setting: 0.05}, numerics=Numerics(), duration=5.0, engine="reduced"
    )
    off, on = sweep.case(0).physics, sweep.case(1).physics
    assert setting not in off.relevant() and getattr(on, setting) == 0.05 and getattr(on, switch) == 0.1
    with pytest.raises(ea.ParameterError, match=f"{setting} has no effect without {switch}"):
        make_sweep("one-pinned", {"sigma": [0.5, 0.6]}, fixed={setting: 0.05}, numerics=Numerics(), duration=5.0)


def test_a_default_dt_follows_the_sampling():
    """dt left at its default becomes a whole fraction of a given sample_dt: the reduced engine, which has no dt,
    takes any sample_dt, and MuJoCo steps a little finer; a dt given is still held to it."""
    numerics = Numerics(sample_dt=0.003)
    assert numerics.dt == pytest.approx(0.0015) and numerics.steps_per_sample == 2 and numerics.given() == ()
    for engine in ("reduced", "mujoco"):
        traj = ea.simulate(ea.Physics(n=3, sigma=0.5), numerics, duration=0.1, engine=engine)
        np.testing.assert_allclose(np.diff(traj.t), 0.003)
    with pytest.raises(ea.ParameterError, match="whole multiple of dt"):
        Numerics(sample_dt=0.003, dt=0.0025)


@pytest.mark.parametrize("sample_dt", [0.05, 0.02])
def test_the_shortest_duration_advised_can_be_measured(sample_dt):
    numerics = Numerics(sample_dt=sample_dt)
    with pytest.raises(ea.ParameterError, match="lengthen duration") as err:  # as Python names it
        numerics.check_duration(0.1)
    advised = float(str(err.value).split("duration (>= ")[1].split(" tau")[0])
    traj = ea.simulate(ea.Physics(n=3, sigma=0.5), numerics, duration=advised, engine="reduced")
    assert ea.measure(traj).amplitude >= 0  # the default transient leaves enough samples


def test_a_rerun_on_the_other_engine_drops_the_settings_it_does_not_read(tmp_path, capsys):
    """run --from a MuJoCo run --engine reduced: the record's dt and integrator, which the reduced engine does not
    read and the user cannot remove, are left behind (they had been refused)."""
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--n",
                "3",
                "--sigma",
                "0.5",
                "--duration",
                "1",
                "--out",
                str(tmp_path / "mujoco"),
                "--quiet",
            ]
        )
        == 0
    )
    assert (
        main(
            [
                "run",
                "--from",
                str(tmp_path / "mujoco"),
                "--engine",
                "reduced",
                "--out",
                str(tmp_path / "reduced"),
                "--quiet",
            ]
        )
        == 0
    )


def test_numpy_integers_are_seeds():
    numerics = Numerics(seed=np.int64(3))
    assert numerics.seed == 3 and type(numerics.seed) is int and numerics == Numerics(seed=3)
    with pytest.raises(ea.ParameterError, match="seed must be a non-negative integer"):
        Numerics(seed=2.5)


def test_a_trajectory_built_from_lists_is_measured():
    traj = ea.simulate(ea.Physics(n=3, sigma=0.5), duration=2.0, engine="reduced")
    rebuilt = ea.Trajectory(t=traj.t.tolist(), theta=traj.theta.tolist(), physics=traj.physics, engine="reduced")
    assert ea.measure(rebuilt).amplitude == ea.measure(traj).amplitude
    with pytest.raises(ea.ParameterError, match=r"Trajectory.theta must have 2 dimension\(s\), one row per time"):
        ea.Trajectory(t=traj.t, theta=traj.theta[:-1], physics=traj.physics, engine="reduced")

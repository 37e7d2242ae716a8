"""One rule for run, sweep and the API: a value given where it does not act is refused in one line naming it.

A parameter the scene does not have (delta on one-pinned), one whose switch is off (contact_radius without
contact, noise_correlation without noise), and a MuJoCo-only numerical setting with the reduced engine (integrator;
dt without noise). Every parameter is declared once (elastoactive.parameters), so the rule is checked for every
scene and every parameter, not for a list of commands.
"""

import numpy as np
import pytest

import elastoactive as ea
from elastoactive import parameters, registry
from elastoactive.cli import main
from conftest import refused
from elastoactive.params import Numerics, scene_parameters
from elastoactive.sweep import make_sweep, parse_grid


def _foreign():
    """(scene, parameter) pairs where the scene does not have the parameter."""
    return [(s, p) for s in registry.names() for p in parameters.names()
            if p not in scene_parameters(registry.get(s))]


@pytest.mark.parametrize("scene, name", _foreign())
def test_a_parameter_the_scene_does_not_have_is_refused_everywhere(scene, name, capsys):
    value = parameters.get(name).default
    message = f"{name} has no effect on scene {scene}"
    with pytest.raises(ea.ParameterError, match=message):
        ea.Physics(scene=scene, **{name: value})
    with pytest.raises(ea.ParameterError, match=message):
        make_sweep(scene, {"sigma": [0.5, 0.8]}, fixed={name: value}, numerics=Numerics(), duration=10.0,
                   engine="mujoco")
    option = parameters.get(name).option
    args = [option] if isinstance(value, bool) else [option, str(value)]
    assert main(["run", scene, *args, "--duration", "5", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


@pytest.mark.parametrize("name, value, switch", [("contact_radius", 0.2, "contact"), ("contact_friction", 0.3, "contact"),
                                                 ("noise_correlation", 1.0, "noise"),
                                                 ("noise_calculus", "stratonovich", "noise")])
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
    sweep = make_sweep("one-pinned", {"sigma": [0.5, 0.8]}, fixed={"loaded": "tip"}, numerics=Numerics(),
                       duration=10.0, engine="mujoco")
    assert sweep.case(0).physics.loaded == "tip"


@pytest.mark.parametrize("argv", [["star", "--hub", "clamped", "--hub-stiffness", "1"],
                                  ["one-pinned", "--alignment-length", "1"],
                                  ["one-pinned", "--clamp-frequency", "0.01"],
                                  ["one-pinned", "--drive-direction", "transverse"],
                                  ["one-pinned", "--contact-radius", "0.1"]])
def test_an_option_typed_where_it_does_not_act_is_refused_even_at_its_default(argv, capsys, no_simulation):
    """The API lets a switch-dependent value equal to its default through (the physics takes it anyway), but a value
    typed on the command line is meant to act: run refuses it in one line naming its switch (it had been dropped)."""
    refused(capsys, ["run", *argv, "--duration", "2"], f"{argv[-2][2:].replace('-', '_')} has no effect without")


def test_stability_refuses_n_on_a_network(capsys):
    refused(capsys, ["stability", "lattice", "--n", "5"], "n has no effect on scene lattice")
    assert main(["stability", "one-pinned"]) == 0  # a chain's N still defaults to 7
    assert "N = 7" in capsys.readouterr().out

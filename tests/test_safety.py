"""Invalid input is refused by name; a diverging run stops loudly instead of resetting."""

import math

import mujoco
import numpy as np
import pytest

from elastoactive import scenes
from elastoactive.cli import main
from elastoactive.core.errors import SimulationDiverged
from elastoactive.core.params import Numerics, ParameterError, Physics
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.engines.timestep import check_timestep, stability_limits
from elastoactive.mjcf.chain import build_model
from elastoactive.scenes import names as scene_names


@pytest.mark.parametrize(
    "kwargs,name",
    [
        (dict(n=0), "n "),
        (dict(n=1, scene="two-pinned"), "n "),
        (dict(n=2.5), "n "),
        (dict(sigma=-1), "sigma"),
        (dict(sigma=math.nan), "sigma"),
        (dict(delta=1.0, scene="two-pinned"), "delta"),
        (dict(delta=-0.1), "delta"),
        (dict(kappa=-2), "kappa"),
        (dict(rho=0), "rho"),
        (dict(rho=math.inf), "rho"),
        (dict(drag_ratio=-1), "drag_ratio"),
        (dict(noise=-0.1), "noise"),
        (dict(scene="three-pinned"), "scene"),
    ],
)
def test_invalid_physics_is_refused_by_name(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        Physics(**kwargs)


@pytest.mark.parametrize(
    "kwargs,name",
    [
        (dict(dt=0), "dt"),
        (dict(dt=-0.01), "dt"),
        (dict(dt=math.nan), "dt"),
        (dict(mass_ratio=0), "mass_ratio"),
        (dict(mass_ratio=1000.0), "mass_ratio"),  # the cap is 100 (heavier chains are inertial, not refused)
        (dict(integrator="leapfrog"), "integrator"),
        (dict(seed=-1), "seed"),
    ],
)
def test_invalid_numerics_is_refused_by_name(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        Numerics(**kwargs)


def test_cli_reports_bad_parameter(capsys):
    assert main(["run", "two-pinned", "--delta", "1.5", "--quiet"]) == 2
    assert "delta" in capsys.readouterr().err


@pytest.mark.parametrize("n,delta", [(2, 0.0), (3, 0.9), (7, 0.1), (9, 0.5), (50, 0.3)])
def test_two_pinned_starts_on_its_pins(n, delta):
    from elastoactive.core.registry import initial_angles
    from elastoactive.reduced.initial import pin_residual

    theta = initial_angles(Physics(scene="two-pinned", n=n, delta=delta), Numerics(perturbation=0.05))
    assert np.abs(pin_residual(theta, delta)).max() < 1e-12


@pytest.mark.parametrize("scene", [s for s in scene_names() if scenes.get(s).term_parameters is None])
def test_autoreset_is_off(scene):  # chain scenes; a network's model: tests/engines/test_network_mujoco.py
    model = build_model(Physics(scene=scene, n=3))
    assert model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_AUTORESET


def test_divergence_stops_with_cause(tmp_path, monkeypatch):
    """Euler with a dt far beyond 2 m / gamma blows up: the error names the mass and dt, and MuJoCo's own log file
    is not left in the working directory."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SimulationDiverged, match=r"(?s)diverged.*mass_ratio too small.*implicitfast"):
        simulate_mujoco(Physics(n=7, sigma=0.8), Numerics(dt=0.01, integrator="Euler"), 5.0)
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


def test_preflight_refuses_unstable_timestep():
    with pytest.raises(ParameterError, match=r"dt = 0.01 is above the stability limit"):
        check_timestep(Physics(n=7), Numerics(dt=0.01, integrator="Euler"))
    with pytest.raises(ParameterError, match="stiffest overdamped mode"):
        check_timestep(
            Physics(n=7), Numerics(dt=0.1, sample_dt=0.1, integrator="implicitfast", mass_ratio=1e-2), safety=0.3
        )
    check_timestep(Physics(n=7), Numerics())  # the defaults are fine


def test_euler_limit_is_twice_mass_over_drag():
    limits = stability_limits(Physics(n=5), Numerics(mass_ratio=1e-3))
    assert limits.limit("Euler") == pytest.approx(2e-3, rel=0.02)
    assert limits.limit("implicitfast") > 0.1


def test_predicted_limit_is_real():
    """Just below the predicted Euler limit the run is stable, well above it it diverges."""
    physics = Physics(n=4, sigma=0.3)
    limit = stability_limits(physics, Numerics(mass_ratio=1e-2)).limit("Euler")
    ok = simulate_mujoco(
        physics, Numerics(dt=0.9 * limit, sample_dt=0.9 * limit, mass_ratio=1e-2, integrator="Euler"), 5.0
    )
    assert np.all(np.isfinite(ok.theta))
    with pytest.raises(SimulationDiverged):
        simulate_mujoco(
            physics, Numerics(dt=1.5 * limit, sample_dt=1.5 * limit, mass_ratio=1e-2, integrator="Euler"), 20.0
        )


def test_sample_spacing_must_be_whole_steps():
    """Both engines must record at the same times: 0.05 is not a multiple of 0.004."""
    with pytest.raises(ParameterError, match="sample_dt .* whole multiple of dt"):
        Numerics(dt=0.004, sample_dt=0.05)
    assert Numerics(dt=0.004, sample_dt=0.048).steps_per_sample == 12


def test_two_pinned_n2_has_no_free_motion():
    """Two angles, two pin constraints: the stability estimate must not fail on an empty spectrum."""
    limits = check_timestep(Physics(scene="two-pinned", n=2, delta=0.1), Numerics())
    assert limits.limit("implicitfast") == np.inf
    traj = simulate_mujoco(Physics(scene="two-pinned", n=2, delta=0.1), Numerics(), 10.0)
    assert np.ptp(traj.theta[traj.t > 5], axis=0).max() < 1e-3


def test_pin_drift_stops_the_run():
    """A soft pin that lets go (tiny mass, large dt) is an error, not a silently wrong snap."""
    with pytest.raises(SimulationDiverged, match="drifted .* off its pin"):
        simulate_mujoco(
            Physics(scene="two-pinned", n=7, sigma=0.8, delta=0.1),
            Numerics(dt=0.04, sample_dt=0.04, mass_ratio=1e-4),
            50.0,
        )


def test_failed_implicit_solve_is_a_divergence():
    from elastoactive.engines.mujoco import BAD_STATE_WARNINGS

    assert mujoco.mjtWarning.mjWARN_INERTIA in BAD_STATE_WARNINGS


def test_both_engines_record_on_one_grid():
    """A duration that is not a whole number of samples gives the same grid in both engines."""
    from elastoactive.engines.reduced import simulate_reduced

    physics, numerics = Physics(n=3, sigma=0.5), Numerics()
    mj, red = simulate_mujoco(physics, numerics, 3.03), simulate_reduced(physics, numerics, 3.03)
    np.testing.assert_array_equal(mj.t, red.t)
    assert mj.t[-1] == pytest.approx(3.0)

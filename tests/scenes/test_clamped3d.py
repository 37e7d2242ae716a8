"""The clamped chain in 3D as a scene (elastoactive.scenes.clamped3d): both engines through the front door, its 3D
observables, its recorded angles, a planar start against the planar scene, its stability report."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.analysis.whirl import settled_whirl
from elastoactive.records import summary
from elastoactive.scenes.clamped3d import ACCURACY_TARGET, angles_of, tangents_of


@pytest.fixture(scope="module")
def runs():
    """N = 3 at sigma = 2.5 (onset 1.163) from the scene's seeded non-planar start, 60 tau in each engine."""
    physics = ea.Physics(scene="clamped-3d", n=3, sigma=2.5)
    return {engine: ea.simulate(physics, duration=60.0, engine=engine) for engine in ("reduced", "mujoco")}


def test_both_engines_whirl_alike(runs):
    results = {engine: ea.measure(traj) for engine, traj in runs.items()}
    reduced, mujoco = results["reduced"], results["mujoco"]
    assert reduced.extra["motion_state"] == mujoco.extra["motion_state"] == "whirl"
    assert mujoco.frequency == pytest.approx(reduced.frequency, rel=0.01)
    assert mujoco.amplitude == pytest.approx(reduced.amplitude, rel=0.01)
    assert mujoco.extra["whirl_rate"] == pytest.approx(reduced.extra["whirl_rate"], rel=0.01)
    assert abs(reduced.extra["whirl_rate"]) == pytest.approx(reduced.frequency, rel=0.01)


def test_recorded_state_and_positions(runs):
    traj = runs["reduced"]
    assert traj.theta.shape == (traj.t.size, 6)
    tangents = tangents_of(traj.theta, 3)
    np.testing.assert_allclose(np.linalg.norm(tangents, axis=-1), 1.0, atol=1e-12)
    np.testing.assert_allclose(angles_of(tangents), traj.theta, atol=1e-9)
    assert traj.positions().shape == (traj.t.size, 1, 3, 3)
    dataset = traj.to_xarray()
    assert dataset["tangent"].dims == ("time", "chain", "particle", "xyz")


def test_planar_start_is_the_planar_scene():
    """Elevations 0 at the start: the chain stays in the plane and its azimuths are the one-pinned scene's angles."""
    theta = 0.01 * np.sin(0.3 * np.arange(1, 6))
    flat = ea.simulate(ea.Physics(scene="clamped-3d", n=5, sigma=0.8), duration=20.0, engine="mujoco",
                       theta0=np.concatenate([theta, np.zeros(5)]))  # fmt: skip
    planar = ea.simulate(ea.Physics(scene="one-pinned", n=5, sigma=0.8), duration=20.0, engine="mujoco", theta0=theta)
    assert np.all(flat.theta[:, 5:] == 0.0)
    assert np.abs(flat.theta[:, :5] - planar.theta).max() < 1e-11


def test_stability_is_the_planar_onset():
    scene = ea.scenes.get("clamped-3d")
    physics = ea.Physics(scene="clamped-3d", n=7, sigma=0.8)
    assert scene.onset(physics).sigma_c == pytest.approx(0.157470, abs=1e-6)
    assert "sigma_c = 0.157469" in "\n".join(scene.stability_report(physics, 0.8))


@pytest.mark.parametrize(
    "n, sigma, drag_ratio",
    [(7, 0.3, 1.0), (7, 0.8, 0.5), (20, 0.8, 1.0), (20, 2.0, 1.0), (40, 0.8, 1.0), (7, 5.0, 2.0)],
)
def test_automatic_dt_meets_the_accuracy_target(n, sigma, drag_ratio):
    """Numerics left at their defaults take a dt whose predicted error on the whirl is within ACCURACY_TARGET: the
    default dt where it meets it (N = 20, sigma = 0.8: the predicted 0.37% is the measured 0.32%), a smaller whole
    fraction of sample_dt where it does not (N = 20, sigma = 2: the default's measured 1.8%), never a larger one."""
    scene = ea.scenes.get("clamped-3d")
    physics = ea.Physics(scene="clamped-3d", n=n, sigma=sigma, drag_ratio=drag_ratio)
    default = ea.Numerics()
    chosen = scene.automatic_numerics(physics, default)
    error = scene.step_error(physics)
    assert chosen.dt * error <= ACCURACY_TARGET * (1 + 1e-9)
    assert chosen.dt <= default.dt
    assert chosen.steps_per_sample * chosen.dt == pytest.approx(default.sample_dt)
    if default.dt * error > ACCURACY_TARGET:  # the largest such dt: one step fewer per sample would miss the target
        assert default.sample_dt / (chosen.steps_per_sample - 1) * error > ACCURACY_TARGET
    else:
        assert chosen.dt == default.dt
    given = ea.Numerics(dt=0.005)
    assert scene.automatic_numerics(physics, given) is given


def test_default_numerics_reproduce_the_whirl():
    """A short MuJoCo run at the default numerics (N = 7, sigma = 0.8) started on Newton's whirl of the reduced model
    keeps its rate and its tip radius within 0.2% (measured: -0.03% and -0.08%; a rotational drag of 2 C dt about each
    link, the earlier twist model, was -0.32% in rate), and records the dt it chose."""
    whirl = settled_whirl(7, 0.8)
    physics = ea.Physics(scene="clamped-3d", n=7, sigma=0.8)
    traj = ea.simulate(physics, duration=60.0, engine="mujoco", theta0=angles_of(whirl.tangents))
    assert traj.info["automatic_numerics"]["dt"] == 0.0025
    tip = tangents_of(traj.theta, 7).sum(axis=1)
    late = traj.t >= 30.0
    turn = np.unwrap(np.arctan2(tip[:, 2], tip[:, 1]))
    rate = np.polyfit(traj.t[late], turn[late], 1)[0] / (2 * np.pi)
    assert rate == pytest.approx(whirl.rate, rel=2e-3)
    assert np.hypot(tip[late, 1], tip[late, 2]).mean() == pytest.approx(whirl.tip_radius, rel=2e-3)


def test_a_long_chain_runs_and_records_its_automatic_dt():
    """N = 30 at sigma = 0.8 (predicted 0.61% at the default dt) runs at dt = 0.002 through the front door and the
    pre-flight check (the kind's fastest_overdamped_rate), and summary.json's numerics say so."""
    physics = ea.Physics(scene="clamped-3d", n=30, sigma=0.8)
    traj = ea.simulate(physics, ea.Numerics(sample_dt=0.01), duration=0.2, engine="mujoco")
    assert traj.info["automatic_numerics"]["dt"] == pytest.approx(0.002)
    assert summary(traj, ea.Numerics(sample_dt=0.01), 0.2, sensitivity=False)["numerics"]["dt"] == pytest.approx(0.002)


@pytest.fixture(scope="module")
def tip_runs():
    """N = 3 loaded at its tip at sigma = 4 (onset 1.943, the planar tip-loaded chain's), 60 tau in each engine."""
    physics = ea.Physics(scene="clamped-3d", n=3, sigma=4.0, loaded="tip")
    return {engine: ea.simulate(physics, duration=60.0, engine=engine) for engine in ("reduced", "mujoco")}


def test_tip_loaded_engines_whirl_alike(tip_runs):
    """The follower force on the last particle only, in MuJoCo (its longitudinal actuator's control) and in the reduced
    model (Chain3D.load): the same whirl within 1%, and not the fully loaded chain's."""
    results = {engine: ea.measure(traj) for engine, traj in tip_runs.items()}
    reduced, mujoco = results["reduced"], results["mujoco"]
    assert reduced.extra["motion_state"] == mujoco.extra["motion_state"] == "whirl"
    assert mujoco.frequency == pytest.approx(reduced.frequency, rel=0.01)
    assert mujoco.amplitude == pytest.approx(reduced.amplitude, rel=0.01)
    assert mujoco.extra["whirl_rate"] == pytest.approx(reduced.extra["whirl_rate"], rel=0.01)
    assert mujoco.extra["tip_radius"] == pytest.approx(reduced.extra["tip_radius"], rel=0.01)
    everywhere = ea.simulate(ea.Physics(scene="clamped-3d", n=3, sigma=4.0), duration=60.0, engine="reduced")
    everywhere = ea.measure(everywhere)
    assert abs(everywhere.extra["whirl_rate"] / reduced.extra["whirl_rate"] - 1) > 0.1


def test_tip_loaded_onset_is_the_planar_tip_loaded_one():
    """A partial load's straight chain linearises as the planar chain with that load in each plane: the numerical
    Jacobian of the reduced 3D right-hand side with load (0, ..., 0, 1) has no coupling between the y and z blocks and
    each block's spectrum is the planar tip-loaded operator's; the scene's onset is that chain's."""
    from elastoactive.analysis import stability
    from elastoactive.reduced.chain3d import Chain3D, rhs

    n, sigma, step = 5, 1.3, 1e-6
    chain = Chain3D(n=n, sigma=sigma, load=(0.0,) * (n - 1) + (1.0,))
    operator = np.empty((2 * n, 2 * n))
    for block, axis in enumerate((1, 2)):
        for k in range(n):
            columns = []
            for sign in (1.0, -1.0):
                t = np.tile([1.0, 0.0, 0.0], (n, 1))
                t[k, axis] = sign * step
                t[k] /= np.linalg.norm(t[k])
                v = rhs(t, chain)
                columns.append(np.concatenate([v[:, 1], v[:, 2]]))
            operator[:, block * n + k] = (columns[0] - columns[1]) / (2 * step)
    assert np.abs(operator[:n, n:]).max() < 1e-6 and np.abs(operator[n:, :n]).max() < 1e-6
    mask = np.zeros(n, dtype=bool)
    mask[-1] = True
    planar = np.sort_complex(stability.eigenvalues(n, sigma, mask))
    for block in (operator[:n, :n], operator[n:, n:]):
        np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(block)), planar, atol=1e-6)
    scene = ea.scenes.get("clamped-3d")
    physics = ea.Physics(scene="clamped-3d", n=n, sigma=sigma, loaded="tip")
    planar_onset = ea.scenes.get("one-pinned").onset(ea.Physics(scene="one-pinned", n=n, loaded="tip"))
    assert scene.onset(physics).sigma_c == pytest.approx(planar_onset.sigma_c, rel=1e-12)
    leading = scene.leading_eigenvalue(physics, sigma)
    assert leading.real == pytest.approx(planar.real.max(), abs=1e-6)
    assert leading.real > 0
    assert abs(leading.imag) == pytest.approx(abs(planar[np.argmax(planar.real)].imag), abs=1e-6)


def test_loaded_is_refused_on_the_free_pivot():
    with pytest.raises(ea.ParameterError, match="loaded has no effect on scene rotating-pin-3d"):
        ea.Physics(scene="rotating-pin-3d", n=5, loaded="tip")


@pytest.mark.parametrize("n, drag_ratio, integrator", [(29, 1.0, "implicitfast"), (30, 1.0, "Euler"),
                                                       (40, 0.5, "Euler"), (40, 2.0, "implicitfast")])  # fmt: skip
def test_a_long_chain_steps_by_explicit_drag_with_a_matched_mass(n, drag_ratio, integrator):
    """From LONG_CHAIN particles on (drag ratio at most 1) the automatic numerics keep the accuracy dt and step it by
    Euler with the mass dt / LONG_CHAIN_DT_PER_MASS, the planar long chain's, which the pre-flight check passes."""
    from elastoactive.core.params import LONG_CHAIN_DT_PER_MASS
    from elastoactive.engines.timestep import check_timestep

    scene = ea.scenes.get("clamped-3d")
    physics = ea.Physics(scene="clamped-3d", n=n, sigma=0.8, drag_ratio=drag_ratio)
    chosen = scene.automatic_numerics(physics, ea.Numerics())
    assert chosen.integrator == integrator
    assert chosen.dt * scene.step_error(physics) <= ACCURACY_TARGET * (1 + 1e-9)
    if integrator == "Euler":
        assert chosen.mass_ratio == pytest.approx(chosen.dt / LONG_CHAIN_DT_PER_MASS)
        check_timestep(physics, ea.Numerics())
    else:
        assert chosen.mass_ratio == ea.Numerics().mass_ratio


@pytest.fixture(scope="module")
def fluid_runs():
    """N = 5 at sigma = 1.6 through the free-space fluid (bead_radius 0.2), 50 tau in each engine, and the same chain
    with the lab-frame drag."""
    physics = ea.Physics(scene="clamped-3d", n=5, sigma=1.6, bead_radius=0.2)
    runs = {engine: ea.simulate(physics, duration=50.0, engine=engine) for engine in ("reduced", "mujoco")}
    runs["local"] = ea.simulate(ea.Physics(scene="clamped-3d", n=5, sigma=1.6), duration=50.0, engine="reduced")
    return runs


def test_through_the_fluid_the_engines_whirl_alike(fluid_runs):
    """The chain's beads coupled by the RPY mobility in the reduced model (reduced.fluid) and in MuJoCo (mjcf.cilia's
    background flow): the same whirl within 1% (measured: frequency -0.05%, amplitude -0.2%), 34% faster than with
    the lab-frame drag."""
    results = {engine: ea.measure(traj) for engine, traj in fluid_runs.items()}
    reduced, mujoco, local = results["reduced"], results["mujoco"], results["local"]
    assert fluid_runs["reduced"].info["mobility"] == "rpy"
    assert reduced.extra["motion_state"] == mujoco.extra["motion_state"] == "whirl"
    for name in ("frequency", "amplitude"):
        assert getattr(mujoco, name) == pytest.approx(getattr(reduced, name), rel=0.01)
    for name in ("whirl_rate", "tip_radius"):
        assert mujoco.extra[name] == pytest.approx(reduced.extra[name], rel=0.01)
    assert reduced.frequency / local.frequency == pytest.approx(1.34, abs=0.02)


def test_through_the_fluid_the_onset_is_the_operators():
    """The onset with the term on is analysis.stability_fluid's for one chain at the origin in free space, the two
    planes together (RPY of collinear beads keeps them degenerate), below the lab-frame drag's and at a higher
    frequency; it tends to the lab-frame drag's as a / l -> 0."""
    from elastoactive.analysis.stability_fluid import leading_eigenvalue_fluid, onset_fluid
    from elastoactive.reduced.fluid import Beds

    scene = ea.scenes.get("clamped-3d")
    onset = scene.onset(ea.Physics(scene="clamped-3d", n=10, bead_radius=0.1))
    beds = Beds(10, 0.8, np.zeros((1, 3)), np.eye(3), mobility="rpy", radius=0.1)
    assert (onset.sigma_c, onset.omega_c) == pytest.approx(onset_fluid(beds), rel=1e-12)
    assert onset.sigma_c == pytest.approx(0.058921, abs=1e-6) and onset.omega_c == pytest.approx(0.014579, abs=1e-6)
    assert onset.kind.startswith("flutter (Hopf), in-plane and out-of-plane pairs together through the fluid")
    physics = ea.Physics(scene="clamped-3d", n=10, sigma=0.2, bead_radius=0.1)
    assert scene.leading_eigenvalue(physics, 0.2) == pytest.approx(leading_eigenvalue_fluid(beds, 0.2), rel=1e-12)
    local = scene.onset(ea.Physics(scene="clamped-3d", n=10))
    assert local.sigma_c == pytest.approx(0.060517, abs=1e-6)
    tiny = scene.onset(ea.Physics(scene="clamped-3d", n=10, bead_radius=1e-6))
    assert tiny.sigma_c == pytest.approx(local.sigma_c, rel=1e-4)


def test_the_fluid_takes_every_bead_loaded_and_no_planar_chain():
    with pytest.raises(ea.ParameterError, match="loaded = tip: with bead_radius"):
        ea.Physics(scene="clamped-3d", n=5, loaded="tip", bead_radius=0.1)
    with pytest.raises(ea.ParameterError, match="drag_ratio = 2 with bead_radius"):
        ea.Physics(scene="clamped-3d", n=5, drag_ratio=2.0, bead_radius=0.1)
    for planar in ("one-pinned", "two-pinned", "rotating-pin", "coupled-pair"):
        with pytest.raises(ea.ParameterError, match=f"bead_radius has no effect on scene {planar} "):
            ea.Physics(scene=planar, bead_radius=0.1)


def test_through_the_fluid_a_planar_start_stays_planar():
    """RPY is isotropic and a planar chain's forces lie in its plane: from zero elevations the chain beats in its
    plane in both engines (elevations exactly 0), the planar scene's chain through the fluid."""
    theta = 0.01 * np.sin(0.3 * np.arange(1, 6))
    physics = ea.Physics(scene="clamped-3d", n=5, sigma=0.8, bead_radius=0.1)
    for engine in ("reduced", "mujoco"):
        traj = ea.simulate(physics, duration=10.0, engine=engine, theta0=np.concatenate([theta, np.zeros(5)]))
        assert np.all(traj.theta[:, 5:] == 0.0) and np.abs(traj.theta[:, :5]).max() > 0.05

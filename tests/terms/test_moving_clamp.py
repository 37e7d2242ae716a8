"""The moving clamp (elastoactive.terms.moving_clamp): a fixed clamp is the plain run, a uniformly moving clamp is a
uniform force field (Galilean check), both engines agree, MuJoCo's clamp tracks its path, bad inputs are refused in
one line, and the beat locks to the clamp inside the tongue and not outside."""

import math

import numpy as np
import pytest
from conftest import refused

import elastoactive as ea
from elastoactive.analysis import locking
from elastoactive.core.errors import ParameterError
from elastoactive.core.parameters import Parameter
from elastoactive.terms import Term
from elastoactive.terms.base import ClampMotion
from elastoactive.terms.moving_clamp import ANGLE_LIMIT, clamp_path

N, SIGMA = 3, 1.28
"""N = 3 at 1.1 sigma_c: a beat at f tau = 0.0701 (a period of 14 tau)."""
F0 = 0.0701
DRIFT = np.array([0.03, -0.02])
"""The Galilean check's clamp velocity (l / tau)."""


class SteadyClamp(Term):
    """A clamp moving at a constant velocity (the test's toy term)."""

    name = "toy-steady-clamp"
    parameters = (Parameter("toy_clamp_on", False, "move the clamp steadily", kind=bool, quiet_default=True),)

    def clamp_motion(self, physics):
        return ClampMotion(
            displacement=lambda t: np.multiply.outer(np.asarray(t, dtype=float), DRIFT),
            velocity=lambda t: DRIFT,
            angle=lambda t: 0.0,
            translates=True,
        )


class Field(Term):
    """The same force on every particle (the test's toy term)."""

    name = "toy-clamp-field"
    parameters = (
        Parameter("toy_field_on", False, "a uniform force -DRIFT on every particle", kind=bool, quiet_default=True),
    )

    def node_forces(self, physics):
        return lambda positions: np.broadcast_to(-DRIFT, positions.shape)


@pytest.fixture
def toys():
    terms = [ea.terms.register(SteadyClamp()), ea.terms.register(Field())]
    yield terms
    for term in terms:
        ea.terms.unregister(term.name)


def test_a_uniformly_moving_clamp_is_a_uniform_force_field(toys):
    """Isotropic drag: a clamp moving at velocity u is the chain in the clamp's frame under the force -gamma u on every
    particle; the clamp's path is the trajectory's head."""
    moving = ea.simulate(ea.Physics(n=N, sigma=SIGMA, toy_clamp_on=True), duration=40, engine="reduced")
    field = ea.simulate(ea.Physics(n=N, sigma=SIGMA, toy_field_on=True), duration=40, engine="reduced")
    assert np.max(np.abs(moving.theta - field.theta)) < 1e-9
    assert np.allclose(moving.head, np.outer(moving.t, DRIFT))
    assert field.head is None


def test_anisotropic_drag_makes_the_moving_clamp_differ_from_the_field(toys):
    """With drag_ratio != 1 the drag of the clamp's motion depends on each pendulum's direction: not a uniform field."""
    moving = ea.simulate(ea.Physics(n=N, sigma=SIGMA, drag_ratio=0.5, toy_clamp_on=True), duration=40, engine="reduced")
    field = ea.simulate(ea.Physics(n=N, sigma=SIGMA, drag_ratio=0.5, toy_field_on=True), duration=40, engine="reduced")
    assert np.max(np.abs(moving.theta - field.theta)) > 1e-3


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
def test_zero_amplitude_is_the_plain_run_bit_for_bit(engine):
    plain = ea.simulate(ea.Physics(n=N, sigma=SIGMA), duration=20, engine=engine)
    still = ea.simulate(ea.Physics(n=N, sigma=SIGMA, clamp_amplitude=0.0), duration=20, engine=engine)
    assert np.array_equal(plain.theta, still.theta) and still.head is None
    assert "moving-clamp" not in [t.name for t in ea.Physics(n=N, clamp_amplitude=0.0).active_terms()]


def test_parameters_act_only_with_an_amplitude():
    with pytest.raises(ParameterError, match="clamp_frequency has no effect without clamp_amplitude"):
        ea.Physics(n=N, clamp_frequency=0.05)
    with pytest.raises(ParameterError, match="clamp_motion has no effect without clamp_amplitude"):
        ea.Physics(n=N, clamp_motion="angle")
    with pytest.raises(ParameterError, match="clamp_motion must be one of transverse, longitudinal, angle"):
        ea.Physics(n=N, clamp_amplitude=0.1, clamp_motion="sideways")
    with pytest.raises(ParameterError, match="clamp_amplitude"):
        ea.Physics(n=N, clamp_amplitude=-0.1)


def test_a_rotating_clamp_needs_its_frequency_alone():
    physics = ea.Physics(n=N, clamp_motion="rotating", clamp_frequency=0.05)
    assert "moving-clamp" in [t.name for t in physics.active_terms()]
    assert physics.given()["clamp_frequency"] == 0.05 and "clamp_amplitude" not in repr(physics)
    with pytest.raises(ParameterError, match="clamp_amplitude has no effect with clamp_motion rotating"):
        ea.Physics(n=N, clamp_motion="rotating", clamp_amplitude=0.1)
    with pytest.raises(ParameterError, match="rotating-pin has no clamp"):
        ea.Physics(scene="rotating-pin", n=N, clamp_motion="rotating")
    assert physics.replace(clamp_motion="angle", clamp_amplitude=0.2).clamp_frequency == 0.05
    assert "clamp_frequency" not in physics.replace(clamp_motion="transverse").given()  # off again: dropped


def test_a_rotating_clamp_drags_the_chain_round_alike_in_both_engines():
    """N = 3 at 1.1 sigma_c, the clamp turning at f tau = 0.05: the chain turns with it as a steady bent shape (the
    beat is gone), its tip 0.819 rad behind the clamp in both engines."""
    physics = ea.Physics(n=N, sigma=SIGMA, clamp_motion="rotating", clamp_frequency=0.05)
    red, muj = (ea.simulate(physics, duration=150, engine=e) for e in ("reduced", "mujoco"))
    assert red.head is None and muj.head is None  # the clamp point stays put
    r, m = ea.measure(red), ea.measure(muj)
    assert r.extra["clamp_lag"] == pytest.approx(0.8188, abs=2e-3)
    assert m.extra["clamp_lag"] == pytest.approx(r.extra["clamp_lag"], rel=0.01)
    late = red.t > 75
    rate = np.polyfit(red.t[late], red.theta[late, 0], 1)[0]
    assert rate == pytest.approx(2 * math.pi * 0.05, rel=1e-3)  # dragged round at the clamp's rate
    assert max(r.amplitude, m.amplitude) < 1e-3  # no beat left


def test_an_angle_amplitude_that_turns_the_chain_into_the_wall_is_refused():
    ea.Physics(n=N, clamp_amplitude=ANGLE_LIMIT - 1e-3, clamp_motion="angle")
    with pytest.raises(ParameterError, match="must be < pi/2"):
        ea.Physics(n=N, clamp_amplitude=ANGLE_LIMIT, clamp_motion="angle")
    ea.Physics(n=N, clamp_amplitude=2.0, clamp_motion="transverse")  # a point's amplitude is a length: no limit


@pytest.mark.parametrize(
    "scene, values, words",
    [
        ("rotating-pin", {}, ("rotating-pin", "has no clamp")),
        ("two-pinned", {}, ("two-pinned", "pins its chain's far end")),
        ("coupled-pair", {}, ("coupled-pair", "coupling spring")),
    ],
)
@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
def test_scenes_without_a_movable_clamp_are_refused_in_one_line(capsys, no_simulation, scene, values, words, engine):
    refused(capsys, ["run", scene, "--clamp-amplitude", "0.1", "--engine", engine, "--duration", "50"], *words)


def test_the_coupled_pairs_clamp_angle_moves_in_both_engines():
    physics = ea.Physics(
        scene="coupled-pair", n=2, sigma=3.3, clamp_amplitude=0.2, clamp_motion="angle", clamp_frequency=0.15
    )
    red = ea.simulate(physics, duration=30, engine="reduced")
    muj = ea.simulate(physics, duration=30)
    assert np.max(np.abs(red.theta - muj.theta)) < 0.01


def test_both_engines_agree_and_mujocos_clamp_tracks_its_path():
    physics = ea.Physics(n=N, sigma=SIGMA, clamp_amplitude=0.1, clamp_frequency=0.07)
    red, muj = (ea.simulate(physics, duration=150, engine=e) for e in ("reduced", "mujoco"))
    path = clamp_path(0.1, 0.07, "transverse").displacement(muj.t)
    assert np.max(np.abs(muj.head - path)) < 1e-4 * 0.1 * 3  # the servo: 1e-5 l at the default dt
    assert np.allclose(red.head, path)
    r, m = ea.measure(red), ea.measure(muj)
    assert abs(m.amplitude / r.amplitude - 1) < 0.01 and abs(m.frequency / r.frequency - 1) < 0.01


@pytest.mark.slow
@pytest.mark.parametrize("motion, amplitude", [("longitudinal", 0.1), ("angle", 0.2)])
def test_both_engines_agree_for_the_other_motions(motion, amplitude):
    physics = ea.Physics(n=N, sigma=SIGMA, clamp_amplitude=amplitude, clamp_frequency=0.07, clamp_motion=motion)
    r, m = (ea.measure(ea.simulate(physics, duration=300, engine=e)) for e in ("reduced", "mujoco"))
    assert abs(m.amplitude / r.amplitude - 1) < 0.01 and abs(m.frequency / r.frequency - 1) < 0.01


def test_validate_offers_the_clamp_cases():
    cases = ea.terms.get("moving-clamp").validation_cases(ea.Physics)
    assert {c.physics.clamp_motion for c in cases} == {"transverse", "angle", "rotating"}


@pytest.mark.parametrize("detuning, locked", [(0.0, True), (0.3, False)])
def test_the_beat_locks_inside_the_tongue_and_not_outside(detuning, locked):
    """Amplitude 0.1 l: Adler's half width is 8.5% of f_0 (the clamp_tongue study); MuJoCo's fast preset."""
    drive = F0 * (1 + detuning)
    physics = ea.Physics(n=N, sigma=SIGMA, clamp_amplitude=0.1, clamp_frequency=drive)
    traj = ea.simulate(physics, ea.Numerics.preset("fast"), duration=450)
    lock = locking.drive_locking(traj.t, traj.theta, drive, transient=150)
    res = ea.measure(traj, transient=150)
    assert res.extra["clamp_frequency_ratio"] == pytest.approx(lock.frequency_ratio)
    if locked:
        assert abs(lock.frequency_ratio - 1) < 1e-3 and lock.phase_spread < 0.2
    else:
        assert abs(lock.frequency_ratio - 1) > 0.05 and lock.phase_spread > 1.0


def test_phase_spread_and_coupling_amplitude():
    assert locking.phase_spread(np.full(10, 0.3)) == pytest.approx(0.0, abs=1e-7)
    assert locking.phase_spread(np.linspace(0, 20 * math.pi, 1000)) > 2
    phases = np.linspace(0, 2 * math.pi, 12, endpoint=False)
    assert locking.coupling_amplitude(phases, 0.4 + 2 * np.cos(phases + 0.3)) == pytest.approx(1.0)
    assert locking.adler_half_width(0.1, 0.5, 1.0) == pytest.approx(0.05)


@pytest.fixture(scope="module")
def tongue(tiny_studies):
    return tiny_studies("clamp_tongue")


def test_clamp_tongue_study_tiny(tongue, round_trip):
    """The tiny study: the phase response is nearly one harmonic, Adler's edges lie between the locked and the unlocked
    detunings, MuJoCo's clamp stays on its path; it saves, reads back, draws and writes its claims."""
    s = tongue[1]["clamp_tongue"].summary
    assert s.coupling == pytest.approx(0.85, rel=0.03) and s.harmonic_fraction > 0.98
    (row,) = s.rows
    assert row.unlocked_low < -row.adler < row.locked_low and row.locked_high < row.adler < row.unlocked_high
    assert s.tracking_error < 1e-4
    assert "clamp" in round_trip(tongue, "clamp_tongue")
    from elastoactive.studies import registry  # the studies load both engines: only this test pays

    rows = registry.get("clamp_tongue").claims_fn(tongue[1]["clamp_tongue"], {})
    assert [c.agree for c in rows] == ["yes", "yes"]


def test_a_saved_run_keeps_the_clamps_path(tmp_path):
    """run --out writes the clamp's position as the trajectory's head, and reading the run back keeps it."""
    from elastoactive.cli import main  # the CLI loads only in the tests that use it
    from elastoactive.records import load_trajectory

    out = tmp_path / "clamp"
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--n",
                "3",
                "--sigma",
                "1.28",
                "--clamp-amplitude",
                "0.1",
                "--clamp-frequency",
                "0.07",
                "--engine",
                "reduced",
                "--duration",
                "30",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    back = load_trajectory(out)
    assert np.allclose(back.head, clamp_path(0.1, 0.07, "transverse").displacement(back.t))


def test_a_drive_faster_than_the_step_is_refused_with_a_passing_setting(capsys, no_simulation):
    """A term's own rate (Term.rate: the clamp's or the tip drive's 2 pi f) is resolved by MuJoCo's pre-flight check
    like the chain's: f = 100 at dt = 0.0025 (4 steps a period) had diverged with a misleading cause; now one line
    names the term, a dt and the frequency that pass."""
    from elastoactive.core.params import Numerics
    from elastoactive.engines import timestep as diagnose

    for option in ("--clamp-amplitude", "--drive-amplitude"):
        name = option[2:].split("-")[0]
        line = refused(
            capsys,
            ["run", "one-pinned", "--n", "3", option, "0.1", f"--{name}-frequency", "100", "--duration", "5"],
            f"{name}_frequency <=",
            "does not resolve",
        )
        dt = float(line.split("--dt ")[1].split()[0])
        diagnose.check_timestep(
            ea.Physics(n=3, **{f"{name}_amplitude": 0.1, f"{name}_frequency": 100.0}), Numerics(dt=dt)
        )


def test_a_fast_clamp_starts_at_its_paths_velocity():
    """The clamp starts moving at u(0) = A omega with the chain at rest in its frame (as the reduced model starts):
    a large clamp speed no longer puts the whole jump B u(0) on the tiny masses (MuJoCo had diverged at t = 0 from
    A f ~ 0.2 l/tau on); the engines agree on the beat it drives."""
    physics = ea.Physics(n=3, sigma=1.28, clamp_amplitude=3.0, clamp_frequency=0.07)
    runs = {
        engine: ea.measure(ea.simulate(physics, engine=engine, duration=60.0), transient=30.0)
        for engine in ("mujoco", "reduced")
    }
    assert runs["mujoco"].amplitude == pytest.approx(runs["reduced"].amplitude, rel=0.01)

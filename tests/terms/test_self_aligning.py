"""Self-aligning active units (elastoactive.terms.self_aligning): exact limits, engine agreement, refusals."""

import math

import numpy as np
import pytest
from conftest import refused

import elastoactive as ea
from elastoactive.engines import polarity
from elastoactive.engines.reduced import rhs as follower_rhs
from elastoactive.engines.reduced import system_of
from elastoactive.records import load_trajectory


def unit(n=1, sigma=0.9, la=2.0, **kw):
    return ea.Physics(n=n, sigma=sigma, active="self-aligning", alignment_length=la, **kw)


def g(alpha, la):
    """G(alpha) = integral of d alpha / (cos alpha / l_a - 1) from 0 (l_a > 1: no zero of the denominator)."""
    from scipy.integrate import quad

    return quad(lambda a: 1.0 / (math.cos(a) / la - 1.0), 0.0, alpha, epsabs=1e-13, epsrel=1e-13)[0]


@pytest.mark.parametrize("engine, tol", [("reduced", 1e-7), ("mujoco", 2e-3)])
def test_single_unit_follows_its_invariant(engine, tol):
    """N = 1: theta' = -theta + sigma sin(alpha), alpha = psi - theta obeys alpha' = theta' (cos alpha / l_a - 1), so
    theta - G(alpha) is constant (whatever sigma), and the motion stops on the line theta = sigma sin(alpha). At
    sigma (1 + 1 / l_a) = 1.35 > 1 the straight state is unstable: the particle swings out to that line."""
    physics = unit()
    traj = ea.simulate(physics, duration=40.0, engine=engine)
    theta, alpha = traj.theta[:, 0], traj.polarity[:, 0] - traj.theta[:, 0]
    invariant = np.array([th - g(a, 2.0) for th, a in zip(theta[::40], alpha[::40])])
    assert abs(theta[-1]) > 0.3  # it moved
    assert np.ptp(invariant) < tol
    assert abs(theta[-1] - 0.9 * math.sin(alpha[-1])) < 10 * tol


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
def test_a_unit_at_rest_keeps_its_polarity(engine):
    """A particle that does not move (N = 1 straight, the unit pushing along the link: an equilibrium) keeps psi."""
    traj = ea.simulate(unit(), duration=5.0, engine=engine, theta0=np.zeros(1))
    assert np.ptp(traj.polarity) < 1e-9 and abs(abs(traj.polarity[0, 0]) - math.pi) < 1e-12
    assert np.abs(traj.theta).max() < 1e-9


def test_at_start_the_two_laws_exert_the_same_force():
    """Polarities along the follower direction: the angles' rates equal the follower chain's, bit for bit up to
    rounding, on a bent chain with some particles unloaded."""
    theta = 0.3 * np.sin(np.arange(7.0))
    physics = unit(n=7, sigma=0.8, loaded="2,5,7")
    mask = physics.load_mask()
    from elastoactive.terms.self_aligning import initial_polarity

    y = np.concatenate([theta, initial_polarity(theta, mask)])
    rates = polarity.rhs(physics, system_of(physics), beta=1.0)(0.0, y)[:7]
    follower = follower_rhs(physics.replace(active="follower"))(0.0, theta)
    assert np.allclose(rates, follower, rtol=0, atol=1e-13)


def test_engines_agree_on_a_winding_chain():
    """One-pinned N = 7, sigma = 0.8, l_a = 2: the chain buckles, curls and winds; both engines' angles and
    polarities stay within 0.03 rad over 40 tau (each turns through ~6 rad; measured 0.019 rad, MuJoCo's small mass
    and dt)."""
    physics = unit(n=7, sigma=0.8, la=2.0)
    a = ea.simulate(physics, duration=40.0, engine="mujoco")
    b = ea.simulate(physics, duration=40.0, engine="reduced")
    assert np.abs(b.theta[-1]).max() > 2.0
    assert np.abs(a.theta - b.theta).max() < 3e-2
    assert np.abs(a.polarity - b.polarity).max() < 3e-2


def test_polarity_is_saved_with_the_run(tmp_path):
    from elastoactive.cli import main

    assert (
        main(
            [
                "run",
                "one-pinned",
                "--n",
                "3",
                "--active",
                "self-aligning",
                "--alignment-length",
                "2",
                "--duration",
                "10",
                "--quiet",
                "--out",
                str(tmp_path / "run"),
            ]
        )
        == 0
    )
    traj = load_trajectory(tmp_path / "run")
    assert traj.polarity.shape == (traj.t.size, 3) and np.all(np.isfinite(traj.polarity))


@pytest.mark.parametrize("value", [0.0, -1.0])
def test_alignment_length_must_be_positive(value):
    with pytest.raises(ea.ParameterError, match="alignment_length"):
        unit(la=value)


def test_alignment_length_needs_the_self_aligning_law(capsys, no_simulation):
    with pytest.raises(ea.ParameterError, match="no effect without active = self-aligning"):
        ea.Physics(alignment_length=2.0)
    refused(capsys, ["run", "one-pinned", "--alignment-length", "2"], "alignment_length", "active = self-aligning")
    with pytest.raises(ea.ParameterError, match="active must be one of follower, self-aligning"):
        ea.Physics(active="sideways")


def test_follower_law_is_quiet_and_unchanged():
    """At its default the term is off: the summary does not name it and the follower run has no polarity."""
    physics = ea.Physics(n=3)
    assert "active" not in physics.relevant() and "alignment_length" not in physics.relevant()
    assert ea.simulate(physics, duration=2.0).polarity is None
    assert unit().relevant()["alignment_length"] == 2.0


def test_reduced_engine_refuses_what_it_does_not_cover():
    with pytest.raises(ea.ParameterError, match="noise"):
        ea.simulate(unit(n=3, noise=0.1), duration=1.0, engine="reduced", check=False)


@pytest.mark.parametrize(
    "scene, extra", [("one-pinned", ["--active", "self-aligning"]), ("trapped-unit", []), ("lattice", ["--rings", "1"])]
)
def test_stiff_units_are_refused_at_once_naming_the_alignment_length(capsys, scene, extra):
    """The units turn at up to sigma / l_a: a tiny alignment length makes them too stiff for the reduced engine's
    explicit solver (it had sat for minutes) and for MuJoCo's explicit step of the polarity (it had returned a wrong
    number): each engine refuses in one line naming alignment_length, before it integrates anything."""
    import time

    start = time.perf_counter()
    for engine in ("reduced", "mujoco"):
        refused(
            capsys,
            ["run", scene, *extra, "--alignment-length", "1e-9", "--duration", "5", "--engine", engine, "--quiet"],
            "alignment_length",
        )
    assert time.perf_counter() - start < 20.0


def test_the_units_turning_sets_mujocos_timestep(capsys, no_simulation):
    """A chain's pre-flight check resolves the units' turning (dt x sigma / l_a <= RESOLUTION) and its suggestion
    passes every check."""
    from elastoactive.core.params import Numerics
    from elastoactive.engines import timestep as diagnose

    line = refused(
        capsys,
        ["run", "one-pinned", "--active", "self-aligning", "--alignment-length", "0.005", "--duration", "5"],
        "self-aligning term",
        "alignment_length >=",
    )
    dt = float(line.split("--dt ")[1].split()[0])
    physics = ea.Physics(active="self-aligning", alignment_length=0.005)
    diagnose.check_timestep(physics, Numerics(dt=dt))
    with pytest.raises(ea.ParameterError, match="self-aligning term"):
        diagnose.check_timestep(physics, Numerics())
    diagnose.check_timestep(ea.Physics(active="self-aligning", alignment_length=0.5), Numerics())

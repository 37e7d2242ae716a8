"""The MuJoCo scenes reproduce the reduced model's physics (numbers, not pictures)."""

import numpy as np
import pytest

from elastoactive.analysis import observables as obs
from elastoactive.checks.validate import compare
from elastoactive.core.params import Numerics, Physics
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.engines.reduced import simulate_reduced

PAPER_CASES = [
    (Physics(scene="one-pinned", n=7, sigma=0.8), 150.0),
    (Physics(scene="two-pinned", n=7, sigma=0.8, delta=0.1), 150.0),
    (Physics(scene="rotating-pin", n=7, sigma=0.8), 100.0),
    (Physics(scene="coupled-pair", n=7, sigma=0.8, rho=4 / 3, kappa=0.5), 150.0),
    (Physics(scene="coupled-pair", n=7, sigma=0.8, rho=4 / 3, kappa=2.0), 150.0),
]
OTHER_CASES = [
    (Physics(scene="one-pinned", n=2, sigma=3.5, drag_ratio=3.0), 150.0),  # anisotropic drag
    (Physics(scene="one-pinned", n=12, sigma=0.1), 150.0),
    (Physics(scene="two-pinned", n=9, sigma=1.0, delta=0.3), 150.0),
]


@pytest.mark.parametrize(
    "physics,duration,angle_tolerance",
    [(p, d, 0.01) for p, d in PAPER_CASES] + [(p, d, 0.02) for p, d in OTHER_CASES],
    ids=lambda c: getattr(c, "scene", ""),
)
def test_mujoco_matches_reduced_model(physics, duration, angle_tolerance):
    """Within 1% on the paper's cases (angles over the transient: 2% on the others)."""
    c = compare(physics, Numerics(), duration)
    for key in ("amplitude", "frequency", "rotation_rate", "snap_amplitude"):
        if key in c.errors:
            assert c.errors[key] < 0.01, (key, c.errors)
    assert c.errors["angle"] < angle_tolerance, c.errors
    if physics.scene == "two-pinned":
        assert c.constraint_violation < 2e-3
    if physics.scene == "coupled-pair":
        assert c.errors["frequency_mismatch_abs"] < 1e-3


def theta_curvature(traj):
    return obs.curvature(traj.chain(0))


def envelope(t, x, t0, t1):
    w = (t >= t0) & (t <= t1)
    return np.abs(x[w]).max()


@pytest.mark.parametrize("sigma,grows", [(2.9, False), (3.1, True)])
def test_n2_hopf_is_bracketed_at_sigma_3(sigma, grows):
    """Below sigma = 3 a kick decays, above it grows (linear rate sigma - 3, in 1/tau)."""
    traj = simulate_mujoco(Physics(n=2, sigma=sigma), Numerics(perturbation=1e-4), 40.0)  # stays linear
    x = theta_curvature(traj)
    early, late = envelope(traj.t, x, 5, 15), envelope(traj.t, x, 30, 40)
    rate = np.log(late / early) / 25.0
    assert (rate > 0) == grows
    assert rate == pytest.approx(sigma - 3.0, abs=0.02)


def test_n2_onset_angular_frequency_is_one_over_tau():
    traj = simulate_mujoco(Physics(n=2, sigma=3.02), Numerics(perturbation=0.01), 80.0)
    omega = 2 * np.pi * obs.frequency(traj.t, theta_curvature(traj), transient=10.0)
    assert omega == pytest.approx(np.sqrt(1 - 0.02**2), rel=5e-3)


def test_straight_chain_stays_straight_below_onset():
    """N = 7 below sigma_c = 0.1575: the pushed chain relaxes back to straight."""
    traj = simulate_mujoco(Physics(n=7, sigma=0.1), Numerics(perturbation=0.05), 200.0)
    start, end = np.abs(traj.theta[0]).max(), np.abs(traj.theta[-1]).max()
    assert end < 0.2 * start


def test_two_pinned_does_not_oscillate_uncompressed():
    """At delta = 0 the exact pin allows no motion. MuJoCo's pin is soft: its violation v lets
    the chain shorten by v, i.e. bend by theta_rms ~ sqrt(2 v / N), like a compression v / N, and
    any compression snaps. So the residual flutter must stay within that compliance bound and
    far below the snapping of a real compression."""
    n = 7
    traj = simulate_mujoco(Physics(scene="two-pinned", n=n, sigma=0.8, delta=0.0), Numerics(), 150.0)
    flutter = obs.snap_amplitude(traj.theta, traj.t)
    assert flutter < 2 * np.sqrt(2 * traj.info["constraint_violation"] / n)
    snapping = simulate_mujoco(Physics(scene="two-pinned", n=n, sigma=0.8, delta=0.1), Numerics(), 150.0)
    assert obs.snap_amplitude(snapping.theta, snapping.t) > 0.1
    assert flutter < 0.01 * obs.snap_amplitude(snapping.theta, snapping.t)
    reduced = simulate_reduced(Physics(scene="two-pinned", n=n, sigma=0.8, delta=0.0), Numerics(), 150.0)
    assert obs.snap_amplitude(reduced.theta, reduced.t) < 1e-6


def test_rotating_pin_turns_at_constant_rate():
    traj = simulate_mujoco(Physics(scene="rotating-pin", n=7, sigma=0.8), Numerics(), 120.0)
    first = obs.rotation_rate(traj.t[traj.t <= 90], traj.theta[traj.t <= 90], transient=60.0)
    second = obs.rotation_rate(traj.t, traj.theta, transient=90.0)
    assert abs(first) > 0.1
    assert second == pytest.approx(first, rel=1e-3)
    bend = obs.curvature(traj.theta)[traj.t > 60]
    assert bend.std() < 1e-3 * abs(bend.mean())  # steady shape


def test_noise_is_seeded_and_reproducible():
    physics = Physics(n=2, sigma=3.5, noise=0.2)
    a = simulate_mujoco(physics, Numerics(seed=4), 20.0)
    b = simulate_mujoco(physics, Numerics(seed=4), 20.0)
    c = simulate_mujoco(physics, Numerics(seed=5), 20.0)
    np.testing.assert_array_equal(a.theta, b.theta)
    assert np.abs(a.theta - c.theta).max() > 1e-3


def test_noise_same_realisation_in_both_engines():
    """Both engines draw the same counter-based noise: one realisation, two integrators."""
    physics, numerics = Physics(n=3, sigma=1.5, noise=0.1), Numerics(dt=0.001, sample_dt=0.05, seed=9)
    mj = simulate_mujoco(physics, numerics, 10.0)
    red = simulate_reduced(physics, numerics, 10.0)
    clean = simulate_reduced(Physics(n=3, sigma=1.5), numerics, 10.0)
    gap = np.abs(mj.theta - red.theta).max()
    assert gap < 0.1 * np.abs(red.theta - clean.theta).max()


def test_error_falls_as_dt_and_mass_shrink():
    """First order in dt (each halving roughly halves the error); inertia error falls with m."""
    from elastoactive.checks.validate import REFERENCE_TOLERANCE

    physics, duration = Physics(n=7, sigma=0.8), 80.0
    reference = simulate_reduced(physics, Numerics(sample_dt=0.04), duration, **REFERENCE_TOLERANCE)

    def error(dt, mass):
        c = compare(physics, Numerics(dt=dt, mass_ratio=mass, sample_dt=0.04), duration, reference=reference)
        return c.errors["amplitude"], c.errors["frequency"]

    by_dt = [error(dt, 1e-5) for dt in (0.01, 0.005, 0.0025)]
    for coarse, fine in zip(by_dt, by_dt[1:]):
        for e_coarse, e_fine in zip(coarse, fine):
            assert 1.6 < e_coarse / e_fine < 2.4
    by_mass = [error(0.00125, m)[1] for m in (1e-2, 1e-3, 1e-4)]
    assert by_mass[0] > by_mass[1] > by_mass[2]

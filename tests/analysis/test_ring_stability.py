"""The pinned ring's rigid rotation and its linear stability (analysis/ring_stability.py, Ring.onset), against the
reduced engine's runs: the rotation is an exact zero mode, the rate is the runs' rotation_rate, a small push of the
turning shape grows or decays at the leading eigenvalue's rate and frequency, and the window where no rigid rotation
is stable (N = 24: from the Hopf onset to the fold of the rigid rotation the ring reaches at sigma = 8) is where the
runs beat."""

import math

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.analysis import ring_stability as rs
from elastoactive.cli import main
from elastoactive.core.errors import ParameterError
from elastoactive.reduced import project_on_pins
from elastoactive.scenes import ring

LONG = 24
SIGMA_H = 0.4377  # N = 24: the Hopf onset of the rigid rotation followed from the polygon
FOLD = 1.6873  # N = 24: the fold below which the rigid rotation reached at sigma = 8 ceases to exist


def _run(n, sigma, duration, theta0=None, sample_dt=0.5):
    return ea.simulate(
        ea.Physics(scene="ring", n=n, sigma=sigma),
        ea.Numerics(sample_dt=sample_dt),
        engine="reduced",
        duration=duration,
        theta0=theta0,
    )


def _theta_spread(traj, after):
    """Peak-to-peak of Theta = theta_N - theta_1 after the time `after` (0 for a rigid rotation)."""
    big = traj.theta[:, -1] - traj.theta[:, 0]
    return float(np.ptp(big[traj.t > after]))


def test_the_rotation_is_an_exact_zero_mode_and_the_shape_modes_decay_at_n7():
    at = rs.linearise(7, 0.8)
    J = rs.ring_jacobian(7, 0.8, at.theta)
    assert np.max(np.abs(J @ np.ones(7))) < 1e-10  # shifting every angle changes no rate
    assert at.zero < 1e-8  # ... so the tangent space's spectrum holds the rotation's 0
    tangent = rs.tangent_spectrum(7, 0.8, at.theta)
    assert tangent.size == 5 and at.spectrum.size == 4
    rest = np.delete(tangent, np.argmin(np.abs(tangent)))
    assert np.allclose(np.sort_complex(rest), np.sort_complex(at.spectrum), atol=1e-10)
    assert at.leading.real < 0
    G = np.vstack([-np.sin(at.theta), np.cos(at.theta)])
    assert np.max(np.abs(G @ J @ rs.tangent_basis(at.theta))) < 1e-10  # the tangent space is invariant under J


def test_the_analytic_jacobian_is_the_limit_of_central_differences():
    at = rs.linearise(LONG, 0.5)
    J = rs.ring_jacobian(LONG, 0.5, at.theta)
    errors = [np.max(np.abs(rs.central_jacobian(LONG, 0.5, at.theta, h) - J)) for h in (1e-3, 1e-4, 1e-5)]
    assert errors[1] < 0.02 * errors[0] and errors[2] < 1e-7  # O(h^2) until round-off
    lam = rs.shape_spectrum(LONG, 0.5, at.theta, jacobian_matrix=rs.central_jacobian(LONG, 0.5, at.theta, 1e-5))
    assert abs(lam[0] - at.spectrum[0]) < 1e-7


def test_the_rate_is_the_torque_balance_and_the_runs_rotation_rate():
    assert rs.rotation_rate_per_sigma(7) == pytest.approx(-math.sin(2 * math.pi / 7) / 2, rel=1e-12)
    assert rs.linearise(7, 1e-4).omega / 1e-4 == pytest.approx(rs.rotation_rate_per_sigma(7), rel=1e-6)
    assert rs.linearise(7, 0.2).omega / 0.2 == pytest.approx(-0.39174, abs=1e-5)  # the rings study's rate / sigma
    at = rs.linearise(7, 0.8)
    run = ea.measure(_run(7, 0.8, 100.0))
    assert run.amplitude < 1e-4 and run.rotation_rate == pytest.approx(at.omega, rel=1e-5)


@pytest.mark.parametrize("sigma", [0.5, 0.4])
def test_a_push_grows_or_decays_at_the_leading_eigenvalue(sigma):
    """N = 24 on either side of the onset: the push along the leading mode, read through the left eigenvector (the
    rotation and the other modes drop out), grows (0.5) or decays (0.4) at Re lambda and turns at Im lambda."""
    at = rs.linearise(LONG, sigma)
    W = rs.shape_basis(at.theta)
    Q = W.T @ rs.ring_jacobian(LONG, sigma, at.theta) @ W
    lam, right = np.linalg.eig(Q)
    k = np.argmin(np.abs(lam - at.leading))
    left_lam, left = np.linalg.eig(Q.T)
    mode = W @ right[:, k].real
    traj = _run(LONG, sigma, 80.0, project_on_pins(at.theta + 1e-5 * mode / np.linalg.norm(mode), 1.0))
    z = (traj.theta - at.theta) @ W @ left[:, np.argmin(np.abs(left_lam - lam[k]))]
    keep = traj.t > 5
    rate = np.polyfit(traj.t[keep], np.log(np.abs(z[keep])), 1)[0]
    turn = abs(np.polyfit(traj.t[keep], np.unwrap(np.angle(z[keep])), 1)[0])
    assert (rate > 0) == (sigma > SIGMA_H) == (at.leading.real > 0)
    assert rate == pytest.approx(at.leading.real, rel=0.01) and turn == pytest.approx(at.leading.imag, rel=0.01)
    assert ea.measure(traj).rotation_rate == pytest.approx(at.omega, rel=1e-4)


def test_the_onset_is_a_hopf_bifurcation_from_n15_on():
    sigma_c, omega_c, branch = rs.onset(LONG)
    assert sigma_c == pytest.approx(SIGMA_H, abs=1e-4) and omega_c == pytest.approx(0.1063, abs=1e-4)
    assert branch.crossings[0].kind == "Hopf" and branch.unstable_arcs() == [(sigma_c, rs.SCAN_MAX)]
    assert math.isinf(rs.onset(14)[0]) and rs.onset(15)[0] == pytest.approx(2.0477, abs=1e-3)
    onset = ring.SCENE.onset(ea.Physics(scene="ring", n=LONG))
    assert (onset.sigma_c, onset.omega_c) == (sigma_c, omega_c) and onset.kind.startswith("Hopf")
    lam = ring.SCENE.leading_eigenvalue(ea.Physics(scene="ring", n=LONG), 0.5)
    assert lam == pytest.approx(rs.linearise(LONG, 0.5).leading, abs=1e-12)


def test_the_rigid_rotation_at_large_sigma_is_another_branch_and_bounds_the_window():
    """N = 24 turns rigidly at sigma = 8 (the rings study), but not on the branch from the polygon (unstable there):
    on one that folds at sigma = 1.687. Started on it, the ring stays rigid at sigma = 2 (where the pushed polygon
    beats) and beats just below the fold."""
    settled = _run(LONG, 8.0, 100.0)
    assert _theta_spread(settled, 50.0) < 1e-4
    assert rs.linearise(LONG, 8.0).leading.real > 0  # the polygon's branch is unstable at 8
    sigma, how, branch = rs.restabilisation(LONG, settled.theta[-1], 8.0)
    assert how == "fold" and sigma == pytest.approx(FOLD, abs=1e-3)
    assert ea.measure(settled).rotation_rate == pytest.approx(branch.omega[0], rel=1e-4)
    above = rs.linearise(LONG, 2.0, branch.theta[np.argmin(np.abs(branch.sigma - 2.0))])
    assert above.leading.real < 0
    kick = 1e-3 * np.sin(np.arange(LONG))
    assert _theta_spread(_run(LONG, 2.0, 100.0, project_on_pins(above.theta + kick, 1.0), 0.1), 60.0) < 1e-4
    fold_shape = branch.theta[np.argmin(branch.sigma)]
    assert _theta_spread(_run(LONG, 1.6, 100.0, fold_shape, 0.1), 50.0) > 1.0


def test_the_command_prints_the_onset_and_refuses_the_free_ring(capsys):
    assert main(["stability", "ring", "--n", "24", "--sigma", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "onset: Hopf" in out and "sigma_c = 0.43765" in out and "growth rate +0.02859" in out
    assert main(["stability", "ring", "--n", "7"]) == 0
    assert "stays linearly stable up to sigma = 100" in capsys.readouterr().out
    assert main(["stability", "ring", "--pin", "free"]) == 2
    assert "free ring" in capsys.readouterr().err
    with pytest.raises(ParameterError, match="N - 3 = 0 shape modes"):
        ring.SCENE.onset(ea.Physics(scene="ring", n=3))

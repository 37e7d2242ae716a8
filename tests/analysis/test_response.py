"""The tip's linear response (analysis.response), the tip-drive term and its time-dependent node forces, and the
response study."""

import cmath
import math

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.analysis import response as rs
from elastoactive.analysis import stability as stab
from elastoactive.core.errors import ParameterError
from elastoactive.engines import node_forces


def test_transfer_function_of_n2_in_closed_form():
    """N = 2: G = e_2^T (i w - M)^-1 e_2 by hand, and at w = 0 the static compliance (K - sigma S)^-1 seen at the
    tip."""
    sigma = 2.0
    m = np.array([[-5.0 + 2 * sigma, 2.0 - sigma], [2.0, -1.0]])  # M of N = 2: trace 2 (sigma - 3), det 1
    for w in (0.0, 0.3, 1.0, 4.0):
        a = 1j * w * np.eye(2) - m
        assert rs.tip_transfer(2, sigma, w)[0] == pytest.approx(a[0, 0] / np.linalg.det(a), rel=1e-12)
    k = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1]])
    s = np.array([[2.0, -1, -1], [0, 1, -1], [0, 0, 0]])
    ones = np.ones(3)
    static = ones @ np.linalg.solve(k - 0.1 * s, ones)  # theta = (K - sigma S)^-1 Q with Q = F (1, 1, 1)
    assert rs.tip_transfer(3, 0.1, 0.0)[0].real == pytest.approx(static, rel=1e-12)


def test_resonance_width_is_the_decay_rate_near_onset():
    n = 7
    sigma_c, omega_c = stab.critical_sigma(n)
    res = rs.resonance(n, 0.98 * sigma_c)
    lam = stab.eigenvalues(n, 0.98 * sigma_c)[0]
    assert res.half_width == pytest.approx(-lam.real, rel=0.02)
    assert res.omega == pytest.approx(abs(lam.imag), rel=0.005) and res.omega < omega_c
    assert abs(rs.tip_transfer(n, 0.98 * sigma_c, res.low)[0]) ** 2 == pytest.approx(res.gain**2 / 2, rel=1e-8)
    with pytest.raises(ParameterError, match="not below the onset"):
        rs.resonance(n, 1.1 * sigma_c)
    with pytest.raises(ParameterError, match="real"):
        rs.resonance(n, 0.3 * sigma_c)


def test_harmonic_response_reads_gain_and_phase():
    t = np.linspace(0, 4 * 2 * math.pi / 0.7, 801)
    g = 2.5 * cmath.exp(0.4j)
    x = 0.1 + abs(g) * 0.01 * np.sin(0.7 * t + cmath.phase(g))
    fit = rs.harmonic_response(t, x, 0.7, 0.01)
    assert fit.gain == pytest.approx(g, rel=1e-10) and fit.offset == pytest.approx(0.1) and fit.residual < 1e-10
    with pytest.raises(ParameterError, match="whole drive period"):
        rs.harmonic_response(t[:10], x[:10], 0.7, 0.01)
    with pytest.raises(ParameterError, match="amplitude"):
        rs.harmonic_response(t, x, 0.7, 0.0)
    with pytest.raises(ParameterError, match="direction"):
        rs.tip_displacement(np.zeros((3, 4)), "sideways")


def test_node_force_laws_of_positions_alone_still_work():
    law = node_forces.time_law(lambda positions: positions * 2)
    assert np.array_equal(law(3.0, np.ones((2, 2))), 2 * np.ones((2, 2)))
    both = node_forces.time_law(lambda t, positions: positions * t)
    assert np.array_equal(both(3.0, np.ones((2, 2))), 3 * np.ones((2, 2)))


def test_compiled_periodic_forces_equal_the_python_path():
    """A PeriodicForce runs in the compiled right-hand side (engines.node_kernels); the same law as a plain
    function of (t, positions) runs in Python: the two agree to the solver's tolerance, on one chain and on a pair
    with forces on both chains and a loaded subset."""
    from elastoactive.engines import reduced as red
    from elastoactive.terms.base import PeriodicForce

    for physics, laws in (
        (ea.Physics(n=7, sigma=0.9, drive_amplitude=0.05, drive_frequency=0.15), None),
        (
            ea.Physics(scene="coupled-pair", n=3, sigma=1.0, kappa=0.5, loaded="1,3"),
            [PeriodicForce(2, (0.02, 0.05), 1.3), PeriodicForce(4, (-0.03, 0.01), 0.7, 0.4)],
        ),
    ):
        laws = laws or [t.node_forces(physics) for t in physics.active_terms() if t.node_forces(physics) is not None]
        assert laws and all(isinstance(law, PeriodicForce) for law in laws)
        system = red.system_of(physics)
        t = np.linspace(0.0, 30.0, 61)
        theta0 = np.random.default_rng(1).uniform(-0.2, 0.2, physics.n_angles)
        kw = dict(rtol=1e-9, atol=1e-11, beta=0.0, loads=red.load_factors(physics))
        fast, _ = node_forces.solve(physics, system, t, theta0, laws, **kw)
        slow, _ = node_forces.solve(physics, system, t, theta0, [lambda s, x, law=law: law(s, x) for law in laws], **kw)
        assert np.abs(fast).max() > 0.01
        np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-8)


def test_tip_drive_parameters():
    assert "tip-drive" in ea.terms.names()
    p = ea.Physics(n=3, sigma=0.5, drive_amplitude=1e-3, drive_frequency=0.1)
    assert p.relevant()["drive_amplitude"] == 1e-3 and "drive_amplitude" not in ea.Physics(n=3).relevant()
    with pytest.raises(ParameterError, match="drive_frequency"):
        ea.Physics(n=3, drive_frequency=0.1)  # no effect without a drive
    with pytest.raises(ParameterError, match="drive_direction"):
        ea.Physics(n=3, drive_amplitude=1e-3, drive_direction="sideways")
    with pytest.raises(ParameterError, match="drive_amplitude"):
        ea.Physics(n=3, drive_amplitude=-1.0)


def test_compiled_drive_equals_its_reference():
    """MuJoCo's callback applies A sin(omega t) along the drive on the tip's site, as controllers/reference.py does."""
    import mujoco  # only the MuJoCo tests need it

    from elastoactive.controllers import compiled_passive, follower_forces, reference_passive
    from elastoactive.mjcf.chain import build_model

    for direction in ("transverse", "longitudinal"):
        model = build_model(
            ea.Physics(n=5, sigma=0.4, drive_amplitude=0.3, drive_frequency=0.2, drive_direction=direction),
            ea.Numerics(),
        )
        data = mujoco.MjData(model)
        data.qpos[:] = np.random.default_rng(3).uniform(-1, 1, model.nq)
        data.time = 0.9
        forces = {}
        for name, callback in (("compiled", compiled_passive), ("reference", reference_passive), ("bare", None)):
            with follower_forces(callback):
                mujoco.mj_forward(model, data)
            forces[name] = data.qfrc_passive.copy()
        np.testing.assert_allclose(forces["compiled"], forces["reference"], atol=1e-12)
        undriven = build_model(ea.Physics(n=5, sigma=0.4), ea.Numerics())
        plain = mujoco.MjData(undriven)
        plain.qpos[:], plain.time = data.qpos, data.time
        with follower_forces(compiled_passive):
            mujoco.mj_forward(undriven, plain)
        drive = forces["compiled"] - plain.qfrc_passive  # the drive's generalised force on the hinges
        f = (
            0.3
            * math.sin(2 * math.pi * 0.2 * 0.9)
            * (np.array([0.0, 1.0]) if direction == "transverse" else np.array([1.0, 0.0]))
        )
        theta = np.cumsum(data.qpos)  # hinge angles are relative: absolute angles are their sums
        absolute = -np.sin(theta) * f[0] + np.cos(theta) * f[1]  # Q_j = F . n_j on the absolute angles
        expected = np.cumsum(absolute[::-1])[::-1]  # hinge j turns every absolute angle beyond it
        np.testing.assert_allclose(drive, expected, atol=1e-12)


def test_tip_drive_in_the_reduced_engine_matches_the_transfer_function():
    n, sigma = 2, 2.7
    omega = 1.2
    g = rs.tip_transfer(n, sigma, omega)[0]
    amp = 1e-3 / abs(g)
    physics = ea.Physics(n=n, sigma=sigma, drive_amplitude=amp, drive_frequency=omega / (2 * math.pi))
    period = 2 * math.pi / omega
    duration = round((40.0 + 3 * period) / 0.05) * 0.05
    traj = ea.simulate(physics, ea.Numerics(sample_dt=0.05, perturbation=0.0), duration=duration, engine="reduced")
    res = ea.measure(traj, transient=duration - 3 * period)
    assert res.extra["drive_gain"] == pytest.approx(abs(g), rel=1e-3)
    assert res.extra["drive_phase"] == pytest.approx(cmath.phase(g), abs=1e-3)
    still = ea.simulate(
        ea.Physics(n=n, sigma=sigma), ea.Numerics(sample_dt=0.05, perturbation=0.0), duration=10.0, engine="reduced"
    )
    assert np.abs(still.theta).max() == 0.0  # without the drive the straight chain stays put: the drive moved it


def test_validate_holds_both_engines_to_one_percent():
    from elastoactive.checks import validate  # validate loads both engines

    case = ea.terms.get("tip-drive").validation_cases(ea.Physics)[0]
    row = validate.compare(case.physics, ea.Numerics(), case.duration)
    assert row.errors["amplitude"] < 0.01 and row.errors["frequency"] < 0.01
    gains = [row.mujoco.extra["drive_gain"], row.reduced.extra["drive_gain"]]
    assert gains[0] == pytest.approx(gains[1], rel=0.01)


@pytest.fixture(scope="module")
def runs(tiny_studies):
    return tiny_studies("response")


def test_response_study_tiny(runs, round_trip):
    s = runs[1]["response"].summary
    assert s.reduced.max_complex_error < 1e-3 and s.mujoco.max_complex_error < 0.01
    for part in (s.reduced, s.mujoco):
        assert len(part.sim_half_power) == 2 and all(h == pytest.approx(0.5, abs=5e-3) for h in part.sim_half_power)
    assert s.width_exponent == pytest.approx(1.0, abs=0.05)
    assert s.width_per_distance == pytest.approx(s.gamma_per_distance, rel=0.05)
    table = round_trip(runs, "response")
    assert "tip force" in table and table.count("| **yes** |") == 2


def test_residue_is_the_pole_of_the_transfer_function():
    """G(omega) = sum_k R_k / (i omega - lambda_k) over the eigenvalues of M; tip_residue is R of the leading pair."""
    from elastoactive.analysis.skin import displacement_operator  # the operator G is built from

    n, sigma = 7, 0.1
    lam, right = np.linalg.eig(displacement_operator(n, sigma))
    residues = right[-1, :] * np.linalg.inv(right)[:, -1]
    for w in (0.0, 0.02, 0.3):
        assert np.sum(residues / (1j * w - lam)) == pytest.approx(rs.tip_transfer(n, sigma, w)[0], rel=1e-9)
    lead = stab.eigenvalues(n, sigma)[0]
    k = int(np.argmin(np.abs(lam - (lead.real + 1j * abs(lead.imag)))))
    assert rs.tip_residue(n, sigma) == pytest.approx(residues[k], rel=1e-9)
    assert rs.adler_half_width(2, 3.3, 0.05, 0.8663569) == pytest.approx(abs(rs.tip_residue(2, 3.3)) * 0.05 / 0.8663569)
    with pytest.raises(ParameterError, match="real"):
        rs.tip_residue(7, 0.3 * stab.critical_sigma(7)[0])
    with pytest.raises(ParameterError, match="tip_amplitude"):
        rs.adler_half_width(2, 3.3, 0.05, 0.0)


@pytest.fixture(scope="module")
def entrained(tiny_studies):
    return tiny_studies("entrainment")


def test_entrainment_study_tiny(entrained, round_trip):
    s = entrained[1]["entrainment"].summary
    (edge,) = s.edges
    assert edge.engines_agree and edge.unlocked_low < -edge.adler < edge.locked_low < 0 < edge.locked_high < edge.adler
    assert s.free_frequency == pytest.approx(0.1528, rel=1e-3)
    table = round_trip(entrained, "entrainment")
    assert "Arnold tongue" in table and "| **yes** |" in table

"""The hydrodynamic coupling of a MuJoCo model (elastoactive.controllers.hydro): the flow is (M - I / g) f of the dense
mobility, the lag's spectrum is the iteration's, and the compiled loop steps exactly as MuJoCo's own steps do."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from elastoactive.controllers.hydro import (
    FLOWS,
    FluidCoupling,
    flow,
    lag_spectrum,
    mobility,
    tension_directions,
)
from elastoactive.core.errors import ParameterError
from elastoactive.mjcf.chain3d import Chain3DModel, prepare3d


def _beads(n: int, seed: int, low: float = 0.05) -> np.ndarray:
    x = np.random.default_rng(seed).uniform(0.0, 2.5, (n, 3))
    x[:, 2] += low
    return x


@pytest.mark.parametrize("name", FLOWS)
@pytest.mark.parametrize("radius", [0.15, 0.5])
def test_flow_is_the_dense_mobility_less_the_drag(name, radius):
    """u = M f - f / g for beads close enough to overlap each other and (rpb) the wall."""
    x = _beads(9, seed=1)
    x[3] = x[2] + [0.1, 0.0, 0.05]  # an overlapping pair
    x[5, 2] = 0.3 * radius  # a bead overlapping the wall
    f = np.random.default_rng(2).standard_normal((9, 3))
    gain = 0.8
    expected = (mobility(x, radius, name) @ f.ravel()).reshape(9, 3) - f / gain
    np.testing.assert_allclose(flow(x, f, radius, name, gain), expected, rtol=0, atol=1e-14)


def test_flow_refuses_bad_input():
    x, f = _beads(3, seed=0), np.ones((3, 3))
    with pytest.raises(ParameterError, match="flow"):
        flow(x, f, 0.2, "oseen")
    with pytest.raises(ParameterError, match="gain"):
        flow(x, f, 0.2, "rpy", gain=0.0)
    with pytest.raises(ParameterError, match="radius"):
        flow(x, f, -0.1, "rpy")
    x[1, 2] = -0.5
    with pytest.raises(ParameterError, match="bead 1"):
        flow(x, f, 0.2, "rpb")


def _chains(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Two bent chains of four beads above the wall: positions (2, 4, 3), anchors (2, 3)."""
    rng = np.random.default_rng(seed)
    bases = np.array([[0.0, 0.0, 0.5], [2.0, 0.5, 0.5]])
    t = np.column_stack([0.4 * rng.standard_normal((8, 2)), np.ones(8)]).reshape(2, 4, 3)
    t /= np.linalg.norm(t, axis=-1)[..., None]
    return bases[:, None, :] + np.cumsum(t, axis=1), bases


def test_tensions_do_no_work_on_the_chains_motions():
    """G's columns are orthogonal to every velocity of the inextensible chains: v_k - v_(k-1) across each link."""
    x, bases = _chains(seed=3)
    g = tension_directions(x, bases)
    behind = np.concatenate([bases[:, None, :], x[:, :-1]], axis=1)
    t = (x - behind).reshape(-1, 3)
    rng = np.random.default_rng(4)
    w = np.cross(rng.standard_normal(t.shape), t)  # each link's end-to-end velocity, across the link
    v = np.cumsum(w.reshape(2, 4, 3), axis=1).ravel()
    np.testing.assert_allclose(g.T @ v, 0.0, atol=1e-12)
    assert np.linalg.matrix_rank(g) == 8


@pytest.mark.parametrize("name", ["rpy", "rpb"])
def test_lag_spectrum_is_the_iterations(name):
    """The flow iterates as -(g M - I) Q, Q the projector onto the tensions: its spectral radius is the spectrum's
    max |g mu - 1|, least at the optimal gain, where it is (mu_max - mu_min) / (mu_max + mu_min)."""
    x, bases = _chains(seed=5)
    g = tension_directions(x, bases)
    q = g @ np.linalg.solve(g.T @ g, g.T)
    m = mobility(x.reshape(-1, 3), 0.3, name)
    spectrum = lag_spectrum(x, bases, 0.3, name)
    for gain in (0.7, 1.0, spectrum.optimal_gain):
        iteration = -(gain * m - np.eye(m.shape[0])) @ q
        assert np.max(np.abs(np.linalg.eigvals(iteration))) == pytest.approx(spectrum.radius(gain), rel=1e-9)
    mu = spectrum.mu
    assert spectrum.radius(spectrum.optimal_gain) == pytest.approx((mu[-1] - mu[0]) / (mu[-1] + mu[0]), rel=1e-12)
    assert spectrum.radius(spectrum.optimal_gain) < min(spectrum.radius(0.7), spectrum.radius(1.0))


def test_the_lab_frame_drags_gain_is_unstable_for_a_long_chain_of_big_beads():
    """Straight, free space, N = 10, a = 0.5: mu_max > 2, so g = 1 diverges; the optimal gain does not."""
    x = np.zeros((1, 10, 3))
    x[0, :, 0] = np.arange(1, 11)
    spectrum = lag_spectrum(x, np.zeros((1, 3)), 0.5, "rpy")
    assert spectrum.mu[-1] > 2.0
    assert spectrum.radius(1.0) > 1.0
    assert spectrum.radius(spectrum.optimal_gain) < 0.95


def _chain(n: int = 4):
    chain = Chain3DModel(n=n, sigma=0.9)
    rng = np.random.default_rng(6)
    t = np.column_stack([np.ones(n), 0.3 * rng.standard_normal((n, 2))])
    model, data = prepare3d(chain, t / np.linalg.norm(t, axis=1)[:, None])
    sites = np.array([model.site(f"particle_{k}").id for k in range(n)])
    acts = np.array([[model.actuator(f"drag_{a}_{k}").id for a in ("long", "y", "z")] for k in range(n)])
    return model, data, sites, acts


def test_identity_flow_steps_as_mujoco():
    """M = I at the gain 1: the flow vanishes and the coupled steps are mj_step's, bit for bit."""
    model, data, sites, acts = _chain()
    reference = mujoco.MjData(model)
    reference.qpos[:], reference.ctrl[:] = data.qpos, data.ctrl
    coupling = FluidCoupling(model, data, sites, acts, 0.2, "identity")
    coupling(model, data, 300)
    mujoco.mj_step(model, reference, nstep=300)
    np.testing.assert_array_equal(data.qpos, reference.qpos)
    np.testing.assert_array_equal(data.qvel, reference.qvel)
    assert not np.any(coupling.u)


def test_compiled_loop_is_the_python_loop():
    """The compiled loop (MuJoCo's C functions called from numba) and mj_step1 / update / mj_step2 from Python give
    the same state, bit for bit, through the free-space flow."""
    model, data, sites, acts = _chain()
    twin = mujoco.MjData(model)
    twin.qpos[:], twin.ctrl[:] = data.qpos, data.ctrl
    one = FluidCoupling(model, data, sites, acts, 0.3, "rpy")
    other = FluidCoupling(model, twin, sites, acts, 0.3, "rpy")
    assert one.compiled
    one(model, data, 400)
    other.python_steps(model, twin, 400)
    np.testing.assert_array_equal(data.qpos, twin.qpos)
    np.testing.assert_array_equal(one.u, other.u)
    assert np.max(np.abs(one.u)) > 0.05


def test_coupling_refuses_anisotropic_drag():
    model, data, sites, acts = _chain()
    model.actuator_gainprm[acts[:, 0], 0] = 2.0
    model.actuator_biasprm[acts[:, 0], 2] = -2.0
    with pytest.raises(ParameterError, match="one gain"):
        FluidCoupling(model, data, sites, acts, 0.2, "rpy")

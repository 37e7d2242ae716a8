"""The MuJoCo cilia (elastoactive.mjcf.cilia): without the fluid each is chain3d's chain, turned; with it the coupled
beads move as the reduced model's (elastoactive.reduced.fluid) at the start and along a run, to first order in dt."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.mjcf.chain3d import Chain3DModel, simulate3d
from elastoactive.mjcf.cilia import (
    CiliaModel,
    lab_positions,
    particle_sites,
    prepare_cilia,
    simulate_cilia,
)
from elastoactive.reduced.fluid import Beds, rhs, solve_fluid

UP = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
"""A cilium's frame: its clamp axis e_x along the wall's normal e_z."""


def _tangents(chains: int, n: int, seed: int, spread: float = 0.2) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.concatenate([np.ones((chains, n, 1)), spread * rng.standard_normal((chains, n, 2))], axis=-1)
    return t / np.linalg.norm(t, axis=-1)[..., None]


PAIR = np.array([[0.0, 0.0, 0.5], [2.0, 0.0, 0.5]])


def test_the_cilia_stand_on_their_bases():
    cilia = CiliaModel(3, 0.5, PAIR, UP)
    t0 = _tangents(2, 3, seed=1)
    run = prepare_cilia(cilia, t0)
    x = run.data.site_xpos[particle_sites(run.model, cilia)].reshape(2, 3, 3)
    np.testing.assert_allclose(x, lab_positions(cilia, t0), atol=1e-12)
    straight = prepare_cilia(cilia, _tangents(2, 3, seed=1, spread=0.0))
    first = straight.data.site_xpos[particle_sites(straight.model, cilia)].reshape(2, 3, 3)[:, 0]
    np.testing.assert_allclose(first, PAIR + [0.0, 0.0, 1.0], atol=1e-12)
    assert run.coupling is None and run.gain == 1.0


def test_without_the_fluid_a_cilium_is_chain3ds_chain_turned():
    """Same start in the chain's frame, same steps: the tangents agree to round-off (the rotation only)."""
    n, sigma, dt = 4, 1.2, 0.0025
    t0 = _tangents(1, n, seed=2)
    ts = np.arange(0.0, 2.0 + 1e-9, 0.25)
    cilium = simulate_cilia(CiliaModel(n, sigma, PAIR[:1], UP, dt=dt, drag_ratio=2.0), ts, t0)
    chain = simulate3d(Chain3DModel(n, sigma, drag_ratio=2.0, dt=dt), ts, t0[0])
    np.testing.assert_allclose(cilium[:, 0], chain, atol=1e-9)


def test_settled_velocities_are_the_reduced_models():
    """At the start, the settled coupling moves the beads of a pair on the wall as J^T M^-1 J q' = J^T F - dU/dq
    (reduced.fluid.rhs): the fixed point of the flow is the overdamped motion, up to MuJoCo's small inertia (its
    centripetal forces ~ mass_ratio: measured 1.2e-4 of the largest velocity at every dt)."""
    n, sigma, a = 4, 1.0, 0.3
    t0 = _tangents(2, n, seed=3, spread=0.4)
    run = prepare_cilia(CiliaModel(n, sigma, PAIR, UP, radius=a, dt=0.001), t0)
    assert 3 < run.settle_steps < 50
    v = np.empty((2 * n, 6))
    for k, site in enumerate(particle_sites(run.model, CiliaModel(n, sigma, PAIR, UP))):
        mujoco.mj_objectVelocity(run.model, run.data, mujoco.mjtObj.mjOBJ_SITE, site, v[k], 0)
    beds = Beds(n, sigma, PAIR, UP, mobility="rpb", radius=a)
    expected = np.cumsum(rhs(t0, beds), axis=1) @ UP.T
    assert np.max(np.abs(expected)) > 0.3
    np.testing.assert_allclose(v[:, 3:], expected.reshape(-1, 3), atol=5e-4 * np.max(np.abs(expected)))


def test_a_coupled_pair_follows_the_reduced_model_to_first_order_in_dt():
    n, sigma, a = 4, 1.5, 0.25
    t0 = _tangents(2, n, seed=4, spread=0.3)
    ts = np.arange(0.0, 1.5 + 1e-9, 0.05)
    reference = solve_fluid(Beds(n, sigma, PAIR, UP, mobility="rpb", radius=a), ts, t0, rtol=1e-10, atol=1e-12)
    local = solve_fluid(Beds(n, sigma, PAIR, UP), ts, t0, rtol=1e-10, atol=1e-12)
    errors = []
    for dt in (0.002, 0.001):
        path = simulate_cilia(CiliaModel(n, sigma, PAIR, UP, radius=a, dt=dt), ts, t0)
        errors.append(np.max(np.abs(path - reference)))
    assert np.max(np.abs(local - reference)) > 20 * errors[0]  # the fluid matters far more than the error
    assert errors[1] < 3e-3
    assert 1.6 < errors[0] / errors[1] < 2.4


def test_the_optimal_gain_keeps_a_long_cilium_of_big_beads_stable():
    """N = 10, a = 0.5 standing on the wall: the lag at the lab-frame drag's gain 1 has spectral radius 1.8 and
    diverges; at the optimal gain (radius 0.87) the run follows the reduced model."""
    n, sigma, a = 10, 1.0, 0.5
    t0 = _tangents(1, n, seed=5, spread=0.05)
    ts = np.arange(0.0, 1.0 + 1e-9, 0.1)
    reference = solve_fluid(Beds(n, sigma, PAIR[:1], UP, mobility="rpb", radius=a), ts, t0, rtol=1e-10, atol=1e-12)
    good = simulate_cilia(CiliaModel(n, sigma, PAIR[:1], UP, radius=a, dt=0.001), ts, t0, settle=False)
    assert np.max(np.abs(good - reference)) < 5e-3
    with np.errstate(all="ignore"):
        try:
            bad = simulate_cilia(CiliaModel(n, sigma, PAIR[:1], UP, radius=a, dt=0.001, gain=1.0), ts, t0, settle=False)
            assert np.max(np.abs(bad - reference)) > 0.1
        except RuntimeError:  # diverged outright
            pass


def test_hooks_are_told():
    calls, times = [], []

    def chunked(stepper):
        def step(model, data, nstep):
            calls.append(nstep)
            stepper(model, data, nstep)

        return step

    prepared = []
    ts = np.arange(0.0, 0.1 + 1e-9, 0.025)
    simulate_cilia(CiliaModel(3, 0.5, PAIR, UP, radius=0.2, dt=0.0025), ts, _tangents(2, 3, seed=6),
                   prepared=prepared.append, chunked=chunked, reached=times.append)  # fmt: skip
    assert calls == [10] * 4 and times == pytest.approx(list(ts[1:]))
    assert prepared[0].coupling is not None and prepared[0].gain > 0


@pytest.mark.parametrize(
    "change, word",
    [
        ({"rotation": np.eye(3) * 2}, "rotation"),
        ({"rotation": -np.eye(3)}, "proper"),
        ({"integrator": "RK4"}, "integrator"),
        ({"radius": 0.2, "drag_ratio": 2.0}, "drag_ratio"),
        ({"radius": 0.2, "flow": "identity"}, "flow"),
        ({"bases": np.zeros((2, 2))}, "bases"),
        ({"gain": -1.0}, "gain"),
        ({"tip_coupling": -1.0}, "tip_coupling"),
        ({"tip_coupling": 1.0, "drag_ratio": 2.0}, "drag_ratio"),
    ],
)
def test_bad_input_is_named(change, word):
    fields = {"n": 3, "sigma": 0.5, "bases": PAIR, "rotation": UP} | change
    with pytest.raises(ParameterError, match=word):
        CiliaModel(**fields).checked()


def test_a_chain_in_free_space_follows_the_reduced_model():
    """The free-space flow (RPY) on clamped-3d's chain (clamp along e_x at the origin): within the first-order error
    of the wall's case."""
    n, sigma, a = 5, 1.5, 0.3
    t0 = _tangents(1, n, seed=7, spread=0.3)
    ts = np.arange(0.0, 1.0 + 1e-9, 0.05)
    origin, eye = np.zeros((1, 3)), np.eye(3)
    reference = solve_fluid(Beds(n, sigma, origin, eye, mobility="rpy", radius=a), ts, t0, rtol=1e-10, atol=1e-12)
    local = solve_fluid(Beds(n, sigma, origin, eye), ts, t0, rtol=1e-10, atol=1e-12)
    path = simulate_cilia(CiliaModel(n, sigma, origin, eye, radius=a, flow="rpy", dt=0.001), ts, t0)
    error = np.max(np.abs(path - reference))
    assert error < 3e-3
    assert np.max(np.abs(local - reference)) > 20 * error


@pytest.mark.parametrize("radius", [0.0, 0.25])
def test_the_tips_spring_is_the_reduced_models(radius):
    """A pair joined by the tips' spring (K = 2), without and with the fluid: the coupling carries the spring's
    explicit force; the run follows reduced.fluid's to its first-order error."""
    n, sigma, k = 4, 1.5, 2.0
    t0 = _tangents(2, n, seed=8, spread=0.3)
    ts = np.arange(0.0, 1.0 + 1e-9, 0.05)
    mobility = "rpb" if radius else "local"
    beds = Beds(n, sigma, PAIR, UP, mobility=mobility, radius=radius, tip_coupling=k)
    reference = solve_fluid(beds, ts, t0, rtol=1e-10, atol=1e-12)
    free = solve_fluid(beds._replace(tip_coupling=0.0), ts, t0, rtol=1e-10, atol=1e-12)
    path = simulate_cilia(CiliaModel(n, sigma, PAIR, UP, radius=radius, tip_coupling=k, dt=0.001), ts, t0)
    error = np.max(np.abs(path - reference))
    assert error < 3e-3
    assert np.max(np.abs(free - reference)) > 20 * error

"""The paraboloid scene: a free chain whose head slides in a harmonic dish, in both engines."""

import json

import mujoco
import numpy as np
import pytest

import elastoactive as ea
from elastoactive import render
from elastoactive.cli import main
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import Numerics, Physics
from elastoactive.mjcf.chain import build_model, prepare, qpos_of, state_of
from elastoactive.records import load_trajectory


def test_trap_is_exactly_minus_k_r_on_every_particle_and_the_head():
    """The tendons (rest length 0) give each site the force -k r: compare MuJoCo's passive forces with J^T (-k r)."""
    p = Physics(scene="paraboloid", n=5, sigma=0.0, trap=0.37)
    model = build_model(p)
    data = mujoco.MjData(model)
    rng = np.random.default_rng(3)
    data.qpos[:] = qpos_of(p, rng.uniform(-2, 2, p.n), rng.uniform(-3, 3, 2))
    mujoco.mj_forward(model, data)
    want = np.zeros(model.nv)
    for site in ["head"] + [f"particle_{i}" for i in range(p.n)]:
        jac = np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, jac, None, model.site(site).id)
        want += jac.T @ (-p.trap * data.site(site).xpos)
    springs = np.zeros(model.nv)  # the hinge springs (no spring at the free first hinge)
    springs[3:] = -data.qpos[3:]
    np.testing.assert_allclose(data.qfrc_passive, want + springs, atol=1e-12)


def test_state_layout_head_first_in_mujoco():
    p = Physics(scene="paraboloid", n=4, sigma=0.3, trap=0.1)
    theta, head = np.array([0.1, 0.3, -0.2, 0.5]), np.array([1.5, -2.0])
    q = qpos_of(p, theta, head)
    assert q.shape == (6,) and np.allclose(q[:2], head)
    back_theta, back_head = state_of(p, q)
    np.testing.assert_allclose(back_theta, theta)
    np.testing.assert_allclose(back_head, head)
    model, data = prepare(p, Numerics(), theta, head)
    np.testing.assert_allclose(data.site("head").xpos[:2], head)
    np.testing.assert_allclose(data.site("particle_3").xpos[:2], head + [np.cos(theta).sum(), np.sin(theta).sum()])


def test_trap_must_be_positive():
    with pytest.raises(ParameterError, match="trap"):
        Physics(scene="paraboloid", trap=0.0)
    with pytest.raises(ParameterError, match="trap"):
        Physics(scene="paraboloid", trap=-1.0)


@pytest.mark.parametrize("trap,state,rate,radius", [(0.1, "orbit", 0.0802, 1.404), (0.3, "spin", 0.155, 0.268)])
def test_engines_agree_on_the_dish(trap, state, rate, radius):
    """The issue's sanity figures (N = 7, sigma = 0.3): trap 0.1 a rigid orbit at 0.080 rad/tau, centre of mass at
    radius 1.40; trap 0.3 curled, spinning at 0.155 rad/tau about radius 0.27; both engines within 1%."""
    physics = Physics(scene="paraboloid", n=7, sigma=0.3, trap=trap)
    mj = ea.measure(ea.simulate(physics, duration=600.0))
    red = ea.measure(ea.simulate(physics, duration=600.0, engine="reduced"))
    for r in (mj, red):
        assert r.dish_state == state
        assert abs(abs(r.rotation_rate) - rate) < 0.01 * rate
        assert abs(r.orbit_radius - radius) < 0.01 * radius
    for name in ("rotation_rate", "orbit_rate"):
        a, b = mj.value(name), red.value(name)
        assert abs(a - b) < 0.01 * abs(b), (name, a, b)


def test_run_writes_the_head_and_renders_it(tmp_path):
    out = tmp_path / "dish"
    assert (
        main(
            [
                "run",
                "paraboloid",
                "--n",
                "5",
                "--sigma",
                "0.3",
                "--trap",
                "0.3",
                "--duration",
                "40",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["trap"] == 0.3
    assert {"rotation_rate", "orbit_rate", "orbit_radius", "curvature", "dish_state", "harmonics"} <= set(
        summary["results"]
    )
    traj = load_trajectory(out)
    assert traj.head.shape == (traj.t.size, 2) and np.all(np.isfinite(traj.head))
    with np.load(out / "trajectory.npz") as f:  # a trajectory without its head is refused, naming what is missing
        np.savez(tmp_path / "bad.npz", **{k: f[k] for k in f.files if k != "head"})
    (tmp_path / "summary.json").write_text(json.dumps({k: v for k, v in summary.items() if k != "trajectory_sha256"}))
    with pytest.raises(ParameterError, match="head"):
        load_trajectory(tmp_path / "bad.npz")
    try:
        render.gl_backend()
    except render.RenderError:
        return  # nothing to draw on this machine (test_render.py says why)
    frame = render.render_frames(traj, fps=2, rate=10, width=160, height=120, start=30, end=30)[0]
    assert frame.std() > 10
    # the chain is drawn where the head took it: the frame differs from one with the head at the origin
    moved = render.render_frames(
        ea.Trajectory(traj.t, traj.theta, traj.physics, "x", head=np.zeros_like(traj.head)),
        fps=2,
        rate=10,
        width=160,
        height=120,
        start=30,
        end=30,
    )[0]
    assert np.abs(frame.astype(int) - moved).mean() > 1.0


def test_sweep_stores_the_dish_state_as_flags(tmp_path):
    """A sweep over the trap: rates as numbers, dish_state as a CF flag variable (index into its meanings)."""
    import xarray as xr

    out = tmp_path / "dish.nc"
    assert (
        main(
            [
                "sweep",
                "paraboloid",
                "--grid",
                "trap=0.1,0.3",
                "--sigma",
                "0.3",
                "--duration",
                "300",
                "--engine",
                "reduced",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    with xr.open_dataset(out) as ds:
        meanings = ds.dish_state.attrs["flag_meanings"].split()
        states = [meanings[int(v)] for v in ds.dish_state.values]
        assert states == ["orbit", "spin"]
        assert abs(abs(float(ds.rotation_rate.sel(trap=0.1))) - 0.0802) < 0.002
        assert ds.trap.attrs["long_name"].startswith("stiffness k l^2 / C1")

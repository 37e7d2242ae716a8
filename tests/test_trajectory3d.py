"""The chain in three dimensions on file: its particles' positions follow from the recorded angles exactly as MuJoCo
places its bodies, a run of either engine writes them (x, y, z) into trajectory.npz with their dimensions and units,
ea.load gives them back, and the planar scenes' files hold what they held."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.mjcf.chain3d import Chain3DModel, prepare3d, qpos_of_tangents
from elastoactive.scenes.clamped3d import tangents_of

N, SIGMA = 3, 4.0
"""A whirl within a few tau (onset 1.16 at N = 3)."""
ROUND_OFF = 1e-13
"""Positions are sums of N unit vectors of order 1: a few ulps each."""


def _particles_and_bodies(model, data, n):
    """MuJoCo's own positions: the particle sites, and the bodies (body k+1 sits at particle k, body 0 at the clamp)."""
    sites = data.site_xpos[:n].copy()
    bodies = np.array([data.body(f"segment_{k}").xpos for k in range(n)])
    return sites, bodies


def test_positions_from_the_angles_are_mujocos_body_positions():
    """A MuJoCo run stepped again beside the engine's: at every sample the positions that Trajectory.positions
    computes from the recorded angles are MuJoCo's particle sites and body origins, to round-off."""
    physics, numerics = ea.Physics(scene="clamped-3d", n=N, sigma=SIGMA), ea.Numerics()
    traj = ea.simulate(physics, numerics, duration=3.0, engine="mujoco")
    used = {name: getattr(numerics, name) for name in ("mass_ratio", "dt", "integrator")}
    used.update({k: v for k, v in traj.info.get("automatic_numerics", {}).items() if k in used})  # the scene's choice
    chain = Chain3DModel(N, SIGMA, **used)
    model, data = prepare3d(chain, physics.scene_def.initial_tangents(physics, numerics))
    steps = round(numerics.sample_dt / chain.dt)
    positions = traj.positions()
    assert positions.shape == (traj.t.size, 1, N, 3)
    assert np.ptp(positions[:, 0, -1, 2]) > 0.1  # out of the plane: z matters
    for i in range(traj.t.size):
        if i:
            mujoco.mj_step(model, data, nstep=steps)
            mujoco.mj_kinematics(model, data)
        sites, bodies = _particles_and_bodies(model, data, N)
        np.testing.assert_allclose(positions[i, 0], sites, rtol=0, atol=ROUND_OFF)
        np.testing.assert_allclose(positions[i, 0, :-1], bodies[1:], rtol=0, atol=ROUND_OFF)
        np.testing.assert_array_equal(bodies[0], 0.0)


def test_a_reduced_run_s_positions_place_mujocos_bodies():
    """The reduced engine's recorded angles, written into MuJoCo's chain (ball joints at zero twist), put its
    particles where Trajectory.positions says."""
    traj = ea.simulate(ea.Physics(scene="clamped-3d", n=N, sigma=SIGMA), duration=3.0, engine="reduced")
    chain = Chain3DModel(N, SIGMA)
    model, data = prepare3d(chain, tangents_of(traj.theta[0], N))
    positions = traj.positions()
    for i in range(0, traj.t.size, 7):
        data.qpos[:] = qpos_of_tangents(chain, tangents_of(traj.theta[i], N))
        mujoco.mj_kinematics(model, data)
        sites, bodies = _particles_and_bodies(model, data, N)
        np.testing.assert_allclose(positions[i, 0], sites, rtol=0, atol=ROUND_OFF)
        np.testing.assert_allclose(positions[i, 0, :-1], bodies[1:], rtol=0, atol=ROUND_OFF)


FILED = [scene.name for scene in ea.scenes.scenes() if scene.file_variables]
"""Every scene whose runs write positions: the 3D kind's."""


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
@pytest.mark.parametrize("scene", FILED)
def test_a_3d_run_writes_its_positions_and_load_gives_them_back(scene, engine, tmp_path):
    out = tmp_path / engine
    assert main(["run", scene, "--n", str(N), "--sigma", str(SIGMA), "--duration", "4", "--engine", engine,
                 "--quiet", "--out", str(out)]) == 0  # fmt: skip
    with np.load(out / "trajectory.npz") as f:
        position, t = f["position"], f["t"]
        assert str(f["position_dims"]) == "time chain particle xyz"
        assert str(f["position_units"]) == "l" and str(f["position_long_name"]) == "particle position"
    assert position.shape == (t.size, 1, N, 3) and position.dtype == np.float64
    traj = ea.load(out)
    np.testing.assert_array_equal(traj.positions(), position)
    np.testing.assert_array_equal(traj.tip(), position[:, :, -1])
    dataset = traj.to_xarray()
    assert dataset["position"].dims == ("time", "chain", "particle", "xyz")
    assert dataset["position"].attrs["units"] == "l" and list(dataset["xyz"].values) == ["x", "y", "z"]
    np.testing.assert_array_equal(dataset["position"].values, position)
    links = np.diff(position[:, 0], axis=1, prepend=np.zeros((t.size, 1, 3)))
    np.testing.assert_allclose(np.linalg.norm(links, axis=-1), 1.0, atol=1e-12)  # every link one l long


def test_a_planar_run_s_file_holds_what_it_held(tmp_path):
    """The planar scenes name no file variables: their trajectory.npz keeps its arrays, no positions added."""
    assert {scene.kind for scene in ea.scenes.scenes() if scene.file_variables} == {"chain3d"}
    out = tmp_path / "planar"
    assert main(["run", "one-pinned", "--n", "3", "--sigma", "4", "--duration", "4", "--quiet", "--out", str(out)]) == 0
    with np.load(out / "trajectory.npz") as f:
        assert sorted(f.files) == ["n", "scene", "settings_sha256", "t", "theta"]

"""The MJCF scenes: each holds what its physics needs and nothing more, for any N."""

import mujoco
import numpy as np
import pytest

from elastoactive import scenes
from elastoactive.core.params import Numerics, Physics
from elastoactive.mjcf import mjcf_path
from elastoactive.mjcf.chain import absolute_angles, build_model, relative_angles

SCENES = [s for s in scenes.names() if scenes.get(s).term_parameters is None]  # chain scenes; networks: test_network*


def scene_path(scene):
    return mjcf_path(scenes.get(scene).base_file)


D = mujoco.mjtDisableBit


def flags(model):
    return {name for name, bit in D.__members__.items() if name != "mjNDISABLE" and model.opt.disableflags & int(bit)}


ALWAYS_OFF = {
    "mjDSBL_CONTACT",
    "mjDSBL_GRAVITY",
    "mjDSBL_AUTORESET",
    "mjDSBL_FRICTIONLOSS",
    "mjDSBL_LIMIT",
    "mjDSBL_SENSOR",
    "mjDSBL_MIDPHASE",
    "mjDSBL_FILTERPARENT",
    "mjDSBL_CLAMPCTRL",
    "mjDSBL_DAMPER",
}


@pytest.mark.parametrize("scene", SCENES)
def test_base_file_opens_on_its_own(scene):
    model = mujoco.MjModel.from_xml_path(str(scene_path(scene)))
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, nstep=10)
    assert np.all(np.isfinite(data.qpos))


@pytest.mark.parametrize("scene", SCENES)
def test_builder_reproduces_base_file(scene):
    """The generator at the paper's defaults gives the model the base file describes."""
    base = mujoco.MjModel.from_xml_path(str(scene_path(scene)))
    built = build_model(scenes.get(scene).base_physics())  # N = 7, sigma = 0.8, the rest as the file holds them
    for field in ("nq", "nv", "nu", "neq", "ntendon", "nbody", "nsite", "nkey"):
        assert getattr(built, field) == getattr(base, field), field
    for field in (
        "jnt_stiffness",
        "body_mass",
        "site_user",
        "actuator_gear",
        "actuator_biasprm",
        "tendon_stiffness",
        "body_pos",
        "site_pos",
        "eq_data",
        "key_qpos",
    ):
        np.testing.assert_allclose(getattr(built, field), getattr(base, field), atol=1e-9, err_msg=field)
    assert built.opt.disableflags == base.opt.disableflags


@pytest.mark.parametrize("scene,n", [(s, n) for s in SCENES for n in (1, 2, 7, 40) if n >= scenes.get(s).min_n])
def test_each_scene_holds_only_what_it_needs(scene, n):
    physics = Physics(scene=scene, n=n)
    model = build_model(physics)
    chains = physics.n_chains
    head = physics.scene_def.head_coordinates  # the paraboloid's sliding head (two slides), the star's hub hinge
    assert model.nq == model.nv == n * chains + head  # one hinge per particle, nothing else
    assert model.nu == 2 * n * chains + head  # two drags per particle, one per head coordinate
    on_sites = model.actuator_trntype == mujoco.mjtTrn.mjTRN_SITE  # the drags on the particles' (and head's) sites,
    assert np.count_nonzero(~on_sites) <= head  # a hinged head's (the hub's) on its joint
    assert np.count_nonzero(model.site_user[:, 0]) == n * chains  # one follower force per particle
    np.testing.assert_allclose(model.site_user[model.site_user[:, 0] != 0, 0], physics.sigma)
    assert model.ngeom and not np.any(model.geom_contype) and not np.any(model.geom_conaffinity)
    off = flags(model)
    assert ALWAYS_OFF <= off
    pinned = physics.scene_def.pinned  # the two-pinned chain's end, the ring's closing particle
    assert model.neq == (1 if pinned else 0)
    tendons = {"coupled-pair": 1, "paraboloid": n + 1, "ring": 1, "star": chains}  # coupling; trap; closure; clamps
    assert model.ntendon == tendons.get(scene, 0)
    if not pinned:
        assert {"mjDSBL_CONSTRAINT", "mjDSBL_EQUALITY", "mjDSBL_WARMSTART"} <= off
    else:
        assert "mjDSBL_CONSTRAINT" not in off and "mjDSBL_EQUALITY" not in off
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert data.ncon == 0
    assert data.nefc == (3 if pinned else 0)
    # mass sits on the particles only: the visual capsules weigh nothing
    links = [i for i in range(model.ngeom) if "link_" in model.geom(i).name]
    assert len(links) == n * chains and not np.any(model.geom_size[links, 0] == 0)
    m = Numerics().mass_ratio  # one bead per particle and one for a moving head (the paraboloid's, the star's hub)
    np.testing.assert_allclose(model.body_mass[1:].sum(), (n * chains + (1 if head else 0)) * m)
    assert np.all(model.body_mass[1:] > 0)


def test_physical_parameters_reach_the_model():
    p = Physics(scene="coupled-pair", n=3, sigma=0.6, kappa=2.5, rho=1.5, drag_ratio=3.0)
    m = build_model(p, Numerics(dt=0.004, sample_dt=0.04, mass_ratio=1e-4, integrator="discrete"))
    np.testing.assert_allclose(m.jnt_stiffness, [1, 1, 1, 1.5, 1.5, 1.5])
    np.testing.assert_allclose(m.tendon_stiffness, [2.5])
    assert m.opt.timestep == 0.004 and m.opt.integrator == mujoco.mjtIntegrator.mjINT_DISCRETE
    np.testing.assert_allclose(m.body_mass[1:], 1e-4)
    long = [a for a in range(m.nu) if m.actuator(a).name.split("_")[-2] == "long"]
    trans = [a for a in range(m.nu) if m.actuator(a).name.split("_")[-2] == "trans"]
    np.testing.assert_allclose(m.actuator_biasprm[long, 2], -3.0)
    np.testing.assert_allclose(m.actuator_biasprm[trans, 2], -1.0)
    rot = build_model(Physics(scene="rotating-pin", n=3))
    np.testing.assert_allclose(rot.jnt_stiffness, [0, 1, 1])


def test_pin_position_follows_delta():
    m = build_model(Physics(scene="two-pinned", n=9, delta=0.25))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    np.testing.assert_allclose(d.site("pin").xpos, [9 * 0.75, 0, 0])
    assert m.eq_obj1id[0] == m.site("particle_8").id
    # the keyframe is an admissible buckled start
    d.qpos[:] = m.key_qpos[0]
    mujoco.mj_forward(m, d)
    np.testing.assert_allclose(d.site("particle_8").xpos, d.site("pin").xpos, atol=1e-12)


def test_angle_conversions_round_trip():
    p = Physics(scene="coupled-pair", n=4)
    theta = np.random.default_rng(0).standard_normal(8)
    np.testing.assert_allclose(absolute_angles(p, relative_angles(p, theta)), theta)
    q = relative_angles(p, theta)
    assert q[0] == theta[0] and q[4] == theta[4]


def test_drag_is_lab_frame_drag():
    """Actuator forces equal -gamma v on each particle, not joint damping."""
    p = Physics(scene="one-pinned", n=3, drag_ratio=2.0)
    m = build_model(p)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(3)
    d.qpos[:] = rng.standard_normal(3)
    d.qvel[:] = rng.standard_normal(3)
    mujoco.mj_forward(m, d)
    expected = np.zeros(3)
    jac = np.zeros((3, 3))
    for i in range(3):
        s = m.site(f"particle_{i}").id
        mujoco.mj_jacSite(m, d, jac, None, s)
        v = jac @ d.qvel
        R = d.site_xmat[s].reshape(3, 3)
        f = -(2.0 * (R[:, 0] @ v) * R[:, 0] + (R[:, 1] @ v) * R[:, 1])
        expected += jac.T @ f
    np.testing.assert_allclose(d.qfrc_actuator, expected, atol=1e-12)

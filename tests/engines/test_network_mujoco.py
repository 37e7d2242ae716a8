"""Elastic networks of active units in MuJoCo: the model (elastoactive.mjcf.network) and the engine's branch.

Checked: every network compiles and steps with no MuJoCo warning; pinned nodes never move; the springs, the trap and
the drag are the exact forces (against a numpy sum over the bonds); the passive lattice relaxes mode by mode at the
dynamical matrix's eigenvalues (within 1%).
"""

import mujoco
import numpy as np
import pytest

import elastoactive as ea
from elastoactive.analysis.network import hexagonal_patch, trap_unit
from elastoactive.controllers import follower_forces
from elastoactive.core.errors import ParameterError
from elastoactive.engines.network_mujoco import simulate_network_mujoco
from elastoactive.mjcf.network import (
    build_network_model,
    free_nodes,
    node_positions,
    polarity_of_units,
    qpos_of_positions,
    set_polarity,
)
from elastoactive.scenes import NetworkScene

PHYSICS = ea.Physics(sigma=0.0)  # a passive network: the builder reads the scene's name and sigma = 0
ACTIVE = ea.Physics(sigma=1.5, active="self-aligning", alignment_length=0.7)  # the units' F_a and l_a
NETWORKS = [(f"R={r} {b}", hexagonal_patch(r, b)) for r in range(1, 7) for b in ("pinned", "free", "centre")]
NETWORKS.append(("trap unit", trap_unit(1.0)))


def _state(network, rng, size=0.05):
    positions = np.asarray(network.positions, dtype=float).copy()
    free = free_nodes(network)
    positions[free] += size * rng.standard_normal((free.size, 2))
    return positions


def dynamical_matrix(network) -> np.ndarray:
    """The Hessian of the spring and trap energy at rest over the free nodes' coordinates (x0, y0, x1, y1, ...):
    sum over bonds of k e e^T blocks, plus trap x identity."""
    count = len(network.positions)
    K = np.zeros((2 * count, 2 * count))
    for (i, j), k in zip(network.bonds, network.stiffness):
        e = network.positions[j] - network.positions[i]
        block = k * np.outer(e, e) / (e @ e)
        for a, b, s in ((i, i, 1), (j, j, 1), (i, j, -1), (j, i, -1)):
            K[2 * a : 2 * a + 2, 2 * b : 2 * b + 2] += s * block
    dofs = np.ravel([[2 * i, 2 * i + 1] for i in free_nodes(network)])
    return K[np.ix_(dofs, dofs)] + network.trap * np.eye(dofs.size)


def spring_forces(network, positions) -> np.ndarray:
    """(P, 2) the springs' and the trap's forces on every node, summed in numpy."""
    force = np.zeros_like(positions)
    for (i, j), k, a in zip(network.bonds, network.stiffness, network.rest_lengths):
        r = positions[j] - positions[i]
        length = np.linalg.norm(r)
        f = k * (length - a) * r / length
        force[i] += f
        force[j] -= f
    force -= network.trap * (positions - network.anchors)
    return force


@pytest.mark.parametrize("label,network", NETWORKS, ids=[n for n, _ in NETWORKS])
def test_every_network_compiles_and_steps_without_a_warning(label, network):
    model = build_network_model(network, ACTIVE)
    data = mujoco.MjData(model)
    data.qpos[:] = qpos_of_positions(network, _state(network, np.random.default_rng(0)))
    units = np.count_nonzero(network.active)
    set_polarity(model, data, np.linspace(0, 6, units))
    with follower_forces():
        mujoco.mj_step(model, data, nstep=200)
    assert all(w.number == 0 for w in data.warning), [
        mujoco.mjtWarning(i).name for i, w in enumerate(data.warning) if w.number
    ]
    assert model.nq == model.nv == 2 * free_nodes(network).size
    assert model.ntendon == sum(not (network.pinned[i] and network.pinned[j]) for i, j in network.bonds)
    assert model.nu == model.na == units and model.neq == 0 and np.isfinite(data.qpos).all()
    assert not np.array_equal(polarity_of_units(model, data), np.linspace(0, 6, units))  # the units turned
    disabled = mujoco.mjtDisableBit
    for flag in (
        disabled.mjDSBL_CONTACT,
        disabled.mjDSBL_GRAVITY,
        disabled.mjDSBL_CONSTRAINT,
        disabled.mjDSBL_AUTORESET,
    ):
        assert model.opt.disableflags & flag
    assert not model.opt.disableflags & disabled.mjDSBL_DAMPER  # the drag is the slide joints' damping


def test_forces_are_the_exact_springs_trap_and_drag():
    network = hexagonal_patch(3, "pinned")._replace(trap=0.7)
    network = network._replace(anchors=network.positions + 0.1)
    rng = np.random.default_rng(3)
    model = build_network_model(network, PHYSICS)
    data = mujoco.MjData(model)
    positions = _state(network, rng, 0.2)
    data.qpos[:] = qpos_of_positions(network, positions)
    data.qvel[:] = rng.standard_normal(model.nv)
    mujoco.mj_forward(model, data)
    expected = spring_forces(network, positions)[free_nodes(network)].ravel() - data.qvel
    np.testing.assert_allclose(data.qfrc_passive, expected, atol=1e-12)
    np.testing.assert_allclose(node_positions(network, data.qpos), positions, atol=1e-15)
    sites = np.array([data.site(f"node_{i}").xpos[:2] for i in range(len(positions))])
    np.testing.assert_allclose(sites, positions, atol=1e-15)


def test_pinned_nodes_do_not_move():
    network = hexagonal_patch(4, "pinned")
    model = build_network_model(network, PHYSICS)
    data = mujoco.MjData(model)
    data.qpos[:] = qpos_of_positions(network, _state(network, np.random.default_rng(1), 0.3))
    pinned = np.flatnonzero(network.pinned)
    for _ in range(20):
        mujoco.mj_step(model, data, nstep=50)
        xpos = np.array([data.site(f"node_{i}").xpos[:2] for i in pinned])
        np.testing.assert_array_equal(xpos, network.positions[pinned])
    assert np.abs(data.qpos).max() > 1e-3  # the free nodes did move


@pytest.mark.parametrize("rings,boundary", [(3, "pinned"), (2, "centre")])
def test_passive_lattice_relaxes_at_the_dynamical_matrix_eigenvalues(rings, boundary):
    """A single mode of the dynamical matrix K, started alone, stays alone and decays at its eigenvalue lambda
    (gamma = 1): the slowest modes, one in the middle and the fastest, within 1%."""
    network = hexagonal_patch(rings, boundary)
    eigenvalues, modes = np.linalg.eigh(dynamical_matrix(network))
    positive = np.flatnonzero(eigenvalues > 1e-9)  # the centre-pinned patch may turn rigidly: lambda = 0
    numerics = ea.Numerics(dt=0.001, mass_ratio=1e-5)
    model = build_network_model(network, PHYSICS, numerics)
    for k in (positive[0], positive[1], positive[positive.size // 2], positive[-1]):
        data = mujoco.MjData(model)
        data.qpos[:] = 1e-4 * modes[:, k]
        span = 2.0 / eigenvalues[k]  # two relaxation times
        steps = int(round(span / numerics.dt))
        t0 = 0.1 * span  # past the inertial start (m / gamma = 1e-5)
        mujoco.mj_step(model, data, nstep=int(round(t0 / numerics.dt)))
        a0 = modes[:, k] @ data.qpos
        mujoco.mj_step(model, data, nstep=steps)
        a1 = modes[:, k] @ data.qpos
        rate = np.log(a0 / a1) / (steps * numerics.dt)
        assert rate == pytest.approx(eigenvalues[k], rel=0.01), (k, eigenvalues[k])
        assert np.linalg.norm(data.qpos - a1 * modes[:, k]) < 1e-3 * abs(a1)  # no other mode took over


def test_node_positions_refuse_a_moved_pin():
    network = hexagonal_patch(1, "pinned")
    moved = network.positions.copy()
    moved[1] += 0.1
    with pytest.raises(ParameterError, match="pinned node"):
        qpos_of_positions(network, moved)
    with pytest.raises(ParameterError, match="network.stiffness"):
        build_network_model(network._replace(stiffness=-network.stiffness), PHYSICS)


def test_active_units_push_along_their_polarity_and_turn_toward_the_velocity():
    """The force F_a (cos psi, sin psi) on every active node and dpsi/dt = (v . n_perp) / l_a (controllers/follower.c
    reached through the network's sites), against numpy."""
    network = hexagonal_patch(2, "pinned")
    rng = np.random.default_rng(5)
    model = build_network_model(network, ACTIVE)
    data = mujoco.MjData(model)
    positions = _state(network, rng, 0.1)
    data.qpos[:] = qpos_of_positions(network, positions)
    data.qvel[:] = rng.standard_normal(model.nv)
    psi = rng.uniform(0, 2 * np.pi, np.count_nonzero(network.active))
    set_polarity(model, data, psi)
    with follower_forces():
        mujoco.mj_forward(model, data)
    free = free_nodes(network)
    velocity = np.zeros_like(positions)
    velocity[free] = data.qvel.reshape(-1, 2)
    active_force = np.zeros_like(positions)
    active_force[network.active] = ACTIVE.sigma * np.column_stack([np.cos(psi), np.sin(psi)])
    expected = (spring_forces(network, positions) + active_force)[free].ravel() - data.qvel
    np.testing.assert_allclose(data.qfrc_passive, expected, atol=1e-12)
    v = velocity[network.active]
    turning = (-v[:, 0] * np.sin(psi) + v[:, 1] * np.cos(psi)) / ACTIVE.alignment_length
    np.testing.assert_allclose(data.act_dot, turning, atol=1e-12)


@pytest.mark.parametrize("sigma,alignment_length,trap", [(2.0, 1.0, 1.0), (3.0, 2.0, 0.5)])
def test_trapped_unit_orbits_on_the_self_aligning_circle(sigma, alignment_length, trap):
    """A self-aligning unit in a harmonic trap k beyond F_a > k l_a circles at radius R = sqrt(F_a l_a / k) with
    angular rate omega = sqrt(k (F_a / l_a - k)) / gamma (steady orbit: F_a n = gamma v + k x, and psi turns with
    the orbit only if k R^2 = F_a l_a); MuJoCo within 0.3% (first order in dt: 0.13% at dt = 0.0025)."""
    physics = ea.Physics(sigma=sigma, active="self-aligning", alignment_length=alignment_length)
    traj = simulate_network_mujoco(
        physics,
        ea.Numerics(),
        60.0,
        network=trap_unit(trap),
        positions0=np.array([[0.1, 0.0]]),
        polarity0=np.array([0.3]),
    )
    assert traj.theta.shape == (traj.t.size, 0) and traj.nodes.shape == (traj.t.size, 1, 2)
    assert traj.polarity.shape == (traj.t.size, 1)
    x = traj.nodes[:, 0]
    late = traj.t > 30.0
    radius = np.linalg.norm(x[late], axis=1)
    rate = np.polyfit(traj.t[late], np.unwrap(np.arctan2(x[late, 1], x[late, 0])), 1)[0]
    assert radius.mean() == pytest.approx(np.sqrt(sigma * alignment_length / trap), rel=3e-3)
    assert radius.std() < 1e-3 * radius.mean()
    assert abs(rate) == pytest.approx(np.sqrt(trap * (sigma / alignment_length - trap)), rel=3e-3)
    heading = np.unwrap(traj.polarity[late, 0])  # the polarity turns with the orbit
    assert np.polyfit(traj.t[late], heading, 1)[0] == pytest.approx(rate, rel=1e-3)


class _Patch(NetworkScene):
    """A network scene of this test alone: the pinned hexagon of two rings (7 active nodes)."""

    name = "test-network-patch"
    summary = "a pinned hexagon of two rings (tests)"
    base_file = "network.xml"
    term_parameters = ("n", "sigma", "loaded", "active", "alignment_length")
    fixed = (("active", "self-aligning", "a network's units are self-aligning"),)

    def network(self, physics):
        return hexagonal_patch(2, "pinned")


@pytest.fixture
def patch_scene():
    scene = ea.scenes.register(_Patch())
    yield scene
    ea.scenes.unregister(scene.name)


def test_simulate_dispatches_a_network_scene_to_the_network_engine(patch_scene):
    physics = ea.Physics(scene=patch_scene.name, sigma=0.5, alignment_length=0.8)
    numerics = ea.Numerics(perturbation=0.05, seed=3)
    traj = ea.simulate(physics, numerics, duration=5.0, check=False)
    network = patch_scene.network(physics)
    start = patch_scene.initial_network(physics, numerics)
    assert traj.engine == "mujoco" and traj.theta.shape == (traj.t.size, 0)
    assert traj.nodes.shape == (traj.t.size, 19, 2) and traj.polarity.shape == (traj.t.size, 7)
    np.testing.assert_allclose(traj.nodes[0], start.positions, atol=1e-15)
    np.testing.assert_allclose(traj.polarity[0], start.polarity, atol=1e-15)
    np.testing.assert_array_equal(
        traj.nodes[:, network.pinned], np.broadcast_to(network.positions[network.pinned], (traj.t.size, 12, 2))
    )
    assert np.abs(traj.nodes[-1] - traj.nodes[0]).max() > 1e-3  # the active units moved the free nodes


def test_network_frames_render_off_screen(patch_scene):
    render = pytest.importorskip("elastoactive.render")
    try:
        render.gl_backend()
    except render.RenderError as err:
        pytest.skip(f"no OpenGL back end can be made to work on this machine, so nothing can be rendered: {err}")
    physics = ea.Physics(scene=patch_scene.name, sigma=1.0)
    traj = ea.simulate(physics, ea.Numerics(perturbation=0.1), duration=2.0, check=False)
    frames = render.render_frames(traj, np.array([0.0, 1.0, 2.0]), width=160, height=120)
    assert frames.shape == (3, 120, 160, 3) and frames.dtype == np.uint8
    assert frames.std() > 10  # drawn, not blank
    assert np.abs(frames[2].astype(int) - frames[0]).max() > 50  # the nodes moved between the frames
    red = (frames[..., 0] > 180) & (frames[..., 1] < 110) & (frames[..., 2] < 110)  # the units' arrows
    assert red[0].sum() > 10


def test_batched_network_runs_are_the_single_runs(patch_scene):
    from elastoactive.engines.mujoco import simulate_mujoco
    from elastoactive.engines.mujoco_batch import simulate_mujoco_batch

    runs = [ea.Physics(scene=patch_scene.name, sigma=s) for s in (0.3, 0.9)]
    numerics = ea.Numerics(perturbation=0.05)
    batched = simulate_mujoco_batch(runs, numerics, 2.0, threads=2)
    for physics, traj in zip(runs, batched):
        single = simulate_mujoco(physics, numerics, 2.0)
        np.testing.assert_array_equal(traj.nodes, single.nodes)
        np.testing.assert_array_equal(traj.polarity, single.polarity)


def test_automatic_euler_is_implicitfast_bit_for_bit(patch_scene):
    """A network's drag is joint damping, implicit in Euler (eulerdamp) as in implicitfast: the same step, so the
    automatic choice (Euler, cheaper) changes no bit of the trajectory."""
    physics = ea.Physics(scene=patch_scene.name, sigma=0.6, alignment_length=0.3)
    automatic = simulate_network_mujoco(physics, ea.Numerics(perturbation=0.05), 3.0)
    used = automatic.info["automatic_numerics"]
    assert used["integrator"] == "Euler" and used["dt"] == 0.000625  # Pi = 2: dt x Pi = TURN_RESOLUTION
    implicit = simulate_network_mujoco(
        physics, ea.Numerics(perturbation=0.05, integrator="implicitfast", dt=used["dt"]), 3.0
    )
    assert "automatic_numerics" not in implicit.info
    np.testing.assert_array_equal(automatic.nodes, implicit.nodes)
    np.testing.assert_array_equal(automatic.polarity, implicit.polarity)


def test_validate_holds_the_network_cases_within_one_percent():
    """elastoactive validate's cases of the lattice and the trapped unit, at the default (automatic) numerics: the
    observables and the node positions over the first 20 gamma / k within 1% of the reduced engine."""
    from elastoactive.checks.validate import compare, validation_cases

    cases = validation_cases("lattice") + validation_cases("trapped-unit")
    assert len(cases) >= 2
    for case in cases:
        comparison = compare(case.physics, ea.Numerics(), case.duration)
        assert comparison.worst() <= 0.01, (case.physics, comparison.errors)
        assert comparison.errors["angle"] > 0  # the node positions were compared


def test_preflight_refuses_an_unresolved_network_in_one_line():
    """diagnose.check_timestep hands network scenes to their own check: dt x (fastest rate) <= 0.2 and the
    overdamped mass limit, each refusal naming the setting."""
    from elastoactive.engines.timestep import check_timestep

    physics = ea.Physics(scene="lattice", rings=2, sigma=0.2, alignment_length=0.1)
    limits = check_timestep(physics, ea.Numerics())  # the automatic numerics pass
    assert limits.fastest_rate == pytest.approx(
        max(np.linalg.eigvalsh(dynamical_matrix(physics.scene_def.network(physics))).max(), 2.0)
    )
    with pytest.raises(ParameterError, match=r"^dt = 0.1 does not resolve .* use dt <= "):
        check_timestep(physics, ea.Numerics(dt=0.1, sample_dt=0.1))
    with pytest.raises(ParameterError, match=r"^mass_ratio = 0.5 is outside the overdamped limit"):
        check_timestep(physics, ea.Numerics(mass_ratio=0.5))


def test_units_on_a_slide_joint_are_the_units_on_the_site(patch_scene):
    """A free node's unit is an actuator on the node's x slide (a joint transmission, O(1) per step) rather than on
    its site (a Jacobian per step): the callback finds the same site, so the trajectory is the same to the bit."""
    from elastoactive.engines.network_mujoco import prepare_network
    from elastoactive.mjcf.network import build_network_spec

    physics = ea.Physics(scene=patch_scene.name, sigma=0.6, alignment_length=0.3)
    numerics = ea.Numerics(perturbation=0.05, dt=0.0025, integrator="Euler")
    network, model, data = prepare_network(physics, numerics)
    assert np.all(model.actuator_trntype == mujoco.mjtTrn.mjTRN_JOINT) and model.nu > 0
    spec = build_network_spec(network, physics, numerics)
    for actuator in spec.actuators:
        actuator.trntype, actuator.target = mujoco.mjtTrn.mjTRN_SITE, actuator.name.removesuffix("_polarity")
    on_site = spec.compile()
    site_data = mujoco.MjData(on_site)
    site_data.qpos[:], site_data.act[:] = data.qpos, data.act
    with follower_forces():
        mujoco.mj_step(model, data, nstep=400)
        mujoco.mj_step(on_site, site_data, nstep=400)
    assert np.abs(data.act - polarity_of_units(model, prepare_network(physics, numerics)[2])).max() > 1e-3  # turned
    np.testing.assert_array_equal(data.qpos, site_data.qpos)
    np.testing.assert_array_equal(data.act, site_data.act)

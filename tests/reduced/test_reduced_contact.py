"""The reduced model's extended terms: a free head, a harmonic trap and self-contact (analysis/reduced: system.py,
kernels.eval_rhs_general, contact.py, equations.drag_and_forces_reference)."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive import reduced as M
from elastoactive.core.errors import ParameterError
from elastoactive.reduced import ChainSystem, kernels
from elastoactive.reduced.contact import capsule_clearance, contact_forces, core_span

BETA = M.DEFAULT_BETA
R = 0.12


def _contact_systems():
    """Every chain kind with all the terms it admits on (contact, trap; a free head where allowed)."""
    common = dict(sigma=0.8, contact_radius=R, contact_stiffness=80.0, gamma_l=0.6)
    return [
        ChainSystem(n=7, clamped=False, head_free=True, trap=0.3, **common),
        ChainSystem(n=9, clamped=True, trap=0.2, **common),
        ChainSystem(n=12, clamped=False, trap=0.0, **common),  # N >= 10: the recursion's size, solved densely
        ChainSystem(n=9, clamped=False, pinned=True, delta=0.3, trap=0.1, **common),
        ChainSystem(n=6, n_chains=2, kappa=0.7, rho=1.3, trap=0.1, **common),
    ]


def _state(system, rng, spread=1.5):
    """A random state (angles as a random walk, the head anywhere near the origin)."""
    y = np.cumsum(rng.normal(0.0, spread, system.n_angles))
    return np.concatenate([y, rng.normal(0.0, 1.0, 2)]) if system.head_free else y


def _clearance(system, y):
    head = y[system.n_angles :] if system.head_free else None
    return min(
        capsule_clearance(y[ch * system.n : (ch + 1) * system.n], system.contact_radius, head if ch == 0 else None)
        for ch in range(system.n_chains)
    )


def _overlapping_states(system, rng, count=25):
    """Random states in which some non-adjacent capsules overlap (but their cores do not meet)."""
    out = []
    while len(out) < count:
        y = _state(system, rng)
        if -2 * R + 0.02 < _clearance(system, y) < 0.0:
            out.append(y)
    return out


def _hairpin(n=9):
    """A chain folded back on itself at joint 4 (links 0-3 out along x, 5-8 back), slightly open."""
    return np.array([0.0] * 4 + [np.pi - 0.3] + [np.pi] * (n - 5))


# ------------------------------------------------------------------------------------------------
# the record
# ------------------------------------------------------------------------------------------------
def test_new_fields_default_off_and_keep_old_records():
    plain = ChainSystem(7, 1, True, False, 0.8)
    assert plain[:5] == (7, 1, True, False, 0.8)
    assert plain.head_free is False and plain.trap == 0.0 and plain.contact_radius == 0.0
    assert not plain.extended and plain.state_size == 7 == plain.n_angles
    free = ChainSystem(n=7, clamped=False, head_free=True)
    assert free.extended and free.state_size == 9 and free.n_head == 2
    assert ChainSystem(n=7, trap=0.1).extended and ChainSystem(n=7, contact_radius=0.1, contact_stiffness=1).extended
    assert 0.0 < core_span(0.1)[0] < core_span(0.1)[1] < 1.0 and M.CONTACT_LENGTH == 0.7


@pytest.mark.parametrize(
    "kw, words",
    [
        (dict(head_free=True, clamped=True), "head_free"),
        (dict(head_free=True, clamped=False, n_chains=2), "head_free"),
        (dict(head_free=True, clamped=False, pinned=True), "head_free"),
        (dict(trap=-1.0), "trap"),
        (dict(trap=np.inf), "trap"),
        (dict(contact_radius=0.1), "contact_stiffness"),
        (dict(contact_radius=0.35, contact_stiffness=1.0), "contact_radius"),
        (dict(contact_radius=-0.1, contact_stiffness=1.0), "contact_radius"),
        (dict(contact_radius=0.1, contact_stiffness=-1.0), "contact_stiffness"),
    ],
)
def test_typed_rejects_what_the_kernels_cannot_solve(kw, words):
    with pytest.raises(ParameterError, match=words):
        ChainSystem(n=7, **kw).typed()


# ------------------------------------------------------------------------------------------------
# kernel against its plain-numpy twin
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("index", range(5))
def test_kernel_matches_plain_twin_in_contact(index):
    system = _contact_systems()[index].typed()
    rng = np.random.default_rng(index)
    fast = M.rhs(system, beta=BETA)
    slow = M.rhs_reference(system, beta=BETA)
    without = M.rhs_reference(system._replace(contact_radius=0.0, contact_stiffness=0.0), beta=BETA)
    pushed = 0.0
    for y in _overlapping_states(system, rng):
        ref = slow(0.0, y)
        assert ref.shape == (system.state_size,)
        np.testing.assert_allclose(fast(0.0, y), ref, rtol=0, atol=1e-12 * max(1.0, np.max(np.abs(ref))))
        pushed = max(pushed, np.max(np.abs(ref - without(0.0, y))))
    assert pushed > 0.1  # contact acted in these states


def test_kernel_matches_plain_twin_with_force_factors():
    system = _contact_systems()[0].typed()
    rng = np.random.default_rng(7)
    fac = 1.0 + 0.3 * rng.standard_normal(system.n_angles)
    fast = M.rhs(system, beta=BETA, factor=fac)
    slow = M.rhs_reference(system, beta=BETA, factor=fac)
    for y in _overlapping_states(system, rng, count=5):
        ref = slow(0.0, y)
        np.testing.assert_allclose(fast(0.0, y), ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))


def test_an_end_on_another_core_has_the_documented_force():
    """Link 3's near core end placed exactly on link 0's core (no separation direction): the force is K 2R along
    -n_0 (away from core 0, on the side of link 3's own core), in the kernel and in its twin alike."""
    s_a, _ = core_span(R)
    v = np.array([-0.5, s_a])  # e_1 + e_2 puts particle 2 at (0.5, s_a), link 3 points down
    mid, half = np.arctan2(v[1], v[0]), np.arccos(np.hypot(*v) / 2)
    theta = np.array([0.0, mid - half, mid + half, -np.pi / 2])
    system = ChainSystem(n=4, clamped=True, sigma=0.0, contact_radius=R, contact_stiffness=80.0).typed()
    e = np.stack([np.cos(theta), np.sin(theta)], 1)
    pivots = np.vstack([np.zeros(2), np.cumsum(e, 0)[:-1]])
    assert capsule_clearance(theta, R) == pytest.approx(-2 * R, abs=1e-12)
    points, energy = contact_forces(pivots, e, R, system.contact_stiffness)
    on_end = [f for link, s, f in points if link == 3 and s == s_a]  # link 3's near end (also as a touched point)
    assert any(np.allclose(f, (0.0, -system.contact_stiffness * 2 * R), atol=1e-9) for f in on_end)
    ref = M.rhs_reference(system, beta=BETA)(0.0, theta)
    np.testing.assert_allclose(M.rhs(system, beta=BETA)(0.0, theta), ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))
    assert np.all(np.isfinite(ref)) and energy >= 0.5 * system.contact_stiffness * (2 * R) ** 2


def test_general_kernel_reduces_to_the_old_paths_without_new_terms():
    """eval_rhs_general on a record with every extended term off (called directly) agrees with the dense and
    recursive paths to round-off: the same D and f, assembled otherwise."""
    rng = np.random.default_rng(3)
    for system in (
        ChainSystem(n=7, sigma=0.8, gamma_l=0.5),
        ChainSystem(n=12, clamped=False, sigma=0.4),
        ChainSystem(n=9, clamped=False, pinned=True, delta=0.2, sigma=2.0),
        ChainSystem(n=5, n_chains=2, kappa=0.5, rho=4 / 3, sigma=0.8),
    ):
        system = system.typed()
        L, C, X, lam = kernels.make_general_workspace(system.n_chains, system.n, system.n_angles)
        fac = np.ones(system.n_angles)
        for _ in range(5):
            th = 0.4 * rng.standard_normal(system.n_angles)
            out = np.empty(system.n_angles)
            kernels.eval_rhs_general(th, fac, system, BETA, out, L, C, X, lam)
            ref = M.rhs(system, beta=BETA)(0.0, th)
            np.testing.assert_allclose(out, ref, rtol=0, atol=1e-12 * max(1.0, np.max(np.abs(ref))))


def test_contact_out_of_reach_changes_nothing_but_round_off():
    """Contact on but no capsules overlapping: the general path runs (not bit for bit the old one), and agrees with
    the system without contact to round-off, over a whole solve too. Without any extended term the old path runs:
    bit for bit the same numbers as a record built without the new fields."""
    rng = np.random.default_rng(4)
    for base in (
        ChainSystem(n=7, sigma=0.8),
        ChainSystem(n=17, clamped=False, sigma=0.2),
        ChainSystem(n=7, clamped=False, pinned=True, delta=0.1, sigma=1.0),
        ChainSystem(n=5, n_chains=2, kappa=0.5, sigma=0.8),
    ):
        contact = base._replace(contact_radius=0.1, contact_stiffness=1e3)
        th = 0.1 * rng.standard_normal(base.n_angles)
        if base.pinned:
            th = M.project_on_pins(0.5 * np.sin(np.linspace(0.3, np.pi - 0.3, base.n)), base.delta)
        assert _clearance(contact.typed(), th) > 0.3
        a, b = M.rhs(base, beta=BETA)(0.0, th), M.rhs(contact, beta=BETA)(0.0, th)
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-13 * max(1.0, np.max(np.abs(a))))
        t = np.linspace(0.0, 10.0, 21)
        ya, _ = M.solve_ode(base, t, th, rtol=1e-10, atol=1e-10, method="numba-DOP853", beta=BETA)
        yb, _ = M.solve_ode(contact, t, th, rtol=1e-10, atol=1e-10, method="numba-DOP853", beta=BETA)
        assert np.all([_clearance(contact.typed(), y) > 0 for y in yb])
        np.testing.assert_allclose(yb, ya, rtol=0, atol=1e-8)
        # the new fields at their defaults: the record is the old one, bit for bit
        old = ChainSystem(*base[:12])
        assert np.array_equal(M.rhs(old, beta=BETA)(0.0, th), a)


# ------------------------------------------------------------------------------------------------
# the drag matrix with a free head; internal forces
# ------------------------------------------------------------------------------------------------
def test_drag_matrix_with_a_free_head_is_positive_definite_and_needs_the_heads_drag():
    rng = np.random.default_rng(5)
    system = ChainSystem(n=7, clamped=False, head_free=True, gamma_l=0.3).typed()
    for _ in range(20):
        y = _state(system, rng)
        D = M.drag_matrix(system, y)
        ref, _ = M.drag_and_forces_reference(system, y)
        np.testing.assert_allclose(D, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))
        assert D.shape == (9, 9) and np.allclose(D, D.T) and np.min(np.linalg.eigvalsh(D)) > 1e-6
        # the first pendulum swinging about particle 0 while the head slides moves no particle: only the head's
        # own drag resists it (without it D would be singular)
        q = np.zeros(9)
        q[0] = 1.0
        q[7:] = np.sin(y[0]), -np.cos(y[0])  # -n_0
        assert q @ D @ q == pytest.approx(system.gamma_t, rel=1e-12)


def test_contact_is_internal_the_drag_on_a_free_chain_sums_to_zero():
    """A free chain (free head, no trap, sigma = 0) in contact: springs and contacts are internal forces, so the
    drag forces on all particles and the head sum to zero, and so do their torques, while contact moves it."""
    system = ChainSystem(
        n=9, clamped=False, head_free=True, contact_radius=R, contact_stiffness=200.0, gamma_l=0.4
    ).typed()
    rng = np.random.default_rng(6)
    f = M.rhs(system, beta=BETA)
    for y in _overlapping_states(system, rng, count=10):
        q = f(0.0, y)
        n = system.n
        th, head, hv = y[:n], y[n:], q[n:]
        e = np.stack([np.cos(th), np.sin(th)], 1)
        nrm = np.stack([-np.sin(th), np.cos(th)], 1)
        pos = head + np.cumsum(e, 0)
        vel = hv + np.cumsum(nrm * q[:n, None], 0)

        def drag(k, v):
            return -(system.gamma_l * np.outer(e[k], e[k]) + system.gamma_t * np.outer(nrm[k], nrm[k])) @ v

        forces = [drag(k, vel[k]) for k in range(n)] + [drag(0, hv)]
        points = list(pos) + [head]
        total = np.sum(forces, axis=0)
        torque = sum(p[0] * F[1] - p[1] * F[0] for p, F in zip(points, forces))
        scale = np.max(np.abs(forces))
        assert scale > 1.0  # the contact drives real motion
        assert np.max(np.abs(total)) < 1e-11 * scale
        assert abs(torque) < 1e-10 * scale * np.max(np.abs(pos))


# ------------------------------------------------------------------------------------------------
# dynamics
# ------------------------------------------------------------------------------------------------
def test_potential_never_increases_without_activity():
    """sigma = 0: D q' = -dU/dq, so U (springs + trap + contact) decreases along every solution."""
    system = ChainSystem(n=9, clamped=False, head_free=True, trap=1.0, contact_radius=0.1, contact_stiffness=300.0)
    t = np.linspace(0.0, 30.0, 151)
    y, info = M.solve_ode(
        system, t, _hairpin(), head0=(-2.0, 0.0), rtol=1e-10, atol=1e-10, method="numba-DOP853", beta=BETA
    )
    assert y.shape == (t.size, 11)
    U = np.array([M.potential_reference(system, s) for s in y])
    assert np.max(np.diff(U)) <= 1e-8 * U[0] and U[-1] < 0.8 * U[0]
    clearance = capsule_clearance(y[:, :9], 0.1, y[:, 9:])
    assert np.min(clearance) < 0  # it got pressed into contact


def test_straight_free_chain_in_a_trap_relaxes_to_the_centre():
    system = ChainSystem(n=7, clamped=False, head_free=True, trap=0.1)
    t = np.linspace(0.0, 150.0, 31)
    y, _ = M.solve_ode(system, t, np.full(7, 0.3), head0=(3.0, 1.0), rtol=1e-9, atol=1e-9, beta=BETA)
    th, head = y[-1, :7], y[-1, 7:]
    particles = head + np.cumsum(np.stack([np.cos(th), np.sin(th)], 1), 0)
    nodes = (particles.sum(0) + head) / 8  # the trap's force -k (sum r_i + h) vanishes at rest
    assert np.hypot(*nodes) < 1e-4 and np.ptp(th) < 1e-6  # still straight (no bending force acted)
    assert np.hypot(*particles.mean(0)) < 0.6  # the particles' centre: within half a link of the trap's centre
    assert np.hypot(*y[0, 7:] - (3.0, 1.0)) == 0.0


def test_pressed_fold_overlaps_by_force_over_stiffness():
    """A folded N = 9 chain (sigma = 0) squeezed by a trap: the penalty's overlap is about force / stiffness, so it
    shrinks tenfold when K grows tenfold, and it is bounded by the trap's total force over K."""
    t = np.linspace(0.0, 40.0, 41)
    depth = {}
    for K in (300.0, 3000.0):
        system = ChainSystem(n=9, clamped=False, head_free=True, trap=1.0, contact_radius=0.1, contact_stiffness=K)
        y, _ = M.solve_ode(
            system, t, _hairpin(), head0=(-2.0, 0.0), rtol=1e-8, atol=1e-8, method="numba-DOP853", beta=BETA
        )
        clearance = capsule_clearance(y[:, :9], 0.1, y[:, 9:])
        th, head = y[-1, :9], y[-1, 9:]
        nodes = np.vstack([head, head + np.cumsum(np.stack([np.cos(th), np.sin(th)], 1), 0)])
        squeeze = 1.0 * np.sum(np.hypot(*nodes.T))  # the trap's total force on the chain
        assert clearance[-1] < 0 and np.min(clearance) >= -squeeze / K
        depth[K] = -clearance[-1]
    assert 8.0 < depth[300.0] / depth[3000.0] < 12.0


def test_jacobian_with_extended_terms_is_a_finite_difference_of_the_rhs():
    rng = np.random.default_rng(8)
    for system in _contact_systems():
        system = system.typed()
        y = _overlapping_states(system, rng, count=1)[0]
        J = M.jacobian(system, beta=BETA)(0.0, y)
        f = M.rhs(system, beta=BETA)
        h = 1e-5
        ref = np.empty_like(J)
        for k in range(y.size):  # a second difference: forward-backward with another step
            dy = np.zeros(y.size)
            dy[k] = h
            ref[:, k] = (f(0.0, y + dy) - f(0.0, y - dy)) / (2 * h)
        np.testing.assert_allclose(J, ref, rtol=0, atol=2e-5 * np.max(np.abs(ref)))
        assert J.shape == (system.state_size,) * 2
        assert np.isfinite(M.stiffness(system, y, beta=BETA))
    # without the extended terms the analytic kernel stays
    plain = ChainSystem(n=7, sigma=0.8)
    assert M.jacobian(plain, beta=BETA).__name__ == "jac"


def test_solvers_take_and_return_the_whole_state():
    system = ChainSystem(
        n=7, clamped=False, head_free=True, trap=0.1, sigma=0.3, contact_radius=0.1, contact_stiffness=100.0
    )
    th0 = 0.05 * np.arange(7)
    t = np.linspace(0.0, 2.0, 11)
    a, info = M.solve_ode(system, t, th0, head0=(0.5, -0.2), rtol=1e-9, atol=1e-9, beta=BETA)
    b, _ = M.solve_ode(system, t, np.concatenate([th0, [0.5, -0.2]]), rtol=1e-9, atol=1e-9, beta=BETA)
    assert a.shape == (11, 9) and np.array_equal(a, b) and info["method"] == "numba-DOP853"
    c, _ = M.solve_ode(system, t, th0, head0=(0.5, -0.2), rtol=1e-9, atol=1e-9, method="Radau", beta=BETA)
    np.testing.assert_allclose(c, a, atol=1e-6)
    for scheme in M.SDE_SCHEMES:
        s, _ = M.solve_sde(
            system,
            t,
            th0,
            head0=(0.5, -0.2),
            dt=1e-3,
            beta=BETA,
            scheme=scheme,
            factors=lambda steps: np.ones((steps.size, 7)),
        )
        assert s.shape == (11, 9)
        np.testing.assert_allclose(s, a, atol=5e-3)
    with pytest.raises(ParameterError, match="head0"):
        M.solve_ode(ChainSystem(n=7), t, th0, head0=(0.0, 0.0), rtol=1e-9, atol=1e-9, beta=BETA)
    with pytest.raises(ParameterError, match="theta0"):
        M.solve_ode(system, t, np.zeros(8), rtol=1e-9, atol=1e-9, beta=BETA)
    # a stiff contact (K = 1e5, in contact at t = 0) makes method=None choose the implicit method
    stiff = ChainSystem(n=9, clamped=False, head_free=True, trap=1.0, contact_radius=0.1, contact_stiffness=1e5)
    fold = _hairpin() + np.array([0.0] * 4 + [0.12] + [0.0] * 4)
    assert capsule_clearance(fold, 0.1) < 0
    _, info = M.solve_ode(stiff, np.linspace(0.0, 0.2, 3), fold, rtol=1e-6, atol=1e-8, beta=BETA)
    assert info["method"] == "Radau" and info["stiffness"] > M.STIFF_RADIUS


@pytest.mark.parametrize("index", range(5))
def test_inertial_kernel_matches_plain_twin_in_contact(index):
    """The inertial model with the extended terms (eval_rhs_inertial_general) against its plain twin; state (q, q')."""
    system = _contact_systems()[index]._replace(mass_ratio=0.05).typed()
    nq = system.n_angles + system.n_head
    assert system.state_size == 2 * nq
    rng = np.random.default_rng(10 + index)
    fast = M.rhs(system, beta=BETA)
    slow = M.rhs_inertial_reference(system, beta=BETA)
    for q in _overlapping_states(system, rng, count=10):
        y = np.concatenate([q, rng.normal(0.0, 1.0, nq)])
        ref = slow(0.0, y)
        np.testing.assert_allclose(fast(0.0, y), ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))
    if system.head_free:
        Mq = M.mass_matrix(system, q)
        assert Mq.shape == (nq, nq) and np.min(np.linalg.eigvalsh(Mq)) > 0
        # a rigid translation of the whole chain moves N particles and the head's bead: m (N + 1)
        assert Mq[-1, -1] == pytest.approx(system.mass_ratio * (system.n + 1))


def test_small_mass_approaches_the_overdamped_free_chain():
    """A free chain in a trap with particle masses m -> 0: the inertial solution (state (q, q')) tends to the
    overdamped one, the gap shrinking about as m."""
    base = ChainSystem(n=7, clamped=False, head_free=True, trap=0.1, sigma=0.3)
    t = np.linspace(0.0, 20.0, 5)
    th0 = 0.1 * np.arange(7)
    ref, _ = M.solve_ode(base, t, th0, head0=(1.0, 0.0), rtol=1e-9, atol=1e-9, beta=BETA)
    gaps = []
    for m in (0.02, 0.002):
        y, info = M.solve_ode(base._replace(mass_ratio=m), t, th0, head0=(1.0, 0.0), rtol=1e-9, atol=1e-9, beta=BETA)
        assert y.shape == (5, 9) and info["model"] == "inertial"
        gaps.append(np.max(np.abs(y - ref)))
    assert gaps[1] < 0.2 * gaps[0] and gaps[1] < 2e-3
    full, _ = M.solve_inertial(
        base._replace(mass_ratio=0.002), t, th0, head0=(1.0, 0.0), rtol=1e-9, atol=1e-9, beta=BETA
    )
    assert full.shape == (5, 18)
    noisy, info = M.solve_sde(
        base._replace(mass_ratio=0.002),
        t,
        th0,
        head0=(1.0, 0.0),
        dt=0.01,
        beta=BETA,
        factors=lambda steps: np.ones((steps.size, 7)),
    )
    assert noisy.shape == (5, 9) and info["model"] == "inertial"
    np.testing.assert_allclose(noisy, full[:, :9], atol=1e-4)


def test_capsule_clearance():
    # a U: links 0 and 2 parallel, 1 apart (link 1 between them): clearance 1 - 2R; a head only shifts it
    u = np.array([0.0, np.pi / 2, np.pi])
    assert capsule_clearance(u, 0.1) == pytest.approx(0.8, abs=1e-12)
    assert capsule_clearance(u, 0.1, head=(3.0, -1.0)) == pytest.approx(0.8, abs=1e-12)
    many = capsule_clearance(np.tile(u, (4, 1)), 0.1, head=np.zeros((4, 2)))
    assert many.shape == (4,) and np.allclose(many, 0.8)
    # neighbours never count; fewer than 3 links: no pair
    assert capsule_clearance(np.zeros(2), 0.1) == np.inf and capsule_clearance(np.zeros(4), 0.1) > 0.9
    # a hairpin folded flat: link 3 runs back over link 0, their cores coincide: clearance -2R
    assert capsule_clearance(np.array([0.0, 0.0, np.pi, np.pi]), 0.1) == pytest.approx(-0.2, abs=1e-12)
    # random chains against a brute-force sampling of the cores
    rng = np.random.default_rng(9)
    theta = np.cumsum(rng.normal(0.0, 1.2, (12, 6)), axis=1)
    head = rng.normal(0.0, 1.0, (12, 2))
    got = capsule_clearance(theta, R, head=head)
    s_a, s_b = core_span(R)
    s = np.linspace(s_a, s_b, 201)
    for k in range(12):
        e = np.stack([np.cos(theta[k]), np.sin(theta[k])], 1)
        pivots = head[k] + np.vstack([np.zeros(2), np.cumsum(e, 0)[:-1]])
        pts = pivots[:, None, :] + s[None, :, None] * e[:, None, :]  # (link, sample, 2)
        best = (
            min(
                np.min(np.hypot(*(pts[i][:, None, :] - pts[j][None, :, :]).transpose(2, 0, 1)))
                for i in range(6)
                for j in range(i + 2, 6)
            )
            - 2 * R
        )
        assert best - 3e-3 < got[k] <= best + 1e-12

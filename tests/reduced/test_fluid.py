"""The reduced equations of chains in a fluid (elastoactive.reduced.fluid): the compiled kernel against the equations
written out (J^T M^-1 J q' = J^T F - dU/dq), and against the 3D chain's model where the mobility is its local drag."""

import numpy as np
import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.reduced import chain3d, fluid

R = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])  # a cilium's: clamp axis e_x -> e_z


def bent(n, chains=1, seed=0, planar=False):
    """Chain-frame tangents (C, N, 3) bent off the clamp axis, slightly off unit length (the kernel normalises)."""
    rng = np.random.default_rng(seed)
    t = np.zeros((chains, n, 3))
    t[..., 0] = 1.0
    t[..., 1] = 0.6 * rng.normal(size=(chains, n))
    t[..., 2] = 0.0 if planar else 0.6 * rng.normal(size=(chains, n))
    t /= np.linalg.norm(t, axis=-1)[..., None]
    return t * (1.0 + (0.0 if planar else 1e-3 * rng.normal(size=(chains, n, 1))))


def beds(chains=1, mobility="identity", radius=0.0, gamma_l=1.0, coupling=0.0, spacing=3.0, sigma=2.3):
    bases = np.array([[c * spacing, 0.0, 1.5] for c in range(chains)])
    return fluid.Beds(7, sigma, bases, R, mobility, radius, gamma_l, coupling).checked()


@pytest.mark.parametrize(("mobility", "gamma_l"), [("identity", 1.0), ("local", 1.0), ("local", 0.5), ("local", 2.0)])
def test_the_local_drag_is_the_3d_chain_s_to_round_off(mobility, gamma_l):
    t = bent(7)
    expected = chain3d.rhs(t[0], chain3d.Chain3D(7, 2.3, gamma_l))
    np.testing.assert_allclose(fluid.rhs(t, beds(1, mobility, gamma_l=gamma_l))[0], expected, rtol=0, atol=1e-13)


@pytest.mark.parametrize("mobility", ["rpy", "rpb", "local"])
def test_the_kernel_solves_the_equations_as_written(mobility):
    radius = 0.0 if mobility == "local" else 0.3
    b = beds(2, mobility, radius, gamma_l=1.0, coupling=0.7)
    t = bent(7, chains=2, seed=3)
    np.testing.assert_allclose(fluid.rhs(t, b), fluid.rhs_reference(t, b), rtol=0, atol=1e-12)


@pytest.mark.parametrize("mobility", ["rpy", "rpb"])
def test_many_chains_solve_the_equations_as_written_by_conjugate_gradients(mobility):
    """Beyond DIRECT_UP_TO links the tensions come from preconditioned conjugate gradients: still the equations' rate
    (the reference solves them densely)."""
    chains = fluid.DIRECT_UP_TO // 7 + 2
    b = beds(chains, mobility, 0.2, spacing=1.5)
    t = bent(7, chains=chains, seed=8) * np.array([1.0, 0.3, 0.3])
    t /= np.linalg.norm(t, axis=-1)[..., None]
    assert chains * 7 > fluid.DIRECT_UP_TO
    np.testing.assert_allclose(fluid.rhs(t, b), fluid.rhs_reference(t, b), rtol=0, atol=1e-10)


def test_a_cutoff_leaves_out_the_far_chains_mobility_and_nothing_else():
    """With a cutoff the kernel solves the equations with M's blocks between chains beyond it zeroed (the reference
    zeroes them in the dense matrix); chains alone within it move as alone, and an infinite cutoff is the exact
    mobility."""
    t = bent(7, chains=4, seed=9) * np.array([1.0, 0.4, 0.4])
    t /= np.linalg.norm(t, axis=-1)[..., None]
    exact = beds(4, "rpb", 0.2)
    cut = exact._replace(cutoff=4.0)  # neighbours (3 apart) interact, the next ones (6 apart) do not
    np.testing.assert_allclose(fluid.rhs(t, cut), fluid.rhs_reference(t, cut), rtol=0, atol=1e-12)
    assert np.abs(fluid.rhs(t, cut) - fluid.rhs(t, exact)).max() > 1e-6
    np.testing.assert_array_equal(fluid.rhs(t, exact._replace(cutoff=np.inf)), fluid.rhs(t, exact))
    alone = fluid.rhs(t, exact._replace(cutoff=1.0))
    for c in range(4):
        single = fluid.Beds(7, 2.3, exact.bases[c : c + 1], R, "rpb", 0.2).checked()
        np.testing.assert_allclose(alone[c], fluid.rhs(t[c : c + 1], single)[0], rtol=0, atol=1e-13)


def test_chains_far_apart_in_free_space_move_as_alone():
    """The RPY coupling decays like a / r: at 10^7 l apart a chain moves as it does alone, to 1e-6."""
    t = bent(7, chains=2, seed=5)
    pair = fluid.rhs(t, beds(2, "rpy", 0.3, spacing=1e7))
    for c in range(2):
        alone = fluid.Beds(7, 2.3, np.array([[0.0, 0.0, 1.5]]), R, "rpy", 0.3).checked()
        np.testing.assert_allclose(pair[c], fluid.rhs(t[c : c + 1], alone)[0], rtol=0, atol=1e-6)


def test_the_wall_slows_a_chain_that_the_free_space_lets_move():
    """Near the wall every bead is more resisted (Faxen): the same forces move the chain less."""
    t = bent(7, seed=2)
    free, wall = (np.linalg.norm(fluid.rhs(t, beds(1, m, 0.3))) for m in ("rpy", "rpb"))
    assert wall < free


def test_a_beat_across_the_wall_stays_in_its_plane():
    """Cilia beating in the lab's xz plane (their own xy plane): the wall's mirror symmetry y -> -y keeps them there,
    the chain-frame z rows exact zeros as in the 3D chain's model."""
    t = bent(7, chains=2, seed=1, planar=True)
    rate = fluid.rhs(t, beds(2, "rpb", 0.3, coupling=0.5))
    assert np.all(rate[..., 2] == 0.0)


def test_the_fluid_forces_move_the_beads_as_the_equations_do():
    """M F = v: the forces on the fluid, pushed back through the mobility, give the beads' velocities."""
    b = beds(2, "rpb", 0.3)
    t = bent(7, chains=2, seed=4)
    t /= np.linalg.norm(t, axis=-1)[..., None]
    forces = fluid.fluid_forces(t, b)
    x = fluid.lab_positions(t, b).reshape(-1, 3)
    velocity = np.cumsum(fluid.rhs(t, b), axis=-2) @ R.T
    m = fluid.mobility_matrix(x, x, b)
    np.testing.assert_allclose(m @ forces.ravel(), velocity.ravel(), atol=1e-12)


def test_a_solve_keeps_the_tangents_unit_and_reaches_its_end():
    b = beds(2, "rpb", 0.2, sigma=1.0)
    ts = np.linspace(0.0, 5.0, 11)
    t0 = bent(7, chains=2, seed=6)
    path = fluid.solve_fluid(b, ts, t0 / np.linalg.norm(t0, axis=-1)[..., None])
    assert path.shape == (11, 2, 7, 3)
    np.testing.assert_allclose(np.linalg.norm(path[-1], axis=-1), 1.0, atol=1e-6)


@pytest.mark.parametrize(
    ("changes", "named"),
    [
        ({"mobility": "rpb", "radius": 0.0}, "radius"),
        ({"mobility": "local", "radius": 0.2}, "radius"),
        ({"mobility": "rpy", "radius": 0.2, "gamma_l": 2.0}, "gamma_l"),
        ({"mobility": "stokes"}, "mobility"),
        ({"tip_coupling": -1.0}, "tip_coupling"),
        ({"rotation": np.ones((3, 3))}, "rotation"),
        ({"mobility": "rpb", "radius": 0.2, "cutoff": 0.0}, "cutoff"),
        ({"interaction": "frozen"}, "interaction"),
    ],
)
def test_a_record_out_of_range_is_refused_naming_its_field(changes, named):
    with pytest.raises(ParameterError, match=named):
        beds(1)._replace(**changes).checked()


def test_the_compiled_loop_takes_scipy_s_steps():
    """DOP853 compiled around the kernel (reduced.dop853_loop) against scipy's solve_ivp(DOP853) on it: the same
    steps, so the same samples to round-off."""
    b = beds(2, "rpb", 0.2, sigma=1.0)
    ts = np.linspace(0.0, 5.0, 11)
    t0 = bent(7, chains=2, seed=6)
    compiled = fluid.solve_fluid(b, ts, t0, rtol=1e-6, atol=1e-8)
    scipy = fluid.solve_fluid(b, ts, t0, rtol=1e-6, atol=1e-8, method="DOP853")
    np.testing.assert_allclose(compiled, scipy, rtol=0, atol=1e-11)


def test_the_compiled_loop_resumes_bit_for_bit_and_reports_its_time():
    """A loop that cuts the compiled calls at 3 steps each gives the same bits as one call, told each time reached."""
    b = beds(2, "rpy", 0.2, sigma=1.0)
    ts = np.linspace(0.0, 3.0, 7)
    t0 = bent(7, chains=2, seed=2)
    reached = []

    def cut(call, paused, told, steps):
        status = paused
        while status == paused:
            status = call(3)
            reached.append(told())
        return status

    whole = fluid.solve_fluid(b, ts, t0)
    np.testing.assert_array_equal(fluid.solve_fluid(b, ts, t0, loop=cut), whole)
    assert len(reached) > 3 and reached == sorted(reached) and reached[-1] == 3.0


def test_a_start_through_the_wall_stops_the_run_in_one_line():
    """Beads below the wall have no mobility (the kernel's rate is NaN there): the loop takes no step and says so."""
    down = np.tile([[-0.7, 0.7, 0.0]], (1, 7, 1))  # chain x is the lab's z: pointing down from h = 0.5
    b = fluid.Beds(7, 1.0, np.array([[0.0, 0.0, 0.5]]), R, "rpb", 0.2).checked()
    assert np.all(np.isnan(fluid.rhs(down, b)))
    with pytest.raises(RuntimeError, match="round-off at t = 0"):
        fluid.solve_fluid(b, np.linspace(0.0, 5.0, 3), down)


def test_an_unknown_method_is_refused_naming_it():
    with pytest.raises(ParameterError, match="method"):
        fluid.solve_fluid(beds(1, "rpy", 0.2), np.linspace(0, 1, 3), bent(7), method="RK45")


def test_the_interaction_is_extrapolated_by_size_and_only_between_chains_in_a_fluid():
    wall = beds(2, "rpb", 0.2)
    many = beds(fluid.EXACT_UP_TO // 7 + 1, "rpb", 0.2)
    assert not wall.extrapolated and many.extrapolated
    assert not many._replace(interaction="exact").extrapolated
    assert wall._replace(interaction="extrapolated").extrapolated
    assert not beds(1, "rpb", 0.2)._replace(interaction="extrapolated").extrapolated
    assert not beds(fluid.EXACT_UP_TO // 7 + 1, "local")._replace(interaction="extrapolated").extrapolated


def _row_of_three(interaction):
    return beds(3, "rpb", 0.1, sigma=2.3)._replace(interaction=interaction)


def test_the_extrapolated_interaction_follows_the_exact_path_closer_with_smaller_steps():
    """Each chain's own block exact at every evaluation, the others' flow exact at each step's start and extrapolated
    over the step: the path is not the exact one (the route is taken), and its distance from it falls faster than
    the steps (rtol 1e-6 -> 1e-9 shrinks them about 2.4 times; the distance here falls about 5 times, in a fast
    transient from a bent start)."""
    ts = np.linspace(0.0, 4.0, 9)
    t0 = bent(7, chains=3, seed=4) * np.array([1.0, 0.3, 0.3])
    t0 /= np.linalg.norm(t0, axis=-1)[..., None]
    gap = []
    for rtol in (1e-6, 1e-9):
        exact = fluid.solve_fluid(_row_of_three("exact"), ts, t0, rtol=rtol, atol=rtol)
        extrapolated = fluid.solve_fluid(_row_of_three("extrapolated"), ts, t0, rtol=rtol, atol=rtol)
        gap.append(np.abs(extrapolated - exact).max())
    assert 0.0 < gap[0] < 0.2
    assert gap[1] < gap[0] / 4.0


def test_the_extrapolated_loop_resumes_bit_for_bit():
    """The record of the steps' starts carries over the compiled loop's calls: cut at 2 steps a call, the same bits."""
    ts = np.linspace(0.0, 2.0, 5)
    t0 = bent(7, chains=3, seed=5) * np.array([1.0, 0.3, 0.3])
    t0 /= np.linalg.norm(t0, axis=-1)[..., None]

    def cut(call, paused, told, steps):
        status = paused
        while status == paused:
            status = call(2)
        return status

    b = _row_of_three("extrapolated")
    whole = fluid.solve_fluid(b, ts, t0, rtol=1e-6, atol=1e-6)
    np.testing.assert_array_equal(fluid.solve_fluid(b, ts, t0, rtol=1e-6, atol=1e-6, loop=cut), whole)

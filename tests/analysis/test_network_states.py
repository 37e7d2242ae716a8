"""The named states of a network run on synthetic polarities with known answers, the depth of each node from the
edge, and the energy share of a degenerate pair read as one subspace whatever basis the eigensolver gives."""

import numpy as np
import pytest

from elastoactive.analysis.network import hexagonal_patch, ring_index, states
from elastoactive.analysis.network import observables as nobs
from elastoactive.networks.lattices import generate

T = np.linspace(0.0, 100.0, 2001)
STILL = states.still_rate(2.0, 1e-8)


def angles(rates, swing=0.0, phases=None):
    """(T, A) polarities turning at `rates` plus a swing of amplitude `swing` at frequency 0.3."""
    rates = np.asarray(rates, dtype=float)
    phases = np.zeros(rates.size) if phases is None else np.asarray(phases)
    return rates * T[:, None] + swing * np.sin(0.3 * T[:, None] + phases) + phases


DEPTHS = np.array([1, 1, 1, 2, 2, 3])


@pytest.mark.parametrize(
    "psi, name",
    [
        (np.ones((T.size, 6)) * 0.3 + 1e-6 * np.exp(-T)[:, None], "frozen"),
        (angles([0.5] * 6, swing=0.4, phases=np.arange(6)), "collective"),
        (angles([-0.5] * 6, swing=0.4, phases=np.arange(6)), "collective"),
        (angles([0.5, -0.5, 0.5, -0.5, 0.5, 0.5]), "mixed"),
        (angles([0.0, 0.0, 0.0, 0.4, 0.4, 0.5], swing=0.5), "heterogeneous"),
        (angles([0.1, 0.1, 0.1, 0.4, 0.4, 0.5]), "heterogeneous"),
        (angles([0.5, 0.5, 0.5, 0.2, 0.2, 0.5]), "irregular"),
        (angles([0.0] * 6, swing=0.5), "oscillating"),
    ],
)
def test_synthetic_states(psi, name):
    assert states.classify(T, psi, DEPTHS, STILL).name == name


def test_ring_rates_are_magnitudes_from_the_edge_in():
    named = states.classify(T, angles([-0.1, 0.1, -0.1, 0.4, -0.4, 0.5]), DEPTHS, STILL)
    assert named.name == "mixed"
    assert np.allclose(named.ring_rates, [0.1, 0.4, 0.5]) and list(named.ring_depths) == [1, 2, 3]
    assert named.edge_rate == pytest.approx(0.1) and named.bulk_rate == pytest.approx(0.5)
    assert named.counter_fraction == pytest.approx(0.5)


def test_a_slip_of_one_turn_breaks_collective():
    """One frequency to the window's resolution: a unit one turn behind the others over the window is not locked."""
    slow = 0.5 - 1.01 * states.FULL_TURN / (T[-1] - T[0])
    assert states.classify(T, angles([0.5] * 5 + [slow]), DEPTHS, STILL).name != "collective"
    assert states.classify(T, angles([0.5] * 5 + [0.5 - 0.02]), DEPTHS, STILL).name == "collective"


def test_still_level_follows_the_solver():
    assert states.still_rate(2.0) == pytest.approx(2e-3)
    assert states.still_rate(2.0, 1e-4) == pytest.approx(0.2)  # a loose solver: its error is not motion


def test_depth_counts_bonds_from_the_edge():
    for rings in (2, 3):
        pinned = states.depth(hexagonal_patch(rings, "pinned"))
        assert np.array_equal(pinned, rings - ring_index(rings))  # the pinned outer ring is 0
        assert np.array_equal(states.depth(hexagonal_patch(rings, "free")), pinned)  # its lower coordination
    kagome = generate("kagome", "hexagonal", 3, "pinned")
    assert states.depth(kagome)[kagome.pinned].max() == 0 and states.depth(kagome)[~kagome.pinned].min() == 1


def test_a_degenerate_pair_is_one_space_in_any_basis():
    values = np.array([1.0, 1.0, 3.0])
    rng = np.random.default_rng(0)
    u = rng.normal(size=(400, 3)) * [1.0, 0.5, 0.2]
    for angle in (0.0, 0.7, 2.1):
        c, s = np.cos(angle), np.sin(angle)
        vectors = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        modes = nobs.mode_energies(u, values, vectors)
        space = nobs.mode_space(modes, values)
        assert (space.rank, space.size) == (1, 2)
        expected = 0.5 * (u[:, :2] ** 2).mean(axis=0).sum() / (0.5 * (u**2 * values).mean(axis=0).sum())
        assert space.share == pytest.approx(expected, rel=1e-12)
    none = nobs.mode_space(nobs.mode_energies(np.zeros((5, 3)), values, np.eye(3), floor=1e-9), values)
    assert (none.rank, none.size) == (0, 0) and np.isnan(none.share)


@pytest.mark.parametrize(
    "psi",
    [
        angles([0.01] * 6),  # a steady turn of 1 rad over the window: a turn takes 628
        0.5 * (1.0 - np.exp(-T / 30.0))[:, None] * np.ones(6),  # a creep one way towards rest
        0.5 * np.sin(0.01 * T[:, None] + np.zeros(6)),  # a quarter of a slow swing: one way within the window
    ],
)
def test_one_way_by_less_than_a_turn_is_undetermined(psi):
    named = states.classify(T, psi, DEPTHS, STILL)
    assert named.name == "undetermined"
    assert named.note.startswith("the window of 100 gamma/k cannot tell a slow drift from an oscillation")
    assert named.needed_window > 100.0 and f"a window of {named.needed_window:.3g} or more" in named.note


def test_a_swing_seen_back_is_oscillating_and_a_long_window_turns():
    assert states.classify(T, 0.5 * np.sin(0.05 * T[:, None] + np.zeros(6)), DEPTHS, STILL).name == "oscillating"
    assert states.classify(T, angles([0.1] * 6), DEPTHS, STILL).name == "collective"  # 10 rad over the window
    assert states.classify(T, angles([0.0] * 6, swing=0.5), DEPTHS, STILL).note == ""


@pytest.mark.parametrize("duration, name", [(20.0, "undetermined"), (200.0, "collective")])
def test_a_turning_unit_is_named_on_a_window_long_enough(duration, name):
    """The trapped unit turning steadily (Pi = 3): 0.7 rad over a 20-long run's window of 10, collective over 200."""
    import elastoactive as ea

    run = ea.simulate(ea.Physics("trapped-unit", Pi=3.0, alignment_length=0.1), duration=duration, engine="reduced")
    assert ea.measure(run).network_state == name

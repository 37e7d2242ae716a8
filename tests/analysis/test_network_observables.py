"""elastoactive.analysis.network.observables: the modes a network's energy is ranked on (mode_energies), where equal
energies are equal whatever their last bits."""

import numpy as np
import pytest

from elastoactive.analysis.network import observables as nobs


def _two_modes(ratio):
    """Displacements on two non-degenerate modes (stiffness 2 and 4, the identity as their vectors) whose energies
    are in the ratio second : first = `ratio`, each as round-off leaves it."""
    values = np.array([2.0, 4.0])
    vectors = np.eye(2)
    phase = np.linspace(0.0, 2 * np.pi, 64, endpoint=False)
    motion = np.column_stack([np.cos(phase), np.sqrt(0.5 * ratio) * np.sin(phase)])
    return motion, values, vectors


def test_energies_equal_to_round_off_tie_to_the_lower_rank():
    """Two modes whose energies differ in their last bits only (the higher rank's larger) are a tie: ranked 1, 2."""
    motion, values, vectors = _two_modes(1.0 + 8e-16)
    modes = nobs.mode_energies(motion, values, vectors)
    assert modes.energy[1] > modes.energy[0]  # round-off alone would put the second mode first
    assert modes.energy[1] - modes.energy[0] < 1e-12 * modes.energy.max()
    assert modes.dominant_modes == (1, 2)
    assert modes.condensation == pytest.approx(1.0, rel=1e-12)


def test_a_real_difference_in_energy_still_ranks():
    """Energies that differ beyond round-off rank the more energetic first, whatever its rank."""
    motion, values, vectors = _two_modes(1.0 + 1e-6)
    assert nobs.mode_energies(motion, values, vectors).dominant_modes == (2, 1)


@pytest.mark.parametrize(
    "energy, ranked",
    [
        ([1.0, 1.0 + 1e-13, 1.0 - 1e-13], [0, 1]),  # a three-way tie: the two lowest ranks
        ([0.5, 1.0, 1.0 + 1e-13, 0.9], [1, 2]),
        ([0.5, 1.0 + 1e-6, 1.0, 0.5 + 1e-13], [1, 2]),
        ([0.2, 0.5 + 1e-13, 0.5, 1.0], [3, 1]),  # the tie is for second place
        ([3.0], [0]),
    ],
)
def test_ranked_modes_reads_equal_energies_as_equal(energy, ranked):
    assert nobs.ranked_modes(np.array(energy), 2).tolist() == ranked

"""A generated network is a network: a patch without a bond, or a boundary that pins no node, is refused in one line
naming the parameter, for every generator, patch and boundary."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.cli import main
from elastoactive.core.errors import ParameterError
from elastoactive.networks.geometry import BOUNDARIES
from elastoactive.networks.lattices import LATTICES, PATCHES, generate


@pytest.mark.parametrize("lattice", LATTICES)
@pytest.mark.parametrize("patch", PATCHES)
@pytest.mark.parametrize("boundary", BOUNDARIES)
def test_every_generated_network_has_bonds_and_its_pins(lattice, patch, boundary):
    for size in (1, 2):
        try:
            network = generate(lattice, patch, size, boundary)
        except ParameterError as refused:
            assert str(refused).startswith(f"size = {size}: ") and "\n" not in str(refused)
            continue
        assert len(network.bonds) > 0
        assert boundary == "free" or np.any(network.pinned)


def test_a_honeycomb_hexagon_of_size_1_is_refused():
    with pytest.raises(ParameterError, match=r"^size = 1: the honeycomb lattice .* 1 node and no bond.*size >= 2$"):
        generate("honeycomb", "hexagonal", 1, "pinned")


def test_a_dilution_that_removes_every_bond_is_refused():
    with pytest.raises(ParameterError, match=r"^dilution = 0.9 removes every bond of the square lattice"):
        generate("square", "hexagonal", 1, "pinned", 0.9)


def test_the_command_line_names_size(capsys):
    assert main(["run", "network", "--geometry", "honeycomb", "--size", "1", "--boundary", "pinned"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("elastoactive: error: size = 1: ") and err.count("\n") == 1

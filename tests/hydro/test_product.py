"""The matrix-free product equals the dense matrix's product, in free space and above the wall."""

import numpy as np
import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.hydro import apply, rpb, rpy


@pytest.mark.parametrize("wall", [False, True])
def test_the_product_equals_the_dense_matrix_times_the_forces(wall):
    rng = np.random.default_rng(4)
    x = rng.uniform([0.0, 0.0, 0.05], [1.5, 1.5, 1.5], size=(30, 3))  # some beads overlap each other and the wall
    x[7] = x[3]
    f = rng.normal(size=(30, 3))
    m = rpb(x, 0.2) if wall else rpy(x, 0.2)
    np.testing.assert_allclose(apply(x, 0.2, f, wall=wall).ravel(), m @ f.ravel(), rtol=0, atol=1e-13)


def test_bad_forces_and_beads_below_the_wall_are_named():
    x = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, -0.5]])
    with pytest.raises(ParameterError, match="forces"):
        apply(x, 0.1, np.zeros((3, 3)), wall=False)
    with pytest.raises(ParameterError, match="positions"):
        apply(x, 0.1, np.zeros((2, 3)), wall=True)

"""The linear stability of straight chains through the fluid (elastoactive.analysis.stability_fluid): the operator
built from the straight chains' mobility against the compiled right-hand side's numerical Jacobian, the local drag's
3D operator recovered, the planes' degeneracy where the symmetry keeps it (free space, a chain along the wall's
normal) and its splitting where it does not (a pair), and the local drag's onset as a / l -> 0."""

import numpy as np
import pytest

from elastoactive.analysis import stability3d
from elastoactive.analysis import stability_fluid as sf
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import Physics
from elastoactive.reduced.fluid import Beds
from elastoactive.scenes.cilium import ROTATION

ONE = np.array([[0.0, 0.0, 0.5]])
PAIR = np.array([[0.0, 0.0, 0.5], [2.0, 0.0, 0.5]])


def beds(mobility, radius, bases=ONE, n=6, coupling=0.0, sigma=0.9):
    return Beds(n, sigma, bases, ROTATION, mobility, radius, tip_coupling=coupling).checked()


@pytest.mark.parametrize(
    ("mobility", "radius", "bases", "coupling"),
    [("local", 0.0, PAIR, 0.4), ("rpy", 0.25, ONE, 0.0), ("rpb", 0.25, ONE, 0.0), ("rpb", 0.2, PAIR, 0.3)],
)
def test_the_operator_is_the_right_hand_side_s_jacobian(mobility, radius, bases, coupling):
    b = beds(mobility, radius, bases, coupling=coupling)
    built = sf.linear_operator_fluid(b, b.sigma)
    numerical = sf.numerical_operator(b)
    np.testing.assert_allclose(built, numerical, rtol=0, atol=1e-8 * np.abs(built).max())


@pytest.mark.parametrize("mobility", ["local", "identity"])
def test_the_local_drag_gives_the_3d_chain_s_operator(mobility):
    np.testing.assert_allclose(
        sf.linear_operator_fluid(beds(mobility, 0.0), 0.7), stability3d.linear_operator3d(6, 0.7), atol=1e-13
    )


@pytest.mark.parametrize("mobility", ["rpy", "rpb"])
def test_one_straight_chain_keeps_the_planes_degenerate(mobility):
    """Free space, or along the wall's normal: the rotations about the axis leave the operator's planes equal."""
    for operator in (sf.linear_operator_fluid(beds(mobility, 0.3), 0.9), sf.numerical_operator(beds(mobility, 0.3))):
        planes = sf.branches_fluid(operator)
        assert planes.coupling < 1e-12
        assert planes.splitting < 1e-9


def test_a_pair_on_the_wall_splits_the_planes_but_does_not_couple_them():
    planes = sf.branches_fluid(sf.linear_operator_fluid(beds("rpb", 0.2, PAIR), 0.9))
    assert planes.coupling == 0.0
    assert planes.splitting > 1e-3


def test_vanishing_beads_give_the_clamped_3d_onset():
    """a / l -> 0: the interactions fall like a / r, the wall's like a / h: the onset tends to the local drag's."""
    sigma_c, omega_c = stability3d.onset3d(6)
    for mobility in ("rpy", "rpb"):
        s, w = sf.onset_fluid(beds(mobility, 1e-5))
        assert abs(s / sigma_c - 1) < 1e-4 and abs(w / omega_c - 1) < 1e-4
    s, _ = sf.onset_fluid(beds("rpy", 0.2))
    assert abs(s / sigma_c - 1) > 1e-2  # the fluid's beads move the onset


def test_the_onset_is_where_the_leading_pair_crosses():
    b = beds("rpb", 0.2)
    sigma_c, omega_c = sf.onset_fluid(b)
    lam = sf.leading_eigenvalue_fluid(b, sigma_c)
    assert abs(lam.real) < 1e-10 and abs(lam.imag - omega_c) < 1e-12
    assert sf.leading_eigenvalue_fluid(b, 0.99 * sigma_c).real < 0 < sf.leading_eigenvalue_fluid(b, 1.01 * sigma_c).real


def test_a_chain_of_one_link_has_no_onset():
    with pytest.raises(ParameterError, match="n = 1"):
        sf.onset_fluid(beds("rpy", 0.2, n=1))


def test_the_cilium_s_stability_is_through_the_fluid_when_it_has_beads():
    physics = Physics(scene="cilium", n=6, bead_radius=0.2)
    onset = physics.scene_def.onset(physics)
    # the same search twice: equal but for the last digits a threaded BLAS's eigenvalues may move
    assert (onset.sigma_c, onset.omega_c) == pytest.approx(sf.onset_fluid(physics.scene_def.beds(physics)), rel=1e-12)
    assert "together through the fluid" in onset.kind
    dry = Physics(scene="cilium", n=6)
    assert dry.scene_def.onset(dry).sigma_c == pytest.approx(stability3d.onset3d(6)[0], rel=1e-12)

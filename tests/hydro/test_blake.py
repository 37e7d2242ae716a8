"""The Rotne-Prager-Blake mobility above a no-slip wall: Blake's point-force limit, the Faxen / Lorentz self-mobility,
the free-space limit far from the wall, and the promises a solver relies on (symmetric, positive definite, the
compiled twin equal to the reference)."""

import numpy as np
import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.hydro import rpb, rpb_into, rpy
from elastoactive.hydro.blake import rpb_cross_kernel


def _block(m, i, j):
    return m[3 * i : 3 * i + 3, 3 * j : 3 * j + 3]


def _blake(x, x0):
    """Blake's (1971) Green's function G, 8 pi mu u(x) = G F for a point force F at x0 above the wall z = 0: the
    Stokeslet, minus its image, plus the image's source doublet and Stokeslet doublet; written out independently
    of the package's form."""
    h = x0[2]
    r, big_r = x - x0, x - x0 * np.array([1.0, 1.0, -1.0])
    rn, big_rn = np.linalg.norm(r), np.linalg.norm(big_r)
    eye, zhat = np.eye(3), np.array([0.0, 0.0, 1.0])
    g = eye / rn + np.outer(r, r) / rn**3 - eye / big_rn - np.outer(big_r, big_r) / big_rn**3
    # d[al, ga] = d/dR_ga [h R_al / R^3 - zhat_al / R - R_al R_z / R^3]
    d = (
        h * (eye / big_rn**3 - 3 * np.outer(big_r, big_r) / big_rn**5)
        + np.outer(zhat, big_r) / big_rn**3
        - (eye * big_r[2] + np.outer(big_r, zhat)) / big_rn**3
        + 3 * big_r[2] * np.outer(big_r, big_r) / big_rn**5
    )
    return g + 2 * h * d @ np.diag([1.0, 1.0, -1.0])


def _packing(rng, n, a, top):
    """n beads clear of the wall (heights in [a, top]) and of each other (separations >= 2a), placed at random in a
    box wide enough that the excluded spheres fill a quarter of it."""
    width = np.sqrt(n * 4 / 3 * np.pi * (2 * a) ** 3 / (0.25 * (top - a)))
    x = np.empty((0, 3))
    for _ in range(100 * n):
        p = rng.uniform([0.0, 0.0, a], [width, width, top])
        if len(x) == 0 or np.linalg.norm(x - p, axis=1).min() >= 2 * a:
            x = np.vstack([x, p])
            if len(x) == n:
                return x
    raise AssertionError("the packing jammed")


def _configurations():
    rng = np.random.default_rng(11)
    yield _packing(rng, 20, 0.2, 1.0), 0.2
    yield _packing(rng, 30, 0.4, 2.0), 0.4
    x = rng.uniform([0.0, 0.0, 0.3], [1.0, 1.0, 1.0], size=(25, 3))  # overlapping beads, some overlapping the wall
    yield x, 0.45
    x = _packing(rng, 10, 0.1, 0.5)
    x[4] = x[7]  # coincident beads
    yield x, 0.1


@pytest.mark.parametrize("case", range(4))
def test_the_compiled_twin_equals_the_reference(case):
    x, a = list(_configurations())[case]
    out = np.full((3 * len(x), 3 * len(x)), np.nan)
    assert rpb_into(x, a, out) is out
    np.testing.assert_allclose(out, rpb(x, a), rtol=0, atol=1e-14)


@pytest.mark.parametrize("case", range(4))
def test_the_blocks_between_two_sets_of_beads_are_the_whole_matrix_s(case):
    x, a = list(_configurations())[case]
    whole = rpb(x, a)
    for split in (1, len(x) // 2):
        out = np.full((3 * split, 3 * (len(x) - split)), np.nan)
        rpb_cross_kernel(x[:split], x[split:], a, out)
        np.testing.assert_allclose(out, whole[: 3 * split, 3 * split :], rtol=0, atol=1e-14)


@pytest.mark.parametrize("case", range(4))
def test_symmetric(case):
    x, a = list(_configurations())[case]
    m = rpb(x, a)
    np.testing.assert_allclose(m, m.T, rtol=0, atol=1e-15)
    fast = rpb_into(x, a, np.empty_like(m))
    np.testing.assert_array_equal(fast, fast.T)


def test_positive_definite_for_beads_clear_of_the_wall_and_of_each_other():
    rng = np.random.default_rng(5)
    lowest = np.inf
    for _ in range(40):
        a = rng.uniform(0.05, 0.5)
        x = _packing(rng, int(rng.integers(2, 25)), a, rng.uniform(1.5, 8) * a)
        lowest = min(lowest, np.linalg.eigvalsh(rpb_into(x, a, np.empty((3 * len(x), 3 * len(x))))).min())
    assert lowest > 0.05


def test_positive_definite_for_overlapping_beads_clear_of_the_wall():
    """Not a theorem: no counterexample in random clouds of overlapping beads at heights >= a (docs/hydrodynamics.md
    lists the wider searches); the smallest eigenvalue falls only as two beads merge, as in free space."""
    rng = np.random.default_rng(9)
    for _ in range(40):
        n, span = int(rng.integers(2, 25)), rng.uniform(0.2, 6.0)
        x = rng.uniform([0.0, 0.0, 1.0], [span, span, 1.0 + rng.uniform(0.01, 6.0)], size=(n, 3))
        closest = np.linalg.norm(x[:, None] - x[None], axis=-1)[np.triu_indices(n, 1)].min()
        lowest = np.linalg.eigvalsh(rpb_into(x, 1.0, np.empty((3 * n, 3 * n)))).min()
        assert lowest > 0.05 * min(closest, 1.0)


@pytest.mark.parametrize("h_over_a", [1.0, 1.5, 3.0, 10.0])
def test_the_self_mobility_is_faxen_and_lorentz_series(h_over_a):
    a = 0.2
    s = 1 / h_over_a
    m = rpb([[0.7, -0.3, h_over_a * a]], a)
    parallel = 1 - 9 / 16 * s + 1 / 8 * s**3 - 1 / 16 * s**5
    perpendicular = 1 - 9 / 8 * s + 1 / 2 * s**3 - 1 / 8 * s**5
    np.testing.assert_allclose(m, np.diag([parallel, parallel, perpendicular]), rtol=0, atol=1e-15)


def test_touching_the_wall_a_bead_keeps_half_its_parallel_and_a_quarter_its_perpendicular_mobility():
    np.testing.assert_allclose(rpb([[0.0, 0.0, 0.3]], 0.3), np.diag([0.5, 0.5, 0.25]), atol=1e-15)


def test_the_pair_tends_to_the_self_block_as_beads_merge():
    """Swan and Brady's pair form at zero separation is the self form: the image of bead j seen from bead i at
    the same place is bead i's own image."""
    a, h = 0.2, 0.5
    for eps, tol in [(1e-4, 1e-3), (1e-8, 1e-7)]:
        m = rpb([[0.0, 0.0, h], [eps, -eps, h + eps]], a)
        np.testing.assert_allclose(_block(m, 0, 1), _block(m, 0, 0), atol=tol)


def test_far_from_the_wall_it_is_the_free_space_mobility():
    """The wall's part falls as a / h: the gap at height h is 9a / 16h on the parallel self term, to O((a/h)^3)."""
    rng = np.random.default_rng(2)
    x, a = rng.uniform(-1.0, 1.0, size=(6, 3)), 0.2
    free = rpy(x, a)
    gaps = []
    for height in (1e2, 1e4):
        gaps.append(np.abs(rpb(x + [0.0, 0.0, height], a) - free).max())
        assert gaps[-1] == pytest.approx(9 / 8 * a / height, rel=0.05)  # the perpendicular self term's 9a / 8h
    assert gaps[1] / gaps[0] == pytest.approx(1e-2, rel=0.05)


def test_small_beads_see_blakes_point_force_solution():
    """As a -> 0 at fixed positions the pair block over a tends to (3/4) G_Blake; the finite-size terms are
    O(a^2) relative."""
    xi, xj = np.array([0.3, -0.2, 1.1]), np.array([-0.5, 0.4, 0.7])
    blake = 0.75 * _blake(xi, xj)
    gaps = [np.abs(_block(rpb(np.array([xi, xj]), a), 0, 1) / a - blake).max() for a in (1e-2, 1e-3)]
    assert gaps[0] < 1e-3 * np.abs(blake).max()
    assert gaps[1] / gaps[0] == pytest.approx(1e-2, rel=1e-3)


def test_the_wall_screens_a_parallel_force_to_a_source_dipole():
    """Two beads at height h, a distance d apart along x: a force along x moves the other bead at 9 a h^2 / d^3
    (Blake's far field, 12 h^2 / d^3 in 8 pi mu units) instead of the free-space 3a / 2d."""
    a, h = 0.1, 0.5
    for d in (20.0, 200.0):
        m = rpb([[0.0, 0.0, h], [d, 0.0, h]], a)
        assert _block(m, 0, 1)[0, 0] == pytest.approx(9 * a * h**2 / d**3, rel=5 * h / d)


def test_a_bead_overlapping_the_wall_is_slowed_to_rest_at_the_wall():
    """Below h = a the mobility is b M(h_eff = a) b with b = h / a: continuous at h = a, zero at the wall."""
    a = 0.3
    at_contact = rpb([[0.0, 0.0, a], [0.5, 0.0, 0.6]], a)
    for h in (a * (1 - 1e-9), 0.5 * a, 1e-6 * a):
        m = rpb([[0.0, 0.0, h], [0.5, 0.0, 0.6]], a)
        b = h / a
        np.testing.assert_allclose(_block(m, 0, 0), b * b * _block(at_contact, 0, 0), atol=1e-15)
        np.testing.assert_allclose(_block(m, 0, 1), b * _block(at_contact, 0, 1), atol=1e-15)
        np.testing.assert_allclose(_block(m, 1, 1), _block(at_contact, 1, 1), atol=1e-15)
        assert np.linalg.eigvalsh(m).min() > 0


@pytest.mark.parametrize("z", [0.0, -0.1, np.nan])
def test_a_bead_at_or_below_the_wall_is_refused(z):
    with pytest.raises(ParameterError, match="positions"):
        rpb([[0.0, 0.0, 1.0], [0.0, 0.0, z]], 0.1)
    with pytest.raises(ParameterError, match="positions"):
        rpb_into([[0.0, 0.0, 1.0], [0.0, 0.0, z]], 0.1, np.empty((6, 6)))

"""The free-space RPY mobility: its forms, limits and the promises a solver relies on (symmetric, positive definite,
the compiled twin equal to the reference)."""

import numpy as np
import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.hydro import rpy, rpy_into
from elastoactive.hydro.rpy import rpy_cross_kernel


def _block(m, i, j):
    return m[3 * i : 3 * i + 3, 3 * j : 3 * j + 3]


def _pair(r, a, direction=(0.3, -0.5, 0.8)):
    e = np.asarray(direction) / np.linalg.norm(direction)
    return rpy(np.array([[0.0, 0.0, 0.0], -r * e]), a), e


def _clouds():
    """Random configurations: sparse ones, dense ones where many beads overlap, and one with coincident beads."""
    rng = np.random.default_rng(7)
    for n, spread, a in [(12, 4.0, 0.1), (30, 1.0, 0.3), (25, 0.3, 0.5), (40, 2.0, 0.45)]:
        yield rng.uniform(-spread, spread, size=(n, 3)), a
    x = rng.normal(size=(8, 3))
    x[5] = x[2]
    yield x, 0.2


@pytest.mark.parametrize("case", range(5))
def test_the_compiled_twin_equals_the_reference(case):
    x, a = list(_clouds())[case]
    out = np.full((3 * len(x), 3 * len(x)), np.nan)
    assert rpy_into(x, a, out) is out
    np.testing.assert_allclose(out, rpy(x, a), rtol=0, atol=1e-14)


@pytest.mark.parametrize("case", range(5))
def test_the_blocks_between_two_sets_of_beads_are_the_whole_matrix_s(case):
    x, a = list(_clouds())[case]
    whole = rpy(x, a)
    for split in (1, len(x) // 2):
        out = np.full((3 * split, 3 * (len(x) - split)), np.nan)
        rpy_cross_kernel(x[:split], x[split:], a, out)
        np.testing.assert_allclose(out, whole[: 3 * split, 3 * split :], rtol=0, atol=1e-14)


@pytest.mark.parametrize("case", range(4))
def test_symmetric_and_positive_definite_even_where_beads_overlap(case):
    x, a = list(_clouds())[case]
    m = rpy(x, a)
    np.testing.assert_allclose(m, m.T, rtol=0, atol=1e-15)
    fast = rpy_into(x, a, np.empty_like(m))
    np.testing.assert_array_equal(fast, fast.T)
    assert np.linalg.eigvalsh(m).min() > 1e-3


def test_coincident_beads_make_it_singular_not_indefinite():
    """Two beads at one point move as one: equal and opposite forces on them move nothing (a null vector)."""
    x, a = list(_clouds())[4]
    m = rpy(x, a)
    null = np.zeros(3 * len(x))
    null[6:9], null[15:18] = [1.0, 2.0, -1.0], [-1.0, -2.0, 1.0]
    np.testing.assert_allclose(m @ null, 0.0, atol=1e-15)
    eig = np.linalg.eigvalsh(m)
    assert eig.min() > -1e-14 and np.sum(eig < 1e-12) == 3 and np.sort(eig)[3] > 1e-3


def test_an_isolated_bead_moves_with_unit_mobility():
    np.testing.assert_array_equal(rpy([[1.0, 2.0, 3.0]], 0.2), np.eye(3))


def test_the_two_forms_meet_at_contact():
    """At r = 2a both forms give 7/16 I + 3/16 rhat rhat^T; across it the block changes by O(epsilon)."""
    a = 0.25
    contact, e = _pair(2 * a, a)
    np.testing.assert_allclose(_block(contact, 0, 1), 7 / 16 * np.eye(3) + 3 / 16 * np.outer(e, e), atol=1e-15)
    for eps in (1e-4, 1e-7):
        inside, outside = _pair(2 * a * (1 - eps), a)[0], _pair(2 * a * (1 + eps), a)[0]
        assert np.abs(_block(inside, 0, 1) - _block(outside, 0, 1)).max() < 2 * eps


def test_the_pair_tends_to_the_self_block_as_beads_merge():
    a = 0.3
    for r, tol in [(1e-3, 1e-3), (1e-6, 1e-6)]:
        np.testing.assert_allclose(_block(_pair(r, a)[0], 0, 1), np.eye(3), atol=tol)


def test_far_apart_the_pair_is_oseens_tensor():
    """|M_ij - 3a/(4r) (I + rhat rhat^T)| = (a^3 / 2 r^3) |I - 3 rhat rhat^T|: the relative gap falls as (a / r)^2."""
    a = 0.1
    gaps = []
    for r in (1.0, 10.0, 100.0):
        m, e = _pair(r, a)
        oseen = 0.75 * a / r * (np.eye(3) + np.outer(e, e))
        np.testing.assert_allclose(
            _block(m, 0, 1) - oseen, a**3 / (2 * r**3) * (np.eye(3) - 3 * np.outer(e, e)), atol=1e-16
        )
        gaps.append(np.abs(_block(m, 0, 1) - oseen).max() / np.abs(oseen).max())
    assert gaps[1] / gaps[0] == pytest.approx(1e-2, rel=1e-9) and gaps[2] / gaps[1] == pytest.approx(1e-2, rel=1e-6)


def test_a_sedimenting_pair_against_batchelor_and_stimson_jeffery():
    """Two equal beads under equal forces F: along their line they fall at (1 + 3a/2r - a^3/r^3) F and across it at
    (1 + 3a/4r + a^3/2r^3) F, Batchelor's (J. Fluid Mech. 1976) far-field series through (a/r)^3. Touching, the exact
    speed along the line is F / 0.6451 = 1.550 F (Stimson and Jeffery 1926); RPY gives 1 + 7/16 + 3/16 = 1.625 F,
    4.8% fast: the known cost of the pairwise far-field form at contact."""
    a = 0.2
    for r in (0.6, 1.5, 5.0):
        x = np.array([[0.0, 0.0, 0.0], [r, 0.0, 0.0]])
        m = rpy(x, a)
        along = (m @ np.array([1.0, 0, 0, 1.0, 0, 0]))[0]
        across = (m @ np.array([0, 0, 1.0, 0, 0, 1.0]))[2]
        assert along == pytest.approx(1 + 1.5 * a / r - (a / r) ** 3, rel=1e-14)
        assert across == pytest.approx(1 + 0.75 * a / r + 0.5 * (a / r) ** 3, rel=1e-14)
    touching = rpy(np.array([[0.0, 0.0, 0.0], [2 * a, 0.0, 0.0]]), a) @ np.array([1.0, 0, 0, 1.0, 0, 0])
    assert touching[0] == pytest.approx(1.625, rel=1e-14)
    assert touching[0] / (1 / 0.6451) - 1 == pytest.approx(0.048, abs=0.001)


def test_the_mobility_is_translation_and_rotation_invariant():
    rng = np.random.default_rng(3)
    x = rng.normal(size=(10, 3))
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    big_q = np.kron(np.eye(10), q)
    np.testing.assert_allclose(rpy(x @ q.T + [5.0, -2.0, 1.0], 0.3), big_q @ rpy(x, 0.3) @ big_q.T, atol=1e-13)


@pytest.mark.parametrize(
    "positions, radius, out, word",
    [
        (np.zeros((3, 2)), 0.1, None, "positions"),
        ([[0.0, np.nan, 0.0]], 0.1, None, "positions"),
        (np.zeros((2, 3)), 0.0, None, "radius"),
        (np.zeros((2, 3)), -1.0, None, "radius"),
        (np.zeros((2, 3)), 0.1, np.zeros((6, 5)), "out"),
        (np.zeros((2, 3)), 0.1, np.zeros((6, 6), dtype=np.float32), "out"),
    ],
)
def test_bad_input_is_named(positions, radius, out, word):
    with pytest.raises(ParameterError, match=word):
        if out is None:
            rpy(positions, radius)
        else:
            rpy_into(positions, radius, out)

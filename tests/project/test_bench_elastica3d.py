"""The 3D filament benchmark's helpers (scripts/bench_elastica3d.py) without PyElastica: PyElastica stays a bench
extra only, the start shape bent into a rod's directors keeps them orthonormal with d3 along each element, and the
measure of a rigid whirl gives its state and its exact rate and radius."""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.append(str(ROOT / "scripts"))  # after everything else: no script shadows a module

import bench_elastica3d as bench  # noqa: E402  (scripts/ is not a package)


def test_pyelastica_is_a_bench_extra_only():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert any(d.startswith("pyelastica") for d in project["optional-dependencies"]["bench"])
    for name, deps in [("main", project["dependencies"])] + list(project["optional-dependencies"].items()):
        if name != "bench":
            assert not any("elastica" in d for d in deps), name


@pytest.mark.parametrize("k", range(5))
def test_least_rotation_carries_the_clamp_frame_to_each_tangent(k):
    ex = np.array([1.0, 0.0, 0.0])
    v = bench.start_tangents(np.array([0.1, 0.4, 0.7, 0.9, 1.0]))[k]
    turn = bench._least_rotation(ex, v)
    np.testing.assert_allclose(turn @ ex, v, atol=1e-14)
    np.testing.assert_allclose(turn @ turn.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(turn) == pytest.approx(1.0)
    base = np.array([[0.0, 0, 1], [0, -1, 0], [1, 0, 0]])  # rows d1, d2, d3 of the straight rod (d2 = d3 x d1)
    directors = base @ turn.T
    np.testing.assert_allclose(directors[2], v, atol=1e-14)


def test_start_leaves_the_plane_and_is_clamped():
    t = bench.start_tangents(np.linspace(0.0, 1.0, 11))
    np.testing.assert_allclose(t[0], [1.0, 0.0, 0.0])
    np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1.0)
    assert abs(t[-1, 2]) > 0.2  # out of the xy plane (and not in any other plane through the axis)
    assert np.linalg.matrix_rank(np.cross(t[1:], t[:-1])[3:]) > 1


@pytest.mark.parametrize("omega", [-250.0, 180.0])
def test_measure_of_a_rigid_whirl(omega):
    n, radius_over_l = 12, 0.3
    s = (np.arange(n) + 0.5) / n
    shape = np.column_stack([np.ones(n), radius_over_l * 2 * s, 0 * s]) / n  # links of a curve, tip at y = 0.3 L
    t = np.linspace(0.0, 8 * 2 * np.pi / abs(omega), 1601)
    c, sn = np.cos(omega * t), np.sin(omega * t)
    links = np.stack([shape[:, 0] + 0 * t[:, None], np.outer(c, shape[:, 1]), np.outer(sn, shape[:, 1])], axis=-1)
    got = bench._measure(t, links, 1.0)
    assert got.state == "whirl"
    assert got.omega == pytest.approx(omega, rel=1e-12)
    assert got.radius == pytest.approx(shape[:, 1].sum(), rel=1e-12)
    assert got.settled < 1e-12

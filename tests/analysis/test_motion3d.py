"""The 3D observables (elastoactive.analysis.motion3d) on paths whose values are known: a circular whirl, a planar beat,
an elliptical path, a chain at rest."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis.motion3d import classify, measure3d, tip_path


def _two_link_chain(y: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Tangents (T, 2, 3): link 1 along e_x, link 2 carrying the tip to (x, y, z) across the axis (|(y, z)| < 1)."""
    second = np.column_stack([np.sqrt(1.0 - y**2 - z**2), y, z])
    first = np.broadcast_to([1.0, 0.0, 0.0], second.shape)
    return np.stack([first, second], axis=1)


T = np.arange(0.0, 200.0, 0.01)
F = 0.05


def test_circular_whirl():
    a = 0.5
    m = measure3d(T, _two_link_chain(a * np.cos(2 * np.pi * F * T), -a * np.sin(2 * np.pi * F * T)))
    assert m.tip_amplitude == pytest.approx(a, rel=1e-4)
    assert m.frequency == pytest.approx(F, rel=1e-4)
    assert m.tip_aspect == pytest.approx(1.0, abs=1e-3)
    assert m.whirl_rate == pytest.approx(-F, rel=1e-3)  # from +y towards -z: clockwise
    assert m.tip_radius == pytest.approx(a, rel=1e-9)
    assert m.bend == pytest.approx(np.arcsin(a), rel=1e-9)
    assert m.state == "whirl"


def test_planar_beat_and_ellipse():
    phase = 2 * np.pi * F * T
    beat = measure3d(T, _two_link_chain(0.4 * np.sin(phase) * np.cos(0.3), 0.4 * np.sin(phase) * np.sin(0.3)))
    assert beat.tip_aspect < 1e-6 and abs(beat.whirl_rate) < 1e-9 and beat.state == "beat"
    assert beat.tip_amplitude == pytest.approx(0.4, rel=1e-4) and beat.frequency == pytest.approx(F, rel=1e-4)
    a, b = 0.4, 0.2
    ellipse = measure3d(T, _two_link_chain(a * np.cos(phase), b * np.sin(phase)))
    assert ellipse.tip_aspect == pytest.approx(b / a, rel=1e-3)
    assert ellipse.whirl_rate == pytest.approx(F * 2 * a * b / (a * a + b * b), rel=1e-3)
    assert ellipse.state == "other"


def test_rest_and_tip_path():
    still = _two_link_chain(np.full(T.size, 0.1), np.zeros(T.size))
    assert measure3d(T, still).state == "rest"
    np.testing.assert_allclose(tip_path(still)[0], [1 + np.sqrt(0.99), 0.1, 0.0])
    assert classify(1.0, 0.95, 0.01, 0.05) == "other"  # round but not turning one way


def test_frequency_counts_the_whole_steady_window():
    """A whirl of 3 periods after a stated transient: its frequency comes from all 3 (counting only the last half of
    the steady window would see fewer than two crossings, return 0 and class it 'other')."""
    t = np.arange(0.0, 100.0, 0.01)  # 5 periods; the first 40 tau are the transient, 3 periods remain
    phase = 2 * np.pi * F * t
    m = measure3d(t, _two_link_chain(0.5 * np.cos(phase), 0.5 * np.sin(phase)), transient=40.0)
    assert m.frequency == pytest.approx(F, rel=1e-3)
    assert m.state == "whirl"

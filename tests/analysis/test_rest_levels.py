"""Rest and rigid turn are judged relative to the motion and to the solver's tolerance (results.rest_level, RIGID_TURN,
RIGID_FRACTION): a chain turning rigidly has no beat (frequency null) in both engines, whatever its solver's jitter in
Theta; a real beat on a turning chain keeps its frequency."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.core.trajectory import Trajectory

T = np.arange(0.0, 200.0, 0.05)
SHAPE = np.array([0.0, 0.3, 0.5, 0.6])


def _turning(scene: str, wiggle: np.ndarray, rate: float = 0.3, rtol: float | None = 1e-9, **values) -> Trajectory:
    """A chain of SHAPE turning at `rate`, its last angle moved by `wiggle` (Theta's oscillation)."""
    theta = SHAPE + rate * T[:, None]
    theta[:, -1] += wiggle
    info = {} if rtol is None else {"rtol": rtol}
    physics = ea.Physics(scene=scene, n=SHAPE.size, **values)
    return Trajectory(t=T, theta=theta, physics=physics, engine="reduced", info=info)


def test_the_solvers_jitter_on_a_long_turn_is_rest_not_a_beat():
    """An adaptive solver's error grows with the angles: 20 rtol |theta| (|theta| ~ 60 rad here) is not a beat."""
    jitter = 20 * 1e-9 * np.abs(0.3 * T) * np.sin(2 * np.pi * 0.378 * T)
    res = ea.measure(_turning("rotating-pin", jitter))
    assert res.frequency is None and res.periodic is True and "no beat" in res.notes[0]
    still = ea.measure(
        Trajectory(
            t=T,
            theta=np.broadcast_to(SHAPE * 60, (T.size, 4)) + jitter[:, None] * [0, 0, 0, 1],
            physics=ea.Physics(n=4),
            engine="reduced",
            info={"rtol": 1e-9},
        )
    )
    assert still.frequency == 0.0 and not still.notes  # at rest: its jitter sits below the rest level


def test_a_chain_turned_by_its_clamp_has_no_beat_though_it_reports_no_rotation_rate():
    res = ea.measure(_turning("one-pinned", 0.0, rtol=None))
    assert res.frequency is None and "no beat" in res.notes[0] and "rotation_rate" not in res.notes[0]


def test_a_residue_decaying_onto_the_rigid_turn_is_no_beat_but_a_real_beat_is():
    decaying = 2e-3 * np.exp(-0.031 * (T - 100.0)) * np.sin(2 * np.pi * 0.026 * T)
    res = ea.measure(_turning("ring", decaying, rate=-0.118, rtol=None))
    assert res.frequency is None and "residual wiggle" in res.notes[0]
    beating = ea.measure(_turning("ring", 0.3 * np.sin(2 * np.pi * 0.04 * T), rate=-0.13, rtol=None))
    assert beating.frequency == pytest.approx(0.04, rel=1e-2) and beating.periodic is True


def test_a_drifting_still_chain_is_at_rest_not_turning():
    """Turning is judged by the angle turned over the window (RIGID_TURN), not by a rate alone."""
    res = ea.measure(_turning("rotating-pin", 0.0, rate=2e-4))  # 0.02 rad over the 100 tau window
    assert res.frequency == 0.0 and not res.notes


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
@pytest.mark.parametrize(
    "physics",
    [
        ea.Physics(n=3, sigma=1.28, clamp_motion="rotating", clamp_frequency=0.05),
        ea.Physics(scene="ring", n=7, sigma=0.8, pin="free"),
    ],
    ids=["clamp", "free-ring"],
)
def test_rigid_turns_have_no_frequency_in_both_engines(engine, physics):
    res = ea.measure(ea.simulate(physics, duration=60.0, engine=engine))
    assert res.frequency is None and res.periodic is True and "no beat" in res.notes[0]

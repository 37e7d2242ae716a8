"""Labels fit the state they name: a window too short to judge is not called irregular, arms that share nothing are not
called locked in a pattern, and a beat small enough to be a soft pin's give says so."""

from __future__ import annotations

import math

import numpy as np

import elastoactive as ea
from elastoactive.core.surface import command_line
from elastoactive.core.trajectory import Trajectory
from elastoactive.scenes.star import clamp_angles

T = np.arange(0.0, 200.0, 0.05)


def _chain(theta_last: np.ndarray, t: np.ndarray = T, info: dict | None = None, **values) -> Trajectory:
    n = values.pop("n", 4)
    theta = np.zeros((t.size, n))
    theta[:, -1] = theta_last
    return Trajectory(t=t, theta=theta, physics=ea.Physics(n=n, **values), engine="mujoco", info=info or {})


def test_a_clean_beat_seen_for_less_than_two_periods_is_not_judged_irregular():
    t = np.arange(0.0, 50.0, 0.05)
    window = t >= 25.0  # the measured window holds 1.06 periods, from an upward crossing: its thirds drift by 1.4 A
    short = _chain(2.9 * np.sin(2 * np.pi * 0.0425 * (t - t[window][0])), t)
    res = ea.measure(short)
    assert res.periodic is None and res.frequency is None
    assert "not judged" in res.notes[0] and "not periodic" not in res.notes[0] and "(duration)" in res.notes[0]
    with command_line():  # the command line's entry names the options to type
        assert "(--duration)" in ea.measure(short).notes[0]
    winding = ea.measure(_chain(0.1 * T))  # Theta wound by 10 rad over the window: no beat does that
    assert winding.periodic is False and "winds up" in winding.notes[0]


def _star(hub: str, lag: float) -> Trajectory:
    """Two arms beating alike, the second `lag` behind the first."""
    n = 4
    values = dict(hub_stiffness=1.0, hub_drag=1.0) if hub == "turning" else {}
    physics = ea.Physics(scene="star", n=n, sigma=0.8, arms=2, hub=hub, **values)
    theta = np.repeat(clamp_angles(2), n)[None, :] + np.zeros((T.size, 1))
    for j in range(2):
        theta[:, j * n : (j + 1) * n] += 0.5 * np.sin(2 * np.pi * 0.1 * T - j * lag)[:, None] * np.linspace(0, 1, n)
    return Trajectory(t=T, theta=theta, physics=physics, engine="reduced", head=np.zeros((T.size, 1)))


def test_arms_on_a_clamped_hub_are_uncoupled_not_locked_in_a_pattern():
    coupled = ea.measure(_star("turning", math.pi)).extra
    assert coupled["sync_state"] == "antiphase" and coupled["phase_locking"] > 0.99
    clamped = ea.measure(_star("clamped", math.pi)).extra
    assert clamped["sync_state"] == "uncoupled" and math.isnan(clamped["phase_locking"])
    assert abs(math.cos(clamped["phase_lag"][1]) + 1) < 0.01  # the phases are still measured: their start's


def test_a_beat_within_a_soft_pins_give_says_so():
    beat = 0.0058 * np.sin(2 * np.pi * 0.031 * T)
    given = _chain(beat, info={"constraint_violation": 2.3e-5}, scene="two-pinned", n=7, delta=0.0)
    soft = ea.measure(given)
    assert soft.frequency > 0 and any("pin's give" in note and "engine = 'reduced'" in note for note in soft.notes)
    with command_line():  # the command line's entry names the options to type
        assert any("pin's give" in note and "--engine reduced" in note for note in ea.measure(given).notes)
    hard = ea.measure(_chain(beat, info={"constraint_violation": 3e-14}, scene="two-pinned", n=7, delta=0.0))
    assert not any("pin's give" in note for note in hard.notes)
    slack = ea.measure(_chain(beat, info={"constraint_violation": 2.3e-5}, scene="two-pinned", n=7, delta=0.1))
    assert not any("pin's give" in note for note in slack.notes)  # a compressed chain bends by its slack

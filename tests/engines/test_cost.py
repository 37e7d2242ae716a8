"""A MuJoCo run says what it will cost before it runs (engines.cost): the estimate holds to the measured wall time,
the run is untouched by it, and a run far slower than the reduced engine would be is named in one line."""

from __future__ import annotations

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.engines import cost
from elastoactive.engines import mujoco as engine


@pytest.mark.parametrize("n,duration", [(4, 200.0), (15, 60.0), (40, 20.0)])  # each about half a second
def test_the_estimate_is_within_a_factor_two_of_the_wall_time(n, duration):
    """The estimate (timed on the run's first samples) against the run's wall time. Both are wall clocks, which
    another process on the same cores can move apart for one run (the suite runs on every core): a wrong cost model
    misses in every attempt, a burst of load in one."""
    physics = ea.Physics(n=n, sigma=0.8 if n < 10 else 130 / n**3)
    attempts = []
    for _ in range(3):
        traj = engine.simulate_mujoco(physics, ea.Numerics(), duration, progress=True)
        attempts.append((traj.info["estimated_wall_s"], traj.wall_time_s))
        if 0.5 <= attempts[-1][0] / attempts[-1][1] <= 2.0:
            return
    pytest.fail(f"estimate against measured wall time, every attempt beyond a factor two: {attempts}")


def test_the_estimate_leaves_the_run_bit_identical():
    physics, numerics = ea.Physics(n=5, sigma=0.9, noise=0.1, noise_correlation=0.5), ea.Numerics(seed=3)
    timed = engine.simulate_mujoco(physics, numerics, 10.0, progress=True)
    plain = engine.simulate_mujoco(physics, numerics, 10.0)
    np.testing.assert_array_equal(timed.theta, plain.theta)


def test_a_run_far_slower_than_the_reduced_engine_is_named_in_one_line(monkeypatch, capsys):
    line = cost.cost_note(cost.MujocoCost(3.0 * 3600, 10**9, 10.8, 5), 40.0)
    assert "3.0 h" in line and "40 s" in line and "--engine reduced" in line and "\n" not in line
    assert cost.cost_note(cost.MujocoCost(20.0, 10**6, 20.0, 5), 0.1) is None  # short: not worth a word
    for reduced_s in (3600.0, None):  # not far beyond, or no reduced estimate: the run's own estimate is announced
        line = cost.cost_note(cost.MujocoCost(3.0 * 3600, 10**9, 10.8, 5), reduced_s)
        assert line.startswith("this MuJoCo run will take about 3.0 h") and "reduced" not in line
    monkeypatch.setattr(cost, "NOTE_SECONDS", 0.0)
    monkeypatch.setattr(cost, "FAR_BEYOND", 0.0)
    engine.simulate_mujoco(ea.Physics(n=4), ea.Numerics(), 5.0, progress=True)
    notes = [line for line in capsys.readouterr().err.splitlines() if line.startswith("elastoactive: note:")]
    assert len(notes) == 1 and "MuJoCo run will take about" in notes[0] and "reduced engine" in notes[0]


def test_a_sample_longer_than_the_probe_budget_is_timed_by_single_steps():
    """A long chain's sample can hold thousands of slow steps (N = 1000: ~0.8 s each): the probe then times single
    steps within its budget instead of stepping whole samples (it sat for minutes), and still scales to a sample."""
    from elastoactive.mjcf.chain import prepare

    physics, numerics = ea.Physics(n=7), ea.Numerics()
    model, data = prepare(physics, numerics)[:2]
    per_sample, timed = cost.sample_cost(model, data, 10**7, 10)  # a sample of 1e7 steps: ~30 s if stepped whole
    assert timed == 0
    per_step = per_sample / 10**7
    assert 1e-8 < per_step < 1e-3  # a real step time (N = 7: a few microseconds), not a whole sample's


def test_a_long_preflight_check_is_announced_with_its_estimated_time(monkeypatch, capsys):
    """MuJoCo's pre-flight stability check is dense in the angles (seconds at N = 200, minutes at N = 1000): before a
    long one starts, one line says how long it will take; a short one is not announced."""
    import elastoactive.engines.timestep as diagnose

    assert cost.check_announcement(ea.Physics(n=7)) is None
    assert cost.check_seconds(1000) > 30 * cost.check_seconds(300)
    text = cost.check_announcement(ea.Physics(n=1000, sigma=1e-7))
    assert text is not None and "N = 1000" in text and "(about " in text and "min" in text

    def stop(*args, **kwargs):
        raise ea.ParameterError("stopped after the announcement")

    monkeypatch.setattr(diagnose, "check_timestep", stop)
    with pytest.raises(ea.ParameterError, match="stopped"):
        ea.simulate(ea.Physics(n=1000, sigma=1e-7), ea.Numerics(), duration=5.0, progress=True)
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "checking dt against the stability limits of the N = 1000 model (about " in err


def test_the_reduced_pilot_of_a_stiff_model_stops_at_its_time_budget(monkeypatch):
    """The pilot grows from a short span and stops once one run takes PILOT_SECONDS: a large model whose stiff solve
    costs seconds per tau is not piloted over its full share (5 tau of the paraboloid at N = 100 took minutes, silent
    before a MuJoCo run)."""
    import elastoactive.engines.reduced as reduced

    spans = []

    def slow(physics, numerics, duration, **kwargs):  # a model whose every run takes 10 s per tau, at least 0.2 s
        spans.append(duration)
        clock[0] += max(0.2, 10.0 * duration)

    clock = [0.0]
    monkeypatch.setattr(reduced, "simulate_reduced", slow)
    monkeypatch.setattr(cost.time, "perf_counter", lambda: clock[0])
    estimate = cost.reduced_cost(ea.Physics(n=7), ea.Numerics(), 300.0)
    assert sum(10.0 * s for s in spans) < 4 * cost.PILOT_SECONDS + 1.0 and max(spans) < 0.2
    assert estimate == pytest.approx(10.0 * 300.0, rel=0.05)

"""Every engine path goes through engines.runner: a run past the step limit is refused before it steps, in one line
naming the parameter and a --duration that passes; a run that goes shows progress (and, when long, its cost) through
io.progress, whose observers may stop it; the numbers are those of a run without progress."""

from __future__ import annotations

import re
import time

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.engines import runner
from elastoactive.io import progress


class Stopped(BaseException):
    """What an observer raises to end a run."""


def observed(physics, numerics=None, duration=300.0, engine="reduced"):
    """The events a run (progress on) shows, the run stopped at its first update that follows an announcement, or at
    its 20th update (about 5 s of its own pace)."""
    events = []

    def watch(event):
        events.append(event)
        kinds = [e.kind for e in events]
        if event.kind == "update" and ("announce" in kinds or kinds.count("update") >= 20):
            raise Stopped

    with pytest.raises(Stopped), progress.observe(watch):
        ea.simulate(physics, numerics, duration=duration, engine=engine, progress=True)
    return events


@pytest.mark.parametrize(
    "values,numerics,duration,named",
    [
        ({"scene": "one-pinned"}, None, 1e12, "duration = 1e+12: "),
        ({"scene": "one-pinned", "clamp_amplitude": 0.1, "clamp_frequency": 1e6}, None, 10.0, "clamp_frequency = "),
        ({"scene": "one-pinned", "noise": 0.1}, None, 1e8, "duration = 1e+08: "),
        ({"scene": "clamped-3d"}, None, 1e12, "duration = 1e+12: "),
    ],
)
def test_an_absurd_reduced_run_is_refused_in_one_line_before_it_steps(values, numerics, duration, named):
    with pytest.raises(ea.ParameterError) as refusal:
        ea.simulate(ea.Physics(**values), numerics, duration=duration, engine="reduced")
    line = str(refusal.value)
    assert "\n" not in line and line.startswith(named) and re.search(r"; use (--)?duration \d", line)


@pytest.mark.parametrize("engine", ["reduced", "mujoco"])
def test_an_absurd_push_is_refused_by_the_numerics_in_every_engine(engine):
    start = time.process_time()
    with pytest.raises(ea.ParameterError, match=r"^perturbation = 1e\+09: the seeded initial push lies in \[0, pi\]"):
        ea.simulate("one-pinned", {"perturbation": 1e9}, duration=10.0, engine=engine)
    assert time.process_time() - start < 1.0


def test_the_duration_a_refusal_gives_passes():
    with pytest.raises(ea.ParameterError) as refusal:
        ea.simulate(ea.Physics(scene="one-pinned", noise=0.1), None, duration=1e8, engine="reduced")
    shorter = float(re.search(r"use (?:--)?duration (\S+)", str(refusal.value)).group(1))
    runner.refuse_steps(shorter / 0.0025, what="x", duration=shorter)  # within the limit: no refusal


def test_mujoco_s_3d_chain_refuses_an_automatic_step_it_cannot_take_before_stepping():
    with pytest.raises(ea.ParameterError, match=r"^sigma = 1e\+06: MuJoCo at dt = .* use (--)?duration"):
        ea.simulate(ea.Physics(scene="clamped-3d", sigma=1e6), None, duration=300.0, engine="mujoco", check=False)


def test_a_long_run_announces_its_cost_then_shows_progress():
    """A run whose cost is not known before it starts (the inertial chain at sigma 1e6) says what its pace projects,
    then updates its bar; the observer's exception stops it."""
    events = observed(ea.Physics(scene="one-pinned", sigma=1e6))
    kinds = [e.kind for e in events]
    said = kinds.index("announce")
    assert "update" in kinds[said:] and "will take about" in events[said].text


def test_a_network_run_reached_through_a_hook_without_the_option_shows_progress():
    """run_engine's progress option holds for the whole run (runner.shown): the network scene's reduced engine
    reports though its hook is not handed the option."""
    events = []
    with progress.observe(events.append):
        ea.simulate(ea.Physics(scene="network"), duration=2e4, engine="reduced", progress=True)
    assert any(e.kind == "update" and e.desc == "reduced network" for e in events)


@pytest.mark.parametrize(
    "scene,values,engine,duration",
    [
        ("one-pinned", {}, "reduced", 30.0),
        ("one-pinned", {"noise": 0.1}, "reduced", 5.0),
        ("one-pinned", {}, "mujoco", 5.0),
        ("trapped-unit", {}, "reduced", 5.0),
        ("clamped-3d", {"n": 4}, "reduced", 5.0),
        ("clamped-3d", {"n": 4}, "mujoco", 2.0),
    ],
)
def test_progress_leaves_the_numbers_bit_identical(scene, values, engine, duration, monkeypatch):
    """Shown progress cuts the loops into more calls (MuJoCo's steps, the compiled loops): the same numbers."""
    monkeypatch.setattr(runner, "PROGRESS_EVERY", 0.0)  # an update at every report: as many cuts as there can be
    physics = ea.Physics(scene=scene, **values)
    shown = ea.simulate(physics, duration=duration, engine=engine, progress=True)
    plain = ea.simulate(physics, duration=duration, engine=engine)
    np.testing.assert_array_equal(shown.theta, plain.theta)


def test_mujoco_steps_in_chunks_are_the_steps_of_one_call():
    import mujoco

    from elastoactive.mjcf.chain import prepare

    physics, numerics = ea.Physics(n=5, sigma=0.9), ea.Numerics()
    (m1, d1), (m2, d2) = prepare(physics, numerics)[:2], prepare(physics, numerics)[:2]
    meter = runner.Meter(10.0, "test", show=True)
    chunks = runner.StepChunks(meter, mujoco.mj_step, chunk=7)
    chunks(m1, d1, 1000)
    mujoco.mj_step(m2, d2, nstep=1000)
    meter.close()
    np.testing.assert_array_equal(d1.qpos, d2.qpos)


def test_a_resumable_loop_is_cut_into_calls_of_about_the_progress_interval():
    counts, left = [], [10_000]

    def call(steps: int) -> int:
        counts.append(steps)
        left[0] -= min(steps, left[0])
        time.sleep(1e-4)
        return 1 if left[0] else 0

    meter = runner.Meter(1.0, "test", show=True)
    assert runner.resume(call, 1, lambda: 1.0 - left[0] / 10_000, meter, 10**9) == 0
    meter.close()
    assert counts[0] <= 256 and sum(counts) >= 10_000


def test_an_unshown_meter_reads_no_clock_and_shows_nothing(monkeypatch):
    meter = runner.Meter(100.0, "test", show=False)
    monkeypatch.setattr(runner.time, "perf_counter", lambda: pytest.fail("read the clock"))
    meter.at(50.0)
    meter.close()

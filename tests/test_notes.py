"""Every note, summary field, caption and label fits the shape of its scene's results (a number, None, or one value per
chain: elastoactive.quantities): a property over every registered scene in every regime a run can end in."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

import elastoactive as ea
from elastoactive import quantities, records, results, sensitivity
from elastoactive.core.trajectory import Trajectory
from elastoactive.sweep.points import _ok_record

SPACING = 0.1
FREQUENCY = 0.1
REGIMES = {  # name: (duration, beat of chain k at times t, rigid rotation rate)
    "rest": (60.0, lambda t, k: 0.0 * t, 0.0),
    "periodic": (100.0, lambda t, k: np.sin(2 * np.pi * FREQUENCY * t + 0.7 * k), 0.0),
    "irregular": (
        150.0,
        lambda t, k: (
            np.sin(2 * np.pi * FREQUENCY * t) * (1 + 0.4 * np.sin(0.08 * t + k))
            + 0.3 * np.sin(2 * np.pi * FREQUENCY * math.sqrt(5) * t)
        ),
        0.0,
    ),
    "too short": (15.0, lambda t, k: np.sin(2 * np.pi * FREQUENCY * t + k), 0.0),
    "one chain still": (100.0, lambda t, k: np.sin(2 * np.pi * FREQUENCY * t) * (k % 2 == 0), 0.0),
    "diverging": (100.0, lambda t, k: np.exp(0.08 * t) * np.sin(2 * np.pi * FREQUENCY * t + k), 0.0),
    "rotating": (100.0, lambda t, k: 0.0 * t, 0.05),
    "beating while rotating": (100.0, lambda t, k: np.sin(2 * np.pi * FREQUENCY * t + k), 0.05),
}
"""Regimes a run can end in, as synthetic trajectories: at rest, a clean beat, an irregular one, a window shorter than a
period, chains that differ (one still), a growing motion, a rigid turn, a beat on a turn."""


def _physics(name: str) -> ea.Physics:
    scene = ea.scenes.get(name)
    return scene.physics() if scene.term_parameters is not None else scene.physics(n=4, sigma=0.8)


def _template(name: str) -> Trajectory:
    """The scene's state at t = 0 (angles, head, polarities, nodes) as its reduced engine starts it: the first sample
    of a run just long enough to be measured (whatever the scene's kind keeps in a trajectory)."""
    physics = _physics(name)
    numerics = ea.Numerics()
    run = ea.simulate(physics, numerics, duration=10 * numerics.sample_dt, engine="reduced")
    first = {k: None if v is None else v[:1] for k, v in (("head", run.head), ("polarity", run.polarity))}
    nodes = None if run.nodes is None else run.nodes[:1]
    return Trajectory(t=run.t[:1], theta=run.theta[:1], physics=physics, engine="reduced", nodes=nodes, **first)


def _synthetic(name: str, regime: str) -> Trajectory:
    """The scene's state at t = 0 moved by the regime's beat (each chain its own) and turned by its rigid rotation."""
    duration, beat, omega = REGIMES[regime]
    start = _template(name)
    physics = start.physics
    t = np.arange(0.0, duration + SPACING / 2, SPACING)
    turn = omega * t[:, None]
    theta = np.repeat(start.theta[:1], t.size, axis=0) + turn * (start.theta.shape[1] > 0)
    n = physics.n
    for k in range(physics.n_chains if start.theta.shape[1] else 0):
        theta[:, k * n : (k + 1) * n] += 0.3 * beat(t, k)[:, None] * np.linspace(0.0, 1.0, n)
    head = None if start.head is None else np.repeat(start.head[:1], t.size, axis=0) + 0.01 * beat(t, 0)[:, None]
    if head is not None and head.shape[1] == 1:  # the star's hub angle turns with its arms
        head = head + turn
    polarity = None if start.polarity is None else start.polarity[0] + 0.3 * beat(t, 0)[:, None] + turn
    nodes = None
    if start.nodes is not None:
        rest = start.nodes[0]
        push = np.random.default_rng(1).normal(size=rest.shape)
        moved = rest + 0.05 * beat(t, 0)[:, None, None] * push
        centre = rest.mean(axis=0)
        c, s = np.cos(turn)[:, :, None], np.sin(turn)[:, :, None]
        rel = moved - centre
        nodes = centre + np.concatenate(
            [c * rel[..., :1] - s * rel[..., 1:], s * rel[..., :1] + c * rel[..., 1:]], axis=-1
        )
    return Trajectory(t=t, theta=theta, physics=physics, engine="reduced", head=head, polarity=polarity, nodes=nodes)


_REPR = re.compile(r"\(\s*-?\d[^()]*,\s*-?\d[^()]*\)\s*(\+-|rad|/tau|\d)|np\.|None|\bnan\b|array\(")
"""What a note must not show: a Python tuple or array written as one number, a None, a bare nan."""


def _check_text(text, where: str) -> None:
    assert isinstance(text, str) and text.strip(), where
    assert "\n" not in text, f"{where}: {text!r} is not one line"
    assert not _REPR.search(text), f"{where}: {text!r}"


@pytest.mark.parametrize("name", ea.scenes.names())
def test_every_note_summary_caption_and_label_fits_the_scenes_result_shape(name):
    physics = _physics(name)
    scene = physics.scene_def
    _check_text(scene.label(physics), f"{name} label")
    _check_text(scene.caption_line(physics), f"{name} caption")
    for regime, (duration, _, _) in REGIMES.items():
        traj = _synthetic(name, regime)
        where = f"{name}, {regime}"
        summary = records.summary(traj, ea.Numerics(), duration)
        json.dumps(records.jsonable(summary), allow_nan=False)
        recorded = summary["results"]
        for note in recorded["notes"]:
            _check_text(note, where)
        measured = results.measure(traj)
        for key in ("amplitude", "frequency", "period_spread"):  # shaped per chain exactly where the scene has chains
            value = measured.value(key)
            assert quantities.per_chain(value) == (physics.n_chains > 1), f"{where}: {key} = {value!r}"
            assert len(quantities.entries(value)) == physics.n_chains
        if "sensitivity" in recorded:
            for key in ("amplitude_error", "frequency_error"):
                error = recorded["sensitivity"][key]
                assert quantities.per_chain(error) == (physics.n_chains > 1), f"{where}: {key} = {error!r}"
        record = _ok_record(measured, {}, 0.0)
        _check_text(record["notes"] or "no notes", where)


def test_the_error_estimate_is_per_chain_where_the_results_are():
    """A pair whose second chain is irregular and first regular: the errors differ, chain by chain."""
    t = np.arange(0.0, 200.0, SPACING)
    physics = ea.Physics(scene="coupled-pair", n=4, sigma=0.8)
    theta = np.zeros((t.size, 8))
    theta[:, 3] = 0.5 * np.sin(2 * np.pi * t / 10.0)
    theta[:, 7] = 0.5 * (1 + 0.2 * np.sin(2 * np.pi * t / 37.0)) * np.sin(2 * np.pi * t / 10.0)
    traj = Trajectory(t=t, theta=theta, physics=physics, engine="reduced")
    amplitude_errors, frequency_errors = sensitivity.cycle_errors(traj, 100.0)
    assert len(amplitude_errors) == len(frequency_errors) == 2
    assert amplitude_errors[0] < 1e-3 < amplitude_errors[1]


@pytest.mark.parametrize(
    "amplitude, frequency, errors",
    [
        ((0.5, 0.6), (0.1, None), ((0.01, None), (1e-4, None))),
        ((0.5, math.nan), (None, None), ((None, None), (None, None))),
        (0.5, 0.1, (0.01, 1e-4)),
        (0.5, None, (None, None)),
    ],
)
def test_the_sensitivity_note_writes_any_result_shape(amplitude, frequency, errors):
    for sensitive in (False, True):
        estimate = sensitivity.Sensitivity(
            1.0 if sensitive else -0.1, sensitive, 9.0 if sensitive else None, errors[0], errors[1], 10.0
        )
        _check_text(estimate.note(amplitude, frequency), f"{amplitude}, {frequency}")

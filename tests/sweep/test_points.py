"""sweep.points: a batch's records are handed over together, once all of them are measured (one fsync a batch), and a
grid point's case is built once."""

import numpy as np
from sweep_helpers import FAST

from elastoactive.batch import Case
from elastoactive.controllers import follower_forces
from elastoactive.core.params import Physics
from elastoactive.sweep import make_sweep
from elastoactive.sweep import points as sweep_points


def test_a_batch_hands_its_records_over_together_after_measuring_them(monkeypatch):
    events = []
    measure = sweep_points.measure

    def logged(trajectory, transient):
        events.append("measure")
        return measure(trajectory, transient)

    monkeypatch.setattr(sweep_points, "measure", logged)
    cases = [Case(Physics(n=3, sigma=s), FAST, 5) for s in (0.5, 1.0, 1.5)]
    cases.append(Case(Physics(n=3, sigma=1.0), FAST, -1.0))  # refused at once (a negative duration)
    with follower_forces():
        records = sweep_points.run_points(cases, threads=1, on_record=lambda j, record: events.append(j))
    assert events[0] == 3  # the refused point at once, before the batch steps
    assert events[1:] == ["measure"] * 3 + [0, 1, 2]  # the batch's three after all three are measured
    assert [r["status"] for r in records] == ["ok", "ok", "ok", "error"]


def test_a_grid_point_is_built_once():
    sweep = make_sweep("one-pinned", {"sigma": np.array([0.5, 1.0])}, numerics=FAST, duration=5)
    first = [sweep.case(i) for i in range(sweep.size)]
    assert [sweep.case(i) for i in range(sweep.size)] == first
    assert all(sweep.case(i) is case for i, case in enumerate(first))
    assert [c.physics.sigma for c in first] == [0.5, 1.0]

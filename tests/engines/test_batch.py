"""engines.mujoco_batch: many MuJoCo runs in one mujoco.batch give exactly what simulate_mujoco gives."""

import threading

import mujoco
import numpy as np
import pytest

from elastoactive.batch import Case, run_case, run_cases
from elastoactive.core.errors import ParameterError, SimulationDiverged
from elastoactive.core.params import Numerics, Physics
from elastoactive.engines.mujoco import simulate_mujoco
from elastoactive.engines.mujoco_batch import Run, plan, run_chunks, signature, simulate_mujoco_batch
from elastoactive.mjcf.chain import build_model

FAST = Numerics.preset("fast")


def reference(run: Run):
    try:
        return simulate_mujoco(run.physics, run.numerics, run.duration)
    except Exception as err:  # noqa: BLE001 (compared with the batch's outcome)
        return err


def assert_same(run: Run, outcome, expected) -> None:
    """The batch's outcome is simulate_mujoco's, bit for bit (or the same exception, same text)."""
    if isinstance(expected, Exception):
        assert type(outcome) is type(expected) and str(outcome) == str(expected), (run, outcome)
        return
    assert not isinstance(outcome, Exception), (run, outcome)
    np.testing.assert_array_equal(outcome.t, expected.t)
    assert np.array_equal(outcome.theta, expected.theta), f"{run}: trajectories differ"
    assert outcome.engine == "mujoco" and outcome.physics == run.physics
    for key in ("steps", "integrator", "constraint_violation"):
        assert outcome.info.get(key) == expected.info.get(key), key


SCENE_RUNS = [
    *[Run(Physics(n=5, sigma=s), FAST, 30) for s in (0.3, 0.8, 1.5)],
    # noise > 0, different seeds and amplitudes: numeric_data per simulation
    *[
        Run(Physics(n=5, sigma=0.8, noise=a), Numerics.preset("fast", seed=seed), 30)
        for a, seed in ((0.1, 0), (0.1, 1), (0.3, 7))
    ],
    # the pinned scene: sigma and delta (the pin's site, its marker, the keyframe) per simulation
    *[
        Run(Physics(scene="two-pinned", n=5, sigma=s, delta=d), FAST, 20)
        for s, d in ((0.8, 0.1), (2.0, 0.3), (2.0, 0.1))
    ],
    # the pair: kappa (the coupling tendon) and rho (chain 2's joint stiffness)
    *[
        Run(Physics(scene="coupled-pair", n=4, sigma=0.8, kappa=k, rho=r), FAST, 20)
        for k, r in ((0.5, 4 / 3), (2.0, 1.0))
    ],
    # the free pin, with the drag ratio (the actuators' gains) per simulation
    *[Run(Physics(scene="rotating-pin", n=3, sigma=s, drag_ratio=g), FAST, 20) for s, g in ((0.5, 1.0), (1.0, 2.0))],
    # dt changes the steps per sample: a batch of its own
    Run(Physics(n=5, sigma=0.8), Numerics.preset("fast", dt=0.005), 10),
]


def test_batch_reproduces_simulate_mujoco_bit_for_bit():
    outcomes = simulate_mujoco_batch(SCENE_RUNS, threads=2)
    for run, outcome in zip(SCENE_RUNS, outcomes):
        assert_same(run, outcome, reference(run))
    sizes = [o.info["batch"]["size"] for o in outcomes]
    # one model per scene (and N), its points in one batch a thread (a batch's threads are fixed when it starts: a
    # thread that finished a cheap scene takes a costly scene's second batch instead of waiting)
    assert sizes == [3] * 6 + [2, 2, 1] + [1] * 2 + [1] * 2 + [1]
    # wall time: each run's share of its batch
    assert all(0 < o.wall_time_s <= o.info["batch"]["wall_s"] for o in outcomes)


def test_batch_on_one_thread_and_in_any_order_is_the_same():
    runs = SCENE_RUNS[:6]
    two = simulate_mujoco_batch(runs, threads=2)
    one = simulate_mujoco_batch(runs[::-1], threads=1)[::-1]
    assert [o.info["batch"]["size"] for o in one] == [6] * 6  # on one thread the points of a scene run together
    for a, b in zip(two, one):
        assert np.array_equal(a.theta, b.theta)


def test_a_diverging_point_is_its_own_error_and_the_others_finish():
    # Euler takes the springs and follower forces explicitly: sigma = 100 blows up at dt = 0.01
    euler = Numerics(integrator="Euler", mass_ratio=1e-2, dt=0.01, sample_dt=0.05)
    # the soft pin lets go at dt = 0.02 for sigma = 2 (the end drifts beyond 0.05 l), not for sigma = 0.8
    loose = Numerics(dt=0.02, sample_dt=0.04)
    runs = [Run(Physics(n=3, sigma=s), euler, 10) for s in (0.5, 100.0, 50.0)]
    runs += [Run(Physics(scene="two-pinned", n=5, sigma=s, delta=0.1), loose, 10) for s in (0.8, 2.0)]
    seen = []
    outcomes = simulate_mujoco_batch(runs, threads=2, on_done=lambda i, o: seen.append((i, threading.current_thread())))
    assert sorted(i for i, _ in seen) == list(range(len(runs)))
    assert all(thread is threading.main_thread() for _, thread in seen)  # on_done runs in the caller's thread
    assert isinstance(outcomes[1], SimulationDiverged) and "diverged by t = 5 tau" in str(outcomes[1])
    assert isinstance(outcomes[4], SimulationDiverged) and "drifted" in str(outcomes[4])
    assert outcomes[0].info["batch"]["size"] == 2 and outcomes[3].info["batch"]["size"] == 1  # a batch a thread
    for run, outcome in zip(runs, outcomes):
        assert_same(run, outcome, reference(run))


def test_invalid_run_is_its_own_error():
    runs = [Run(Physics(n=3), FAST, 10), Run(Physics(n=3), FAST, -1.0)]
    ok, bad = simulate_mujoco_batch(runs, threads=1)
    assert_same(runs[0], ok, reference(runs[0]))
    assert "duration" in str(bad)


def test_models_share_a_batch_only_when_they_may():
    base = build_model(Physics(n=5), FAST)
    same = [Physics(n=5, sigma=2.0), Physics(n=5, noise=0.2), Physics(n=5, drag_ratio=3.0)]
    assert all(signature(build_model(p, FAST)) == signature(base) for p in same)
    assert signature(build_model(Physics(n=5), Numerics.preset("fast", seed=3, dt=0.005))) == signature(base)
    # N changes the sizes, the mass ratio the statistics the solver reads
    assert signature(build_model(Physics(n=6), FAST)) != signature(base)
    assert signature(build_model(Physics(n=5), Numerics.preset("fast", mass_ratio=1e-2))) != signature(base)
    runs = [Run(Physics(n=n, sigma=s), FAST, 10) for n in (3, 4) for s in (0.5, 1.0, 1.5)]
    assert plan(runs) == [[0, 1, 2], [3, 4, 5]]
    assert plan(runs, max_points=2) == [[0, 1], [2], [3, 4], [5]]
    assert plan(runs, min_chunks=3) == [[0], [1], [2], [3], [4], [5]]
    # a sweep plans its batch.Case objects the same way (not one batch per point)
    cases = [Case(Physics(n=n, sigma=s), FAST, 10) for n in (3, 4) for s in (0.5, 1.0, 1.5)]
    assert plan(cases) == [[0, 1, 2], [3, 4, 5]]
    # long chains group by the numerics they run with (Numerics.for_physics), at the defaults too
    long = [Case(Physics(n=30, sigma=s), Numerics(), 10) for s in (0.05, 0.1)] + [Case(Physics(n=7), Numerics(), 10)]
    assert plan(long) == [[0, 1], [2]]


def test_run_chunks_shares_the_threads_and_keeps_the_callback():
    calls = []
    lock = threading.Lock()

    def task(chunk, k, emit, cancel):
        with lock:
            calls.append((tuple(chunk), k))
        emit(len(chunk))

    before = mujoco.get_mjcb_passive()
    items = list(run_chunks([[1] * 16], 2, task))
    assert items == [16] and calls == [((1,) * 16, 2)]  # one big batch: every thread
    calls.clear()
    assert sorted(run_chunks([[1, 2, 3], [4, 5, 6]], 2, task)) == [3, 3]
    assert sorted(k for _, k in calls) == [1, 1]  # 3 on 2 threads: side by side, one thread each
    calls.clear()
    assert list(run_chunks([[1, 2], [3]], 1, task, weight=lambda chunk: 10 if chunk == [3] else 1)) == [1, 2]
    assert calls == [((3,), 1), ((1, 2), 1)]  # the costliest chunk (weight) first
    assert mujoco.get_mjcb_passive() == before  # restored

    def failing(chunk, k, emit, cancel):
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError, match="boom"):
        list(run_chunks([[1], [2]], 2, failing))


def test_run_cases_matches_run_case():
    cases = [Case(Physics(n=3, sigma=s), FAST, 20) for s in (0.4, 0.9)]
    cases.append(Case(Physics(n=3, sigma=0.9), FAST, 20, engine="reduced"))
    order = []
    results = run_cases(cases, workers=2, progress=False, on_result=lambda i, r: order.append(i))
    assert sorted(order) == [0, 1, 2]
    for case, result in zip(cases, results):
        expected = run_case(case)
        np.testing.assert_equal(result.results.as_dict(), expected.results.as_dict())  # NaN == NaN here
    with pytest.raises(ParameterError, match="dt"):  # the gate refuses what would diverge, before it runs
        run_cases(
            [
                Case(
                    Physics(n=3, sigma=100.0),
                    Numerics(integrator="Euler", mass_ratio=1e-2, dt=0.01, sample_dt=0.05),
                    10,
                )
            ],
            workers=1,
            progress=False,
        )


def test_run_cases_runs_both_engines_at_once_and_raises_the_first_failure():
    """MuJoCo and reduced cases together: the reduced ones run on the pool beside the MuJoCo threads, the results in
    input order as run_case gives them; a failed case raises once the others have finished."""
    cases = [Case(Physics(n=3, sigma=0.9), FAST, 20, engine=e) for e in ("reduced", "mujoco", "reduced", "mujoco")]
    seen = []
    results = run_cases(cases, workers=2, progress=False, keep_trajectory=True, on_result=lambda i, r: seen.append(i))
    assert sorted(seen) == [0, 1, 2, 3]
    for case, result in zip(cases, results):
        assert result.trajectory.engine == case.engine
        np.testing.assert_array_equal(result.trajectory.theta, run_case(case, keep_trajectory=True).trajectory.theta)
    broken = cases[:2] + [Case(Physics(n=3, sigma=0.9), FAST, -1.0, engine="reduced"), cases[2]]
    seen.clear()
    with pytest.raises(ParameterError, match="duration"):
        run_cases(broken, workers=2, progress=False, on_result=lambda i, r: seen.append(i))
    assert sorted(seen) == [0, 1, 3]


def test_run_cases_unmeasured_gives_the_same_trajectories_without_results():
    cases = [Case(Physics(n=3, sigma=0.9), FAST, 20, engine=e) for e in ("mujoco", "reduced", "reduced")]
    measured = run_cases(cases, workers=2, progress=False, keep_trajectory=True)
    bare = run_cases(cases, workers=2, progress=False, keep_trajectory=True, measured=False)
    for m, b in zip(measured, bare):
        assert m.results is not None and b.results is None
        np.testing.assert_array_equal(m.trajectory.theta, b.trajectory.theta)


@pytest.mark.parametrize("integrator", ["implicitfast", "implicit", "discrete", "Euler", "RK4"])
def test_every_integrator(integrator):
    num = Numerics(integrator=integrator, dt=0.005, mass_ratio=1e-2, sample_dt=0.05)
    runs = [
        Run(Physics(scene=scene, n=4, sigma=s), num, 5) for scene in ("one-pinned", "two-pinned") for s in (0.5, 1.2)
    ]
    for run, outcome in zip(runs, simulate_mujoco_batch(runs, threads=2)):
        assert_same(run, outcome, reference(run))


def _model_bytes(model: mujoco.MjModel) -> bytes:
    buffer = np.zeros(mujoco.mj_sizeModel(model), np.uint8)
    mujoco.mj_saveModel(model, None, buffer)
    return buffer.tobytes()


def test_cached_scene_template_builds_the_same_model_as_parsing_the_file(monkeypatch):
    """model.build_spec starts from a copy of a template parsed once per base file: every scene, with contact
    capsules and coloured noise too, compiles to the model a fresh parse gives, byte for byte, and building
    one model leaves the template as it was."""
    from elastoactive.core import registry
    from elastoactive.mjcf import chain as model_module
    from elastoactive.mjcf import mjcf_path

    def fresh(scene):
        spec = mujoco.MjSpec.from_file(str(mjcf_path(scene.base_file)))
        for element in [*spec.actuators, *spec.keys, *spec.equalities, *spec.tendons]:
            spec.delete(element)
        for prefix in scene.chain_prefixes():
            spec.delete(spec.body(f"{prefix}segment_0"))
        return spec

    cases = []
    variants = (
        (dict(), Numerics()),
        (dict(n=9, sigma=0.4), FAST),
        (dict(n=6, contact=True, contact_friction=0.3), Numerics()),
        (dict(n=5, noise=0.1, noise_correlation=0.5), Numerics()),
    )
    chain_scenes = [name for name in registry.names() if registry.get(name).builder == "elastoactive.mjcf.chain"]
    for name in chain_scenes:  # a network's model is network_model's, from its own template
        for values, numerics in variants:
            try:
                cases.append((Physics(scene=name, **values), numerics))
            except ParameterError:  # a scene that refuses a term (the ring has no self-contact)
                assert "contact" in values
    assert len(cases) >= 3 * len(chain_scenes)
    for physics, numerics in cases:
        cached = [_model_bytes(build_model(physics, numerics)) for _ in range(2)]
        with monkeypatch.context() as m:
            m.setattr(model_module, "_template", fresh)
            parsed = _model_bytes(build_model(physics, numerics))
        assert cached[0] == cached[1] == parsed, physics

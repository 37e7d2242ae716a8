"""pytest-benchmark versions of scripts/benchmark.py's measurements (not part of the default test run).

  .venv/bin/pytest benchmarks --benchmark-only          (testpaths = tests, so plain pytest skips these)

Each benchmark is a single hot operation; compare e.g. test_step_compiled_callback with test_step_bare
for the callback overhead, test_reduced_compiled with test_reduced_reference for the reduced speed-up.
"""

from __future__ import annotations

import mujoco
import pytest

from elastoactive.controllers import compiled_passive, follower_forces, reference_passive
from elastoactive.core.params import Numerics, Physics
from elastoactive.engines.mujoco import prepare, simulate_mujoco
from elastoactive.engines.reduced import simulate_reduced, simulate_reference

CHAIN = Physics(n=7, sigma=0.8)
NSTEP = 2000


@pytest.fixture(params=["implicitfast", "implicit", "discrete", "Euler", "RK4"])
def model_data(request):
    integrator = request.param
    numerics = Numerics(integrator=integrator, **({"mass_ratio": 1e-2} if integrator in ("Euler", "RK4") else {}))
    return prepare(CHAIN, numerics)


def _steps(model, data, callback, nstep=NSTEP):
    q0 = data.qpos.copy()

    def run():
        mujoco.mj_resetData(model, data)
        data.qpos[:] = q0
        with follower_forces(callback):
            mujoco.mj_step(model, data, nstep=nstep)

    return run


def test_step_bare(benchmark, model_data):
    benchmark(_steps(*model_data, None))


def test_step_compiled_callback(benchmark, model_data):
    benchmark(_steps(*model_data, compiled_passive))


def test_step_python_callback(benchmark, model_data):
    benchmark.pedantic(_steps(*model_data, reference_passive, NSTEP // 10), rounds=5)


def test_reduced_compiled(benchmark):
    simulate_reduced(CHAIN, Numerics(), 1.0)
    benchmark(lambda: simulate_reduced(CHAIN, Numerics(), 100.0, method="numba-DOP853"))


def test_reduced_reference(benchmark):
    benchmark.pedantic(lambda: simulate_reference(CHAIN, Numerics(), 100.0), rounds=3)


@pytest.mark.parametrize("preset", ["accurate", "fast"])
def test_simulate_mujoco_100_tau(benchmark, preset):
    numerics = Numerics.preset(preset)
    benchmark.pedantic(lambda: simulate_mujoco(CHAIN, numerics, 100.0), rounds=5)

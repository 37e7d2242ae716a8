"""dop853_loop: the DOP853 step loop every compiled DOP853 drives (here through the network's driver)."""

from __future__ import annotations

import numpy as np
import pytest

from elastoactive.analysis.network import hexagonal_patch, initial_state
from elastoactive.reduced import network as m
from elastoactive.reduced import network_kernels
from elastoactive.reduced.dop853_loop import integrate, run_loop


class Stopped(KeyboardInterrupt):
    def __init__(self, samples: np.ndarray):
        super().__init__()
        self.samples = samples


def _case():
    network = hexagonal_patch(2)
    system = m.network_system(network, 0.2, 0.1)
    return m.kernel_args(system), m.pack(system, initial_state(network, 0.2, 1)), np.arange(0.0, 20.0001, 0.25)


def test_cut_into_calls_the_run_is_the_whole_one_bit_for_bit():
    args, y0, ts = _case()
    whole = integrate(network_kernels.dop853, args, ts, y0, 1e-8, 1e-10)
    calls = []

    def counting(call, paused, reached, steps):
        calls.append(steps)
        return run_loop(lambda k: calls.append(k) or call(k), paused, reached, steps)

    pieces = integrate(network_kernels.dop853, args, ts, y0, 1e-8, 1e-10, counting, steps=3)
    assert whole.status == 0 and whole.t == ts[-1] and whole.naccept > 30
    np.testing.assert_array_equal(pieces.y, whole.y)
    assert pieces[1:] == whole[1:]
    assert len(calls) == 1 + -(-whole.naccept // 3) and set(calls) == {3}


def test_an_interrupt_keeps_the_samples_reached_or_passes_through():
    """on_interrupt(samples) is raised with exactly the samples reached when Ctrl-C comes between two calls; without
    it the KeyboardInterrupt passes through as it is."""
    args, y0, ts = _case()
    whole = integrate(network_kernels.dop853, args, ts, y0, 1e-8, 1e-10)
    reached_at = []

    def ctrl_c_after_four_calls(call, paused, reached, steps):
        status = paused
        while status == paused:
            status = call(steps)
            reached_at.append(reached())
            if len(reached_at) == 4:
                raise KeyboardInterrupt
        return status

    with pytest.raises(Stopped) as stopped:
        integrate(
            network_kernels.dop853, args, ts, y0, 1e-8, 1e-10, ctrl_c_after_four_calls, steps=5, on_interrupt=Stopped
        )
    samples = stopped.value.samples
    assert 1 < len(samples) == np.searchsorted(ts, reached_at[-1], side="right") < ts.size
    np.testing.assert_array_equal(samples, whole.y[: len(samples)])
    reached_at.clear()
    with pytest.raises(KeyboardInterrupt) as plain:
        integrate(network_kernels.dop853, args, ts, y0, 1e-8, 1e-10, ctrl_c_after_four_calls, steps=5)
    assert type(plain.value) is KeyboardInterrupt


def test_a_driven_rate_sees_each_stage_at_its_own_time_as_scipy_does():
    """The tip drive's driver (reduced.node_kernels.dop853) against scipy's solve_ivp(DOP853) on the same compiled
    right-hand side: the stages' times are scipy's, so the same steps and the same samples to round-off."""
    from scipy.integrate import solve_ivp

    import elastoactive as ea
    from elastoactive.engines import reduced as red
    from elastoactive.reduced import node_kernels
    from elastoactive.reduced.dop853 import Interrupted

    physics = ea.Physics(n=4, sigma=0.6, drive_amplitude=0.2, drive_frequency=0.3)
    system = red.system_of(physics).typed()
    laws = [t.node_forces(physics) for t in physics.active_terms() if t.node_forces(physics) is not None]
    fac, table = system.force_factors(None), node_kernels.force_table(laws)
    ts, y0 = np.arange(0.0, 40.0001, 0.5), np.full(physics.n_angles, 0.01)
    run = integrate(node_kernels.dop853, (system, 0.0, fac, table), ts, y0, 1e-9, 1e-11, on_interrupt=Interrupted)
    L, D, X, lam = node_kernels.workspace(system)
    n = physics.n
    scratch = (np.zeros((n, n)), np.zeros((n, n)), np.zeros(physics.n_angles))

    def f(t, y):
        out = np.empty(y.size)
        node_kernels.periodic_rhs(t, np.ascontiguousarray(y), fac, system, 0.0, out, L, D, X, lam, table, *scratch)
        return out

    sol = solve_ivp(f, (0.0, ts[-1]), y0, method="DOP853", t_eval=ts, rtol=1e-9, atol=1e-11)
    assert run.status == 0 and run.naccept > 50
    extra = sol.nfev - run.nfev  # scipy also takes the dense output's 3 stages where a sample is a step's end
    assert 0 <= extra <= 30 and extra % 3 == 0
    np.testing.assert_allclose(run.y, sol.y.T, rtol=0, atol=1e-12)
    undriven = integrate(node_kernels.dop853, (system, 0.0, fac, table[:0]), ts, y0, 1e-9, 1e-11)
    assert np.abs(run.y - undriven.y).max() > 1e-3  # the drive acts, at the stages' times

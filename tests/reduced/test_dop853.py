"""The planar chain's compiled DOP853 (reduced.dop853): dop853_loop's driver around kernels.eval_state."""

from __future__ import annotations

import numpy as np

from elastoactive import reduced as M
from elastoactive.reduced import dop853

BETA = 10.0


def test_takes_scipys_steps_and_samples_to_round_off():
    """The same tableau, error norm, initial step, step control and dense output as solve_ivp(DOP853): the same
    samples to round-off (its sums' order is not scipy's), the same number of evaluations within the few a
    different rounding of the step control can change."""
    from scipy.integrate import solve_ivp

    system = M.ChainSystem(n=5, sigma=0.8).typed()
    ts = np.arange(0.0, 20.0001, 0.05)
    theta0 = 0.05 * np.sin(np.arange(5.0))
    y, status, nfev, naccept, nreject = dop853.integrate(system, ts, theta0, rtol=1e-9, atol=1e-11, beta=BETA)
    reference = solve_ivp(
        M.rhs(system, beta=BETA), (0.0, 20.0), theta0, method="DOP853", t_eval=ts, rtol=1e-9, atol=1e-11
    )
    assert status == 0 and reference.success
    assert naccept > 0 and abs(nfev - reference.nfev) <= 0.01 * reference.nfev
    np.testing.assert_allclose(y, reference.y.T, rtol=0, atol=1e-11)


def test_a_start_outside_the_domain_ends_at_once():
    """A right-hand side that is not finite at the start: status -1 and no step (not a loop on NaN step sizes)."""
    system = M.ChainSystem(n=3, sigma=0.8).typed()
    theta0 = np.array([0.1, np.nan, 0.0])
    y, status, nfev, naccept, nreject = dop853.integrate(
        system, np.linspace(0.0, 1.0, 5), theta0, rtol=1e-9, atol=1e-11, beta=BETA
    )
    assert status == -1 and naccept == 0 and nfev == 1


def test_resumes_bit_for_bit_and_an_interrupt_keeps_the_samples_reached(monkeypatch):
    """Cut into calls of three steps, the run is the whole one bit for bit; a Ctrl-C between two calls raises
    Interrupted with exactly the samples reached so far."""
    system = M.ChainSystem(n=7, sigma=0.8).typed()
    ts = np.arange(0.0, 30.0, 0.05)
    theta0 = 0.01 * np.sin(np.arange(7.0))
    whole = dop853.integrate(system, ts, theta0, rtol=1e-9, atol=1e-11, beta=BETA)
    monkeypatch.setattr(dop853, "STEP_BUDGET", 3 * dop853.STEP_BUDGET // dop853.steps_per_call(system, 7))  # 3 a call
    assert dop853.steps_per_call(system, 7) == 3
    times = []
    pieces = dop853.integrate(system, ts, theta0, rtol=1e-9, atol=1e-11, beta=BETA, on_time=times.append)
    np.testing.assert_array_equal(pieces[0], whole[0])
    assert pieces[1:] == whole[1:]
    assert len(times) == -(-whole[3] // 3) and times == sorted(times) and times[-1] == ts[-1]

    def ctrl_c_at(time):
        if time > 10.0:
            raise KeyboardInterrupt

    try:
        dop853.integrate(system, ts, theta0, rtol=1e-9, atol=1e-11, beta=BETA, on_time=ctrl_c_at)
    except dop853.Interrupted as err:
        samples = err.samples
    else:
        raise AssertionError("no Interrupted")
    assert 10.0 / 0.05 < len(samples) < ts.size
    np.testing.assert_array_equal(samples, whole[0][: len(samples)])

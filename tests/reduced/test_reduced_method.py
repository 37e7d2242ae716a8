"""Which ODE method the reduced engine picks by itself (explicit DOP853 for short chains, implicit LSODA where the
stiffness ratio of a long chain near its onset makes explicit steps pile up), that both give the same answer, the
O(N^2) Jacobian the implicit method uses on long chains, and the --method option."""

from __future__ import annotations

import json

import numpy as np
import pytest

from elastoactive import reduced as M
from elastoactive.cli import main
from elastoactive.core.params import Numerics, Physics
from elastoactive.engines.reduced import simulate_reduced
from elastoactive.reduced import kernels as K
from elastoactive.reduced.blas import _openblas_controls, one_blas_thread

FILAMENT_S = 100.0  # N^3 sigma: the clamped filament above its onset (76.1)


def _filament(n):
    """The N-particle chain at sigma = S / N^3 and its beat period in tau (about 2 pi N^4 / 249)."""
    return Physics(scene="one-pinned", n=n, sigma=FILAMENT_S / n**3), 2 * np.pi * n**4 / 249.0


def test_short_chain_keeps_the_explicit_method_bit_for_bit():
    physics, numerics = Physics(scene="one-pinned", n=7, sigma=0.8), Numerics()
    auto = simulate_reduced(physics, numerics, 300.0)
    assert auto.info["method"] == "numba-DOP853"
    assert auto.info["stiffness_ratio"] < M.IMPLICIT_RATIO
    explicit = simulate_reduced(physics, numerics, 300.0, method="numba-DOP853")
    np.testing.assert_array_equal(auto.theta, explicit.theta)
    implicit = simulate_reduced(physics, numerics, 300.0, method="LSODA")
    np.testing.assert_allclose(implicit.theta, auto.theta, atol=1e-5)


def test_long_chain_near_onset_picks_the_implicit_method_with_the_same_answer():
    physics, period = _filament(30)
    auto = simulate_reduced(physics, Numerics(sample_dt=100.0, perturbation=0.3), 4 * period)
    assert auto.info["method"] == "LSODA"
    assert auto.info["stiffness_ratio"] > 10 * M.IMPLICIT_RATIO  # grows like N^4
    # the same answer as the explicit method, over a window short enough for its many small steps
    numerics = Numerics(sample_dt=5.0, perturbation=0.3)
    explicit = simulate_reduced(physics, numerics, 3000.0, method="numba-DOP853")
    implicit = simulate_reduced(physics, numerics, 3000.0, method="LSODA")
    np.testing.assert_allclose(implicit.theta, explicit.theta, atol=1e-6)


def test_short_runs_stay_explicit_whatever_the_ratio():
    """Below IMPLICIT_WORK (duration x fastest decay) the explicit steps are few: no switch."""
    physics, period = _filament(30)
    run = simulate_reduced(physics, Numerics(sample_dt=5.0), 1000.0)
    assert run.info["stiffness_ratio"] > M.IMPLICIT_RATIO
    assert run.info["method"] == "numba-DOP853"


@pytest.mark.parametrize(
    "kind",
    [
        dict(),
        dict(gamma_l=2.5),
        dict(clamped=False, gamma_l=1.6),
        dict(clamped=False, pinned=True, delta=0.1, gamma_l=1.7),
        dict(n_chains=2, kappa=1.3, rho=1.4, gamma_l=0.6),
    ],
)
def test_recursive_jacobian_equals_the_dense_one(kind):
    system = M.ChainSystem(n=23, sigma=0.7, **kind).typed()
    rng = np.random.default_rng(3)
    th = 0.6 * rng.standard_normal(system.n_angles)
    if system.pinned:
        th = M.project_on_pins(th * 0.5, system.delta) + 1e-3 * rng.standard_normal(system.n_angles)
    dense = np.empty((th.size, th.size))
    K.eval_jacobian(th, system, 3.0, dense, *K.workspace(system, dense=True))
    recursive = np.empty((th.size, th.size))
    _, U, X, lam = K.workspace(system, dense=False)
    K.eval_jacobian_recursive(th, system, 3.0, recursive, U, X, lam)
    np.testing.assert_allclose(recursive, dense, atol=1e-12 * np.abs(dense).max())
    np.testing.assert_array_equal(M.jacobian(system, beta=3.0)(0.0, th), recursive)


def test_one_blas_thread_sets_and_restores():
    controls = _openblas_controls()
    before = [get() for _, get in controls]
    with one_blas_thread():
        assert all(get() == 1 for _, get in controls)
    assert [get() for _, get in controls] == before


def test_method_option_is_recorded_and_refused_where_it_does_not_apply(tmp_path, capsys):
    out = tmp_path / "run"
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--engine",
                "reduced",
                "--method",
                "Radau",
                "--duration",
                "60",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    assert json.loads((out / "summary.json").read_text())["solver"]["method"] == "Radau"
    capsys.readouterr()
    assert main(["run", "one-pinned", "--method", "Radau", "--duration", "60", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "reduced engine" in err[0]
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--engine",
                "reduced",
                "--noise",
                "0.1",
                "--method",
                "LSODA",
                "--duration",
                "60",
                "--quiet",
            ]
        )
        == 2
    )
    assert "--method" in capsys.readouterr().err


def test_a_solver_that_gives_up_says_what_to_change_in_one_line(monkeypatch, capsys):
    """numba-DOP853 giving up (as at sigma = 500 with contact, where its step fell below round-off after ~8 s)
    is a SimulationDiverged naming the settings and the fix, printed by the CLI as one line (exit 3)."""
    from elastoactive.reduced import dop853

    def gives_up(system, t, y0, **kw):
        return np.zeros((t.size, y0.size)), -1, 10, 1, 0

    monkeypatch.setattr(dop853, "integrate", gives_up)
    assert main(["run", "one-pinned", "--sigma", "5", "--engine", "reduced", "--duration", "20", "--quiet"]) == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "numba-DOP853 gave up" in err[0] and "sigma = 5" in err[0] and "--method LSODA" in err[0]


def test_ctrl_c_stops_a_long_reduced_run_within_a_second(tmp_path):
    import os
    import resource
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    # a terminal's Ctrl-C, whatever the shell that started the tests left (a background job ignores SIGINT, and
    # an ignored signal stays ignored across exec): handled here while the run starts, so that exec gives it the
    # default disposition, on which Python raises KeyboardInterrupt
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        proc = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "elastoactive",
                "run",
                "one-pinned",
                "--engine",
                "reduced",
                "--duration",
                "200000",
                "--sample-dt",
                "1",
                "--quiet",
            ],
            cwd=tmp_path,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
    finally:
        signal.signal(signal.SIGINT, previous)
    time.sleep(6.0)  # start-up, then well into the integration (the whole run takes ~15 s)
    assert proc.poll() is None
    # the run's own CPU after the signal, not the wall time, which a loaded machine stretches past any bound
    ticks = os.sysconf("SC_CLK_TCK")
    spent = sum(int(x) for x in Path(f"/proc/{proc.pid}/stat").read_text().rsplit(")", 1)[1].split()[11:13]) / ticks
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc.send_signal(signal.SIGINT)
    sent = time.perf_counter()
    _, err = proc.communicate(timeout=30)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    total = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    assert total - spent < 1.0 and time.perf_counter() - sent < 10.0
    assert proc.returncode == 130
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "interrupted at t = " in lines[0] and "Traceback" not in err


def test_every_allowed_chain_length_finishes_or_is_refused_at_once():
    """N = 1000, the largest allowed: the overdamped chain runs (its O(N) path, ~1 s); the dense paths (the
    inertial model that the default mass ratio needs at sigma = 0.8, self-contact) are refused in one line
    before any work (they sat in their stiffness check for over 300 s)."""
    import time

    from elastoactive.core.errors import ParameterError

    physics = Physics(scene="one-pinned", n=1000)
    clock = time.perf_counter()
    with pytest.raises(ParameterError, match=r"limited to 100 angles.*smaller numerics\.mass_ratio"):
        simulate_reduced(physics, Numerics(), 10.0)
    with pytest.raises(ParameterError, match="self-contact .*limited to 100 angles"):
        simulate_reduced(physics.replace(contact=True), Numerics(mass_ratio=1e-7), 10.0)
    assert time.perf_counter() - clock < 10.0
    run = simulate_reduced(physics, Numerics(mass_ratio=1e-5), 10.0)
    assert run.info["model"] == "overdamped" and np.all(np.isfinite(run.theta))


def test_run_from_repeats_the_recorded_method(tmp_path):
    """`run --from` re-runs a reduced run with the ODE method it ran with (a --method given, or the automatic
    choice), so the trajectory is the same bit for bit."""
    first, again = tmp_path / "first", tmp_path / "again"
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--engine",
                "reduced",
                "--method",
                "Radau",
                "--duration",
                "30",
                "--out",
                str(first),
                "--quiet",
            ]
        )
        == 0
    )
    assert main(["run", "--from", str(first), "--out", str(again), "--quiet"]) == 0
    a, b = (json.loads((p / "summary.json").read_text()) for p in (first, again))
    assert a["solver"]["method"] == b["solver"]["method"] == "Radau"
    assert a["trajectory_sha256"] == b["trajectory_sha256"]


@pytest.mark.parametrize("mass_ratio", [None, 0.5])  # the overdamped model, and the inertial one
def test_a_slow_reduced_run_shows_its_progress_in_tau_and_computes_the_same(capsys, monkeypatch, mass_ratio):
    """scipy's methods (a long chain's implicit solver runs for minutes) report the solver's time on a progress bar in
    tau; the run is bit for bit the one without it."""
    import elastoactive as ea
    from elastoactive.io import progress

    monkeypatch.setattr(progress, "LOG_INTERVAL", 0.0)  # a line at every update (a real run logs every few seconds)

    physics = ea.Physics(n=5, sigma=0.8)
    numerics = ea.Numerics() if mass_ratio is None else ea.Numerics(mass_ratio=mass_ratio)
    quiet = ea.simulate(physics, numerics, duration=5, engine="reduced", method="Radau")
    capsys.readouterr()
    shown = ea.simulate(physics, numerics, duration=5, engine="reduced", method="Radau", progress=True)
    err = capsys.readouterr().err
    assert "reduced one-pinned" in err and "tau" in err, err
    np.testing.assert_array_equal(shown.theta, quiet.theta)
    assert shown.info["model"] == ("overdamped" if mass_ratio is None else "inertial")

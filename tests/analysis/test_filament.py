"""The filament limit: the beat measures and the extrapolation in 1/N (analysis.filament), and the ladder
command (elastoactive filament) on a small, fast ladder."""

from __future__ import annotations

import json

import numpy as np
import pytest

from elastoactive.analysis.filament import beat, resample, richardson
from elastoactive.cli import main
from elastoactive.cli.filament import ladder
from elastoactive.core.errors import ParameterError


def test_richardson_is_exact_on_a_polynomial_in_one_over_n_and_estimates_its_error():
    ns = [20, 40, 80, 160]
    exact = richardson(ns, [3.0 + 2 / n + 5 / n**2 - 7 / n**3 for n in ns])
    assert exact.value == pytest.approx(3.0, abs=1e-12)
    truncated = richardson(ns, [3.0 + 2 / n + 5 / n**2 - 7 / n**3 + 40 / n**4 for n in ns])
    assert abs(truncated.value - 3.0) <= truncated.error  # the estimate bounds the true error here
    assert truncated.error < 1e-4
    assert richardson(ns[::-1], [1.0 / n for n in ns[::-1]]).value == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(ValueError, match="distinct"):
        richardson([20, 20], [1.0, 2.0])


@pytest.mark.parametrize("samples", [60, 400])
def test_beat_measures_period_and_amplitude_between_the_samples(samples):
    period = 1.3
    t = np.arange(0, 8 * period, period / samples)
    x = 0.7 * np.sin(2 * np.pi * t / period + 0.3) + 0.1 * np.sin(4 * np.pi * t / period) + 0.2
    fine = np.linspace(0, period, 400001)
    xf = 0.7 * np.sin(2 * np.pi * fine / period + 0.3) + 0.1 * np.sin(4 * np.pi * fine / period) + 0.2
    b = beat(t, x)
    assert b.periods >= 6
    assert b.period == pytest.approx(period, rel=1e-9)
    assert b.amplitude == pytest.approx(0.5 * (xf.max() - xf.min()), rel=2e-6 if samples == 60 else 1e-9)
    with pytest.raises(ValueError, match="two whole periods"):
        beat(t[:samples], x[:samples])


def test_resample_keeps_a_smooth_shape():
    s = lambda n: (np.arange(n) + 0.5) / n  # noqa: E731
    np.testing.assert_allclose(resample(0.3 * s(20) ** 2, 80)[4:-4], 0.3 * s(80)[4:-4] ** 2, atol=2e-4)
    np.testing.assert_array_equal(resample(np.arange(5.0), 5), np.arange(5.0))


def test_filament_command_extrapolates_a_small_ladder(capsys):
    assert main(["filament", "--S", "100", "--ns", "10,14,20", "--json", "--quiet"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert [r["n"] for r in result["rungs"]] == [10, 14, 20]
    assert all(r["settled"] for r in result["rungs"])
    # the continuum: omega = 248.92, amplitude 0.9419 (four rungs from N = 20 to 160: docs/filament.md); three short
    # rungs, the finest N = 20 still 8% and 31% off, extrapolate to within 0.5% and 0.2%
    assert result["rungs"][-1]["omega"] < 229.0 and result["rungs"][-1]["amplitude"] > 1.23
    assert abs(result["omega"]["value"] / 248.92 - 1) < 5e-3
    assert abs(result["amplitude"]["value"] / 0.9419 - 1) < 2e-3
    assert abs(result["onset"]["value"] - 76.10) < 0.3
    assert result["omega"]["error"] > 0 and result["amplitude"]["error"] > 0


def test_filament_refuses_loads_below_the_onset_in_one_line(capsys):
    assert main(["filament", "--S", "70", "--quiet"]) == 2  # the chains up to N ~ 25 beat at 70, the filament not
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "below the filament's onset" in err[0]
    with pytest.raises(ParameterError, match="N = 10 .* does not beat"):
        ladder(60.0, (10, 14))


@pytest.mark.parametrize("S,ns", [("1e5", None), ("1e6", None), ("3000", "10,20")])
def test_filament_refuses_a_load_its_ladder_does_not_resolve_before_it_runs(S, ns, capsys):
    """The coarsest rung must have a link per bending length L S^(-1/3): coarser, the chain is not in the 1/N regime."""
    from elastoactive.cli.filament import DEFAULT_LADDER, largest_resolved_S

    argv = ["filament", "--S", S, "--quiet"] + (["--ns", ns] if ns else [])
    assert main(argv) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    coarsest = int(ns.split(",")[0]) if ns else DEFAULT_LADDER[0]
    assert len(err) == 1 and err[0].startswith(f"elastoactive: error: --S {float(S):g} ")
    assert f"resolves S up to {largest_resolved_S(coarsest):.4g}" in err[0] and captured.out == ""


def test_filament_plans_each_chunk_at_the_beat_it_finds(capsys):
    """Far above the onset the beat is much faster than the onset's (here ~90 times): the rung measures it (its first
    chunk planned from the S^(4/3) quickening, any chunk too coarsely sampled run again at the period it found)."""
    assert main(["filament", "--S", "3375", "--ns", "15,20", "--json", "--quiet"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert all(r["settled"] for r in result["rungs"])
    assert 17000 < result["rungs"][0]["omega"] < 17700 and result["omega"]["converging"]


def test_filament_flags_rungs_that_do_not_converge():
    from elastoactive.cli.filament import converging

    assert converging([228.45, 238.43, 243.60, 246.24]) and converging([1.0, 2.0])
    assert not converging([2.99, 2.19, 2.31]) and not converging([1.0, 1.5, 2.5])

"""The idealisation studies (inertia, noise_readings) at the tiny size: they run, round-trip through
save/load, draw their figures and render their claim rows."""

from __future__ import annotations

import math

import pytest

from elastoactive.analysis import flutter as fl
from elastoactive.studies.inertia import experiment_scales
from elastoactive.studies.noise import experiment_noise
from elastoactive.studies.paper import PAPER


@pytest.fixture(scope="module")
def runs(tiny_studies):
    return tiny_studies("inertia", "noise_readings")


def test_paper_literature_values():
    assert PAPER.ziegler_undamped == pytest.approx(fl.ZIEGLER_UNDAMPED)
    assert PAPER.ziegler_damped_limit == pytest.approx(41 / 28)
    assert PAPER.force_relative_spread == pytest.approx(3.1 / 15.7)


def test_experiment_estimates():
    e = experiment_scales()
    # tau = gamma l sigma / F_a: 0.63 * 0.0714 * 0.8 / 0.0157 = 2.29 s
    assert e.tau_s[e.sigmas.index(0.8)] == pytest.approx(0.63 * (0.5 / 7) * 0.8 / 0.0157)
    assert 1e-3 < e.mass_ratio_max < 0.1 and abs(e.sigma_c_7_shift_at_max) < 0.01
    x = experiment_noise()
    assert x.tau_c[1] < 1 and x.amplitude[0] < x.amplitude[1] < 0.2


@pytest.mark.parametrize("name", ["inertia", "noise_readings"])
def test_round_trip_figures_and_rows(runs, name, round_trip):
    table = round_trip(runs, name)
    assert ("Ziegler" in table) if name == "inertia" else ("Stratonovich" in table)


def test_inertia_numbers(runs):
    s = runs[1]["inertia"].summary
    assert s.ziegler_max_rel_err < 1e-8
    assert s.shift_mass_ratio["7"] > s.shift_mass_ratio["2"] > 0
    assert s.overdamped_justified and s.engines_max_rel_diff < 0.01
    assert s.sigma_c_0["7"] == pytest.approx(0.1574695, rel=1e-6)


def test_noise_readings_ito_dies_stratonovich_survives(runs):
    s = runs[1]["noise_readings"].summary
    by = {r.reading: r for r in s.readings}
    assert by["ito"].reduced.not_sustained == ["0.3"]
    assert by["stratonovich"].mujoco is None and by["stratonovich"].survives
    assert math.isfinite(by["stratonovich"].reduced.period_cv["0.3"])

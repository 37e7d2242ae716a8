"""Numerics left at their defaults are automatic for long chains, and what they pick always passes the pre-flight
check: a chain of LONG_CHAIN particles or more runs with the defaults at any sigma (the README's promise)."""

import json

import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.core.params import LONG_CHAIN, Numerics
from elastoactive.engines.timestep import check_timestep


@pytest.mark.parametrize("n, sigma", [(LONG_CHAIN, 0.05), (LONG_CHAIN, 10.0), (100, 0.05), (100, 0.8), (200, 10.0)])
def test_automatic_numerics_pass_the_preflight_check(n, sigma):
    physics = ea.Physics(n=n, sigma=sigma)
    check_timestep(physics, Numerics())  # raises ParameterError if what the defaults become is refused


def test_a_given_setting_is_still_checked_as_given():
    with pytest.raises(ea.ParameterError, match="does not resolve"):
        check_timestep(ea.Physics(n=100), Numerics(dt=0.0025))


def test_long_chain_runs_with_the_defaults_and_records_what_ran(tmp_path):
    out = tmp_path / "long"
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--n",
                "100",
                "--duration",
                "1",
                "--transient",
                "0.2",
                "--sample-dt",
                "0.05",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    numerics = json.loads((out / "summary.json").read_text())["numerics"]
    used = Numerics().for_physics(ea.Physics(n=100))
    assert numerics["dt"] == pytest.approx(used.dt) and used.dt < 0.0025


def test_a_long_run_records_a_bounded_number_of_samples(tmp_path):
    """sample_dt left at its default is coarsened (whole steps of dt) so that a long run records at most
    AUTO_SAMPLES samples: a long chain's beat lasts ~1e6 tau. A given sample_dt is kept."""
    from elastoactive.core.params import AUTO_SAMPLES

    numerics = Numerics().for_duration(3e6)
    assert numerics.sample_times(3e6).size <= AUTO_SAMPLES + 1
    assert numerics.steps_per_sample * numerics.dt == pytest.approx(numerics.sample_dt)
    assert Numerics().for_duration(300.0) is not None and Numerics().for_duration(300.0).sample_dt == 0.05
    with pytest.raises(ea.ParameterError, match="samples"):
        Numerics(sample_dt=0.05).for_duration(3e6).check_duration(3e6)
    out = tmp_path / "n40"
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--engine",
                "reduced",
                "--n",
                "40",
                "--sigma",
                "0.0015625",
                "--duration",
                "2e5",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    assert json.loads((out / "summary.json").read_text())["numerics"]["sample_dt"] == pytest.approx(2.0)

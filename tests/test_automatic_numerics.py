"""Numerics left at their defaults are automatic for long chains, and what they pick always passes the pre-flight
check: a chain of LONG_CHAIN particles or more runs with the defaults at any sigma (the README's promise)."""

import json

import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.diagnose import check_timestep
from elastoactive.params import LONG_CHAIN, Numerics


@pytest.mark.parametrize("n, sigma", [(LONG_CHAIN, 0.05), (LONG_CHAIN, 10.0), (100, 0.05), (100, 0.8), (200, 10.0)])
def test_automatic_numerics_pass_the_preflight_check(n, sigma):
    physics = ea.Physics(n=n, sigma=sigma)
    check_timestep(physics, Numerics())  # raises ParameterError if what the defaults become is refused


def test_a_given_setting_is_still_checked_as_given():
    with pytest.raises(ea.ParameterError, match="does not resolve"):
        check_timestep(ea.Physics(n=100), Numerics(dt=0.0025))


def test_long_chain_runs_with_the_defaults_and_records_what_ran(tmp_path):
    out = tmp_path / "long"
    assert main(["run", "one-pinned", "--n", "100", "--duration", "1", "--transient", "0.2", "--sample-dt", "0.05", "--out", str(out),
                 "--quiet"]) == 0
    numerics = json.loads((out / "summary.json").read_text())["numerics"]
    used = Numerics().for_physics(ea.Physics(n=100))
    assert numerics["dt"] == pytest.approx(used.dt) and used.dt < 0.0025

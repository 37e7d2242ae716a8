"""The seed of the initial perturbation and the noise (Numerics.seed) is an integer from 0 to MAX_SEED, refused in one
line naming it otherwise, from Python and on every command line, before anything runs."""

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.core.params import MAX_SEED, Numerics

TOO_LARGE = "99999999999999999999"


@pytest.mark.parametrize("seed", [MAX_SEED + 1, 2**63, 2**64, int(TOO_LARGE), float(2**60), -1])
def test_a_seed_out_of_range_is_refused_naming_it(seed):
    with pytest.raises(ea.ParameterError, match=r"^seed must be .* at most 2\^53 = 9007199254740992, got "):
        Numerics(seed=seed)


@pytest.mark.parametrize("seed", [0, 1, MAX_SEED, np.uint64(MAX_SEED), float(2**40)])
def test_every_seed_in_range_is_taken_as_an_int(seed):
    numerics = Numerics(seed=seed)
    assert numerics.seed == int(seed) and type(numerics.seed) is int


def test_the_largest_seed_survives_mujocos_double():
    """Every seed allowed reaches MuJoCo's noise callback exactly (through a double), so both engines draw alike."""
    assert int(float(MAX_SEED)) == MAX_SEED and int(float(MAX_SEED - 1)) == MAX_SEED - 1


@pytest.mark.parametrize(
    "argv",
    [
        ["run", "lattice", "--rotational-diffusion", "0.1", "--engine", "reduced", "--seed", TOO_LARGE],
        ["run", "lattice", "--rotational-diffusion", "0.1", "--engine", "mujoco", "--seed", TOO_LARGE],
        ["run", "one-pinned", "--noise", "0.1", "--seed", TOO_LARGE],
        ["validate", "--seed", TOO_LARGE],
        ["sweep", "one-pinned", "--noise", "0.1", "--grid", "sigma=0.3,0.4", "--seed", TOO_LARGE, "--out", "{tmp}"],
        ["ramp", "lattice", "--rings", "1", "--ramp", "Pi=0.6,0.7", "--seeds", TOO_LARGE, "--out", "{tmp}"],
    ],
)
def test_a_seed_too_large_is_one_line_on_the_command_line(argv, capsys, tmp_path, no_simulation):
    argv = [a.replace("{tmp}", str(tmp_path / "out.nc")) for a in argv]
    assert main([*argv, "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "seed" in err[0] and TOO_LARGE in err[0] and "Traceback" not in err[0], err

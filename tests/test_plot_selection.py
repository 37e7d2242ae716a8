"""ea.plot.sweep_map draws every dimension or has it selected: a value or a dimension the dataset does not have, and a
dimension it would otherwise hide (a ramp's seed and leg, a pair's chain, a third swept parameter), are refused in one
line naming them and their values; the title says what was selected."""

import json

import matplotlib
import numpy as np
import pytest
import xarray as xr

import elastoactive as ea

matplotlib.use("Agg")


@pytest.fixture(autouse=True)
def _closed():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


def _sweep():
    """A coupled pair's sweep over sigma x kappa x n, as its netCDF reads back (per-chain amplitude)."""
    sigma, kappa, n, chain = [0.5, 0.6, 0.7], [1.0, 2.0], [3, 4], [1, 2]
    amplitude = np.arange(24.0).reshape(3, 2, 2, 2)
    return xr.Dataset(
        {
            "amplitude": (("sigma", "kappa", "n", "chain"), amplitude, {"long_name": "amplitude", "units": "rad"}),
            "wall_time_s": (("sigma", "kappa", "n"), np.ones((3, 2, 2)), {"units": "s"}),
        },
        coords={"sigma": sigma, "kappa": kappa, "n": n, "chain": chain},
        attrs={"grid": "sigma kappa n"},
    )


def _ramp():
    """A ramp's netCDF: seed x direction x Pi, the ramped parameter named in its `ramp` attribute."""
    values = np.arange(12.0).reshape(2, 2, 3)
    return xr.Dataset(
        {"amplitude": (("seed", "direction", "Pi"), values, {"long_name": "amplitude", "units": "rad"})},
        coords={"seed": [0, 1], "direction": np.array(["up", "down"], dtype=object), "Pi": [0.6, 0.7, 0.8]},
        attrs={"ramp": json.dumps({"parameter": "Pi", "values": [0.6, 0.7, 0.8]})},
    )


def _one_line(match, call):
    with pytest.raises(ea.ParameterError, match=match) as refused:
        call()
    assert "\n" not in str(refused.value)
    return str(refused.value)


def test_a_ramp_is_not_drawn_as_seed_against_leg():
    message = _one_line(
        r"beyond the Pi drawn: seed \(0, 1\); direction \('up', 'down'\)", lambda: ea.plot.sweep_map(_ramp())
    )
    assert "sweep_map(ds, 'amplitude', seed=0, direction='up')" in message
    ax = ea.plot.sweep_map(_ramp(), "amplitude", seed=1, direction="down")
    np.testing.assert_array_equal(ax.get_lines()[0].get_xydata(), [[0.6, 9.0], [0.7, 10.0], [0.8, 11.0]])
    assert ax.get_title() == "seed = 1, direction = 'down'"


def test_a_third_swept_parameter_and_the_chain_are_selected_not_cut():
    message = _one_line(
        r"beyond the sigma and kappa drawn: n \(3, 4\); chain \(1, 2\)", lambda: ea.plot.sweep_map(_sweep())
    )
    assert "e.g. sweep_map(ds, 'amplitude', n=3, chain=1)" in message
    _one_line(r"beyond the sigma and kappa drawn: n \(3, 4\);", lambda: ea.plot.sweep_map(_sweep(), chain=2))
    ax = ea.plot.sweep_map(_sweep(), "amplitude", n=4, chain=2)
    mesh = ax.collections[0]
    np.testing.assert_array_equal(np.asarray(mesh.get_array()).reshape(3, 2), _sweep()["amplitude"][:, :, 1, 1])
    assert ax.get_title() == "n = 4, chain = 2"
    assert ea.plot.sweep_map(_sweep(), "wall_time_s", n=3).get_title() == "n = 3"


def test_a_selection_made_before_is_in_the_title():
    ax = ea.plot.sweep_map(_sweep().sel(n=4, kappa=2.0), "amplitude", chain=1)
    assert ax.get_title() == "kappa = 2, n = 4, chain = 1" and len(ax.get_lines()) == 1


@pytest.mark.parametrize(
    "selection, words",
    [
        ({"n": 99}, r"^n=99: not a value of n in the sweep \(its values: 3, 4\)$"),
        ({"sigma": 0.65, "n": 3, "chain": 1}, r"^sigma=0.65: not a value of sigma .*\(its values: 0.5, 0.6, 0.7\)$"),
        ({"chain": "1"}, r"^chain='1': not a value of chain"),
        ({"amplitude": 1}, r"^amplitude: not a dimension of amplitude \(its dimensions: sigma, kappa, n, chain\)$"),
    ],
)
def test_a_value_or_dimension_the_sweep_lacks_is_refused_with_what_exists(selection, words):
    _one_line(words, lambda: ea.plot.sweep_map(_sweep(), "amplitude", **selection))


def test_grid_values_match_within_round_off():
    ax = ea.plot.sweep_map(_sweep(), "amplitude", n=3, chain=1, kappa=2.0 * (1 + 1e-12))
    assert ax.get_title() == "kappa = 2, n = 3, chain = 1"
    _one_line("not a value of direction", lambda: ea.plot.sweep_map(_ramp(), seed=0, direction="sideways"))

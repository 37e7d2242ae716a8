"""A grid's size is checked when it is parsed: one too large to be sensible is refused in one line, at once."""

import time

import numpy as np
import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.sweep.grid import MAX_GRID_POINTS, make_sweep, parse_grid


@pytest.mark.parametrize(
    "specs", [["sigma=0.2:1:100000"], ["sigma=0.2:1:1000000000000"], ["sigma=0.2:1:200", "n=3:102:100"]]
)
def test_a_grid_beyond_the_limit_is_refused_when_parsed(specs):
    start = time.perf_counter()
    with pytest.raises(ParameterError, match=f"points, more than {MAX_GRID_POINTS}") as err:
        parse_grid(specs)
    assert time.perf_counter() - start < 1.0 and "\n" not in str(err.value) and "sigma" in str(err.value)


def test_a_grid_given_as_values_is_held_to_the_same_limit():
    with pytest.raises(ParameterError, match="more than"):
        make_sweep("one-pinned", {"sigma": np.linspace(0.2, 1, 101), "n": np.arange(3, 103)}, engine="reduced")
    assert parse_grid([f"sigma=0.2:1:{MAX_GRID_POINTS}"])["sigma"].size == MAX_GRID_POINTS


def test_an_integer_past_what_a_grid_holds_exactly_is_refused_naming_it():
    """A seed of 1e20 read as a float is no integer the grid can hold: refused naming the value, not cast to
    -9223372036854775808 with numpy's RuntimeWarning."""
    with pytest.raises(ParameterError, match=r"grid seed: 1e\+20 is past the integers a grid holds exactly") as err:
        parse_grid(["seed=99999999999999999999,1"])
    assert "\n" not in str(err.value)
    assert parse_grid(["seed=9007199254740992,1"])

"""sweep.grid: a grid's repeated values are refused, and parsing a grid loads no more of numpy than it uses."""

import subprocess
import sys

import pytest

from elastoactive.core.errors import ParameterError
from elastoactive.sweep import parse_grid


@pytest.mark.parametrize("axis", ["sigma=0.5,0.5", "sigma=0.0,-0.0", "n=3,3", "seed=1,1"])
def test_repeated_values_are_refused(axis):
    with pytest.raises(ParameterError, match="repeated values"):
        parse_grid([axis])


def test_distinct_values_pass_in_their_order():
    assert parse_grid(["sigma=1.0,0.5,0.75"])["sigma"].tolist() == [1.0, 0.5, 0.75]


def test_parsing_a_grid_does_not_load_numpy_ma():
    """numpy.ma (np.unique loads it) costs a sweep ~10 ms of start-up before its first step."""
    code = "import sys; from elastoactive.sweep import parse_grid; parse_grid(['sigma=0.3:1.0:16', 'n=5,7']); "
    code += "print('numpy.ma' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"

"""sweep.grid: a grid's repeated values are refused, and parsing a sweep loads no more than it uses."""

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


def test_parsing_a_sweep_loads_neither_numpy_ma_nor_scipy():
    """Before its first step a MuJoCo sweep needs neither: numpy.ma (np.unique loads it) costs ~10 ms, scipy.signal
    (a scene's module importing it at its top) ~0.4 s of start-up on an idle machine."""
    argv = ["sweep", "one-pinned", "--grid", "sigma=0.3:1.0:16", "--grid", "n=5,7", "--out", "x.nc"]
    code = (
        "import sys; from elastoactive.cli import build_parser; from elastoactive.sweep import parse_grid; "
        f"args = build_parser(lazy=True).parse_args({argv!r}); parse_grid(args.grid); "
        "print(sorted(m for m in ('numpy.ma', 'scipy') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"

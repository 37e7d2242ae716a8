"""What the sweep tests share: the fast preset, a saved dataset read back, the volatile variables, a stop signal."""

import xarray as xr

from elastoactive.core.params import Numerics

FAST = Numerics.preset("fast")
VOLATILE = ["wall_time_s", "finished_at"]
"""Variables that differ between two runs of the same point (times)."""
REDUCED = dict(fixed={"n": 3}, numerics=FAST, duration=20, engine="reduced", progress=False, workers=1)
"""A small reduced-engine sweep's settings."""


def load(path):
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


class Stop(Exception):
    """Raised from a callback to interrupt a sweep part way."""

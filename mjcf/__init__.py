"""The MJCF base scenes: one XML file per scene, each including the shared common.xml.

Paper defaults N = 7, sigma = 0.8; elastoactive.mjcf.chain regenerates the chain for any N.
"""

from importlib import resources
from pathlib import Path


def mjcf_path(name: str) -> Path:
    """Path of an MJCF file shipped with elastoactive (e.g. a scene's `base_file`)."""
    path = Path(str(resources.files(__name__).joinpath(name)))
    if not path.is_file():
        raise FileNotFoundError(f"no MJCF file {name!r} in {path.parent}")
    return path

"""The MJCF base scenes (one XML file per scene; paper defaults N = 7, sigma = 0.8)."""

from importlib import resources
from pathlib import Path

from ..params import SCENES


def scene_path(scene: str) -> Path:
    """Path of the base MJCF file of a scene."""
    if scene not in SCENES:
        raise ValueError(f"unknown scene {scene!r}; choose one of {', '.join(SCENES)}")
    return Path(str(resources.files(__name__).joinpath(f"{scene}.xml")))

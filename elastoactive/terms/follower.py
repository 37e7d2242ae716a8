"""The follower force: F_a = sigma C1 / l on each loaded particle, along its link (the paper's active force).

Its parameters: sigma (the elasto-active number) and loaded (which particles carry it). MuJoCo applies it in the
compiled passive callback (controllers/follower.c) on the particle sites whose user value is non-zero
(elastoactive.mjcf.chain); the reduced model reads sigma from its record and the load mask as per-particle force
factors (elastoactive.engines.reduced.load_factors).
"""

from __future__ import annotations

import numpy as np

from ..core.errors import ParameterError
from ..core.parameters import Parameter
from ..core.units import NETWORK, Worded
from .base import Term

SIGMA = Parameter(
    "sigma",
    0.8,
    "elasto-active number F_a l / C1",
    low=0.0,
    title="elasto-active number",
    symbol="σ",
    worded=(Worded(NETWORK.name, "active force of each unit F_a / (k a) = l_e / a"),),
)
LOADED = Parameter(
    "loaded",
    "all",
    "particles carrying the follower force: all, tip, or 1-based indices like 1,3,7",
    kind=str,
    quiet_default=True,
)


def loaded_indices(text: str, n: int) -> list[int]:
    """The 1-based particle indices of a `loaded` value other than "all" and "tip" (checked)."""
    parts = [p.strip() for p in text.split(",")]
    try:
        idx = [int(p) for p in parts]
    except ValueError:
        raise ParameterError(
            f"loaded must be all, tip, or comma-separated 1-based particle indices like 1,3,7; got {text!r}"
        ) from None
    bad = [i for i in idx if not 1 <= i <= n]
    if bad:
        raise ParameterError(f"loaded: particle indices must lie in 1..{n} (N = {n}), got {bad[0]} in {text!r}")
    dup = sorted({i for i in idx if idx.count(i) > 1})
    if dup:
        raise ParameterError(f"loaded: particle index {dup[0]} appears more than once in {text!r}")
    return idx


def normalise_loaded(value, n: int) -> str:
    """The checked, normalised `loaded` value: "all", "tip", or sorted indices "1,3,7" (a list of ints is accepted)."""
    if not isinstance(value, str):
        if isinstance(value, (list, tuple)) and all(isinstance(i, int) and not isinstance(i, bool) for i in value):
            value = ",".join(str(i) for i in value)
        else:
            raise ParameterError(f"loaded must be a string (all, tip, or indices like 1,3,7), got {value!r}")
    text = value.strip().lower()
    if text in ("all", "tip"):
        return text
    if not text:
        raise ParameterError("loaded must be all, tip, or comma-separated 1-based particle indices like 1,3,7; got ''")
    return ",".join(str(i) for i in sorted(loaded_indices(text, n)))


def load_mask(loaded: str, n: int) -> np.ndarray:
    """Boolean mask of the particles of one chain that carry the force."""
    mask = np.zeros(n, dtype=bool)
    if loaded == "all":
        mask[:] = True
    elif loaded == "tip":
        mask[-1] = True
    else:
        mask[np.array(loaded_indices(loaded, n)) - 1] = True
    return mask


class Follower(Term):
    name = "follower"
    summary = "the active force sigma along each loaded particle's link"
    labelled = False
    parameters = (SIGMA, LOADED)

    def prepare(self, values: dict) -> None:
        values["loaded"] = normalise_loaded(values["loaded"], values["n"])

    def load_mask(self, physics) -> np.ndarray:
        return load_mask(physics.loaded, physics.n)

    def active(self, physics) -> bool:
        return True  # sigma = 0 is a chain without activity, still the record's value

    def reduced_system(self, system, physics):
        return system._replace(sigma=physics.sigma)


TERM = Follower()

"""Hydrodynamic mobilities of beads: who moves how fast under whose force, through the fluid.

Arrays in, arrays out (numpy and numba; nothing of the package but elastoactive.core: the error type, numba's keyed
cache). Units are the paper's: lengths in l, the drag of one bead gamma = 6 pi mu a = 1, so an isolated bead's self-
mobility is the identity; the bead radius a / l is the parameter `radius`. A mobility is a (3n, 3n) array whose block
(i, j) maps the force on bead j to the velocity of bead i.

- `rpy`, `rpy_into`: free space, Rotne-Prager-Yamakawa with the overlap correction (elastoactive.hydro.rpy).
- `rpb`, `rpb_into`: above a no-slip plane wall at z = 0, Rotne-Prager-Blake with Swan and Brady's finite-size
  corrections (elastoactive.hydro.blake).
- `apply`: either mobility's product with forces, never forming the matrix (elastoactive.hydro.product).
"""

from ..core.jit_cache import use_keyed_cache

use_keyed_cache()  # before any kernel module: numba reads its cache folder when first imported

from .blake import rpb, rpb_into  # noqa: E402
from .product import apply  # noqa: E402
from .rpy import rpy, rpy_into  # noqa: E402

__all__ = ["apply", "rpb", "rpb_into", "rpy", "rpy_into"]

"""The package's mathematics. Importing it first points numba's on-disk cache at a folder keyed by the compiled
sources (analysis.jit_cache), so an edited kernel is never loaded stale from the cache of another."""

from .jit_cache import use_keyed_cache

use_keyed_cache()

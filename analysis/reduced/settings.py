"""The reduced model's solver settings that code outside the solvers needs, importable without numba (the engine
and the pre-flight check read them at start-up; solve.py, which loads numba, uses them)."""

DEFAULT_BETA = 10.0
"""Baumgarte rate of the two-pinned constraint drift (per tau)."""

STIFF_RADIUS = 2.0e3
"""Fastest decay rate of the Jacobian at theta0 (see solve.stiffness) above which method=None picks implicit Radau."""

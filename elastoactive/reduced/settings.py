"""The reduced model's solver settings that code outside the solvers needs, importable without numba (the engine
and the pre-flight check read them at start-up; solve.py, which loads numba, uses them)."""

COMPILED_METHODS = ("numba-DOP853",)
"""Methods compiled with the right-hand side (dop853.py)."""
SCIPY_METHODS = ("RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA")
"""scipy.integrate.solve_ivp methods solve_ode accepts."""
METHODS = COMPILED_METHODS + SCIPY_METHODS
"""Every method name solve_ode takes (None: the automatic choice); the command line's --method choices."""

DEFAULT_BETA = 10.0
"""Baumgarte rate of the two-pinned constraint drift (per tau)."""

STIFF_RADIUS = 2.0e3
"""Fastest decay rate of the Jacobian at theta0 (see solve.stiffness) above which method=None picks implicit Radau."""

IMPLICIT_RATIO = 2.0e3
"""Stiffness ratio (solve.stiffness_ratio: fastest decay rate over the slow dynamics at theta0) above which
method=None picks the implicit LSODA with the analytic Jacobian instead of numba-DOP853. Measured crossover
(clamped chain at S = N^3 sigma = 100, wall time per beat period): ratio 430 (N = 10) DOP853 0.008 s against
LSODA 0.018 s; ratio 8500 (N = 20) DOP853 0.19 s against LSODA 0.03 s; the explicit cost grows with the ratio
(~ N^4), the implicit one does not. The paper's N = 7 runs have ratios below 200."""

IMPLICIT_WORK = 2.0e5
"""Duration x fastest decay rate (about 3 x the explicit DOP853's steps) below which method=None keeps
numba-DOP853 whatever the stiffness ratio: ~6e4 explicit steps cost a fraction of a second at any N, and the
paper's chains keep the method they always had (N = 7 has stiffness ratios above IMPLICIT_RATIO only well below
its onset, sigma <~ 0.05, where this allows ~14000 tau). At N = 20, S = 100 one beat period is ~6e4."""

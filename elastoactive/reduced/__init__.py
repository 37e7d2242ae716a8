"""The reduced pendulum model, overdamped (the paper's) or with the particles' inertia (MuJoCo's chain at a
finite mass), solved without MuJoCo: arrays and records in, arrays out.

  system.py                a system of chains as a typed record, ChainSystem (built by each scene)
  equations.py             the derivations (overdamped and inertial), the paper's errata, rhs_reference and
                           rhs_inertial_reference (plain numpy)
  constraints.py           the two-pinned constraints g = 0: residual, Jacobian, projection
  contact.py               self-contact of a chain's capsules (plain numpy): geometry, capsule_clearance, penalty
  kernels.py               numba kernels: drag matrix, forces, right-hand side, Jacobian, Euler-Maruyama;
                           the inertial model's right-hand side (dense mass matrix), its Jacobian and RK4
  dop853_coefficients.py   the DOP853 tableau (copied from scipy, BSD)
  dop853.py                the chain's DOP853: dop853_loop's driver around the compiled right-hand side
  regime.py                the overdamped limit: when a particle mass needs the inertial model (numpy)
  settings.py              solver settings read outside the solvers (Baumgarte rate, stiffness thresholds)
  blas.py                  one BLAS thread while the implicit solvers factorise (ctypes)
  solve.py                 the public solvers on a ChainSystem: rhs, jacobian, solve_ode, solve_sde,
                           solve_inertial, ...
  node_kernels.py          the right-hand side with periodic point forces (numba)
  network.py               the elastic network of self-aligning units: right-hand side, Jacobian, normal modes
                           (dense, or sparse for large networks), the solvers
  network_kernels.py       the network's compiled kernels: right-hand side, DOP853, Euler-Maruyama, the noise draw
  chain3d.py               the chain in three dimensions: unit tangents, O(N) drag solve, Jacobian, solve3d
  fluid.py                 chains coupled through the fluid: J^T M^-1 J q' = J^T F - dU/dq by the links' tensions
  fluid_kernels.py         its compiled right-hand side and DOP853 (numba)
  fluid_extrapolated.py    the interaction taken at each step's start and extrapolated over the step (numba)
  tensions.py              those tensions' system: Cholesky, or block-preconditioned conjugate gradients
  dop853_loop.py           DOP853's step loop, written once: every compiled DOP853 is a cached driver of it

This package knows no scene and no Physics: elastoactive.engines.reduced turns a Physics into a
ChainSystem (Scene.reduced_system) and a Trajectory. Importing it is cheap (numpy and numba's import); the names
of solve.py, which need numba, load it on first use.
"""

from ..core.jit_cache import use_keyed_cache

use_keyed_cache()  # before any kernel module: numba reads its cache folder when first imported

from .constraints import pin_jacobian, pin_residual, project_on_pins
from .contact import capsule_clearance
from .equations import drag_and_forces_reference, potential_reference, rhs_inertial_reference, rhs_reference
from .regime import (
    INERTIA_RESOLUTION,
    force_jacobian,
    inertia_number,
    needs_inertia,
    outside_overdamped_limit,
    overdamped_rate,
    rate_bound,
)
from .settings import DEFAULT_BETA, IMPLICIT_RATIO, STIFF_RADIUS
from .system import BEAD_INERTIA_FACTOR, CONTACT_LENGTH, ChainSystem

SOLVE_NAMES = (  # the public names of solve.py (its __all__), loaded on first use
    "COMPILED_METHODS",
    "IMPLICIT_METHODS",
    "RK4_STEP",
    "SCIPY_METHODS",
    "SDE_SCHEMES",
    "STIFF_RATIO",
    "constraint_violation",
    "drag_matrix",
    "jacobian",
    "mass_matrix",
    "rhs",
    "solve_inertial",
    "solve_ode",
    "solve_sde",
    "spectral_radius",
    "stiffness",
    "stiffness_ratio",
)

__all__ = [
    "BEAD_INERTIA_FACTOR",
    "COMPILED_METHODS",
    "CONTACT_LENGTH",
    "ChainSystem",
    "DEFAULT_BETA",
    "IMPLICIT_METHODS",
    "IMPLICIT_RATIO",
    "INERTIA_RESOLUTION",
    "RK4_STEP",
    "SCIPY_METHODS",
    "SDE_SCHEMES",
    "STIFF_RADIUS",
    "STIFF_RATIO",
    "capsule_clearance",
    "constraint_violation",
    "drag_and_forces_reference",
    "drag_matrix",
    "force_jacobian",
    "inertia_number",
    "jacobian",
    "mass_matrix",
    "needs_inertia",
    "outside_overdamped_limit",
    "overdamped_rate",
    "pin_jacobian",
    "pin_residual",
    "potential_reference",
    "project_on_pins",
    "rate_bound",
    "rhs",
    "rhs_inertial_reference",
    "rhs_reference",
    "solve_inertial",
    "solve_ode",
    "solve_sde",
    "spectral_radius",
    "stiffness",
    "stiffness_ratio",
]


def __getattr__(name: str):
    # start-up time: solve.py imports numba (~0.2 s), and every scene imports ChainSystem from this
    # package when elastoactive is imported; the solvers are loaded on first use
    if name in SOLVE_NAMES:
        from . import solve  # loaded on first use (numba; see above)

        return getattr(solve, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(SOLVE_NAMES))

"""The reduced-model package as a package: its DOP853 tableau, its compiled kernels' specialisations,
its imports, and its API on a bare ChainSystem (no scene, no Physics)."""

from __future__ import annotations

import ast
import pathlib

import numpy as np
import pytest

from elastoactive import reduced as M
from elastoactive.core.errors import ParameterError
from elastoactive.reduced import dop853, dop853_coefficients, kernels

PACKAGE = "elastoactive.reduced"
SOURCES = sorted(pathlib.Path(M.__file__).parent.glob("*.py"))


# ------------------------------------------------------------------------------------------------
# the DOP853 tableau
# ------------------------------------------------------------------------------------------------
def test_dop853_coefficients_equal_scipys():
    # The only import of a private scipy module in the project, on purpose: our copy of the tableau
    # must stay equal to the one scipy's solve_ivp(method="DOP853") uses.
    from scipy.integrate._ivp import dop853_coefficients as scipy_coef

    for name in ("N_STAGES", "N_STAGES_EXTENDED", "INTERPOLATOR_POWER"):
        assert getattr(dop853_coefficients, name) == getattr(scipy_coef, name), name
    for name in ("A", "B", "C", "E3", "E5", "D"):
        ours, theirs = getattr(dop853_coefficients, name), getattr(scipy_coef, name)
        assert ours.shape == theirs.shape, name
        np.testing.assert_array_equal(ours, theirs, err_msg=name)


# ------------------------------------------------------------------------------------------------
# one compiled specialisation per kernel
# ------------------------------------------------------------------------------------------------
def _systems():
    """Two records with different values, and fields given as numpy scalars or ints where floats belong."""
    a = M.ChainSystem(
        n=np.int64(4), n_chains=2, clamped=np.bool_(True), sigma=1, gamma_l=2, kappa=np.float32(0.5), rho=2
    )
    b = M.ChainSystem(n=4, n_chains=2, clamped=True, sigma=0.7, gamma_l=1.5, kappa=1.25, rho=1.4)
    return a, b


def _record_types(dispatcher):
    """The ChainSystem argument types of each compiled signature of `dispatcher` (given itself, or in a tuple of
    arguments: dop853._dop853's args)."""
    args = [arg for sig in dispatcher.signatures for arg in sig]
    args += [inner for arg in args if type(arg).__name__ in ("Tuple", "UniTuple") for inner in arg.types]
    return {arg for arg in args if "NamedTuple" in type(arg).__name__}


def test_kernels_compile_once_for_chain_systems():
    rng = np.random.default_rng(0)
    t = 0.05 * np.arange(41)
    for system in _systems():
        th = 0.3 * rng.standard_normal(system.n_angles)
        M.rhs(system, beta=M.DEFAULT_BETA)(0.0, th)
        M.jacobian(system, beta=3)(0.0, th)  # an integer beta too
        M.solve_ode(system, t, th, rtol=1e-8, atol=1e-10, method="numba-DOP853", beta=M.DEFAULT_BETA)
        M.solve_sde(system, t, th, dt=0.01, factors=lambda steps: np.ones((steps.size, 8)), beta=M.DEFAULT_BETA)
    for dispatcher in (kernels.eval_rhs, kernels.eval_jacobian, kernels.euler_maruyama, dop853._dop853):
        assert len(dispatcher.signatures) == 1, (dispatcher, dispatcher.signatures)
        (record,) = _record_types(dispatcher)
        # n, n_chains; clamped, pinned; sigma .. inertia_factor; head_free; trap, contact_radius, contact_stiffness;
        # closed; star, hub_free; hub_stiffness, hub_drag
        assert [str(ty) for ty in record.types] == (
            ["int64"] * 2 + ["bool"] * 2 + ["float64"] * 8 + ["bool"] + ["float64"] * 3 + ["bool"] * 3 + ["float64"] * 2
        )


def test_typed_coerces_and_checks():
    a, b = _systems()
    ta = a.typed()
    assert [type(v) for v in ta] == [int, int, bool, bool] + [float] * 8 + [bool] + [float] * 3 + [bool] * 3 + [
        float
    ] * 2
    assert ta == a and b.typed() == b
    with pytest.raises(ParameterError):
        M.ChainSystem(n=0).typed()
    with pytest.raises(ParameterError):
        M.ChainSystem(n=3, n_chains=3).typed()
    with pytest.raises(ParameterError):
        M.ChainSystem(n=3, n_chains=2, pinned=True).typed()


# ------------------------------------------------------------------------------------------------
# imports: pure mathematics
# ------------------------------------------------------------------------------------------------
def _imports(path: pathlib.Path):
    """(absolute module name, at module level?) of every import in a source file of the package."""
    tree = ast.parse(path.read_text(), str(path))
    package = PACKAGE.split(".")
    top_level = set(map(id, tree.body))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, id(node) in top_level
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package[: len(package) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            yield base, id(node) in top_level
            for alias in node.names:
                yield f"{base}.{alias.name}", id(node) in top_level


def test_package_imports_nothing_of_elastoactive_but_the_records_below_it():
    """Only itself, the network records, the mobilities (elastoactive.hydro), errors, constants and numba's keyed
    cache: the reduced engine knows no scene, term or Physics."""
    assert {p.name for p in SOURCES} >= {
        "__init__.py",
        "system.py",
        "equations.py",
        "constraints.py",
        "kernels.py",
        "dop853_coefficients.py",
        "dop853.py",
        "solve.py",
    }
    for path in SOURCES:
        for name, _ in _imports(path):
            if name == "elastoactive" or name.startswith("elastoactive."):
                allowed = name.startswith(
                    (
                        "elastoactive.reduced",
                        "elastoactive.networks",
                        "elastoactive.hydro",
                        "elastoactive.core.errors",
                        "elastoactive.core.constants",
                        "elastoactive.core.jit_cache",
                    )
                )
                assert allowed, f"{path.name} imports {name}"


def test_package_imports_no_private_scipy_and_scipy_integrate_only_lazily():
    for path in SOURCES:
        for name, top in _imports(path):
            assert not name.startswith("scipy.integrate._"), f"{path.name} imports the private {name}"
            if name.startswith("scipy.integrate"):
                assert not top, f"{path.name} imports {name} at module level (start-up time)"


# ------------------------------------------------------------------------------------------------
# the API on a bare record
# ------------------------------------------------------------------------------------------------
def test_solvers_on_a_bare_record():
    system = M.ChainSystem(n=3, sigma=0.5)
    t = 0.1 * np.arange(11)
    th0 = np.array([0.1, -0.05, 0.02])
    theta, info = M.solve_ode(system, t, th0, rtol=1e-9, atol=1e-11, beta=M.DEFAULT_BETA)
    assert theta.shape == (11, 3) and info["method"] == "numba-DOP853" and info["stiffness"] < M.STIFF_RADIUS
    np.testing.assert_array_equal(theta[0], th0)
    radau, rinfo = M.solve_ode(system, t, th0, rtol=1e-10, atol=1e-12, method="Radau", beta=M.DEFAULT_BETA)
    assert rinfo["njev"] > 0 and np.max(np.abs(radau - theta)) < 1e-7
    # Euler-Maruyama with unit factors converges to the ODE solution
    em, einfo = M.solve_sde(system, t, th0, dt=1e-4, factors=lambda s: np.ones((s.size, 3)), beta=M.DEFAULT_BETA)
    assert einfo["nsteps"] == 10000 and np.max(np.abs(em - theta)) < 1e-4
    assert M.constraint_violation(system, theta) == 0.0
    with pytest.raises(ParameterError):
        M.solve_ode(system, t, th0[:2], rtol=1e-9, atol=1e-11, beta=M.DEFAULT_BETA)
    with pytest.raises(ParameterError):
        M.solve_ode(system, t, th0, rtol=1e-9, atol=1e-11, method="Euler", beta=M.DEFAULT_BETA)
    with pytest.raises(ParameterError):
        M.solve_sde(system, t, th0, dt=0.01, factors=lambda s: np.ones((s.size, 2)), beta=M.DEFAULT_BETA)
    with pytest.raises(ParameterError):
        M.rhs(system, beta=M.DEFAULT_BETA, factor=np.ones(4))


def test_pinned_record_keeps_its_pins():
    n, delta = 6, 0.1
    arch = M.project_on_pins(0.5 * np.cos(np.pi * (np.arange(1, n + 1) - 0.5) / n), delta)
    system = M.ChainSystem(n=n, pinned=True, sigma=0.8, delta=delta)
    theta, _ = M.solve_ode(system, 0.5 * np.arange(21), arch, rtol=1e-9, atol=1e-11, beta=M.DEFAULT_BETA)
    assert M.constraint_violation(system, theta) < 1e-8
    assert M.constraint_violation(system, theta[-1]) == pytest.approx(np.abs(M.pin_residual(theta[-1], delta)).max())
    f, ref = M.rhs(system, beta=3.0), M.rhs_reference(system, beta=3.0)
    np.testing.assert_allclose(f(0.0, theta[-1]), ref(0.0, theta[-1]), rtol=0, atol=1e-12)

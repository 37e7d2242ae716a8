"""`elastoactive stability SCENE`: the linear stability of a scene's straight chain, without simulating.

For every scene with a linear operator about its base state (analysis/stability.py): where the straight chain
loses stability (sigma_c) and how (omega_c: the flutter's angular frequency; 0 for the free pin's steady
rotation), the growth rate and frequency of its least stable mode at a given --sigma, and the continuum
filament's onset (analysis/continuum.py) with what it means at this N. The one-pinned chain's onset is computed
in O(N) per sigma (stability.onset): ~0.1 s at N = 200, ~0.3 s at N = 1000.
"""

from __future__ import annotations

import argparse
import math

from ..errors import ParameterError
from .options import UNITS

SCENES = ("one-pinned", "rotating-pin", "coupled-pair")
"""The scenes with a linear operator about a base state that does not depend on sigma (the straight chains)."""
NO_OPERATOR = {
    "two-pinned": "its base state, the buckled arch, is held by the pins and moves with the load",
    "paraboloid": "a free chain in a dish has no fixed base state (it drifts and turns as a whole)",
}
DENSE_GROWTH_MAX = 400
"""Up to this many angles the growth rate at --sigma comes from every eigenvalue (dense); beyond, from the
slowest modes (stability.slow_eigenvalues), which hold the least stable one near the onset."""
SLOW_GROWTH_MODES = 16
"""Slowest modes searched for the least stable one beyond DENSE_GROWTH_MAX."""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "stability", help="onset sigma_c, omega_c and growth rates from the linear operator (no simulation)",
        description="Linear stability of a scene's straight chain: sigma_c and omega_c, the growth rate at --sigma, "
        "and the continuum filament's onset. " + UNITS, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", metavar="SCENE", help=f"one of: {', '.join(SCENES)}")
    p.add_argument("--n", type=int, default=7, help="particles per chain N (default 7)")
    p.add_argument("--sigma", type=float, default=None, help="also the growth rate of the least stable mode here")
    p.add_argument("--kappa", type=float, default=None, help="coupled-pair: coupling stiffness (default the scene's)")
    p.add_argument("--rho", type=float, default=None, help="coupled-pair: stiffness ratio C2 / C1 (default the scene's)")
    p.set_defaults(func=main)


def _physics(args):
    """The scene's Physics (checks N, sigma, kappa, rho in one line each), or a ParameterError naming why not."""
    from ..params import Physics

    if args.scene in NO_OPERATOR:
        raise ParameterError(f"stability: {args.scene} has no linear operator here ({NO_OPERATOR[args.scene]}); "
                             f"scenes: {', '.join(SCENES)}")
    if args.scene not in SCENES:
        raise ParameterError(f"stability: scene must be one of {', '.join(SCENES)}, got {args.scene!r}")
    given = {k: getattr(args, k) for k in ("kappa", "rho") if getattr(args, k) is not None}
    if args.n < 2:
        raise ParameterError(f"n must be >= 2 for a chain that can bend, got {args.n}")
    sigma = 0.0 if args.sigma is None else args.sigma
    return Physics(scene=args.scene, n=args.n, sigma=sigma, **given)


def main(args) -> int:
    from ..analysis import stability as stab
    from ..analysis.continuum import continuum_critical
    from ..analysis.reduced.blas import one_blas_thread

    physics = _physics(args)
    n = physics.n
    with one_blas_thread():
        if physics.scene == "one-pinned":
            sigma_c, omega_c = stab.onset(n)
            kind = "flutter (Hopf)"
        elif physics.scene == "rotating-pin":
            sigma_c, omega_c = stab.rotation_threshold(n), 0.0
            kind = "steady rotation (a real eigenvalue crosses 0)"
        else:
            sigma_c, omega_c = _pair_onset(stab, n, physics.kappa, physics.rho)
            kind = "flutter (Hopf) of the pair"
        print(f"{physics.scene}, N = {n}" + (f", kappa = {physics.kappa:g}, rho = {physics.rho:g}"
                                            if physics.scene == "coupled-pair" else "") + ":")
        print(f"  onset: {kind} at sigma_c = {sigma_c:.10g} (N^3 sigma_c = {n**3 * sigma_c:.6g}), "
              f"omega_c = {omega_c:.6g} rad/tau (f_c tau = {omega_c / (2 * math.pi):.6g}, N^4 omega_c = "
              f"{n**4 * omega_c:.6g})")
        if args.sigma is not None:
            lam = _leading(stab, physics, args.sigma)
            state = "unstable" if lam.real > 0 else "stable"
            print(f"  at sigma = {args.sigma:g}: growth rate {lam.real:+.6g} /tau, angular frequency "
                  f"{abs(lam.imag):.6g} rad/tau ({state}; sigma / sigma_c = {args.sigma / sigma_c:.4g})")
    if physics.scene == "one-pinned":
        s_c, w_c = continuum_critical()
        print(f"  continuum filament (clamped, distributed follower load f, drag zeta): S_c = f L^3 / B = {s_c:.4f}, "
              f"omega_c = {w_c:.4f} B / (zeta L^4); at N = {n} (sigma = S / N^3, omega in 1 / (N^4 tau)): "
              f"sigma = {s_c / n**3:.6g}, omega = {w_c / n**4:.6g} rad/tau; the chain's N^3 sigma_c is "
              f"{100 * (n**3 * sigma_c / s_c - 1):+.2f}% from it")
    return 0


def _leading(stab, physics, sigma: float) -> complex:
    """The least stable eigenvalue of the scene's linear operator at sigma."""
    import numpy as np

    n = physics.n
    if physics.scene == "rotating-pin":
        lam = np.linalg.eigvals(stab.rotating_operator(n, sigma))
    elif physics.scene == "coupled-pair":
        lam = stab.pair_eigenvalues(n, sigma, physics.kappa, physics.rho)
    elif n <= DENSE_GROWTH_MAX:
        lam = stab.eigenvalues(n, sigma)
    else:
        lam = stab.slow_eigenvalues(n, sigma, SLOW_GROWTH_MODES)
    return complex(lam[np.argmax(lam.real)])


def _pair_onset(stab, n: int, kappa: float, rho: float) -> tuple[float, float]:
    """(sigma_c, omega_c) of the coupled pair: the first sigma where the pair's least stable eigenvalue crosses 0,
    bracketed from below by a geometric scan from a quarter of the softer chain's onset."""
    import numpy as np
    from scipy.optimize import brentq

    def growth(s: float) -> float:
        return float(np.max(np.linalg.eigvals(stab.pair_linear_operator(n, s, kappa, rho)).real))

    lo = 0.25 * min(1.0, rho) * stab.onset(n)[0]
    while growth(lo) >= 0:
        lo /= 4.0
    hi = lo
    while growth(hi) < 0:
        lo, hi = hi, 1.25 * hi
        if hi > 1e6:
            raise ParameterError(f"stability: the pair (kappa = {kappa:g}, rho = {rho:g}) is stable up to sigma = 1e6")
    sigma_c = brentq(growth, lo, hi, xtol=1e-300, rtol=1e-12)
    lam = stab.pair_eigenvalues(n, sigma_c, kappa, rho)
    return float(sigma_c), float(abs(lam[0].imag))

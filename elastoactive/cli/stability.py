"""`elastoactive stability SCENE`: the linear stability of a scene's straight chain (or a network's rest states),
without simulating.

For every scene with a linear operator about its base state (analysis/stability.py): where the straight chain
loses stability (sigma_c) and how (omega_c: the flutter's angular frequency; 0 for the free pin's steady
rotation), the growth rate and frequency of its least stable mode at a given --sigma, and the continuum
filament's onset (analysis/continuum.py) with what it means at this N. The one-pinned chain's onset is computed
in O(N) per sigma (stability.onset): ~0.1 s at N = 200, ~0.3 s at N = 1000. A network scene (lattice,
trapped-unit) reports in its coupling Pi = sigma / l_a; the lattice's fixed points form a family, so its onset is
what is proved (every fixed point stable below lambda_1, none above the ceiling) apart from what a search found (one
stable up to at least its Pi) (analysis/network/stability.py).
"""

from __future__ import annotations

import argparse
import math

from .. import registry
from ..errors import ParameterError
from ..parameters import get as parameter_spec
from .options import UNITS


def _with_operator() -> tuple[str, ...]:
    """The registered scenes with a linear operator about their base state (Scene.no_linear_operator empty)."""
    return tuple(s.name for s in registry.scenes() if not s.no_linear_operator)


def _own_parameters() -> dict[str, list[str]]:
    """The own parameters of the scenes with a linear operator, each with the scenes that have it."""
    owners: dict[str, list[str]] = {}
    for scene in registry.scenes():
        if not scene.no_linear_operator:
            for name in scene.own_parameter_names():
                owners.setdefault(name, []).append(scene.name)
    return owners


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "stability",
        help="onset sigma_c, omega_c and growth rates from the linear operator (no simulation)",
        description="Linear stability of a scene's straight chain: sigma_c and omega_c, the growth rate at --sigma, "
        "and the continuum filament's onset. " + UNITS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scene", metavar="SCENE", help=f"one of: {', '.join(_with_operator())}")
    p.add_argument("--n", type=int, default=None, help="particles per chain N (default 7; chains only)")
    p.add_argument("--sigma", type=float, default=None, help="also the growth rate of the least stable mode here")
    p.add_argument(
        "--alignment-length",
        dest="alignment_length",
        type=float,
        default=None,
        help="networks (lattice, trapped-unit): the units' alignment length l_a (default 1); the coupling "
        "is Pi = sigma / l_a",
    )
    for name, owners in _own_parameters().items():  # the scenes' own parameters (the pair's kappa, rho), from specs
        spec = parameter_spec(name)
        default = f"{spec.default:.4g}" if isinstance(spec.default, float) else spec.default
        p.add_argument(
            spec.option, type=spec.kind, default=None, help=f"{', '.join(owners)}: {spec.help} (default {default})"
        )
    p.set_defaults(func=main)


def _physics(args):
    """The scene's Physics (N, sigma and the scene's own parameters checked in one line each), or a ParameterError
    naming why the scene has no linear operator."""
    from ..params import Physics  # start-up time: only a command that runs needs it

    try:
        scene = registry.get(args.scene)
    except registry.UnknownScene:
        raise ParameterError(
            f"stability: scene must be one of {', '.join(_with_operator())}, got {args.scene!r}"
        ) from None
    if scene.no_linear_operator:
        raise ParameterError(
            f"stability: {args.scene} has no linear operator here ({scene.no_linear_operator}); "
            f"scenes: {', '.join(_with_operator())}"
        )
    own = scene.own_parameter_names()
    given = {k: getattr(args, k) for k in _own_parameters() if getattr(args, k) is not None}
    refused = [k for k in given if k not in own]
    if refused:
        raise ParameterError(f"stability: {refused[0]} has no effect on scene {args.scene}")
    sigma = 0.0 if args.sigma is None else args.sigma
    if scene.term_parameters is not None and "alignment_length" in scene.term_parameters:  # a network: no chain
        if args.n is not None:
            raise ParameterError(
                f"stability: n has no effect on scene {args.scene} (a network's size is set by its own "
                "parameters, e.g. --rings)"
            )
        if args.alignment_length is not None:
            given["alignment_length"] = args.alignment_length
        return Physics(scene=args.scene, sigma=sigma, **given)
    if args.alignment_length is not None:
        raise ParameterError(f"stability: alignment_length has no effect on scene {args.scene}")
    n = 7 if args.n is None else args.n
    if n < 2:
        raise ParameterError(f"n must be >= 2 for a chain that can bend, got {n}")
    return Physics(scene=args.scene, n=n, sigma=sigma, **given)


def _network_report(physics, sigma: float | None) -> None:
    """A network's onset in the coupling Pi = l_e / l_a (Scene.coupling). Where its fixed points form a family: what is
    proved (every one stable below lambda_1, none above the ceiling) apart from what a search found (one stable up to
    at least its Pi), and, at --sigma, which of these the given Pi falls in."""
    scene, la = physics.scene_def, physics.alignment_length
    onset = scene.onset(physics)
    own = ", ".join(f"{k} = {getattr(physics, k)}" for k in scene.own_parameter_names())
    print(f"{physics.scene}, {own}, l_a = {la:g}:")
    print(f"  onset: {onset.kind}")

    def at(value: float) -> str:
        return f"Pi = {scene.coupling(physics, value):.6g}, sigma = {value:.6g}"

    if onset.sigma_all is None:
        print(f"  at sigma_c = {onset.sigma_c:.10g} (Pi_c = {scene.coupling(physics, onset.sigma_c):.6g})")
    else:
        print(f"  every fixed point is stable below {at(onset.sigma_c)} (lambda_1, proved)")
        print(f"  some fixed point is stable up to at least {at(onset.sigma_all)} (the best found)")
        print(f"  no fixed point is stable above {at(onset.sigma_ceiling)} (proved ceiling)")
        print("  between, which fixed points are stable depends on their polarities")
    if sigma is not None:
        lam = scene.leading_eigenvalue(physics, sigma)
        which = "the least stable fixed point's" if onset.sigma_all is not None else "the rest state's"
        state = "unstable" if lam.real > 0 else "stable"
        line = (
            f"  at sigma = {sigma:g} (Pi = {scene.coupling(physics, sigma):.6g}): {which} growth rate "
            f"{lam.real:+.6g} k/gamma ({state}"
        )
        if onset.sigma_all is not None and lam.real > 0:
            line += (
                "; some fixed point is stable"
                if sigma < onset.sigma_all
                else "; no fixed point is stable"
                if sigma > onset.sigma_ceiling
                else "; whether some fixed point is stable is not settled"
            )
        print(line + ")")


def main(args) -> int:
    from ..analysis.continuum import continuum_critical  # start-up time: scipy loads only when a command runs
    from ..reduced.blas import one_blas_thread

    physics = _physics(args)
    scene, n = physics.scene_def, physics.n
    if scene.network(physics) is not None:
        with one_blas_thread():
            _network_report(physics, args.sigma)
        return 0
    with one_blas_thread():
        onset = scene.onset(physics)
        sigma_c, omega_c = onset.sigma_c, onset.omega_c
        own = "".join(
            f", {k} = {v}" if isinstance(v := getattr(physics, k), str) else f", {k} = {v:g}"
            for k in scene.own_parameter_names()
        )
        print(f"{physics.scene}, N = {n}{own}:")
        if math.isfinite(sigma_c):
            print(
                f"  onset: {onset.kind} at sigma_c = {sigma_c:.10g} (N^3 sigma_c = {n**3 * sigma_c:.6g}), "
                f"omega_c = {omega_c:.6g} rad/tau (f_c tau = {omega_c / (2 * math.pi):.6g}, N^4 omega_c = "
                f"{n**4 * omega_c:.6g})"
            )
        else:  # stable over the whole range the scene searched
            print(f"  onset: {onset.kind}")
        if args.sigma is not None:
            lam = scene.leading_eigenvalue(physics, args.sigma)
            state = "unstable" if lam.real > 0 else "stable"
            print(
                f"  at sigma = {args.sigma:g}: growth rate {lam.real:+.6g} /tau, angular frequency "
                f"{abs(lam.imag):.6g} rad/tau ({state}"
                + (f"; sigma / sigma_c = {args.sigma / sigma_c:.4g})" if math.isfinite(sigma_c) else ")")
            )
    if scene.filament:
        s_c, w_c = continuum_critical()
        print(
            f"  continuum filament (clamped, distributed follower load f, drag zeta): S_c = f L^3 / B = {s_c:.4f}, "
            f"omega_c = {w_c:.4f} B / (zeta L^4); at N = {n} (sigma = S / N^3, omega in 1 / (N^4 tau)): "
            f"sigma = {s_c / n**3:.6g}, omega = {w_c / n**4:.6g} rad/tau; the chain's N^3 sigma_c is "
            f"{100 * (n**3 * sigma_c / s_c - 1):+.2f}% from it"
        )
    return 0

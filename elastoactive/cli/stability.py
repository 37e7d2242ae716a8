"""`elastoactive stability SCENE`: the linear stability of a scene's straight chain (or a network's rest states),
without simulating.

For every scene with a linear operator about its base state (analysis/stability.py): where the straight chain
loses stability (sigma_c) and how (omega_c: the flutter's angular frequency; 0 for the free pin's steady
rotation), the growth rate and frequency of its least stable mode at a given --sigma, and the continuum
filament's onset (analysis/continuum.py) with what it means at this N. The one-pinned chain's onset is computed
in O(N) per sigma (stability.onset): ~0.1 s at N = 200, ~0.3 s at N = 1000; the clamped 3D chain's is the same
computation (its linearisation is the planar one twice, analysis/stability3d.py). A network scene (lattice,
trapped-unit) reports in its coupling Pi = sigma / l_a; the lattice's fixed points form a family, so its onset is
what is proved (every fixed point stable below lambda_1, none above the ceiling) apart from what a search found (one
stable up to at least its Pi) (analysis/network/stability.py). A network whose units have their own force f_u and
alignment length l_u (a network file's unit_force, unit_alignment_length) gets the same bracket with each unit weighed
by w_u = f_u l_a / l_u, the run's l_a the reference of Pi.
"""

from __future__ import annotations

import argparse

from ..core import registry
from ..core.errors import ParameterError
from ..core.parameters import get as parameter_spec
from ..core.params import Physics
from .options import UNITS


def _with_operator() -> tuple[str, ...]:
    """The registered scenes with a linear operator about their base state (Scene.no_linear_operator empty)."""
    return tuple(s.name for s in registry.scenes() if not s.no_linear_operator)


def _own_parameters() -> dict[str, list[str]]:
    """The own parameters of the scenes with a linear operator and the term parameters their operators read
    (Scene.operator_parameters), each with the scenes that have it."""
    owners: dict[str, list[str]] = {}
    for scene in registry.scenes():
        if not scene.no_linear_operator:
            for name in (*scene.own_parameter_names(), *scene.operator_parameters):
                owners.setdefault(name, []).append(scene.name)
    return owners


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "stability",
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
        help="networks (lattice, network, trapped-unit): the units' alignment length l_a (default 1); the "
        "coupling is Pi = sigma / l_a (the reference where a network's units have their own)",
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
    own = (*scene.own_parameter_names(), *scene.operator_parameters)
    given = {k: getattr(args, k) for k in _own_parameters() if getattr(args, k) is not None}
    refused = [k for k in given if k not in own]
    if refused:
        raise ParameterError(f"stability: {refused[0]} has no effect on scene {args.scene}")
    sigma = 0.0 if args.sigma is None else args.sigma
    if not scene.sized_by_n:  # a network: its own parameters size it
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


def main(args) -> int:
    from ..explore import stability  # the subcommand's boundary: the front door's analysis

    print(stability(_physics(args), args.sigma))  # ea.stability: the scene's kind's analysis
    return 0

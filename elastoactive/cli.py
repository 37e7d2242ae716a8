"""`elastoactive`: the command line, in the paper's dimensionless parameters."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .params import INTEGRATORS, SCENES, Numerics, ParameterError, Physics

SCENE_HELP = """scenes:
  one-pinned    chain clamped at one end: flagellar beating above sigma_c (N=7: 0.15)
  two-pinned    last particle also pinned at (N l (1-delta), 0): self-snapping
  rotating-pin  first hinge free (no clamp spring): steady rotation about the pin
  coupled-pair  two chains (stiffness C1, C2 = rho C1) joined by a spring kappa between
                their first pendula: frequency entrainment above kappa ~ 1.1"""

UNITS = "Units: l = C1 = gamma = 1, so times are in tau = gamma l^2 / C1 and frequencies are f*tau."


def _physics_args(p: argparse.ArgumentParser) -> None:
    d = Physics()
    g = p.add_argument_group("physics (the paper's dimensionless numbers)")
    g.add_argument("--n", type=int, default=d.n, help="particles per chain N (default %(default)s)")
    g.add_argument("--sigma", type=float, default=d.sigma, help="elasto-active number F_a l / C1 (default %(default)s)")
    g.add_argument("--delta", type=float, default=d.delta, help="compression of the two-pinned chain, in [0, 1) (default %(default)s)")
    g.add_argument("--kappa", type=float, default=d.kappa, help="coupling stiffness K l^2 / C1 of the pair (default %(default)s)")
    g.add_argument("--rho", type=float, default=d.rho, help="stiffness ratio C2 / C1 of the pair; chain 2 has sigma/rho (default 4/3)")
    g.add_argument("--drag-ratio", type=float, default=d.drag_ratio, help="anisotropy gamma_L / gamma_T of the drag (default 1: isotropic)")
    g.add_argument("--noise", type=float, default=d.noise, help="amplitude a of multiplicative white noise on F_a (default 0)")


def _numerics_args(p: argparse.ArgumentParser) -> None:
    d = Numerics()
    g = p.add_argument_group("numerics")
    g.add_argument("--dt", type=float, default=d.dt, help="MuJoCo timestep in tau (default %(default)s)")
    g.add_argument("--mass-ratio", type=float, default=d.mass_ratio, help="particle mass m / (gamma tau); the overdamped limit is 0 (default %(default)s)")
    g.add_argument("--integrator", choices=INTEGRATORS, default=d.integrator, help="MuJoCo integrator (default %(default)s)")
    g.add_argument("--seed", type=int, default=d.seed, help="seed of the initial perturbation and the noise (default %(default)s)")
    g.add_argument("--perturbation", type=float, default=d.perturbation, help="size of the random initial kick, rad (default %(default)s)")
    g.add_argument("--sample-dt", type=float, default=d.sample_dt, help="spacing of the recorded trajectory, tau (default %(default)s)")


def physics_from(args, scene: str) -> Physics:
    return Physics(scene=scene, n=args.n, sigma=args.sigma, delta=args.delta, kappa=args.kappa, rho=args.rho,
                   drag_ratio=args.drag_ratio, noise=args.noise)


def numerics_from(args) -> Numerics:
    return Numerics(dt=args.dt, mass_ratio=args.mass_ratio, integrator=args.integrator, seed=args.seed,
                    perturbation=args.perturbation, sample_dt=args.sample_dt)


def cmd_run(args) -> int:
    from .diagnose import check_timestep
    from .results import summary, write_run

    physics, numerics = physics_from(args, args.scene), numerics_from(args)
    if args.engine == "mujoco":
        from .simulate import simulate_mujoco

        check_timestep(physics, numerics)
        traj = simulate_mujoco(physics, numerics, args.duration, progress=not args.quiet)
    else:
        from .analysis.reduced import simulate_reduced

        traj = simulate_reduced(physics, numerics, args.duration)
    s = summary(traj, numerics, args.duration, args.transient)
    if args.out:
        write_run(Path(args.out), traj, s)
    print(json.dumps({"wall_time_s": round(s["wall_time_s"], 3), **s["results"]}, indent=2, default=float))
    if args.out:
        print(f"wrote {Path(args.out) / 'summary.json'} and {Path(args.out) / 'trajectory.npz'}")
    if args.video:  # rendered from the recorded trajectory, after the simulation
        from .render_cli import video_after_run

        return video_after_run(args, traj, numerics)
    return 0


def cmd_validate(args) -> int:
    from .validate import PAPER_CASES, compare, format_table

    if args.convergence:
        from .validate import convergence, format_convergence

        for physics, duration in PAPER_CASES:
            if args.scene in (None, physics.scene) and physics.kappa != 0.5:
                print(f"\n{physics.scene}: error against the reduced model as dt shrinks (mass ratio 1e-5), "
                      "then as the mass ratio shrinks (dt = 0.00125)\n")
                print(format_convergence(convergence(physics, duration)))
        return 0
    numerics = numerics_from(args)
    cases = [(p, d) for p, d in PAPER_CASES if args.scene in (None, p.scene)]
    rows = []
    for physics, duration in cases:
        rows.append(compare(physics, numerics, duration))
        if not args.quiet:
            print(f"  done {physics.scene} ({rows[-1].mujoco_wall_s:.2f} s MuJoCo, {rows[-1].reduced_wall_s:.2f} s reduced)",
                  file=sys.stderr)
    print(format_table(rows))
    worst = max(r.worst() for r in rows)
    verdict = "PASS" if worst <= args.tolerance else "FAIL"
    print(f"\nlargest relative error {100 * worst:.3f}% (tolerance {100 * args.tolerance:g}%): {verdict}")
    return 0 if verdict == "PASS" else 1


# Subcommands defined in their own modules: each module has register(subparsers), which adds
# its parser cheaply (heavy imports go inside the command's function).
COMMAND_MODULES = ("elastoactive.render_cli", "elastoactive.sweep", "elastoactive.accuracy", "elastoactive.reproduce")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="elastoactive",
        description="Elasto-active chains in MuJoCo (Zheng et al., 'Self-oscillation and synchronisation "
        "transitions in elasto-active structures'), checked against the reduced overdamped model. " + UNITS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=SCENE_HELP,
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    run = sub.add_parser("run", help="simulate one scene and write summary.json + trajectory.npz",
                         description="Simulate one scene. " + UNITS, epilog=SCENE_HELP,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    run.add_argument("scene", choices=SCENES, metavar="SCENE", help="one of: " + ", ".join(SCENES))
    _physics_args(run)
    _numerics_args(run)
    run.add_argument("--duration", type=float, default=300.0, help="simulated time in tau (default %(default)s)")
    run.add_argument("--transient", type=float, default=None, help="time discarded before measuring, tau (default: half the run)")
    run.add_argument("--engine", choices=("mujoco", "reduced"), default="mujoco", help="MuJoCo scene or the reduced ODE (default %(default)s)")
    run.add_argument("--out", type=Path, help="folder for summary.json and trajectory.npz")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.add_argument("--video", type=Path, help="also render the run to this MP4 (see `elastoactive render -h`)")
    from .render_cli import add_video_args

    add_video_args(run)
    run.set_defaults(func=cmd_run)

    val = sub.add_parser("validate", help="run MuJoCo and the reduced model on the paper's cases and tabulate the error",
                         description="Cross-validate the MuJoCo scenes against the reduced model on the paper's cases. " + UNITS)
    val.add_argument("scene", nargs="?", choices=SCENES, metavar="SCENE", help="only this scene (default: all)")
    _numerics_args(val)
    val.add_argument("--tolerance", type=float, default=0.01, help="largest acceptable relative error (default 0.01)")
    val.add_argument("--convergence", action="store_true", help="instead: tabulate the error as dt and the mass ratio shrink")
    val.add_argument("--quiet", action="store_true")
    val.set_defaults(func=cmd_validate)

    import importlib

    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    from .diagnose import SimulationDiverged

    try:
        return args.func(args)
    except ParameterError as err:
        print(f"elastoactive: error: {err}", file=sys.stderr)
        return 2
    except SimulationDiverged as err:
        print(f"elastoactive: {err}", file=sys.stderr)
        return 3


if __name__ == "__main__":
    sys.exit(main())

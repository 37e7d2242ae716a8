#!/usr/bin/env python
"""Synchronisation of two coupled chains: frequency mismatch against kappa for the paper's pair
(N = 7, sigma_1 = 0.8, rho = 4/3, Fig. 5e-f), the Arnold tongue over (rho, kappa), and the N = 2
near-onset threshold against kappa_c = 11/(4 sqrt 6) sqrt(mu |1 - rho|).

    .venv/bin/python scripts/synchronisation.py [--tiny | --full] [--out DIR] [--workers K]
"""

from elastoactive.report.reproduce import save_all, scenario_parser, scenario_size
from elastoactive.studies import sync_n2_study, sync_study, tongue_study
from elastoactive.studies.paper import PAPER


def main(argv=None):
    args = scenario_parser(__doc__, "out/synchronisation").parse_args(argv)
    size = scenario_size(args)
    sync = sync_study(size, args.workers)
    tongue = tongue_study(size, args.workers)
    n2 = sync_n2_study(size, args.workers)
    save_all([sync, tongue, n2], args.out)
    for eng in ("mujoco", "reduced"):
        s = sync.summary.engine(eng)
        print(
            f"N = 7 pair ({eng}): kappa_c = {s.kappa_c:.4g} (bracket {list(s.kappa_c_bracket)}); paper "
            f"{PAPER.kappa_c_7:g}"
        )
    q = n2.summary
    print(f"N = 2: kappa_c / sqrt(mu |1 - rho|) = {q.prefactor_fit:.3f} (paper {q.prefactor_formula:.3f})")


if __name__ == "__main__":
    main()

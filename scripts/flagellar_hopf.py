#!/usr/bin/env python
"""Flagellar beating (one pinned end): linear stability and the N^-3 law (Fig. 3c-d, size effect),
the Hopf diagram of N = 7 from MuJoCo and the reduced model (Figs. 2, 3a-b), and the N = 2
normal form (which printed Landau-Stuart coefficient holds).

    .venv/bin/python scripts/flagellar_hopf.py [--tiny | --full] [--out DIR] [--workers K]
"""

from elastoactive.report.reproduce import save_all, scenario_parser, scenario_size
from elastoactive.studies import growth_study, hopf_study, normal_form_study, stability_study
from elastoactive.studies.paper import PAPER


def _complex(z: complex) -> str:
    return f"{z.real:g} {'-' if z.imag < 0 else '+'} {abs(z.imag):g} i"


def main(argv=None):
    args = scenario_parser(__doc__, "out/flagellar").parse_args(argv)
    size = scenario_size(args)
    stab = stability_study(size)
    growth = growth_study(size, args.workers)
    hopf = hopf_study(size, args.workers)
    nf = normal_form_study(size, args.workers)
    save_all([stab, growth, hopf, nf], args.out)

    s = stab.summary
    print(
        f"linear stability: sigma_c(7) = {s.sigma_c_7:.6f}, f_c tau = {s.f_c_7:.6f}; "
        f"N^3 sigma_c -> {s.n3_sigma_c_limit:.3f} (continuum {s.continuum_onset:.3f})"
    )
    for eng in ("mujoco", "reduced"):
        fit = hopf.summary.engine(eng).power_law
        if fit:
            p, e = fit.params, fit.errors
            print(
                f"Hopf N = 7 ({eng}): sigma_c = {p['onset']:.5f} +/- {e['onset']:.1g}, beta = {p['beta']:.3f} +/- "
                f"{e['beta']:.1g}"
            )
        c = nf.summary.engine(eng)
        print(
            f"Landau-Stuart c ({eng}) = {c.re_c:.3f} {c.im_c:+.3f} i  (supplement: "
            f"{_complex(PAPER.landau_supplement.at_onset)}; main text: {_complex(PAPER.landau_main.at_onset)})"
        )


if __name__ == "__main__":
    main()

#!/usr/bin/env python
"""Self-snapping (both ends pinned): snap amplitude (std of theta_3) and frequency against the
compression delta for N = 7 at sigma = 0.6 and 0.8 (Fig. 4c-d), and the (delta, sigma) map of
N = 9 (supplement), with the sigma below which a compressed chain stays still.

    .venv/bin/python scripts/self_snapping.py [--tiny | --full] [--out DIR] [--workers K]
"""

from elastoactive.report.reproduce import save_all, scenario_parser, scenario_size
from elastoactive.studies import snapping_study


def main(argv=None):
    args = scenario_parser(__doc__, "out/snapping").parse_args(argv)
    study = snapping_study(scenario_size(args), args.workers)
    save_all([study], args.out)
    d, s = study.data, study.summary
    for sigma in s.n7_sigmas:
        print(f"N = 7, sigma = {sigma}:  delta  std(theta_3) MuJoCo / reduced   f tau MuJoCo")
        for i, delta in enumerate(d["delta"]):
            print(
                f"    {delta:6.3f}   {d[f'snap_{sigma:g}_mujoco'][i]:.4f} / {d[f'snap_{sigma:g}_reduced'][i]:.4f}"
                f"          {d[f'freq_{sigma:g}_mujoco'][i]:.5f}"
            )
    print(
        f"N = 9, delta = {s.threshold_delta}: snapping above sigma = {s.mujoco.sigma_snap_n9:.3f} (MuJoCo), "
        f"{s.reduced.sigma_snap_n9:.3f} (reduced)"
    )


if __name__ == "__main__":
    main()

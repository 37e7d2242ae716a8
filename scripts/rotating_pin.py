#!/usr/bin/env python
"""Freely rotating pin: steady rotation rate and shape against sigma for N = 7, and the sense of
rotation chosen spontaneously (several seeds at the experiment's sigma = 0.33).

    .venv/bin/python scripts/rotating_pin.py [--tiny | --full] [--out DIR] [--workers K]
"""

from elastoactive.report.reproduce import save_all, scenario_parser, scenario_size
from elastoactive.studies import rotation_study


def main(argv=None):
    args = scenario_parser(__doc__, "out/rotating_pin").parse_args(argv)
    study = rotation_study(scenario_size(args), args.workers)
    save_all([study], args.out)
    d, s = study.data, study.summary
    print(f"straight chain unstable above sigma_r = {s.sigma_r_linear:.5f} (linear stability)")
    for sigma, w_m, w_r in zip(d["sigma"], d["rate_mujoco"], d["rate_reduced"]):
        print(f"  sigma = {sigma:6.4f}: rotation rate {w_m:+.5f} (MuJoCo) {w_r:+.5f} (reduced) rad/tau")
    m = s.mujoco
    print(f"seeds at sigma = {s.sigma_seeds}: {m.n_positive} counter-clockwise, {m.n_negative} clockwise")


if __name__ == "__main__":
    main()

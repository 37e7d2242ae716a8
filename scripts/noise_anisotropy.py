#!/usr/bin/env python
"""Noise and anisotropic drag for N = 2 at sigma = 3.5 (supplement): limit cycles (Omega, Theta)
with multiplicative white noise on the active force, and with tau_L / tau_T != 1 (onset unchanged,
amplitude shrinking).

    .venv/bin/python scripts/noise_anisotropy.py [--tiny | --full] [--out DIR] [--workers K]
"""

from elastoactive.report.reproduce import save_all, scenario_parser, scenario_size
from elastoactive.studies import anisotropy_study, noise_study


def main(argv=None):
    args = scenario_parser(__doc__, "out/noise_anisotropy").parse_args(argv)
    size = scenario_size(args)
    noise = noise_study(size, args.workers)
    aniso = anisotropy_study(size, args.workers)
    save_all([noise, aniso], args.out)
    d = noise.data
    for a, cv_m, cv_r in zip(d["noise"], d["period_cv_mujoco"], d["period_cv_reduced"]):
        print(f"noise a = {a:g}: period CV {cv_m:.4f} (MuJoCo) {cv_r:.4f} (reduced)")
    d = aniso.data
    for r, amp, onset in zip(d["ratio"], d["amplitude_mujoco"], d["onset_mujoco"]):
        print(f"tau_L/tau_T = {r:g}: amplitude {amp:.4f} rad, onset sigma {onset:.4f} (MuJoCo)")


if __name__ == "__main__":
    main()

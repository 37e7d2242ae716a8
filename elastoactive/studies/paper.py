"""The paper's numbers: every value Zheng et al. quote that the project sets its results against,
in one place (the studies, the claim table and the figures read them from here).

    from elastoactive.studies.paper import PAPER
    PAPER.sigma_c_7_linear          # 0.15
    PAPER.source("sigma_c_7_linear")  # where the paper says it

Each field gives its source: "main text", "supplement" (the appendices) or a figure, and for the
two continuum values the project's model notes (docs/model.md, section 5), which quotes the
filament literature rather than the paper. What the project finds instead is in report.md; the
paper's printed formulas that turn out wrong are discussed in analysis/reduced and claims.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

__all__ = ["LandauCoefficient", "Paper", "PAPER"]


@dataclass(frozen=True)
class LandauCoefficient:
    """The cubic coefficient c of the N = 2 Landau-Stuart form dz/dt = (i + mu) z + c |z|^2 z, as
    printed: c(mu) = at_onset + slope mu with mu = sigma - 3."""

    at_onset: complex
    slope: complex
    printed: str
    """The paper's expression for c."""
    printed_at_onset: str
    """Its value at mu = 0, as the paper's fractions."""


def _quoted(value, source: str):
    return field(default=value, metadata={"source": source})


@dataclass(frozen=True)
class Paper:
    """The paper's quoted numbers (units: l = C1 = gamma = 1, so tau = 1)."""

    # ------------------------------------------------------------------ one pinned end (Figs. 2-3)
    sigma_c_7_linear: float = _quoted(
        0.15, "main text, Fig. 3 caption and text: linear stability of N = 7, Hopf at sigma = 0.15"
    )
    sigma_c_7_sim: float = _quoted(
        0.16, "main text, Fig. 3a: simulations and experiment of N = 7, sigma_c = 0.16 +/- 0.005"
    )
    sigma_c_7_sim_err: float = _quoted(0.005, "main text, Fig. 3a: the +/- of sigma_c = 0.16 +/- 0.005")
    hopf_exponent: float = _quoted(0.5, "main text, Fig. 3a inset: amplitude ~ (sigma - sigma_c)^0.5")
    fig2_sigmas: tuple[float, ...] = _quoted(
        (0.166, 0.695), "main text, Fig. 2b-c caption: the experiments' chains at sigma = 0.166 and 0.695"
    )
    fig2_sigma_simulation: float = _quoted(0.8, "main text, Fig. 2e-f caption: simulation results at sigma = 0.8")
    # ------------------------------------------------------------------ N = 2 and the normal form
    sigma_c_2: float = _quoted(3.0, "main text, Landau-Stuart form dz/dt = (i + sigma - 3) z + ...: onset at sigma = 3")
    omega_c_2: float = _quoted(1.0, "main text, same equation: linear part i z at onset, angular frequency 1/tau")
    landau_main: LandauCoefficient = _quoted(
        LandauCoefficient(complex(-0.5, 1.25), complex(-1.0, -1.0), "-(sigma - 5/2) + i(17/4 - sigma)", "-1/2 + 5i/4"),
        "main text, Landau-Stuart equation after Eqs. (1)-(2): c = i(17/4 - sigma) - (sigma - 5/2)",
    )
    landau_supplement: LandauCoefficient = _quoted(
        LandauCoefficient(complex(-1.0, -0.125), complex(-0.5, 1.25), "-1 - mu/2 + i(-1/8 + 5 mu/4)", "-1 - i/8"),
        "supplement, 'Derivation of the canonical form of the Hopf bifurcation', Eq. (Hopf)",
    )
    # ------------------------------------------------------------------ size effect and continuum
    size_exponent: float = _quoted(-3.0, "supplement, Fig. 'Size effects' caption: sigma_c ~ N^-3")
    continuum_onset: float = _quoted(
        76.0, "docs/model.md section 5 (not the paper): the continuum onset f L^3 / B of a clamped filament is near 76"
    )
    continuum_bracket: tuple[float, float] = _quoted(
        (72.0, 80.0), "docs/model.md section 5 (not the paper): public filament codes test that 72 decays and 80 grows"
    )
    # ------------------------------------------------------------------ two pinned ends (Fig. 4)
    snapping_sigma_experiment: float = _quoted(
        0.6, "supplement, 'Chain pinned at both ends': sigma = 0.6, the experimental case"
    )
    snapping_sigma: float = _quoted(0.8, "main text, Fig. 4 caption: the chain's elasto-active number sigma = 0.8")
    snapping_map_n: int = _quoted(9, "supplement, Fig. 'Self-snapping' (map over delta and sigma): N = 9")
    # ------------------------------------------------------------------ freely rotating pin
    rotation_sigma: float = _quoted(
        0.33, "supplement, Fig. 'Elasto-active chains in various confinements' (a): sigma = 0.33"
    )
    # ------------------------------------------------------------------ synchronisation (Fig. 5)
    sync_sigma_1: float = _quoted(0.8, "main text, Fig. 5 text: chain 1 with sigma_1 = 0.8")
    sync_sigma_2: float = _quoted(0.6, "main text, Fig. 5 text: chain 2 with sigma_2 = 0.6")
    sync_rho: float = _quoted(
        4.0 / 3.0, "sigma_1 / sigma_2 of main text Fig. 5 (C2 = rho C1, so sigma_2 = sigma_1 / rho)"
    )
    kappa_c_7: float = _quoted(1.1, "main text, Fig. 5c,f and text: the synchronisation transition at kappa = 1.1")
    fig5_kappas: tuple[float, float] = _quoted(
        (0.8, 1.2), "main text, Fig. 5b caption: coupling K = 0.8 (slipping) and 1.2 (locked)"
    )
    kappa_c_n2_prefactor: float = _quoted(
        11.0 / (4.0 * math.sqrt(6.0)),
        "supplement, 'Synchronization of two coupled elasto-active chains': kappa_c = 11/(4 sqrt 6) sqrt(mu |1 - rho|)",
    )
    kappa_c_n2_printed: str = _quoted(
        "11/(4 sqrt 6) sqrt(mu |1 - rho|)", "supplement, same section: the formula as printed"
    )
    phase_detuning: float = _quoted(11.0 / 8.0, "supplement, same section: d nu = 11/8 (rho - 1) in the phase equation")
    # ------------------------------------------------------------------ noise and anisotropic drag (supplement)
    noise_sigma: float = _quoted(3.5, "supplement, 'Role of noise' (N = 2; sigma as in the anisotropy figure, 3.5)")
    anisotropy_sigma: float = _quoted(3.5, "supplement, Fig. 'Role of anisotropy' caption: sigma = 3.5, tau_T = 1")
    # ----------------------------------------------------------- the experiment's own numbers (main text, supplement)
    active_force_n: float = _quoted(
        0.0157, "main text and supplement Appendix B: pinned Hexbug force F_a = 15.7 +/- 3.1 mN (mean)"
    )
    active_force_std_n: float = _quoted(
        0.0031, "supplement Appendix B: the force 'fluctuated rapidly', Gaussian with standard deviation 3.1 mN"
    )
    drag_n_s_per_m: float = _quoted(0.63, "main text: gamma = F_a / v_a = 0.63 +/- 0.11 N s/m (v_a = 0.025 m/s)")
    chain_length_m: float = _quoted(
        0.5, "main text, Fig. 4 caption: undeformed chain length L = 500 mm (7 bugs: link pitch ~ L / 7)"
    )
    experiment_sigmas: tuple[float, ...] = _quoted(
        (0.166, 0.17, 0.21, 0.695, 0.8),
        "main text, Figs. 1-2 captions: the experiments' chains at sigma = 0.17, 0.21, 0.80 and 0.166, 0.695",
    )
    # ------------------------------------------------------------------ supplement: experiments no model covered
    long_chain_n: int = _quoted(17, "supplement, Appendix B 'Chains pinned at one end with N = 17'")
    long_chain_sigma: float = _quoted(0.8, "supplement, Appendix B: the N = 17 chain at sigma = 0.8")
    long_chain_words: str = _quoted(
        "in addition to the lowest harmonic seen in the short chain and in the stability analysis, higher harmonic "
        "seem to be occurring, which we speculate are due to self-contact interactions",
        "supplement, Appendix B, N = 17 (the words as printed)",
    )
    dish_sigma: float = _quoted(
        0.30, "supplement, Appendix B, caption of the confinement figure: satellite dish, sigma = 0.30"
    )
    dish_words: str = _quoted(
        "when the chain is confined in a paraboloid, it tends to rotate around the center of the paraboloid, but this "
        "time is also craws in circles at the same time",
        "supplement, Appendix B 'Chains confined on a freely rotating pin and in a paraboloid' (the words as printed)",
    )
    # ------------------------------------------------------------------ literature (not the paper): Ziegler's column
    ziegler_undamped: float = _quoted(
        3.5 - math.sqrt(2.0),
        "literature (not the paper): Ziegler 1952, undamped double pendulum, P_c = (7/2 - sqrt 2) C/l",
    )
    ziegler_damped_limit: float = _quoted(
        41.0 / 28.0,
        "literature (not the paper): Ziegler 1952 / Kirillov (destabilisation paradox), P_c -> 41/28 C/l as joint "
        "damping vanishes",
    )

    @property
    def link_pitch_m(self) -> float:
        """The experiment's link length l ~ L / N = 0.5 m / 7 = 71 mm."""
        return self.chain_length_m / 7.0

    @property
    def force_relative_spread(self) -> float:
        """std / mean of the measured active force: 3.1 / 15.7 = 0.197."""
        return self.active_force_std_n / self.active_force_n

    @property
    def snapping_sigmas(self) -> tuple[float, float]:
        """The two sigma of the N = 7 snapping curves: the experiment's 0.6 and Fig. 4's 0.8."""
        return (self.snapping_sigma_experiment, self.snapping_sigma)

    def source(self, name: str) -> str:
        """Where the paper quotes field `name`."""
        for f in fields(self):
            if f.name == name:
                return f.metadata["source"]
        raise KeyError(name)


PAPER = Paper()
"""The paper's numbers (the only instance)."""

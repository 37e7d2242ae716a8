"""The studies (elastoactive.studies) and the mathematics they use (analysis.normal_form,
analysis.synchronisation, analysis.stability) on cases with known answers, at the tiny size."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
import pytest

from elastoactive import studies as st
from elastoactive.analysis import stability as stab
from elastoactive.analysis import synchronisation as syn
from elastoactive.analysis.fits import Fit
from elastoactive.engines import reduced as R
from elastoactive.scenes import rotating_pin
from elastoactive.studies.base import EngineParts, Study, Summary, to_jsonable
from elastoactive.studies.normal_form import landau_prediction
from elastoactive.studies.paper import PAPER
from elastoactive.studies.sync import kappa_c_formula, kappa_c_phase_equation


# ------------------------------------------------------------------------------------ pure helpers
def test_landau_predictions():
    z2, om = landau_prediction(1e-4, "supplement")
    assert z2 == pytest.approx(1e-4, rel=1e-3) and (om - 1) / z2 == pytest.approx(-0.125, rel=1e-2)
    z2, om = landau_prediction(1e-4, "main")
    assert z2 == pytest.approx(2e-4, rel=1e-3) and (om - 1) / z2 == pytest.approx(1.25, rel=1e-2)
    with pytest.raises(ValueError):
        landau_prediction(0.1, "other")


def test_kappa_c_formulas():
    assert kappa_c_formula(0.1, 0.98) == pytest.approx(11 / (4 * math.sqrt(6)) * math.sqrt(0.1 * 0.02))
    # the supplement's phase equation: kappa_c -> 11/8 |1 - rho| when |rho - 1| << mu
    assert kappa_c_phase_equation(0.1, 1 - 1e-5) == pytest.approx(11 / 8 * 1e-5, rel=1e-3)
    assert kappa_c_phase_equation(0.1, 0.97) != pytest.approx(float(kappa_c_formula(0.1, 0.97)), rel=0.1)
    # the bindings use the paper's numbers
    assert PAPER.kappa_c_n2_prefactor == pytest.approx(11 / (4 * math.sqrt(6)))
    assert syn.kappa_c_sqrt_law(0.1, 0.98, 2.0) == pytest.approx(2.0 * math.sqrt(0.1 * 0.02))


def test_locking_threshold():
    k = [0.0, 0.1, 0.2, 0.3, 0.4]
    assert syn.locking_threshold(k, [False, False, True, True, True]) == (0.1, 0.2)
    assert syn.locking_threshold(k, [False, True, False, True, True]) == (0.2, 0.3)  # isolated early lock ignored
    lo, hi = syn.locking_threshold(k, [False] * 5)
    assert lo == 0.4 and hi == math.inf
    lo, hi = syn.locking_threshold(k, [True] * 5)
    assert math.isnan(lo) and hi == 0.0


@pytest.mark.parametrize("sigma", [0.05, 0.3])
def test_rotating_operator_matches_reduced_jacobian(sigma):
    n = 5
    J = R.jacobian(rotating_pin.SCENE.physics(n=n, sigma=sigma))(0.0, np.zeros(n))
    lam_j = np.linalg.eigvals(J)
    lam_j = lam_j[np.abs(lam_j) > 1e-9]  # drop the rigid rotation
    lam_o = np.linalg.eigvals(stab.rotating_operator(n, sigma))
    np.testing.assert_allclose(np.sort_complex(lam_j), np.sort_complex(lam_o), atol=1e-9)


def test_rotation_threshold_is_a_real_eigenvalue_crossing():
    s_r = stab.rotation_threshold(7)
    below = np.linalg.eigvals(stab.rotating_operator(7, 0.99 * s_r))
    above = np.linalg.eigvals(stab.rotating_operator(7, 1.01 * s_r))
    assert below.real.max() < 0 < above.real.max()
    assert abs(above[np.argmax(above.real)].imag) < 1e-12


def test_paper_numbers_have_sources():
    for f in fields(PAPER):
        assert PAPER.source(f.name), f.name
    assert PAPER.snapping_sigmas == (0.6, 0.8)


# ------------------------------------------------------------------------------- saving and loading
@dataclass(frozen=True)
class _Part(Summary):
    x: float
    flags: list[bool]


@dataclass(frozen=True)
class _Demo(EngineParts):
    a: float
    b: float
    c: float
    bracket: tuple[float, float]
    by_key: dict[str, float]
    z: complex
    fit: Fit | None
    mujoco: _Part
    reduced: _Part | None = None
    note: str | None = None


def test_study_save_and_load_roundtrip(tmp_path):
    fit = Fit({"onset": 0.1575, "beta": 0.5}, {"onset": 1e-5, "beta": float("nan")}, 0.99, 7, {"cov": -1.0})
    summary = _Demo(
        a=1.5,
        b=np.float64(2.0),
        c=float("nan"),
        bracket=(0.4, math.inf),
        by_key={"0.5": 1.0, "1": -math.inf},
        z=complex(-1, -0.125),
        fit=fit,
        mujoco=_Part(np.float64(3.0), [True, np.bool_(False)]),
    )
    s = Study("demo", "tiny", {"x": np.arange(3.0)}, summary, 0.1)
    s.save(tmp_path)
    back = Study.load(tmp_path, "demo", _Demo)
    np.testing.assert_array_equal(back.data["x"], np.arange(3.0))
    b = back.summary
    assert isinstance(b, _Demo) and isinstance(b.mujoco, _Part) and b.reduced is None and b.note is None
    assert b.a == 1.5 and b.b == 2.0 and math.isnan(b.c)
    assert b.bracket == (0.4, math.inf) and b.by_key == {"0.5": 1.0, "1": -math.inf}
    assert b.z == complex(-1, -0.125)
    assert isinstance(b.fit, Fit) and b.fit.params == fit.params and b.fit.n == 7 and math.isnan(b.fit.errors["beta"])
    assert b.engine("mujoco").flags == [True, False]
    assert to_jsonable(b) == to_jsonable(summary)
    assert back.wall_s == 0.1 and back.size == "tiny"


def test_real_study_roundtrip(tmp_path):
    s = st.stability_study("tiny")
    s.save(tmp_path)
    back = st.load_study(tmp_path, "stability")
    assert isinstance(back.summary, st.StabilitySummary)
    assert back.summary.table[0].n == 2 and back.summary.fit_n3.params == s.summary.fit_n3.params
    assert to_jsonable(back.summary) == to_jsonable(s.summary)
    with pytest.raises(ValueError):
        st.load_study(tmp_path, "nonsense")


def test_unknown_size_rejected():
    with pytest.raises(ValueError):
        st.stability_study("huge")


# --------------------------------------------------------------------------------- studies, tiny
def test_stability_study_known_answers():
    s = st.stability_study("tiny")
    assert s.summary.sigma_c_2 == pytest.approx(3.0, abs=1e-6)
    assert s.summary.omega_c_2 == pytest.approx(1.0, abs=1e-6)
    assert s.summary.sigma_c_7 == pytest.approx(0.15747, abs=1e-5)
    # N^-3: the local exponent approaches -3 from above and N^3 sigma_c approaches the continuum onset
    loc = s.data["local_exponent"]
    assert np.all(np.diff(loc[5:]) < 0) and -3.0 < loc[-1] < -2.8
    assert abs(s.summary.n3_sigma_c_limit - s.summary.continuum_onset) < 0.5
    # eigenvalue curves: N = 2 real parts are sigma - 3 in the oscillatory range
    sig, re = s.data["eig_sigma_2"], s.data["eig_re_2"][:, 0]
    osc = np.abs(sig - 3) < 1
    np.testing.assert_allclose(re[osc], sig[osc] - 3, atol=1e-9)


def test_growth_study_rates_match_eigenvalues():
    s = st.growth_study("tiny", workers=2, progress=False)
    assert s.summary.reduced.max_rel_err_rate < 1e-3
    assert s.summary.mujoco.max_rel_err_rate < 0.02
    assert s.summary.mujoco.max_rel_err_omega < 0.005
    for row in s.summary.per_n:
        assert row.sigma_c_mujoco == pytest.approx(row.sigma_c_linear, rel=0.01)


def test_normal_form_study_sides_with_the_supplement():
    s = st.normal_form_study("tiny", workers=2, progress=False)
    mu = s.data["mu"]
    for eng in ("reduced", "mujoco"):
        z2 = s.data[f"z2_{eng}"]
        assert np.all(np.abs(z2 - mu) < 0.2 * mu)  # supplement: |z|^2 ~ mu (1 + O(mu))
        assert np.all(np.abs(z2 - 2 * mu) > 0.5 * mu)  # main text: |z|^2 ~ 2 mu
        om = s.data[f"omega_{eng}"]
        assert np.all(om < 1.0)  # the frequency falls with amplitude (Im c < 0), not rises


def test_noise_and_anisotropy_studies():
    no = st.noise_study("tiny", workers=2, progress=False)
    cv = no.data["period_cv_mujoco"]
    assert cv[0] < 1e-3 < 0.02 < cv[1]
    an = st.anisotropy_study("tiny", workers=2, progress=False)
    for eng in ("mujoco", "reduced"):
        assert np.all(np.abs(an.data[f"onset_{eng}"] - 3.0) < 0.005)
        amp = an.data[f"amplitude_{eng}"]
        assert amp[1] < 0.7 * amp[0]  # ratio 4 vs 1


def test_every_bisection_step_shows_its_progress(monkeypatch):
    """sync_n2's bisection runs one batch per step: each must show (it hid all but the first, so a quick reproduce's
    progress lines accounted for a sixth of the study's time)."""
    from elastoactive.studies import sync_n2

    shown = []

    def fake_run(cases, workers, progress, desc):
        shown.append((progress, desc))
        return [None] * len(cases)

    monkeypatch.setattr(sync_n2, "run", fake_run)
    monkeypatch.setattr(sync_n2, "pair_measures", lambda tr, transient: {"locked": True})
    make = lambda c, k: type("FakeCase", (), {"physics": type("P", (), {"kappa": k})(), "duration": 10.0})()  # noqa: E731
    lo, hi = sync_n2._bisect_locking(
        [(0.1, 0.98)], make, {(0.1, 0.98): 0.0}, {(0.1, 0.98): 1.0}, 4, 1, True, "kappa_c N=2", lambda case: 5.0
    )
    assert hi[(0.1, 0.98)] == 0.0625
    assert [p for p, _ in shown] == [True] * 4 and len({d for _, d in shown}) == 4 and "step 4/4" in shown[-1][1]


def test_snapping_threshold_bracket_narrows_to_the_first_probe_that_snaps():
    from elastoactive.studies.snapping import narrow

    assert narrow(0.1, 0.4, [(0.2, False), (0.3, True)]) == (0.2, 0.3)
    assert narrow(0.1, 0.4, [(0.2, True), (0.3, True)]) == (0.1, 0.2)
    assert narrow(0.1, 0.4, [(0.2, False), (0.3, False)]) == (0.3, 0.4)
    assert narrow(0.1, 0.4, [(0.2, True), (0.3, False)]) == (0.1, 0.2)  # the smallest sigma that snaps

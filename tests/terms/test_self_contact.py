"""Self-contact (--contact): capsules on the links that collide with non-adjacent links of their own chain."""

import json

import mujoco
import numpy as np
import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.core.errors import ParameterError
from elastoactive.core.params import Numerics, Physics
from elastoactive.mjcf.chain import build_model, qpos_of
from elastoactive.reduced.contact import capsule_clearance, core_span
from elastoactive.reduced.system import CONTACT_LENGTH


def test_capsules_only_with_contact_and_only_within_a_chain():
    plain = build_model(Physics(scene="coupled-pair", n=5))
    assert not np.any(plain.geom_contype) and not np.any(plain.geom_conaffinity)
    model = build_model(Physics(scene="coupled-pair", n=5, contact=True, contact_radius=0.12, contact_friction=0.3))
    caps = [g for g in range(model.ngeom) if "capsule_" in model.geom(g).name]
    assert len(caps) == 10 and np.allclose(model.geom_size[caps, 0], 0.12)
    assert {int(model.geom_contype[g]) for g in caps} == {1, 2}  # one collision bit per chain: no cross-chain pairs
    assert np.all(model.geom_contype[caps] == model.geom_conaffinity[caps])
    assert np.all(model.geom_condim[caps] == 3) and np.allclose(model.geom_friction[caps, 0], 0.3)
    s_a, s_b = core_span(0.12)
    # the capsule is CONTACT_LENGTH long, centred on its link: half-length of the core plus the radius
    assert np.allclose(model.geom_size[caps, 1] + 0.12, CONTACT_LENGTH / 2) and np.isclose(
        (s_b - s_a) / 2, model.geom_size[caps[0], 1]
    )
    off = model.opt.disableflags
    for flag in (
        mujoco.mjtDisableBit.mjDSBL_CONTACT,
        mujoco.mjtDisableBit.mjDSBL_FILTERPARENT,
        mujoco.mjtDisableBit.mjDSBL_CONSTRAINT,
    ):
        assert not off & int(flag)
    frictionless = build_model(Physics(n=5, contact=True))
    caps = [g for g in range(frictionless.ngeom) if "capsule_" in frictionless.geom(g).name]
    assert np.all(frictionless.geom_condim[caps] == 1)


def test_neighbours_never_collide_and_folded_links_do():
    p = Physics(n=5, contact=True)
    model = build_model(p)
    data = mujoco.MjData(model)
    data.qpos[:] = qpos_of(p, np.array([0.0, 0.0, 2.6, 2 * 2.6, 2 * 2.6]))  # sharp bends at every joint
    mujoco.mj_forward(model, data)
    pairs = {tuple(sorted((model.geom(c.geom1).name, model.geom(c.geom2).name))) for c in data.contact[: data.ncon]}
    assert pairs, "the folded chain must touch itself"
    for a, b in pairs:
        i, j = int(a.split("_")[1]), int(b.split("_")[1])
        assert abs(i - j) >= 2, (a, b)


def test_contact_without_touching_changes_nothing():
    """N = 7 at sigma = 0.8 never touches itself: --contact gives the same trajectory, bit for bit."""
    plain = ea.simulate(Physics(n=7, sigma=0.8), duration=150.0)
    touch = ea.simulate(Physics(n=7, sigma=0.8, contact=True), duration=150.0)
    np.testing.assert_array_equal(plain.theta, touch.theta)
    r = ea.measure(touch)
    assert r.contact_fraction == 0.0 and r.min_clearance > 0.5
    assert ea.measure(plain).contact_fraction is None


def test_long_chain_passes_through_itself_without_contact_and_not_with_it():
    """The issue's N = 17, sigma = 0.8: without contact the capsules' cores cross (the chain passes through itself);
    with contact the capsules overlap by at most a few thousandths of l."""
    plain = ea.simulate(Physics(n=17, sigma=0.8), duration=300.0)
    assert capsule_clearance(plain.theta[plain.t > 150], 0.1).min() < -0.2 + 1e-9  # cores cross: overlap 2R
    r = ea.measure(ea.simulate(Physics(n=17, sigma=0.8, contact=True), duration=300.0))
    assert 0.2 < r.contact_fraction < 0.9
    assert -0.005 < r.min_clearance < 0.0


def test_overlap_converges_like_dt_and_does_not_depend_on_the_mass():
    """contact_solref: the overlap falls ~ dt and is the same for mass ratios 1e-4 and 1e-5."""
    p = Physics(n=17, sigma=0.8, contact=True)
    overlap = {}
    for dt, m in ((0.0025, 1e-4), (0.00125, 1e-4), (0.0025, 1e-5)):
        r = ea.measure(ea.simulate(p, Numerics(dt=dt, mass_ratio=m), duration=200.0))
        overlap[dt, m] = -r.min_clearance
    assert 0.25 < overlap[0.00125, 1e-4] / overlap[0.0025, 1e-4] < 0.6
    assert abs(overlap[0.0025, 1e-5] / overlap[0.0025, 1e-4] - 1) < 0.2


def test_run_reports_contact_and_harmonics(tmp_path):
    out = tmp_path / "c"
    assert (
        main(
            [
                "run",
                "one-pinned",
                "--n",
                "17",
                "--sigma",
                "0.8",
                "--contact",
                "--duration",
                "200",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["contact"] is True and summary["parameters"]["contact_radius"] == 0.1
    res = summary["results"]
    assert 0 < res["contact_fraction"] <= 1 and res["min_clearance"] < 0
    assert len(res["harmonics"]) == 5 and res["harmonics"][0] == 1.0
    # off by default: the parameters of a run without contact do not mention it
    assert main(["run", "one-pinned", "--duration", "20", "--out", str(tmp_path / "p"), "--quiet"]) == 0
    assert "contact" not in json.loads((tmp_path / "p" / "summary.json").read_text())["parameters"]


@pytest.mark.parametrize(
    "kw,name",
    [
        ({"contact_radius": 0.35}, "contact_radius"),
        ({"contact_radius": 0.0}, "contact_radius"),
        ({"contact_friction": -0.1}, "contact_friction"),
        ({"contact": "yes"}, "contact"),
    ],
)
def test_bad_contact_parameters_name_themselves(kw, name):
    with pytest.raises(ParameterError, match=name):
        Physics(**kw)


def test_reduced_engine_refuses_friction_it_does_not_model():
    with pytest.raises(ParameterError, match="contact_friction"):
        ea.simulate(Physics(n=7, contact=True, contact_friction=0.3), duration=10.0, engine="reduced")

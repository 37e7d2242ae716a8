"""Observables are declared by the scene or term that measures them and found through one lookup
(elastoactive.core.observables): summary.json, validate, the pre-flight check and the sweep's netCDF read it."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

import elastoactive as ea
from elastoactive.core import observables
from elastoactive.results import Results, check_measurable
from elastoactive.sweep.grid import scene_variables, variable_attrs


def test_every_reported_observable_has_one_spec_with_its_owner():
    for scene in ea.scenes.scenes():
        for name in (*scene.observable_names(), *observables.names_of(scene.occasional_observables)):
            spec = observables.get(name)
            assert spec.units and spec.long_name, name
            assert observables.owner(name).startswith(("scene ", "term ")), name
    for term in ea.terms.terms():
        for name in term.observable_names():
            assert observables.owner(name) == f"term {term.name}"
    for name in ("amplitude", "frequency", "period_spread", "harmonics"):  # the beat's: every run reports them
        assert observables.get(name).per_chain and observables.owner(name) == "every run"
    assert observables.owner("rotation_rate") == "scene rotating-pin"  # declared once, named by the ring and the dish
    assert observables.owner("contact_fraction") == "term contact"


def test_netcdf_attributes_come_from_the_spec():
    spec = observables.get("dish_state")
    attrs = variable_attrs("dish_state")
    assert attrs["units"] == spec.units and attrs["long_name"] == spec.long_name
    assert attrs["flag_meanings"].split() == list(spec.categories)
    np.testing.assert_array_equal(attrs["flag_values"], np.arange(len(spec.categories)))
    assert variable_attrs("clamp_lag")["units"] == "rad"  # a term's observable too
    assert variable_attrs("constraint_violation")["units"] == "l" and variable_attrs("nothing_declares_it") == {}
    assert scene_variables("paraboloid")[4:] == (
        "rotation_rate",
        "orbit_rate",
        "orbit_radius",
        "curvature",
        "dish_state",
    )


def test_min_n_of_a_declared_observable_refuses_a_short_chain():
    with pytest.raises(ea.ParameterError, match="it measures curvature, which needs N >= 2"):
        check_measurable(ea.Physics(scene="paraboloid", n=1))


def test_results_read_declared_observables_as_attributes():
    res = Results(0.1, 0.2, True, extra={"rotation_rate": -0.3, "toy_undeclared": 1.0})
    assert res.rotation_rate == res.value("rotation_rate") == -0.3
    assert res.snap_amplitude is None and res.value("snap_amplitude") is None  # declared, not measured here
    assert res.value("toy_undeclared") == 1.0
    with pytest.raises(AttributeError):
        res.toy_undeclared  # noqa: B018  (an undeclared name is no attribute)
    assert list(res.as_dict()) == [
        "amplitude",
        "frequency",
        "periodic",
        "period_spread",
        "notes",
        "harmonics",
        "rotation_rate",
        "toy_undeclared",
    ]
    back = pickle.loads(pickle.dumps(res))  # the batch's processes send Results back pickled
    assert back.extra == res.extra and back.rotation_rate == -0.3 and math.isnan(back.period_spread)

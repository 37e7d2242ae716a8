"""A ramp up and down: each step starts where the one before ended, one netCDF with the direction as a coordinate,
resumable from its journal (a finished step is not run again), another ramp on the same file refused."""

import numpy as np
import pytest

import elastoactive as ea
from elastoactive import protocols
from elastoactive.core.errors import ParameterError
from elastoactive.starts import last_state

UNIT = ea.Physics(scene="trapped-unit", trap=1.0, alignment_length=0.5, sigma=0.25)
SAMPLES = ea.Numerics(sample_dt=0.1)


def small_ramp(**kw):
    options = dict(numerics=SAMPLES, seeds=(0, 1), duration=40.0)
    options.update(kw)
    return protocols.make_ramp(UNIT, "Pi", [0.5, 2.0], **options)


def test_the_loop_is_one_netcdf_with_the_direction(tmp_path):
    outcome = protocols.run_ramp(small_ramp(), tmp_path / "loop.nc", workers=1)
    data = ea.load_sweep(outcome.path)
    assert dict(data.sizes) == {"seed": 2, "direction": 2, "Pi": 2, "unit": 1}
    assert list(data.direction.values) == ["up", "down"] and list(data.Pi.values) == [0.5, 2.0]
    assert data.order.sel(seed=0).values.tolist() == [[0, 1], [3, 2]]
    states = data.network_state.attrs["flag_meanings"].split()
    named = np.array(states)[data.network_state.values.astype(int)]
    assert (named[:, :, 0] == "frozen").all() and (named[:, :, 1] == "collective").all()
    rate = np.sqrt(2.0 - 1.0)  # the orbit's k_t sqrt(Pi - 1)
    assert np.allclose(data.unit_rate.sel(Pi=2.0, direction="down").values, rate, rtol=1e-2)  # settled by then
    assert not (tmp_path / "loop.nc.journal").exists()
    assert protocols.ramp_figure(outcome.path, tmp_path / "loop.png").stat().st_size > 0


def test_each_step_starts_from_the_last_state(tmp_path):
    ramp = small_ramp(seeds=(3,))
    outcome = protocols.run_ramp(ramp, tmp_path / "loop.nc", workers=1)
    first = ea.simulate(ramp.physics_at(0.5), ramp.numerics_of(3), duration=40.0, engine="reduced")
    second = ea.simulate(ramp.physics_at(2.0), ramp.numerics_of(3), duration=40.0, engine="reduced", start=first)
    third = ea.simulate(ramp.physics_at(2.0), ramp.numerics_of(3), duration=40.0, engine="reduced", start=second)
    data = ea.load_sweep(outcome.path)
    for direction, trajectory in (("up", second), ("down", third)):
        assert (
            data.polarity_speed.sel(seed=3, direction=direction, Pi=2.0).item()
            == ea.measure(trajectory, 20.0).polarity_speed
        )
    assert last_state(third).source.startswith("trapped-unit")


def test_a_killed_ramp_resumes_without_running_finished_steps(tmp_path, monkeypatch):
    ramp = small_ramp(seeds=(0,))
    whole = ea.load_sweep(protocols.run_ramp(ramp, tmp_path / "whole.nc", workers=1).path)
    real, calls = protocols.run_step, []

    def dies_at_the_third(*args):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(args)
        return real(*args)

    monkeypatch.setattr(protocols, "run_step", dies_at_the_third)
    with pytest.raises(KeyboardInterrupt):
        protocols.run_ramp(ramp, tmp_path / "loop.nc", workers=1)
    assert (tmp_path / "loop.nc.journal").is_file() and not (tmp_path / "loop.nc").exists()
    monkeypatch.setattr(protocols, "run_step", real)
    outcome = protocols.run_ramp(ramp, tmp_path / "loop.nc", workers=1)
    assert (outcome.ran, outcome.kept) == (2, 2)
    resumed = ea.load_sweep(outcome.path)
    for name in ("polarity_speed", "orbit_radius", "order"):
        assert np.array_equal(resumed[name].values, whole[name].values, equal_nan=True), name


def test_another_ramp_on_the_same_file_is_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(protocols, "run_step", lambda *a: (_ for _ in ()).throw(KeyboardInterrupt))
    with pytest.raises(KeyboardInterrupt):
        protocols.run_ramp(small_ramp(), tmp_path / "loop.nc", workers=1)
    with pytest.raises(ParameterError, match="another ramp .*duration"):
        protocols.run_ramp(small_ramp(duration=50.0), tmp_path / "loop.nc", workers=1)


@pytest.mark.parametrize(
    "kw, words",
    [
        (dict(parameter="rings", values=[1, 2]), "not a real-valued"),
        (dict(parameter="bogus", values=[1, 2]), "not a physics parameter"),
        (dict(parameter="Pi", values=[2.0, 1.0]), "increasing"),
        (dict(parameter="Pi", values=[1.0]), "two or more"),
    ],
)
def test_bad_ramps_are_refused_in_one_line(kw, words):
    physics = ea.Physics(scene="lattice", rings=1)
    with pytest.raises(ParameterError, match=words):
        protocols.make_ramp(physics, kw["parameter"], kw["values"], duration=10.0)

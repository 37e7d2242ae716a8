"""The Python API for analysis: positions from a trajectory, loading a run or a sweep, plots with units, and help on
Physics generated from the parameter table."""

import inspect

import matplotlib
import numpy as np
import pytest

import elastoactive as ea
from elastoactive.cli import main
from elastoactive.core.parameters import Parameter
from elastoactive.core.trajectory import particle_positions
from elastoactive.terms import Term

matplotlib.use("Agg")


def _run(scene_physics, duration=4.0):
    return ea.simulate(scene_physics, ea.Numerics(sample_dt=0.1), duration=duration, engine="reduced")


def _links(xy, pivot):
    """Distances between each particle and the one before it (particle 0: its pivot)."""
    points = np.concatenate([pivot[..., None, :], xy], axis=-2)
    return np.linalg.norm(np.diff(points, axis=-2), axis=-1)


@pytest.mark.parametrize(
    "physics",
    [
        ea.Physics(n=5, sigma=3.0),
        ea.Physics(scene="coupled-pair", n=4, sigma=3.0),
        ea.Physics(scene="paraboloid", n=4, sigma=1.0, trap=0.3),
    ],
    ids=lambda p: p.scene,
)
def test_positions_are_the_chains_geometry(physics):
    """Every link 1 long, from the chain's pivot (the origin, the pair's offset pivots, a moving head)."""
    traj = _run(physics)
    xy = traj.positions()
    assert xy.shape == (len(traj.t), physics.n_chains, physics.n, 2)
    for k in range(physics.n_chains):
        pivot = np.zeros((len(traj.t), 2))
        pivot[:, 1] = physics.scene_def.chain_offset(physics, k)
        if traj.head is not None and k == 0:
            pivot += traj.head
        np.testing.assert_allclose(_links(xy[:, k], pivot), 1.0, atol=1e-12)
    assert np.ptp(xy[:, 0, -1], axis=0).max() > 1e-3  # the chain moves
    np.testing.assert_array_equal(traj.tip(), xy[:, :, -1, :])
    points = xy if traj.head is None else np.concatenate([traj.head[:, None, None, :], xy], axis=2)
    np.testing.assert_allclose(traj.centre_of_drag(), points.mean(axis=2))  # a free head carries drag too


def test_the_pinned_particle_stays_at_its_pin():
    physics = ea.Physics(scene="two-pinned", n=6, sigma=8.0, delta=0.2)
    xy = _run(physics).positions()
    np.testing.assert_allclose(xy[:, 0, -1], np.tile([6 * (1 - 0.2), 0.0], (len(xy), 1)), atol=1e-6)
    np.testing.assert_allclose(_links(xy[:, 0], np.zeros((len(xy), 2))), 1.0, atol=1e-12)


def test_positions_refuse_angles_of_another_chain():
    with pytest.raises(ea.ParameterError, match="theta must have 10 angles per sample"):
        particle_positions(ea.Physics(scene="coupled-pair", n=5), np.zeros((3, 7)))


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda traj: ea.plot.shape(traj, time=1e9), "time must lie within the record"),
        (lambda traj: ea.plot.shape(traj, time="soon"), "time must be a time in tau"),
        (lambda traj: ea.plot.limit_cycle(traj, transient=-1), "transient must be a finite time >= 0"),
        (lambda traj: ea.plot.limit_cycle(traj, transient=100), "leaves fewer than 3 samples"),
        (lambda traj: ea.plot.angles(traj, chain=1), "chain must be a chain index from 0 to 0"),
        (lambda traj: ea.plot.tip_path(traj, transient=float("nan")), "transient must be a finite time"),
    ],
)
def test_plot_arguments_are_named(call, message):
    traj = _run(ea.Physics(n=3, sigma=3.0), duration=2.0)
    with pytest.raises(ea.ParameterError, match=message):
        call(traj)
    with pytest.raises(TypeError, match="traj must be an ea.Trajectory"):
        ea.plot.theta(traj.theta)


def test_a_network_s_positions_are_its_nodes():
    traj = _run(ea.Physics(scene="lattice", rings=1, sigma=0.5), duration=1.0)
    np.testing.assert_array_equal(traj.positions(), traj.nodes)
    assert traj.centre_of_drag().shape == (len(traj.t), 2)
    with pytest.raises(ea.ParameterError, match="network, which has no tip"):
        traj.tip()
    ds = traj.to_xarray()
    assert ds["position"].dims == ("time", "node", "xy") and ds["position"].attrs["units"] == "a"
    assert ea.plot.shape(traj).get_xlabel() == "$x$ (a)"


def test_to_xarray_carries_units_and_long_names():
    traj = _run(ea.Physics(scene="coupled-pair", n=4, sigma=3.0))
    ds = traj.to_xarray()
    assert ds["theta"].dims == ("time", "chain", "particle") and ds["theta"].attrs["units"] == "rad"
    assert ds["position"].attrs["units"] == "l" and ds["time"].attrs["units"] == "tau"
    for name in ("theta", "position", "tip", "time"):
        assert ds[name].attrs["long_name"], name
    np.testing.assert_array_equal(ds["tip"].values, traj.tip())
    np.testing.assert_array_equal(ds["theta"].values.reshape(len(traj.t), -1), traj.theta)
    assert ds.attrs["scene"] == "coupled-pair" and ds.attrs["kappa"] == 1.0 and ds.attrs["engine"] == "reduced"


def test_tip_path_plotted_from_a_loaded_run(tmp_path, capsys):
    out = tmp_path / "run"
    argv = ["run", "one-pinned", "--n", "5", "--sigma", "3", "--duration", "20", "--engine", "reduced", "--quiet"]
    assert main([*argv, "--out", str(out)]) == 0
    capsys.readouterr()
    for path in (out, out / "summary.json", str(out / "trajectory.npz")):
        traj = ea.load(path)
        assert isinstance(traj, ea.Trajectory) and traj.info["summary"]["parameters"]["sigma"] == 3
    ax = ea.plot.tip_path(traj)
    line = ax.get_lines()[0]
    np.testing.assert_array_equal(line.get_xydata(), traj.tip()[:, 0])
    assert ax.get_xlabel() == "tip $x$ (l)"
    for draw in (ea.plot.theta, ea.plot.limit_cycle, ea.plot.angles, ea.plot.shape):
        assert draw(traj) is not None
    mine = matplotlib.pyplot.figure().add_subplot()
    assert ea.plot.limit_cycle(traj, ax=mine) is mine


def test_load_names_what_it_cannot_read(tmp_path):
    with pytest.raises(ea.ParameterError, match="path: .*absent not found"):
        ea.load(tmp_path / "absent")
    with pytest.raises(ea.ParameterError, match="holds no summary.json"):
        ea.load(tmp_path)
    (tmp_path / "notes.txt").write_text("x")
    with pytest.raises(ea.ParameterError, match="neither a run"):
        ea.load(tmp_path / "notes.txt")
    (tmp_path / "bad.nc").write_text("not netcdf")
    with pytest.raises(ea.ParameterError, match="not a readable netCDF"):
        ea.load(tmp_path / "bad.nc")
    with pytest.raises(TypeError, match="path must be"):
        ea.load(3)


def test_a_sweep_opened_and_plotted_with_units(tmp_path, capsys):
    out = tmp_path / "sweep.nc"
    argv = ["sweep", "one-pinned", "--grid", "sigma=2,3", "--grid", "n=3,4", "--duration", "20", "--engine", "reduced"]
    assert main([*argv, "--workers", "1", "--quiet", "--out", str(out)]) == 0
    capsys.readouterr()
    ds = ea.load(out)
    assert ds.equals(ea.load_sweep(str(out))) and set(ds["amplitude"].dims) == {"sigma", "n"}
    ax = ea.plot.sweep_map(ds, "amplitude")
    colourbar = ax.figure.axes[-1]
    assert colourbar.get_ylabel() == f"{ds['amplitude'].attrs['long_name']} ($\\mathrm{{rad}}$)"
    assert ds["sigma"].attrs["long_name"] in ax.get_ylabel() + ax.get_xlabel()
    line = ea.plot.sweep_map(ds.sel(n=4), "frequency")
    assert line.get_lines()[0].get_xydata().shape == (2, 2)
    with pytest.raises(ea.ParameterError, match="variable: the sweep has no 'bogus'"):
        ea.plot.sweep_map(ds, "bogus")
    with pytest.raises(ea.ParameterError, match="variable: status holds"):
        ea.plot.sweep_map(ds, "status")
    with pytest.raises(ea.ParameterError, match="chain: not a dimension of amplitude"):
        ea.plot.sweep_map(ds, "amplitude", chain=1)
    with pytest.raises(TypeError, match="dataset must be an xarray.Dataset"):
        ea.plot.sweep_map({"amplitude": [1.0]}, "amplitude")


def test_help_on_physics_lists_every_parameter_with_units():
    text = inspect.getdoc(ea.Physics)
    signature = inspect.signature(ea.Physics)
    for scene in ea.scenes.scenes():
        assert scene.name in text
    from elastoactive.core import parameters

    for name in parameters.names():
        spec = parameters.get(name)
        assert f"\n{name} : {spec.kind.__name__}" in text, name
        if spec.units not in ("1", ""):
            assert f"[{spec.units}]" in text.split(f"\n{name} : ")[1].split("\n")[0], name
        assert signature.parameters[name].default == spec.default
    assert "Parameters\n----------" in text


class _Probe(Term):
    name = "test-probe-term"
    parameters = (Parameter("probe_strength", 0.0, "a probe's strength", units="C1/l", quiet_default=True),)


def test_help_on_physics_follows_the_registry():
    assert "probe_strength" not in ea.Physics.__doc__
    ea.terms.register(_Probe())
    try:
        assert "probe_strength : float, default 0.0 [C1/l]" in ea.Physics.__doc__
        assert "probe_strength" in inspect.signature(ea.Physics).parameters
    finally:
        ea.terms.unregister(_Probe.name)


def test_every_public_name_is_documented():
    """Every public name of ea has a docstring; every function and public method of the API's own modules a numpydoc
    Parameters or Returns section."""
    for name in ea.__all__:
        assert inspect.getdoc(getattr(ea, name)), name
    functions = [ea.load, ea.load_sweep, ea.simulate, ea.measure, ea.save, ea.sweep.__wrapped__, ea.ramp, ea.stability]
    functions += [getattr(ea.plot, name) for name in ea.plot.__all__]
    functions += [ea.Trajectory.positions, ea.Trajectory.tip, ea.Trajectory.centre_of_drag, ea.Trajectory.to_xarray]
    for fn in functions:
        assert "Returns\n-------" in inspect.getdoc(fn), fn.__qualname__

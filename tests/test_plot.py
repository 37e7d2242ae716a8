"""ea.plot draws each structure in the views that show its motion, decided by its scene's kind: a 3D chain's tip path
across its clamp axis (a whirl's circle) and in 3D, a free pivot's in the plane of its turn, a network's pinned nodes
and its units' polarities; every label the module makes is valid mathtext; integer coordinates get whole-number ticks.
What was drawn is read back from the artists (lines, quivers, labels, ticks), on trajectories built from known motion
(no engine runs)."""

import re

import matplotlib
import numpy as np
import pytest
import xarray as xr

import elastoactive as ea
from elastoactive.scenes.clamped3d import angles_of

matplotlib.use("Agg")

T = np.linspace(0.0, 20.0, 201)
RADII = np.array([0.1, 0.25, 0.4])
"""Lateral tilt of each link of the synthetic whirl (the tangent's component across e_x before normalising)."""


@pytest.fixture(autouse=True)
def _closed():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


def _whirl(scene: str = "clamped-3d") -> ea.Trajectory:
    """A chain of three links whirling rigidly about e_x at one radian per tau: its tip turns on a circle across the
    clamp axis."""
    lateral = RADII[None, :, None] * np.stack([np.cos(T), np.sin(T)], axis=-1)[:, None, :]
    tangents = np.concatenate([np.ones((T.size, 3, 1)), lateral], axis=-1)
    physics = ea.Physics(scene=scene, n=3, sigma=2.0)
    return ea.Trajectory(T, angles_of(tangents / np.linalg.norm(tangents, axis=-1, keepdims=True)), physics, "reduced")


def _turn() -> ea.Trajectory:
    """A bent chain of three links on a free pivot turning rigidly in the xy plane."""
    phi = T[:, None] + np.array([0.0, 0.4, 0.8])
    theta = np.concatenate([phi, np.zeros_like(phi)], axis=1)
    return ea.Trajectory(T, theta, ea.Physics(scene="rotating-pin-3d", n=3, sigma=2.0), "reduced")


def _lattice() -> ea.Trajectory:
    """A one-ring patch at rest (its outer ring pinned, its centre a unit), the unit's polarity turning."""
    physics = ea.Physics(scene="lattice", rings=1, sigma=0.5)
    network = physics.scene_def.network(physics)
    nodes = np.repeat(network.positions[None], 3, axis=0)
    polarity = np.array([[0.0], [0.5], [1.2]])
    return ea.Trajectory(T[:3], np.empty((3, 0)), physics, "reduced", polarity=polarity, nodes=nodes)


def test_a_whirl_is_drawn_across_the_clamp_axis_and_in_3d():
    traj = _whirl()
    ax = ea.plot.tip_path(traj)
    tip = traj.tip()[:, 0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("tip $y$ (l)", "tip $z$ (l)")
    y, z = ax.get_lines()[0].get_data()
    np.testing.assert_allclose(np.stack([y, z], axis=-1), tip[:, 1:])
    np.testing.assert_allclose(np.hypot(y, z), np.hypot(y, z).mean(), rtol=1e-12)  # a circle, not a line
    (view,) = [a for a in ax.figure.axes if a.name == "3d"]
    np.testing.assert_allclose(np.stack(view.get_lines()[0].get_data_3d(), axis=-1), tip)
    assert view.get_zlabel() == "tip $z$ (l)"


def test_a_given_axes_gets_the_view_it_can_show():
    import matplotlib.pyplot as plt

    traj = _whirl()
    plane = ea.plot.tip_path(traj, ax=plt.figure().add_subplot())
    assert len(plane.figure.axes) == 1 and plane.get_xlabel() == "tip $y$ (l)"
    cube = ea.plot.tip_path(traj, ax=plt.figure().add_subplot(projection="3d"), transient=10.0)
    assert len(cube.get_lines()[0].get_data_3d()[0]) == np.count_nonzero(T >= 10.0)


def test_a_free_pivot_s_turn_is_drawn_in_its_plane():
    traj = _turn()
    ax = ea.plot.tip_path(traj)
    assert ax.get_title() == "in the plane of the turn" and ax.get_xlabel() == "tip $u$ (l)"
    np.testing.assert_allclose(ax.get_lines()[0].get_xydata(), traj.tip()[:, 0, :2], atol=1e-12)  # the xy plane


def test_a_planar_chain_s_tip_path_is_one_xy_view():
    physics = ea.Physics(scene="one-pinned", n=3, sigma=1.0)
    theta = 0.3 * np.sin(T)[:, None] * np.array([1.0, 2.0, 3.0])
    ax = ea.plot.tip_path(ea.Trajectory(T, theta, physics, "reduced"))
    assert len(ax.figure.axes) == 1 and (ax.get_xlabel(), ax.get_ylabel()) == ("tip $x$ (l)", "tip $y$ (l)")


def test_a_network_shows_its_pinned_nodes_and_its_units_polarities():
    traj = _lattice()
    network = traj.physics.scene_def.network(traj.physics)
    ax = ea.plot.shape(traj, time=T[1])
    (pinned,) = [line for line in ax.get_lines() if line.get_label() == "pinned"]
    np.testing.assert_allclose(pinned.get_xydata(), network.positions[network.pinned])
    (arrows,) = [c for c in ax.collections if c.get_label() == "polarity"]
    np.testing.assert_allclose(arrows.get_offsets(), network.positions[network.active])
    direction = np.column_stack([arrows.U, arrows.V])
    np.testing.assert_allclose(direction / np.linalg.norm(direction), [[np.cos(0.5), np.sin(0.5)]])
    assert ax.get_title() == r"$t$ = 0.1 $\gamma/k$"


_MATH = re.compile(r"\$([^$]*)\$")


def _mathtext_problems(text: str) -> list[str]:
    """Subscripts or superscripts of more than one character left unbraced ($y_tip$ sets only the t low)."""
    return [m for math in _MATH.findall(text) for m in re.findall(r"[_^][A-Za-z0-9]{2,}", math)]


@pytest.mark.parametrize("scene", ea.scenes.names())
def test_every_label_is_mathtext(scene):
    """Every scene's labels (ea.plot.labels) set no multi-character sub- or superscript unbraced, and render."""
    import matplotlib.pyplot as plt

    texts = list(vars(ea.plot.labels(ea.scenes.get(scene).physics())).values())
    assert not [p for text in texts for p in _mathtext_problems(text)], texts
    figure = plt.figure()
    for k, text in enumerate(texts):
        figure.text(0.1, 0.1 * k, text)
    figure.canvas.draw()  # a mathtext error raises here


def test_a_3d_chain_s_signal_label_braces_its_subscript():
    labels = ea.plot.labels(ea.Physics(scene="clamped-3d", n=3, sigma=2.0))
    assert labels.signal.startswith(r"$y_{\mathrm{tip}}$") and r"$dy_{\mathrm{tip}}/dt$" in labels.rate
    ax = ea.plot.theta(_whirl())
    ax.figure.canvas.draw()
    assert ax.get_ylabel() == labels.signal


def _over_n() -> xr.Dataset:
    values = np.arange(10.0).reshape(5, 2)
    return xr.Dataset(
        {"frequency": (("n", "seed"), values, {"long_name": "frequency", "units": "1/tau"})},
        coords={"n": np.arange(3, 8), "seed": np.array([0, 1])},
        attrs={"grid": "n seed"},
    )


def test_integer_coordinates_get_whole_number_ticks():
    line = ea.plot.sweep_map(_over_n(), "frequency", seed=0)
    line.figure.canvas.draw()
    ticks = line.get_xticks()
    assert np.array_equal(ticks, np.round(ticks)) and line.get_ylabel() == r"frequency ($1/\tau$)"
    mesh = ea.plot.sweep_map(_over_n(), "frequency")
    mesh.figure.canvas.draw()
    for ticks in (mesh.get_xticks(), mesh.get_yticks()):
        assert np.array_equal(ticks, np.round(ticks)), ticks


@pytest.mark.parametrize("make", [_whirl, _lattice, _turn], ids=["clamped-3d", "lattice", "rotating-pin-3d"])
def test_xarray_labels_its_own_plots_on_one_line(make):
    """Every variable's and coordinate's long_name with its units fits xarray's 30-character axis label (xarray wraps
    longer ones onto lines a figure clips); the longer words are in `description`."""
    from xarray.plot.utils import label_from_attrs

    ds = make().to_xarray()
    for name in [*ds.data_vars, *ds.coords]:
        assert ds[name].attrs["description"], name
        assert "\n" not in label_from_attrs(ds[name]), name

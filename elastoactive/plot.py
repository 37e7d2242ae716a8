"""Quick figures of a run or a sweep, each on a matplotlib Axes that it returns.

    import elastoactive as ea

    traj = ea.load("out/run")
    ea.plot.theta(traj)                   # Theta = theta_N - theta_1 against time
    ea.plot.limit_cycle(traj)             # Theta against dTheta/dt
    ea.plot.shape(traj, time=100.0)       # the chain (or the network) at a time
    ea.plot.tip_path(traj)                # the tips' paths
    ea.plot.sweep_map(ea.load("sweep.nc"), "amplitude")

Every function takes an optional ``ax`` (a new figure's Axes when None) and labels its axes with the quantities'
units, in the scene's own (`labels`: a network's times in gamma/k and lengths in a; a sweep's from its netCDF
attributes).

matplotlib is imported inside _axes, the drawing's boundary: `import elastoactive` does not load it.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass

import numpy as np

from .core.errors import ParameterError
from .core.params import Physics
from .core.trajectory import Trajectory
from .core.units import THETA, beat_signal, scene_units

_TEX = {"tau": r"\tau", "gamma": r"\gamma", "Theta": r"\Theta", "Omega": r"\Omega", "psi": r"\psi"}
"""Symbols drawn as Greek letters in labels."""


def _word(token: str) -> str:
    """One name in TeX: a Greek name as its letter, a longer word upright (rad as \\mathrm{rad}), a letter as is."""
    if token in _TEX:
        return _TEX[token]
    return rf"\mathrm{{{token}}}" if len(token) > 1 and token.isalpha() else token


def _tex(text: str) -> str:
    """A units string or a symbol in matplotlib's mathtext: Greek names as letters, other words upright, a subscript
    braced whole (y_tip as y_{\\mathrm{tip}}, not y_t followed by ip)."""

    def symbol(match: re.Match) -> str:
        base, _, sub = match.group(0).partition("_")
        return _word(base) + (f"_{{{_word(sub)}}}" if sub else "")

    return "$" + re.sub(r"[A-Za-z]+(?:_[A-Za-z0-9]+)?", symbol, text).replace(" ", r"\,") + "$"


@dataclass(frozen=True)
class Labels:
    """The axis labels of a physics' figures, in its scene's units (units.Units) and about its beat signal
    (Scene.beat_signal): a chain's Theta in rad against time in tau, a network's in its own units."""

    time: str
    """The time axis: 'time $t$ ($\\tau$)'."""
    time_units: str
    """The time unit alone, in TeX."""
    signal: str
    """The beat signal's axis (ea.plot.theta, limit_cycle)."""
    rate: str
    """The beat signal's rate (limit_cycle)."""
    length: str
    """The length unit of positions."""

    @classmethod
    def of(cls, physics: Physics) -> Labels:
        units, signal = scene_units(physics.scene_def), beat_signal(physics)
        top, _, bottom = signal.units.partition("/")
        per_time = f"{top or '1'}/{bottom + '^2' if bottom == 'tau' else 'tau'}" if bottom in ("", "tau") else ""
        symbol = signal.symbol if signal is not THETA else "Theta"
        shown = r"$\Theta = \theta_N - \theta_1$" if signal is THETA else _tex(signal.symbol)
        time = _tex(units.time_units)
        return cls(
            time=f"time $t$ ({time})",
            time_units=time,
            signal=f"{shown} ({_tex(units.of(signal.units))})",
            rate=f"$d{_tex(symbol)[1:-1]}/dt$ ({_tex(units.of(per_time))})" if per_time else f"rate of {shown}",
            length=units.length,
        )


def labels(physics: Physics) -> Labels:
    """The axis labels ea.plot draws for `physics`, in its scene's units and about its beat signal.

    Parameters
    ----------
    physics : Physics
        The run's physics (its scene says the units: Scene.units, Scene.beat_signal).

    Returns
    -------
    Labels
        ``time`` (the time axis), ``time_units``, ``signal`` (the beat signal's axis), ``rate`` (its rate's) and
        ``length`` (the unit of positions): '$\\Theta = \\theta_N - \\theta_1$ ($\\mathrm{rad}$)' for a chain,
        '$u_x$ ($a$)' for a held network.
    """
    return Labels.of(physics)


def _axes(ax):
    """`ax`, or a new figure's Axes."""
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt  # start-up time: matplotlib loads only when a figure is drawn

    return plt.figure().add_subplot()


def _trajectory(traj) -> Trajectory:
    if not isinstance(traj, Trajectory):
        raise TypeError(f"traj must be an ea.Trajectory (from ea.simulate or ea.load), got {type(traj).__name__}")
    return traj


def _time_label(traj: Trajectory) -> str:
    return labels(traj.physics).time


def _chains(traj: Trajectory) -> list[str]:
    """The legend's name of each chain (none for a single chain)."""
    count = traj.physics.scene_def.chain_count(traj.physics)
    return [f"chain {k + 1}" for k in range(count)] if count > 1 else [""]


def angles(traj: Trajectory, ax=None, chain: int = 0):
    """The absolute angle of every link of one chain against time.

    Parameters
    ----------
    traj : Trajectory
        A chain scene's trajectory.
    ax : matplotlib.axes.Axes, optional
        Where to draw; default a new figure's.
    chain : int
        Which chain (0-based).

    Returns
    -------
    matplotlib.axes.Axes
    """
    traj, ax = _trajectory(traj), _axes(ax)
    if not traj.physics.n_angles:
        raise ParameterError(
            f"chain: the {traj.physics.scene} scene is a {traj.physics.scene_def.kind}, which has no angles"
        )
    if not isinstance(chain, (int, np.integer)) or not 0 <= chain < traj.physics.n_chains:
        raise ParameterError(f"chain must be a chain index from 0 to {traj.physics.n_chains - 1}, got {chain!r}")
    for i, column in enumerate(traj.chain(chain).T):
        ax.plot(traj.t, column, label=rf"$\theta_{{{i + 1}}}$")
    ax.set(xlabel=_time_label(traj), ylabel=r"absolute angle $\theta_i$ (rad)")
    ax.legend(fontsize="small", ncol=2)
    return ax


def theta(traj: Trajectory, ax=None):
    """The beat signal against time: Theta = theta_N - theta_1 of every chain (a network: its scene's signal).

    Parameters
    ----------
    traj : Trajectory
        From ea.simulate or ea.load.
    ax : matplotlib.axes.Axes, optional
        Where to draw; default a new figure's.

    Returns
    -------
    matplotlib.axes.Axes
    """
    traj, ax = _trajectory(traj), _axes(ax)
    signals = traj.physics.scene_def.beat_signals(traj)
    for label, signal in zip(_chains(traj), signals, strict=False):
        ax.plot(traj.t, signal, label=label or None)
    ax.set(xlabel=_time_label(traj), ylabel=_signal_label(traj))
    if len(signals) > 1:
        ax.legend(fontsize="small")
    return ax


def _signal_label(traj: Trajectory) -> str:
    return labels(traj.physics).signal


def limit_cycle(traj: Trajectory, ax=None, transient: float | None = None):
    """The phase portrait: Theta against dTheta/dt after the transient (a beat's limit cycle is a closed loop).

    Parameters
    ----------
    traj : Trajectory
        From ea.simulate or ea.load.
    ax : matplotlib.axes.Axes, optional
        Where to draw; default a new figure's.
    transient : float, optional
        Time (tau) left out at the start; default half the run.

    Returns
    -------
    matplotlib.axes.Axes
    """
    traj, ax = _trajectory(traj), _axes(ax)
    t = traj.t
    start = t[0] + (0.5 * (t[-1] - t[0]) if transient is None else _time("transient", transient))
    keep = t >= start
    if keep.sum() < 3:
        raise ParameterError(f"transient {start - t[0]:g} tau leaves fewer than 3 samples of the {t[-1] - t[0]:g} tau")
    signals = traj.physics.scene_def.beat_signals(traj)
    for label, signal in zip(_chains(traj), signals, strict=False):
        ax.plot(signal[keep], np.gradient(signal, t)[keep], label=label or None)
    rate = labels(traj.physics).rate
    ax.set(xlabel=_signal_label(traj), ylabel=rate)
    if len(signals) > 1:
        ax.legend(fontsize="small")
    return ax


def _time(name: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a time in tau, got {value!r}") from None
    if not np.isfinite(value) or value < 0:
        raise ParameterError(f"{name} must be a finite time >= 0 in tau, got {value}")
    return value


def _sample(traj: Trajectory, time) -> int:
    """The index of the sample nearest `time` (default: the last)."""
    if time is None:
        return len(traj.t) - 1
    time = _time("time", time)
    if not traj.t[0] <= time <= traj.t[-1]:
        raise ParameterError(f"time must lie within the record, {traj.t[0]:g} to {traj.t[-1]:g} tau; got {time:g}")
    return int(np.abs(traj.t - time).argmin())


def shape(traj: Trajectory, time: float | None = None, ax=None):
    """The chain (every chain of the scene, from its pivot) or the network (its nodes and springs) at one time.

    Parameters
    ----------
    traj : Trajectory
        From ea.simulate or ea.load.
    time : float, optional
        Time (tau) of the sample drawn (the nearest one); default the last.
    ax : matplotlib.axes.Axes, optional
        Where to draw; default a new figure's.

    Returns
    -------
    matplotlib.axes.Axes
    """
    traj, ax = _trajectory(traj), _axes(ax)
    i = _sample(traj, time)
    units = traj.length_units
    traj.physics.scene_def.draw_shape(ax, traj, i, _chains(traj))  # the scene's kind: chains or a network
    ax.set(
        xlabel=f"$x$ ({units})",
        ylabel=f"$y$ ({units})",
        title=f"$t$ = {traj.t[i]:g} " + labels(traj.physics).time_units,
    )
    ax.set_aspect("equal", adjustable="datalim")
    return ax


def tip_path(traj: Trajectory, ax=None, transient: float = 0.0):
    """The path of every chain's tip (the last particle), in the views its scene draws it in (Scene.tip_views): a
    planar chain's in the lab frame's xy plane; a chain in three dimensions across its clamp axis (where a whirl is a
    circle; a free pivot's: in the plane of its turn), then in a 3D view.

    Parameters
    ----------
    traj : Trajectory
        A chain scene's trajectory.
    ax : matplotlib.axes.Axes, optional
        Where to draw the first view (a 3D Axes: the 3D view); default a new figure's, which holds every view side by
        side. Given an Axes, only the view it can show is drawn.
    transient : float
        Time (tau) left out at the start.

    Returns
    -------
    matplotlib.axes.Axes
        The first view's (the others are its figure's other Axes).
    """
    traj = _trajectory(traj)
    keep = traj.t >= traj.t[0] + _time("transient", transient)
    views = traj.physics.scene_def.tip_views(traj, keep)
    if ax is not None:  # the one view the Axes can show: a 3D view on a 3D Axes
        views = [next((v for v in views if (len(v.axes) == 3) == (ax.name == "3d")), views[0])]
        axes = [ax]
    else:
        axes = _figure_axes([len(v.axes) for v in views])
    length, chains = labels(traj.physics).length, _chains(traj)
    for view, ax in zip(views, axes, strict=True):
        for k, label in enumerate(chains):
            ax.plot(*(view.points[:, k, c] for c in range(len(view.axes))), lw=1, label=label or None)
        names = ("xlabel", "ylabel", "zlabel")
        ax.set(**{name: f"tip ${axis}$ ({length})" for name, axis in zip(names, view.axes, strict=False)})
        if view.title:
            ax.set_title(view.title)
        if len(view.axes) == 2:
            ax.set_aspect("equal", adjustable="datalim")
        if len(chains) > 1:
            ax.legend(fontsize="small")
    return axes[0]


def _figure_axes(dimensions: list[int]) -> list:
    """A new figure's Axes side by side, one per view: 2 for a plane, 3 for a 3D view."""
    import matplotlib.pyplot as plt  # start-up time: matplotlib loads only when a figure is drawn

    figure = plt.figure(figsize=(6.4 * len(dimensions) if len(dimensions) > 1 else 6.4, 4.8))
    return [
        figure.add_subplot(1, len(dimensions), k + 1, projection="3d" if d == 3 else None)
        for k, d in enumerate(dimensions)
    ]


def _label(array) -> str:
    """'long name (units)' from a netCDF variable's or coordinate's attributes, the units in mathtext."""
    name = array.attrs.get("long_name", array.name)
    units = array.attrs.get("units")
    return f"{name} ({_tex(str(units))})" if units not in (None, "", "1") else str(name)


def _integer_ticks(axis, coordinate) -> None:
    """Ticks at whole numbers only on an axis that draws an integer coordinate (N, a seed)."""
    if coordinate.dtype.kind in "iu":
        from matplotlib.ticker import MaxNLocator  # start-up time: matplotlib loads only when a figure is drawn

        axis.set_major_locator(MaxNLocator(integer=True))


def _shown(value) -> str:
    """A coordinate's value as Python would write it: 0.6, 3, 'up'."""
    value = value.item() if isinstance(value, np.generic) else value
    return f"{value:g}" if isinstance(value, float) else repr(value)


def _values(coordinate, limit: int = 8) -> str:
    """A coordinate's values in a message, the first `limit` of them."""
    shown = [_shown(v) for v in coordinate.values[:limit]]
    return ", ".join(shown) + (f", ... ({coordinate.size} in all)" if coordinate.size > limit else "")


SAME_VALUE = 1e-9
"""Relative difference within which a value asked for is a coordinate's value (a grid's 0.1 steps are not exact)."""


def _position(coordinate, value) -> int | None:
    """Where `value` is in a 1-D coordinate (the first match; numbers within SAME_VALUE), None when it is not."""
    values = coordinate.values
    number = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))
    if values.dtype.kind in "biuf":
        if not number:
            return None
        found = np.flatnonzero(np.isclose(values.astype(float), float(value), rtol=SAME_VALUE, atol=0.0))
    else:
        found = np.flatnonzero([v == value for v in values.tolist()])
    return int(found[0]) if found.size else None


def _swept(dataset) -> list[str]:
    """The parameters a sweep's or a ramp's netCDF varies over its grid (empty when it does not say)."""
    names = str(dataset.attrs.get("grid", "")).split()
    try:
        ramp = json.loads(dataset.attrs["ramp"])
        names += [ramp["parameter"]] if isinstance(ramp, dict) and isinstance(ramp.get("parameter"), str) else []
    except (KeyError, TypeError, ValueError):
        pass
    return names


def sweep_map(dataset, variable: str = "amplitude", ax=None, **selection):
    """A sweep's observable over its grid: a line over one swept parameter, a colour map over two.

    Parameters
    ----------
    dataset : xarray.Dataset
        From ea.load_sweep (or ea.load of a .nc file: a sweep's, or a ramp's).
    variable : str
        The observable drawn (a data variable of the sweep, e.g. "amplitude", "frequency").
    ax : matplotlib.axes.Axes, optional
        Where to draw; default a new figure's.
    **selection
        One value of each dimension not drawn (``chain=1``, a third swept parameter, a ramp's ``seed`` and
        ``direction``): a value of its coordinate (numbers equal within SAME_VALUE).

    Every dimension is drawn or selected: the swept parameters (the netCDF's grid, a ramp's parameter) are drawn, two
    at most; every other dimension, and a swept one beyond two, must be given a value in `selection` unless it has a
    single one, else a ParameterError lists them with their values. The title says what was selected.

    Returns
    -------
    matplotlib.axes.Axes
        Labelled with the long names and units of the netCDF attributes, titled with the values selected.
    """
    if not hasattr(dataset, "data_vars") or not hasattr(dataset, "attrs"):
        raise TypeError(f"dataset must be an xarray.Dataset (from ea.load_sweep), got {type(dataset).__name__}")
    if not isinstance(variable, str) or variable not in dataset.data_vars:
        names = ", ".join(map(str, dataset.data_vars))
        raise ParameterError(f"variable: the sweep has no {variable!r} (its variables: {names or 'none'})")
    data = dataset[variable]
    if data.dtype.kind not in "biuf":
        raise ParameterError(f"variable: {variable} holds {data.dtype} values, not numbers to draw")
    unknown = [k for k in selection if k not in data.dims]
    if unknown:
        raise ParameterError(f"{unknown[0]}: not a dimension of {variable} (its dimensions: {', '.join(data.dims)})")
    for name, value in selection.items():
        at = _position(data[name], value)
        if at is None:
            raise ParameterError(
                f"{name}={_shown(value)}: not a value of {name} in the sweep (its values: {_values(data[name])})"
            )
        data = data.isel({name: at})
    swept = [d for d in data.dims if d in _swept(dataset)] or list(data.dims)
    drawn = swept[:2]
    data = data.isel({d: 0 for d in data.dims if d not in drawn and data.sizes[d] == 1})  # one value: nothing hidden
    hidden = [d for d in data.dims if d not in drawn]
    if hidden:
        listed = "; ".join(f"{d} ({_values(data[d])})" for d in hidden)
        example = ", ".join(f"{d}={_shown(data[d].values[0])}" for d in hidden)
        raise ParameterError(
            f"{variable} has dimensions beyond the {' and '.join(drawn)} drawn: {listed}; select one value of each, "
            f"e.g. sweep_map(ds, {variable!r}, {example})"
        )
    if data.ndim == 0:
        raise ParameterError(f"variable: {variable} has no swept dimension to draw")
    ax = _axes(ax)
    title = ", ".join(f"{name} = {_shown(c.values[()])}" for name, c in data.coords.items() if c.ndim == 0)
    if title:
        ax.set_title(title)
    if data.ndim == 1:
        coordinate = data[data.dims[0]]
        ax.plot(coordinate.values, data.values, "o-")
        ax.set(xlabel=_label(dataset[data.dims[0]]), ylabel=_label(dataset[variable]))
        _integer_ticks(ax.xaxis, coordinate)
        return ax
    y, x = (dataset[d] for d in data.dims)
    mesh = ax.pcolormesh(x.values, y.values, np.asarray(data.values, dtype=float), shading="auto")
    ax.figure.colorbar(mesh, ax=ax, label=_label(dataset[variable]))
    ax.set(xlabel=_label(x), ylabel=_label(y))
    _integer_ticks(ax.xaxis, x)
    _integer_ticks(ax.yaxis, y)
    return ax


__all__ = ["angles", "labels", "limit_cycle", "shape", "sweep_map", "theta", "tip_path"]

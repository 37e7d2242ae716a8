"""Turn a trajectory into the numbers a run reports (Results, measure) and the checks that it can be measured; a run's
record on disk (summary.json, trajectory.npz and the inputs it read) is elastoactive.records."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields

import numpy as np

from . import quantities
from .analysis import observables as obs
from .analysis import spectrum
from .core import observables
from .core.errors import ParameterError
from .core.observables import HARMONICS
from .core.params import MIN_SAMPLES, Physics, option
from .core.trajectory import Trajectory
from .core.units import beat_signal, scene_units
from .reduced.blas import one_blas_thread
from .terms.base import ALIASING, fastest_term, slower_advice

PerChain = float | tuple[float, ...]

STEADY_AMPLITUDE = 1e-6
"""rad: a Theta whose half peak-to-peak stays below this is at rest (frequency 0), whatever the engine; the rest level
of a run also grows with its solver's error (SOLVER_JITTER)."""
SOLVER_JITTER = 100.0
"""The rest level's multiple of the solver's relative tolerance (the reduced engine's rtol) times the angles' magnitude:
an adaptive solver's error in each angle scales with the angle, so a chain turning for long has a Theta that wiggles by
~20 rtol |theta| (2e-6 rad at |theta| ~ 100 rad, rtol 1e-9) at rest in its turning frame; below the level it is the
integration's error, not motion (five times the jitter seen: a loose rtol of 1e-4 still resolves beats above 0.01
rad on a chain whose angles stay within 1 rad)."""
SMALL_AMPLITUDE = 1e-3
"""rad: below this a Theta counts as steady for the periodicity verdict (wiggles at round-off or a last
decaying transient are not an irregular beat)."""
PERIODIC_SPREAD = 0.01
"""A beat is periodic when its cycle periods and cycle amplitudes vary by less than this (std / mean).
A limit cycle gives ~1e-5; noise, chaos, or a beat still growing in the window give more."""
MIN_CYCLES = 2
"""Whole cycles the measured window must hold to judge whether the beat is periodic."""
WINDING = 2 * math.pi
"""rad: with fewer than MIN_CYCLES cycles in the window, Theta's thirds must drift apart by more than this to call the
motion one that winds up or creeps (not periodic): a bounded beat seen over less than two periods drifts by up to 1.4
times its amplitude between thirds, and a beat whose Theta drifts by a full turn has its tip turned past its base."""
PIN_GIVE = 3.0
"""A beat of a chain held at both ends whose amplitude is below this multiple of sqrt(2 x the pin's largest violation
in l) (the bending a pin that gives by that much lets a chain held at its full length make) gets a note: it may be the
soft pin's (MuJoCo's) rather than the chain's."""
RIGID_TURN = 0.03
"""rad: a chain that turns by at least this over the measured window (|rotation rate| x window) turns; less is at rest
(the rate alone would call a long run's drift of a still chain a turn, or a short run's slow turn rest)."""
RIGID_FRACTION = 1e-3
"""A turning chain whose Theta oscillates by less than this fraction of the angle it turns through in one period of
that oscillation (over the window, without a period) turns rigidly: the residue is the solver's jitter or the last of
a transient decaying onto the rigid turn, not a beat; frequency is null and a note gives the residue."""
TURNING = "rotation_rate"
"""The observable whose value, when a scene reports it, is the chain's rigid turning rate (rad/tau) that RIGID_TURN
and RIGID_FRACTION judge; without it the slope of each chain's first angle is used."""


@dataclass(frozen=True)
class Results:
    """What a run measures after its transient (ea.measure).

    amplitude, frequency  of Theta = theta_N - theta_1: floats, or one per chain (tuple) for the pair;
                          frequency is None when the window holds fewer than two periods of a
                          beating chain (a longer run fixes it) or the chain turns rigidly (no beat:
                          RIGID_TURN, RIGID_FRACTION), 0.0 for a chain at rest (below rest_level)
    periodic              True for a steady state or a regular beat (the single numbers describe it),
                          False for an irregular one (period or amplitude varying by more than
                          PERIODIC_SPREAD from cycle to cycle: use statistics, not one number), None
                          when the window holds too few cycles to tell
    period_spread         std / mean of the cycle periods of Theta (per chain; NaN below 2 cycles)
    harmonics             amplitudes of harmonics 1 .. HARMONICS of Theta relative to the fundamental (element 0
                          is 1; per chain for the pair); NaN without a periodic beat (analysis.spectrum)
    notes                 what a user should know about these numbers (the CLI prints them as warnings)
    extra                 the scene's and the active terms' own observables (Scene.measure_extra, Term.measure), in
                          the order measured: the scene's, then each term's; their meaning is their spec
                          (elastoactive.core.observables: declared by the scene or term that measures them)

    A declared observable also reads as an attribute (results.rotation_rate, results.contact_fraction): its value in
    `extra`, None when this run did not measure it.
    """

    amplitude: PerChain
    frequency: PerChain | None
    periodic: bool | None = None
    period_spread: PerChain = math.nan
    notes: tuple[str, ...] = ()
    harmonics: tuple[float, ...] | tuple[tuple[float, ...], ...] = ()
    extra: Mapping[str, float] = field(default_factory=dict)

    def __getattr__(self, name: str):
        """A declared observable that is not a field: its value in `extra` (None when not measured)."""
        if name.startswith("_") or name == "extra" or not observables.known(name):
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        return self.extra.get(name)

    def as_dict(self) -> dict:
        """The observables that are set, as summary.json's `results` holds them (lists per chain): the beat's, the
        notes, then `extra` in its order."""
        out: dict = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "extra":
                out.update(value)
            elif f.name in ("frequency", "periodic") or value is not None:  # null says "could not be measured"
                out[f.name] = _listed(value)
        return out

    def value(self, name: str):
        """An observable by name (for code that loops over Scene.observables): a field, else its value in `extra`
        (None when not measured)."""
        if name in _FIELDS:
            return getattr(self, name)
        return self.extra.get(name)


_FIELDS = frozenset(f.name for f in fields(Results)) - {"extra"}


def _listed(value):
    """Tuples (per chain, harmonics; nested for the pair's harmonics) as lists."""
    return [_listed(v) for v in value] if isinstance(value, tuple) else value


def default_transient(duration: float) -> float:
    """Time discarded before measuring the steady state: half the run."""
    return 0.5 * duration


def measure(traj: Trajectory, transient: float | None = None) -> Results:
    """amplitude and frequency of Theta = theta_N - theta_1 (per chain for the pair), plus the
    scene's own observables (Scene.measure_extra: snap_amplitude, rotation_rate, ...). On one BLAS thread: its
    fits are small least-squares problems, where OpenBLAS's threads only spin (a third of a loaded run's CPU)."""
    with one_blas_thread():
        return _measure(traj, transient)


def _measure(traj: Trajectory, transient: float | None) -> Results:
    t = traj.t
    transient = default_transient(t[-1] - t[0]) if transient is None else transient
    physics = traj.physics
    scene = physics.scene_def
    thetas = scene.beat_signals(traj)  # Theta = theta_N - theta_1 per chain; a network scene's own signal
    rest = rest_level(traj, transient)
    words = _Words.of(physics)  # the notes name the scene's beat signal and units (a network's is not Theta)
    beats = [_beat(t, x, transient, max(rest, _solver_level(traj, t, x, transient)), words) for x in thetas]
    spectra = [tuple(float(a) for a in spectrum.harmonics(t, x, transient, HARMONICS)) for x in thetas]
    extra = scene.measure_extra(traj, transient)
    for term in physics.measured_terms():  # the terms' own observables (self-contact's clearance, a plug-in's)
        extra.update(term.measure(traj, transient))
    window = float(t[-1] - t[0] - transient)
    turns = _turning(traj, transient, extra.get(TURNING))
    reported = TURNING in extra
    beats = [_rigid(b, rate, window, reported) for b, rate in zip(beats, turns)]
    verdicts = [b.periodic for b in beats]
    periodic = False if False in verdicts else (None if None in verdicts else True)
    notes = []
    for k, b in enumerate(beats):
        where = f"chain {k + 1}: " if physics.n_chains > 1 else ""
        notes += [where + note for note in b.notes]
    notes += _aliasing(traj)
    notes += _pin_give(traj, beats)
    columns = ([b.amplitude for b in beats], [b.frequency for b in beats], [b.period_spread for b in beats])
    if physics.n_chains == 1:
        amplitude, frequency, spread = (c[0] for c in columns)
    else:
        amplitude, frequency, spread = (tuple(c) for c in columns)
    harmonics = spectra[0] if physics.n_chains == 1 else tuple(spectra)
    return Results(amplitude, frequency, periodic, spread, tuple(notes), harmonics, extra=extra)


def _aliasing(traj: Trajectory) -> list[str]:
    """A note when the record is sampled too coarsely for the fastest rate a term imposes (a drive's 2 pi f, the
    self-aligning units' turning sigma / l_a): rates and frequencies measured from it may be aliased, even in sign."""
    if traj.t.size < 2:
        return []
    spacing = float(traj.t[1] - traj.t[0])
    rate, term = fastest_term(traj.physics)
    if term is None or rate * spacing <= ALIASING:
        return []
    return [
        f"the record may alias the motion: the {term.name} term turns or drives at up to {rate:.3g} rad per unit "
        f"time, {rate * spacing:.2g} rad between samples (sample_dt = {spacing:g}); rates and frequencies may be "
        f"wrong, even in sign: rerun with {option('sample_dt')} <= {ALIASING / rate:.2g} (and {option('dt')}; the "
        "reduced engine records "
        f"no finer than the default dt){slower_advice(term, traj.physics, ALIASING / spacing)}"
    ]


def rest_level(traj: Trajectory, transient: float) -> float:
    """rad: the largest Theta amplitude of a chain at rest in this run: STEADY_AMPLITUDE, or the solver's error in its
    angles (SOLVER_JITTER x the reduced engine's rtol x the largest angle of the measured window) where larger."""
    rtol = traj.info.get("rtol") if isinstance(traj.info, Mapping) else None
    if not isinstance(rtol, (int, float)) or not rtol > 0 or traj.theta.size == 0:
        return STEADY_AMPLITUDE
    steady = traj.theta[traj.t - traj.t[0] >= transient - 1e-12 * max(1.0, transient)]
    scale = float(np.max(np.abs(steady))) if steady.size and np.all(np.isfinite(steady)) else 0.0
    return max(STEADY_AMPLITUDE, SOLVER_JITTER * float(rtol) * scale)


def _solver_level(traj: Trajectory, t: np.ndarray, x: np.ndarray, transient: float) -> float:
    """The rest level of a signal that is not built from the recorded angles (a network's): its own magnitude times
    the solver's tolerance (as rest_level)."""
    rtol = traj.info.get("rtol") if isinstance(traj.info, Mapping) else None
    if traj.theta.size or not isinstance(rtol, (int, float)) or not rtol > 0:
        return STEADY_AMPLITUDE
    _, xs = obs.steady_part(t, x, transient=transient)
    return SOLVER_JITTER * float(rtol) * float(np.max(np.abs(xs))) if np.all(np.isfinite(xs)) else STEADY_AMPLITUDE


def _turning(traj: Trajectory, transient: float, reported: float | None) -> list[float | None]:
    """Each chain's mean turning rate (rad/tau) over the measured window: the scene's reported rotation_rate, else the
    slope of the chain's first angle (a chain turned by a rotating clamp); None for a network (no chains' angles)."""
    chains = traj.physics.n_chains
    if traj.theta.shape[1] < traj.physics.n * chains or traj.theta.shape[1] == 0:
        return [reported] * chains
    rates = []
    for k in range(chains):
        try:
            rates.append(
                obs.rotation_rate(traj.t, traj.chain(k), transient) if reported is None or chains > 1 else reported
            )
        except ValueError:
            rates.append(reported)
    return rates


def _pin_give(traj: Trajectory, beats: list) -> list[str]:
    """A note for a beat of a chain held at both ends (not closed on itself) small enough to come from its pin's give
    (PIN_GIVE): a chain held at its full length can bend only as far as the pin lets its ends approach (a chain whose
    pins leave it slack bends by its slack, so no note)."""
    violation = traj.info.get("constraint_violation") if isinstance(traj.info, Mapping) else None
    if not isinstance(violation, (int, float)) or not violation > 0 or not math.isfinite(violation):
        return []
    system = traj.physics.scene_def.reduced_system(traj.physics)
    give = math.sqrt(2.0 * violation)
    slack = traj.physics.n * float(system.delta)  # l: how much nearer than its length the pins hold the ends
    if not system.pinned or system.closed or math.sqrt(2.0 * slack) >= PIN_GIVE * give:
        return []
    small = [k for k, b in enumerate(beats) if b.frequency and b.amplitude < PIN_GIVE * give]
    if not small:
        return []
    where = "" if traj.physics.n_chains == 1 else f"chain {', '.join(str(k + 1) for k in small)}: "
    amplitude = quantities.text(
        tuple(beats[k].amplitude for k in small) if where else beats[small[0]].amplitude, ".2g", "rad"
    )
    return [
        f"{where}the beat (amplitude {amplitude}) is within what the pin's give allows: the pin gave by up to "
        f"{violation:.2g} l, which lets a chain held at its full length bend by ~{give:.2g} rad; it may be the "
        f"{traj.engine} engine's soft pin, not the chain's beat: compare {option('engine', 'reduced')} (hard pins) or "
        f"a smaller {option('dt')}"
    ]


@dataclass(frozen=True)
class _Beat:
    amplitude: float
    frequency: float | None
    periodic: bool | None
    period_spread: float
    notes: tuple[str, ...]


@dataclass(frozen=True)
class _Words:
    """How the beat's notes name the signal, its units and the time unit (the scene's: units.beat_signal)."""

    signal: str = "Theta"
    units: str = "rad"
    time: str = "tau"

    @classmethod
    def of(cls, physics: Physics) -> _Words:
        units, signal = scene_units(physics.scene_def), beat_signal(physics)
        return cls(signal.symbol, units.of(signal.units), units.time_units)


def _beat(
    t: np.ndarray, theta_diff: np.ndarray, transient: float, rest: float = STEADY_AMPLITUDE, words: _Words = _Words()
) -> _Beat:
    """Amplitude, frequency and regularity of one chain's Theta (a scene's beat signal, named by `words` in the notes)
    over the measured window (at rest below `rest`)."""
    theta, rad, tau = words.signal, words.units, words.time
    amplitude = obs.amplitude(t, theta_diff, transient)
    if amplitude <= rest:
        return _Beat(amplitude, 0.0, True, math.nan, ())
    if amplitude <= SMALL_AMPLITUDE:
        return _Beat(amplitude, obs.frequency(t, theta_diff, transient), True, math.nan, ())
    cycles = obs.cycles(t, theta_diff, transient)
    window = f"the measured window ({t[-1] - transient:.4g} {tau} after a transient of {transient:.4g} {tau})"
    _, xs = obs.steady_part(t, theta_diff, transient=transient)
    third = max(xs.size // 3, 1)
    drift = abs(xs[-third:].mean() - xs[:third].mean())
    if cycles.count < MIN_CYCLES and drift > WINDING:  # no beat's thirds drift a full turn apart
        return _Beat(
            amplitude,
            None,
            False,
            math.nan,
            (
                f"the motion is not periodic: {theta} drifts by {drift:.3g} {rad} over {window} (it winds up or "
                "creeps) with fewer than two cycles about its mean; amplitude is half the range covered",
            ),
        )
    if cycles.count < MIN_CYCLES and drift > amplitude:  # less than two periods of a beat drift this much too
        return _Beat(
            amplitude,
            None,
            None,
            math.nan,
            (
                f"periodicity and frequency not judged: {theta} moves by {drift:.3g} {rad} one way over {window}, with "
                "fewer than two cycles about its mean: a beat slower than the window, or a motion that creeps; run "
                f"longer ({option('duration')}) or discard less ({option('transient')})",
            ),
        )
    if cycles.count < 1:
        return _Beat(
            amplitude,
            None,
            None,
            math.nan,
            (
                f"frequency not measured: {window} holds fewer than two periods of {theta}; run longer "
                f"({option('duration')}) or discard less ({option('transient')})",
            ),
        )
    frequency = obs.frequency(t, theta_diff, transient)
    if cycles.count < MIN_CYCLES:
        return _Beat(
            amplitude,
            frequency,
            None,
            cycles.period_spread,
            (
                f"periodicity not judged: {window} holds {cycles.count} whole cycle(s), fewer than {MIN_CYCLES}; "
                f"run longer ({option('duration')})",
            ),
        )
    spread = max(cycles.period_spread, cycles.amplitude_spread)
    if spread > PERIODIC_SPREAD:
        return _Beat(
            amplitude,
            frequency,
            False,
            cycles.period_spread,
            (
                f"the beat is not periodic: its cycle periods vary by {cycles.period_spread:.2g} and its cycle "
                f"amplitudes by {cycles.amplitude_spread:.2g} (std / mean, over {cycles.count} cycles; periodic: "
                f"<= {PERIODIC_SPREAD:g}); amplitude and frequency are averages over an irregular motion (noise, "
                "chaos, or a beat still growing: run longer)",
            ),
        )
    return _Beat(amplitude, frequency, True, cycles.period_spread, ())


def _rigid(beat: _Beat, rotation_rate: float | None, window: float, reported: bool = True) -> _Beat:
    """A chain that turns (by RIGID_TURN or more over the window) with a Theta at rest, or oscillating by less than
    RIGID_FRACTION of the angle it turns through per period of that oscillation, turns rigidly: no beat, so the
    frequency is null (not 0.0, which would say the chain is at rest) and a note says why."""
    if rotation_rate is None or not math.isfinite(rotation_rate) or not abs(rotation_rate) * window >= RIGID_TURN:
        return beat
    rate = abs(rotation_rate)
    if beat.frequency == 0.0:
        residue = ""
    else:
        per_period = rate / beat.frequency if beat.frequency else rate * window
        if not beat.amplitude < RIGID_FRACTION * per_period:
            return beat
        wiggle = "" if beat.frequency is None else f" at f = {beat.frequency:.3g}"
        residue = (
            f"; its residual wiggle{wiggle} is below {RIGID_FRACTION:g} of the {per_period:.3g} rad the chain "
            "turns through per wiggle (solver error or a transient decaying onto the rigid turn)"
        )
    return _Beat(
        beat.amplitude,
        None,
        True,
        math.nan,
        (
            f"no beat: Theta is {'steady' if not residue else 'all but steady'} (amplitude "
            f"{quantities.text(beat.amplitude, '.2g', 'rad')}) while the chain turns "
            f"as a rigid body at {rotation_rate:.3g} rad/tau{residue}; frequency is null"
            + (", rotation_rate describes the motion" if reported else ""),
        ),
    )


def check_transient(duration: float, transient: float | None, times: np.ndarray | None = None) -> float:
    """The transient a run will discard: default half the run; refused unless 0 <= transient < duration and, given
    the run's sample times (from its start), unless at least MIN_SAMPLES samples remain after it to be measured."""
    if transient is None:
        transient = default_transient(duration)
    elif not (math.isfinite(transient) and 0 <= transient < duration):
        raise ParameterError(
            f"transient ({transient} tau) must lie in [0, duration = {duration:g} tau): the results are "
            "measured on the part of the run after it"
        )
    if times is not None:
        kept = int(np.count_nonzero(times >= transient - 1e-12 * max(1.0, transient)))  # as observables' steady part
        if kept < MIN_SAMPLES:
            latest = times[-MIN_SAMPLES] if times.size >= MIN_SAMPLES else 0.0
            raise ParameterError(
                f"transient ({transient:g} tau) leaves {kept} recorded sample(s) of the {duration:g} tau run; at least "
                f"{MIN_SAMPLES} are needed to measure it: use {option('transient')} <= {latest:.4g} or a longer "
                f"{option('duration')}"
            )
    return float(transient)


def check_measurable(physics: Physics) -> None:
    """Refuse, before simulating, a chain too short for one of its scene's observables (Observable.min_n)."""
    for name in physics.scene_def.observable_names():
        spec = observables.find(name)
        need = spec.min_n if spec is not None else 1
        if physics.n < need:
            raise ParameterError(
                f"n = {physics.n} is too short for scene {physics.scene}: it measures {name}, which needs "
                f"N >= {need} particles; use {option('n', need)} or more"
            )

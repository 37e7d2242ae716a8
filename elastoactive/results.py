"""Turn a trajectory into the numbers a run reports, and write a run's files."""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import math
import warnings
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from . import plugins, quantities
from .analysis import observables as obs
from .analysis import spectrum
from .core import observables
from .core.errors import ParameterError
from .core.observables import HARMONICS
from .core.params import MIN_SAMPLES, Numerics, Physics, option
from .core.trajectory import Trajectory
from .core.units import beat_signal, scene_units
from .io.jsonio import from_jsonable, to_jsonable
from .io.outputs import InputFile, sha256, write_files, write_text
from .networks.files import SUFFIX as NETWORK_SUFFIX
from .sensitivity import estimate as estimate_sensitivity
from .sensitivity import needs_estimate
from .terms.base import ALIASING, fastest_term, slower_advice
from .wording import summary_units

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
    scene's own observables (Scene.measure_extra: snap_amplitude, rotation_rate, ...)."""
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


ENGINE_NUMERICS = {
    "mujoco": ("dt", "mass_ratio", "integrator", "perturbation", "sample_dt", "seed"),
    # the reduced model: its mass ratio decides overdamped or inertial (engines.reduced.regime); dt only with noise
    "reduced": ("sample_dt", "perturbation", "seed", "mass_ratio"),
}
"""The numerical settings each engine uses, which its summary.json records (all a re-run needs)."""


def recorded_numerics(engine: str, physics: Physics) -> tuple[str, ...]:
    """The Numerics fields a run of `physics` with `engine` uses: what summary.json records and `run --from` needs."""
    names = ENGINE_NUMERICS[engine]
    return names + ("dt",) if engine == "reduced" and physics.noise > 0 else names


def summary(
    traj: Trajectory,
    numerics: Numerics,
    duration: float,
    transient: float | None = None,
    provenance: dict | None = None,
    sensitivity: bool = True,
) -> dict:
    """Everything summary.json holds: parameters, numerical settings, wall time, results, their units (the scene's:
    wording.summary_units), solver information and (when given) the provenance record of elastoactive.io.outputs.
    An irregular run's results also carry `sensitivity` (elastoactive.sensitivity: errors of its numbers, whether its
    dynamics is sensitive) unless sensitivity=False. Measuring runs here: what it raises propagates (the record of a run
    whose measuring failed is `unmeasured_summary`)."""
    transient = check_transient(duration, transient)
    numerics, out = _record(traj, numerics, duration, transient, provenance)
    results = measure(traj, transient)
    recorded = results.as_dict()
    if sensitivity and needs_estimate(traj, results.periodic):  # an irregular run: its numbers with their errors
        try:
            estimate = estimate_sensitivity(traj, transient, numerics)
        except ParameterError as refusal:  # the pilots run the reduced engine, which may not cover this run's terms
            recorded["notes"] = [
                *recorded["notes"],
                f"irregular, and no error estimate: its pilots run the reduced "
                f"engine, which refuses this run ({refusal}); rerun at dt / 2 to gauge its error",
            ]
        else:
            recorded["sensitivity"] = estimate.as_dict()
            recorded["notes"] = [*recorded["notes"], estimate.note(results.amplitude, results.frequency)]
    out["results"] = recorded
    out["units"] = summary_units(traj.physics, recorded)
    return _ordered(out)


MEASURING = "not measured: the run stopped while its trajectory was being measured"
"""The measure_error of the summary written with a run's trajectory, before it is measured (`unmeasured_summary`):
what a folder holds when the process is killed while measuring."""


def unmeasured_summary(
    traj: Trajectory,
    numerics: Numerics,
    duration: float,
    transient: float | None = None,
    provenance: dict | None = None,
    error: str = MEASURING,
) -> dict:
    """summary.json of a run that has not been measured, or whose measuring failed: the settings and solver
    information as `summary` records them (the same settings digest), `results` null and `measure_error`, one line."""
    transient = check_transient(duration, transient)
    _, out = _record(traj, numerics, duration, transient, provenance)
    out["results"] = None
    out["measure_error"] = " ".join(str(error).split())
    out["units"] = summary_units(traj.physics, {})
    return _ordered(out)


def error_line(err: BaseException) -> str:
    """An exception as one line: its type and message, whitespace collapsed."""
    return " ".join(f"{type(err).__name__}: {err}".split())


_ORDER = ("engine", "parameters", "numerics", "wall_time_s", "results", "measure_error", "units", "solver")


def _ordered(out: dict) -> dict:
    return {**{k: out[k] for k in _ORDER if k in out}, **{k: v for k, v in out.items() if k not in _ORDER}}


def _record(
    traj: Trajectory, numerics: Numerics, duration: float, transient: float, provenance: dict | None
) -> tuple[Numerics, dict]:
    """The numerics as the run used them, and the summary's settings and solver information (no results)."""
    if traj.engine == "mujoco":  # what ran: a long chain's or a network's automatic numerics, so --from repeats it
        numerics = numerics.for_physics(traj.physics)
        ran = traj.info.get("automatic_numerics") or {}  # the engine's record (a network's: engines.network_mujoco)
        numerics = dataclasses.replace(
            numerics, **{k: v for k, v in ran.items() if k in ("integrator", "dt", "mass_ratio")}
        )
    settings = dataclasses.asdict(numerics)
    if traj.engine in ENGINE_NUMERICS:
        settings = {k: settings[k] for k in recorded_numerics(traj.engine, traj.physics)}
    out = {
        "engine": traj.engine,
        "parameters": traj.physics.relevant(),
        "numerics": {**settings, "duration": duration, "transient": transient},
        "wall_time_s": traj.wall_time_s,
        "solver": traj.info,
    }
    if provenance is not None:
        out["provenance"] = provenance
    return numerics, out


def jsonable(value):
    """summary.json's JSON form of `value` (jsonio.to_jsonable): numpy scalars as Python numbers, non-finite
    floats as null."""
    return to_jsonable(value, nonfinite="null")


SETTINGS = ("engine", "parameters", "numerics")
"""What defines a run in its summary.json: covered by settings_sha256, recorded in the summary and in the
trajectory file, so that an edited summary (another sigma on the same trajectory) is refused rather than used."""
INPUTS = "inputs"
"""The summary's record of the files and plug-ins a run read (RunInputs); covered by settings_sha256 when present."""


def settings_digest(summary_dict: Mapping) -> str:
    """SHA-256 of a summary's SETTINGS, and its INPUTS where it has them, as canonical JSON (the same before writing
    and after reading back)."""
    settings = {k: summary_dict.get(k) for k in SETTINGS}
    if summary_dict.get(INPUTS) is not None:
        settings[INPUTS] = summary_dict[INPUTS]
    return hashlib.sha256(json.dumps(jsonable(settings), sort_keys=True, separators=(",", ":")).encode()).hexdigest()


NETWORK_COPY = "network.json"
"""The run folder's copy of the network file a network run read (its `geometry`)."""
START_COPY = "start.npz"
"""The run folder's copy of the state a run started from (--start-from)."""
STATE_ARRAYS = ("theta", "positions", "polarity")
"""The arrays of a start state (elastoactive.starts.Start), in the order state_digest reads them."""


def state_digest(arrays: Mapping[str, np.ndarray | None]) -> str:
    """SHA-256 of a start state: each of STATE_ARRAYS that is given, by name, shape and float64 bytes."""
    digest = hashlib.sha256()
    for name in STATE_ARRAYS:
        value = arrays.get(name)
        if value is not None:
            value = np.ascontiguousarray(value, dtype=np.float64)
            digest.update(f"{name}{value.shape}".encode())
            digest.update(value.tobytes())
    return digest.hexdigest()


@dataclass(frozen=True)
class StartInput:
    """The state a run started from: `path`, the start run's folder (absolute), `state_sha256` (state_digest) and
    `copy`, the run folder's file holding that state (START_COPY)."""

    path: str
    state_sha256: str
    copy: str = START_COPY


@dataclass(frozen=True)
class RunInputs:
    """What a run read besides its settings, as summary.json's `inputs` records it: the network file
    (`network_file`), the plug-in files (`plugin_files`, elastoactive.plugins), the entry points of installed
    distributions that provided its scene or terms (`entry_points`), the state it started from (`start`). `copies`
    maps a file name in the run's folder to the bytes written there (the network file's and plug-in files' bytes as
    read, the start state); not recorded."""

    network_file: InputFile | None = None
    plugin_files: tuple[InputFile, ...] = ()
    entry_points: tuple[plugins.EntryPointSource, ...] = ()
    start: StartInput | None = None
    copies: Mapping[str, bytes] = field(default_factory=dict, compare=False, repr=False)

    def as_dict(self) -> dict:
        """summary.json's `inputs` (the empty ones left out)."""
        out = {
            "network_file": self.network_file,
            "plugin_files": list(self.plugin_files),
            "entry_points": list(self.entry_points),
            "start": self.start,
        }
        return to_jsonable({k: v for k, v in out.items() if v})

    @classmethod
    def of(cls, record: Mapping, where: str = "summary.json") -> RunInputs:
        """The inputs a summary records (none for a record without them); malformed ones are refused naming
        `where`."""
        inputs = record.get(INPUTS)
        if inputs is None:
            return cls()
        try:
            network = inputs.get("network_file")
            start = inputs.get("start")
            return cls(
                network_file=None if network is None else from_jsonable(InputFile, network),
                plugin_files=tuple(plugins.plugin_files(record).values()),
                entry_points=tuple(plugins.entry_points(record)),
                start=None if start is None else from_jsonable(StartInput, start),
            )
        except (TypeError, KeyError, ValueError, AttributeError):
            raise ParameterError(f"{where}: its inputs record is not one elastoactive run writes") from None


def network_file(physics: Physics) -> Path | None:
    """The network file a run of `physics` reads (its `geometry`, when that names a file), else None."""
    geometry = physics.relevant().get("geometry")
    if isinstance(geometry, str) and geometry.endswith(NETWORK_SUFFIX):
        return Path(geometry).expanduser()
    return None


def resolved_inputs(physics: Physics) -> Physics:
    """`physics` with its network file's path absolute and resolved, so a record names it from any folder."""
    path = network_file(physics)
    if path is None or str(path.resolve()) == physics.geometry:
        return physics
    return physics.replace(geometry=str(path.resolve()))


def run_inputs(
    physics: Physics, start_state: Mapping[str, np.ndarray | None] | None = None, start_path=None
) -> RunInputs:
    """The inputs of a run of `physics` (RunInputs), read now: its network file's bytes, the bytes its plug-in files
    ran from (elastoactive.plugins.loaded_file), the entry points that provided its scene and terms, and the state it
    starts from (`start_state`: a Start's arrays, from the run at `start_path`)."""
    copies: dict[str, bytes] = {}
    network = None
    path = network_file(physics)
    if path is not None:
        try:
            network, copies[NETWORK_COPY] = InputFile.of(path, NETWORK_COPY)
        except OSError as err:
            raise ParameterError(f"geometry: the network file {path} cannot be read ({err.strerror or err})") from None
    files = []
    for spec in plugins.needed(physics):
        loaded = plugins.loaded_file(spec)
        if loaded is None:
            continue
        digest, data = loaded
        name = _copy_name(f"plugin-{Path(spec).stem}", ".py", copies)
        copies[name] = data
        files.append(InputFile(spec, digest, name))
    start = None
    if start_state is not None:
        buffer = io.BytesIO()
        np.savez(buffer, **{k: np.asarray(v, dtype=np.float64) for k, v in start_state.items() if v is not None})
        copies[START_COPY] = buffer.getvalue()
        where = str(Path(start_path).expanduser().resolve()) if start_path is not None else "given"
        start = StartInput(where, state_digest(start_state))
    return RunInputs(network, tuple(files), tuple(plugins.entry_point_sources(physics)), start, copies)


def _copy_name(stem: str, suffix: str, taken: Mapping[str, bytes]) -> str:
    name, k = stem + suffix, 1
    while name in taken:
        k += 1
        name = f"{stem}-{k}{suffix}"
    return name


COMPRESS_BYTES = 64 * 2**20
"""A trajectory of up to this many bytes of arrays is written compressed; a larger one as it is: sampled floats
compress by a tenth at most, and deflating the 330 MB of a 10 000-node network's run took 12 s of its whole
process (np.load reads either kind)."""


def file_variables(traj: Trajectory) -> dict[str, np.ndarray]:
    """The arrays a run's trajectory.npz holds for its scene's `file_variables` (Scene.file_variables): each named
    variable of Scene.state_variables under its name, its dimensions joined by spaces under NAME_dims and each of its
    attributes as a string under NAME_<attribute> (NAME_units, NAME_long_name), as the netCDF of
    Trajectory.to_xarray has them. The 3D chain's: position (T, 1, N, 3), position_dims "time chain particle xyz",
    position_units "l". Empty for a scene that names none (the planar and network scenes: their files are unchanged)."""
    scene = traj.physics.scene_def
    if not scene.file_variables:
        return {}
    _, variables = scene.state_variables(traj)
    arrays = {}
    for name in scene.file_variables:
        dims, values, attrs = variables[name]
        arrays[name] = np.asarray(values, dtype=float)
        arrays[f"{name}_dims"] = np.array(" ".join(dims))
        arrays.update({f"{name}_{key}": np.array(str(value)) for key, value in attrs.items()})
    return arrays


class RunWriteError(OSError):
    """A run's trajectory.npz could not be written (write_run); `summary` is the summary.json written without it, or
    None when none was (the folder keeps the run it held)."""

    def __init__(self, errno: int | None, strerror: str, filename: str, summary: Path | None):
        super().__init__(errno, strerror, filename)
        self.summary = summary


def write_run(out: Path, traj: Trajectory, summary_dict: dict, copies: Mapping[str, bytes] | None = None) -> list[Path]:
    """summary.json and trajectory.npz (t in tau, theta: one column per particle; head (T, 2) for a scene whose
    pivot moves; the scene's file variables, e.g. the 3D chain's positions: file_variables; compressed up to
    COMPRESS_BYTES), and the run's copies of its inputs (`copies`: file name -> bytes, RunInputs.copies), written
    together: each into a temporary file first, the trajectory and the copies renamed into place before the summary
    that records their SHA-256, so a summary never describes another trajectory unnoticed. Both record the digest of
    the run's settings (settings_digest), so neither can be edited into describing another run unnoticed.
    A trajectory that cannot be written (a full disk, the file-size limit) does not take the summary with it: into a
    folder holding no earlier run the summary is written alone, with trajectory_sha256 null and trajectory_error; an
    earlier run's files are kept whole. Either way a RunWriteError naming trajectory.npz is raised after."""
    checksum = {}
    digest = settings_digest(summary_dict)

    def trajectory(tmp: Path) -> None:
        head = {} if traj.head is None else {"head": traj.head}
        if traj.polarity is not None:
            head["polarity"] = traj.polarity
        if traj.nodes is not None:
            head["nodes"] = traj.nodes
        arrays = {"t": traj.t, "theta": traj.theta, **head, **file_variables(traj)}
        save = np.savez_compressed if sum(a.nbytes for a in arrays.values()) <= COMPRESS_BYTES else np.savez
        save(tmp, scene=traj.physics.scene, n=traj.physics.n, settings_sha256=digest, **arrays)
        checksum["sha256"] = sha256(tmp)

    def summary_file(tmp: Path) -> None:
        tmp.write_text(_summary_text(summary_dict, digest, checksum.get("sha256"), checksum.get("error")))

    def copy(data: bytes):
        return lambda tmp: tmp.write_bytes(data)

    out = Path(out)
    earlier = [name for name in ("summary.json", "trajectory.npz") if (out / name).exists()]
    writers = {"trajectory.npz": trajectory, **{name: copy(data) for name, data in (copies or {}).items()}}
    try:
        return write_files(out, {**writers, "summary.json": summary_file})
    except OSError as err:
        if err.filename != str(out / "trajectory.npz"):
            raise
        if earlier:  # an earlier run's files: kept whole, not half replaced
            raise RunWriteError(
                err.errno, f"{err.strerror}; nothing was replaced: {out} keeps the run it held", err.filename, None
            ) from None
        failed = err
    # the trajectory (the large file) could not be written: the summary (small: the results, the settings) still is,
    # recording the failure and no trajectory checksum
    checksum.pop("sha256", None)
    checksum["error"] = f"not written: {failed.strerror}"
    try:
        written = write_files(out, {"summary.json": summary_file})
    except OSError:
        raise failed from None
    raise RunWriteError(
        failed.errno,
        f"{failed.strerror}; {written[0]} was written without it (the run's results and "
        "settings; re-run it with --from to have the trajectory)",
        failed.filename,
        written[0],
    ) from None


def _summary_text(summary_dict: Mapping, digest: str, trajectory_sha256: str | None, error: str | None) -> str:
    record = {**summary_dict, "settings_sha256": digest, "trajectory_sha256": trajectory_sha256}
    if error is not None:
        record["trajectory_error"] = error
    return json.dumps(jsonable(record), indent=2) + "\n"


def rewrite_summary(out: Path, summary_dict: dict) -> Path:
    """Replace, atomically, the summary.json that write_run wrote into `out` for this run by `summary_dict` (the same
    run: the same settings digest, e.g. its record once measured), keeping what that one recorded of the trajectory
    file (its checksum, or why it was not written). Refuses (ValueError) a summary.json of other settings."""
    path = Path(out) / "summary.json"
    current = json.loads(path.read_text())
    digest = settings_digest(summary_dict)
    if current.get("settings_sha256") != digest:
        raise ValueError(f"{path} holds another run's summary; not replaced")
    return write_text(
        path, _summary_text(summary_dict, digest, current.get("trajectory_sha256"), current.get("trajectory_error"))
    )


def _edited(path: Path) -> ParameterError:
    return ParameterError(
        f"{path} was changed after the run wrote it (its engine, parameters or numerics no longer "
        "match the checksum recorded with them); restore it, or re-run the simulation"
    )


def read_summary(path: Path) -> dict:
    """A run's summary.json (a folder written by `run --out`, or the file itself), refused (ParameterError) unless
    it holds settings_sha256 and that digest matches its settings (settings_digest): an edited summary, its digest
    removed or not, never reads as a run's record."""
    path = Path(path)
    if path.is_dir():
        path = path / "summary.json"
    try:
        summary_dict = json.loads(path.read_text())
    except FileNotFoundError:
        raise ParameterError(
            f"{path} not found: give a folder written by `elastoactive run --out` or its summary.json"
        ) from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise ParameterError(f"{path} is not a readable summary.json ({err})") from None
    if not isinstance(summary_dict, dict) or not isinstance(summary_dict.get("parameters"), dict):
        raise ParameterError(f"{path} is not a summary.json written by elastoactive run (no parameters)")
    recorded = summary_dict.get("settings_sha256")
    if recorded is None:  # without its checksum a summary's settings cannot be told from an edit of them
        raise ParameterError(
            f"{path} has no settings_sha256 (the checksum `elastoactive run` records with its engine, "
            "parameters and numerics), so it may have been changed after the run wrote it; restore "
            "it, or re-run the simulation"
        )
    if recorded != settings_digest(summary_dict):
        raise _edited(path)
    return summary_dict


class RecordWarning(UserWarning):
    """An input of a run's record (its network file, a plug-in file, the distribution of a plug-in) changed since the
    run; the message, one line, says what is read instead."""


def recorded_physics(summary_dict: Mapping, folder: Path, what: str) -> tuple[Physics, list[str]]:
    """The Physics a run's summary describes, reading what the run read, and one note per input that changed since:
    the distributions its entry-point scene and terms came from must provide them here (elastoactive.plugins.
    check_entry_points; refused otherwise, one line starting with `what`); its network file is the original while
    that holds the bytes the run read, else the copy in the run's `folder` (a note says so), and neither is refused;
    plug-in files that changed are noted (elastoactive.plugins.recorded loads the run's copy)."""
    notes = plugins.check_entry_points(dict(summary_dict), what)
    inputs = RunInputs.of(summary_dict, f"{what}: summary.json")
    parameters = dict(summary_dict["parameters"])
    if inputs.network_file is not None:
        found, note = inputs.network_file.locate(folder, "network file")
        if found is None:
            raise ParameterError(f"{what}: {note}; restore the network file it ran")
        if note is not None:
            notes.append(note)
            parameters["geometry"] = str(found)
    notes += plugins.file_notes(folder, dict(summary_dict))
    return Physics(**parameters), notes


def load_trajectory(path: Path, physics: Physics | None = None) -> Trajectory:
    """Read a trajectory.npz written by write_run (the physics from summary.json beside it: recorded_physics, whose
    notes are issued as RecordWarning); see read_run."""
    traj, notes = read_run(path, physics)
    for note in notes:
        warnings.warn(note, RecordWarning, stacklevel=2)
    return traj


def read_run(path: Path, physics: Physics | None = None, what: str | None = None) -> tuple[Trajectory, list[str]]:
    """A trajectory.npz written by write_run (the physics from summary.json beside it: recorded_physics, whose refusals
    start with `what`, default the path) and the notes on its inputs. Its records are read (t, theta, head, polarity,
    nodes); the scene's file variables (the 3D chain's positions) are not: they are what Trajectory.positions computes
    again from the angles, the same numbers.

    Refuses, naming the file, a truncated or foreign file, missing or misshapen arrays, non-finite
    angles, and a trajectory that is not the one its summary.json describes (checksum)."""
    path = Path(path)
    if path.is_dir():
        path = path / "trajectory.npz"
    summary_file = path.with_name("summary.json")
    recorded = read_summary(summary_file) if summary_file.exists() else None
    notes: list[str] = []
    if physics is None:
        if recorded is None:
            raise ParameterError(f"{summary_file} not found: the physics of {path} is unknown")
        physics, notes = recorded_physics(recorded, path.parent, what or str(path.parent))
    try:
        with np.load(path) as f:
            t, theta = np.asarray(f["t"], dtype=float), np.asarray(f["theta"], dtype=float)
            moving = physics.scene_def.head_count(physics) or "head" in f.files  # a moving pivot, or a moving clamp
            head = np.asarray(f["head"], dtype=float) if moving else None
            digest = str(f["settings_sha256"]) if "settings_sha256" in f.files else None
            polarity = np.asarray(f["polarity"], dtype=float) if "polarity" in f.files else None
            nodes = np.asarray(f["nodes"], dtype=float) if "nodes" in f.files else None
    except FileNotFoundError:
        raise ParameterError(f"{path} not found") from None
    except KeyError as err:
        raise ParameterError(
            f"{path} lacks the array {err} (expected t and theta, and head for a moving pivot)"
        ) from None
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as err:
        raise ParameterError(f"{path} is not a readable trajectory.npz (truncated or foreign file: {err})") from None
    if t.ndim != 1 or t.size < 2 or theta.shape != (t.size, physics.n_angles):
        raise ParameterError(
            f"{path}: expected t of shape (T,) with T >= 2 and theta of shape (T, {physics.n_angles}) "
            f"for {physics.scene_def.label(physics)}; got {t.shape} and {theta.shape}"
        )
    if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)):
        raise ParameterError(f"{path}: the sample times t are not finite and increasing")
    columns = physics.scene_def.head_count(physics) or 2  # the scene's moving pivot, or a moving clamp's (x_c, y_c)
    if head is not None and head.shape != (t.size, columns):
        raise ParameterError(f"{path}: expected head of shape ({t.size}, {columns}), got {head.shape}")
    if polarity is not None and (polarity.ndim != 2 or polarity.shape[0] != t.size):
        raise ParameterError(f"{path}: expected polarity of shape ({t.size}, units), got {polarity.shape}")
    if nodes is not None and (nodes.ndim != 3 or nodes.shape[0] != t.size or nodes.shape[2] != 2):
        raise ParameterError(f"{path}: expected nodes of shape ({t.size}, nodes, 2), got {nodes.shape}")
    state = theta if head is None else np.hstack([theta, head])
    if nodes is not None:
        state = np.hstack([state, nodes.reshape(t.size, -1)])
    if not np.all(np.isfinite(state)):
        bad = t[~np.all(np.isfinite(state), axis=1)][0]
        raise ParameterError(f"{path}: the angles are not finite from t = {bad:g} tau on (a diverged run?)")
    if recorded is not None and recorded.get("trajectory_sha256") not in (None, sha256(path)):
        raise ParameterError(
            f"{path} is not the trajectory {summary_file.name} describes (checksum differs: an "
            "interrupted or mixed write); re-run the simulation"
        )
    if recorded is not None and digest is not None and digest != settings_digest(recorded):
        raise _edited(summary_file)
    traj = Trajectory(
        t=t,
        theta=theta,
        physics=physics,
        engine=(recorded or {}).get("engine", "file"),
        head=head,
        polarity=polarity,
        nodes=nodes,
    )
    return traj, notes

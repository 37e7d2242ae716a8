"""Sensitive (chaotic) dynamics flagged at run time, with the error of the numbers measured in it.

Where a chain sits on locally unstable dynamics (sigma >= 10 on long chains, sigma = 100 at N = 7:
docs/performance.md), the timestep's and the mass ratio's errors grow like e^(Lambda t): MuJoCo and the reduced
model part after a predictability horizon and single numbers can be 10-30% apart. Such a run is irregular, so the
check costs nothing for a regular one: only a run whose beat is judged irregular (and has no noise, which makes
it irregular by design) gets the estimate.

The estimate: the standard errors of amplitude and frequency from the run's own cycle-to-cycle spread (free), and
two short reduced-model pilots from the run's state at the end of its transient, integrated at two tolerances (the
analogue of dt and dt/2: they differ by the solver's error, ~1e-7 rad), whose separation gives the finite-time
Lyapunov exponent Lambda (`separation_rate`). Above SENSITIVE_RATE the run is sensitive: pointwise angles are
reproducible only up to a horizon. The pilots run only from a state on the motion's attractor (`unsettled`: the window
holds whole cycles of a beat that no longer grows or decays); before it, the state may still be leaving an unstable
base state, whose linear growth is not chaos, and the run is "too short to measure". summary.json's results carry
`sensitivity` and a note gives the numbers with their errors.

engines.reduced is imported inside `estimate`, the reduced engine's boundary: only an irregular run's pilots load it
(its compiled kernels), not every measurement.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from . import quantities
from .analysis import observables as obs
from .core.params import Numerics, replace
from .core.trajectory import Trajectory
from .reduced.settings import METHODS

SENSITIVE_RATE = 0.5
"""1/tau: a finite-time Lyapunov exponent above this makes a run sensitive (docs/performance.md: the sensitive
cells sit at +1.2 to +7.4/tau, the paper's limit cycles at -0.04 to -0.4/tau)."""
PILOT_TAU = 10.0
"""Length of each pilot, tau (at most the measured window): ln(0.1 / 1e-9) / SENSITIVE_RATE ~ 37 tau would be
needed to saturate at the threshold itself, but the separation's slope shows well before."""
PILOT_TOLERANCES = ((1e-9, 1e-11), (1e-7, 1e-9))
"""(rtol, atol) of the two pilots: their solver errors seed the separation whose growth is measured."""
SATURATION = 0.1
"""rad: a separation this large has left the linear regime; its growth is measured before it."""
HORIZON_ERROR = 0.1
"""rad: the horizon is the time an error of 1e-6 rad (a MuJoCo run's error over a tau) takes to grow to this."""
SETTLED_CYCLES = 2
"""Whole cycles of the beat the measured window must hold for the pilots to start on the motion's attractor: before
them the state may still be leaving an unstable base state, whose linear growth the pilots would read as chaos."""
SETTLING = 0.01
"""Relative change of the cycle amplitudes, steady in one direction over at least three cycles, that marks a beat still
growing or decaying towards its attractor (the periodicity verdict's PERIODIC_SPREAD)."""


Errors = float | None | tuple[float | None, ...]
"""A standard error, None without one, or one per chain (elastoactive.quantities)."""


class Sensitivity(NamedTuple):
    """What the pilots found: the rate at which nearby states part and, when sensitive, the errors of the numbers; or,
    on a window that does not reach the motion's attractor, no verdict (sensitive None) and why (`unsettled`)."""

    lyapunov: float | None  # 1/tau, finite-time Lyapunov exponent of the pilots' separation (None: not measured)
    sensitive: bool | None  # None: too short to measure (`unsettled` says why)
    horizon_tau: float | None  # time over which pointwise angles stay reproducible (sensitive runs)
    amplitude_error: Errors  # standard errors of the run's amplitude and frequency (cycle-to-cycle spread), shaped
    frequency_error: Errors  # as the results they belong to: one per chain where those are per chain
    pilot_tau: float
    unsettled: str | None = None  # why the pilots did not run: the window does not reach the attractor

    def as_dict(self) -> dict:
        return self._asdict()

    def note(self, amplitude, frequency) -> str:
        """The numbers with their errors, and whether the dynamics is sensitive (one line). amplitude and frequency
        are the run's results in their shape (a number, None, or one per chain: elastoactive.quantities)."""
        measured = any(e is not None for e in quantities.entries(self.amplitude_error))
        if self.sensitive is None:
            return (
                f"irregular, and too short to measure whether its dynamics is sensitive: {self.unsettled}; run "
                "longer (--duration)" + (f"; {self._errors(amplitude, frequency)}" if measured else "")
            )
        return self._verdict(
            self._errors(amplitude, frequency)
            if measured
            else "amplitude and frequency have no error estimate: fewer than two whole cycles in the "
            "measured window (run longer)"
        )

    def _errors(self, amplitude, frequency) -> str:
        return (
            f"amplitude {quantities.text_with_error(amplitude, self.amplitude_error, unit='rad')} and frequency "
            f"{quantities.text_with_error(frequency, self.frequency_error)} (standard errors from the "
            "cycle-to-cycle spread; none for a chain with fewer than two whole cycles)"
        )

    def _verdict(self, errors: str) -> str:
        if not self.sensitive:
            return (
                f"error estimate of an irregular motion: {errors}; nearby states part at {self.lyapunov:.2g}/tau "
                f"(two reduced-model pilots of {self.pilot_tau:g} tau): not sensitive"
            )
        return (
            f"sensitive dynamics: nearby states part at {self.lyapunov:.2g}/tau (two reduced-model pilots of "
            f"{self.pilot_tau:g} tau from the state after the transient); angles are reproducible only over ~"
            f"{self.horizon_tau:.2g} tau, and the numbers are averages over a chaotic motion: {errors}"
        )


def separation_rate(t: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Finite-time Lyapunov exponent (1/tau) of two trajectories a, b (T, n) from the same state: the growth rate of
    their largest angle difference from its early level to where it saturates (SATURATION) or ends. Pure."""
    sep = np.max(np.abs(np.asarray(a) - np.asarray(b)), axis=1)
    early = max(float(np.median(sep[1 : max(2, sep.size // 10)])), 1e-15)
    start = int(np.argmax(sep >= early))
    saturated = np.nonzero(sep >= SATURATION)[0]
    end = int(saturated[0]) if saturated.size else sep.size - 1
    if end <= start or t[end] <= t[start]:
        return 0.0
    return float(math.log(max(sep[end], 1e-15) / early) / (t[end] - t[start]))


def _signal_errors(t: np.ndarray, x: np.ndarray, transient: float) -> tuple[float | None, float | None]:
    """Standard errors of one beat signal's amplitude and frequency; None with fewer than two whole cycles."""
    cycles = obs.cycles(t, x, transient)
    if cycles.count < 2:
        return None, None
    amplitude = obs.amplitude(t, x, transient)
    frequency = obs.frequency(t, x, transient)
    root = math.sqrt(cycles.count)
    return (
        float(amplitude * np.nan_to_num(cycles.amplitude_spread) / root),
        float(frequency * np.nan_to_num(cycles.period_spread) / root),
    )


def cycle_errors(traj: Trajectory, transient: float) -> tuple[Errors, Errors]:
    """Standard errors of the amplitude and frequency of each beat signal (Scene.beat_signals: Theta of each chain)
    from the cycle-to-cycle spread of the measured window, shaped as results.measure shapes the numbers they belong
    to: one value for a single signal, one per chain otherwise; None for a signal with fewer than two whole cycles."""
    signals = traj.physics.scene_def.beat_signals(traj)
    errors = [_signal_errors(traj.t, x, transient) for x in signals]
    if traj.physics.n_chains == 1:
        return errors[0]
    return tuple(a for a, _ in errors), tuple(f for _, f in errors)


def unsettled(traj: Trajectory, transient: float) -> str | None:
    """Why the measured window does not yet show the motion's attractor, or None when it does: a beat signal
    (Scene.beat_signals) must hold SETTLED_CYCLES whole cycles, and none may still grow or decay steadily (cycle
    amplitudes monotone over three or more cycles, changing by more than SETTLING). Pure: no pilot runs."""
    t = traj.t
    window = f"the measured window ({t[-1] - t[0] - transient:.3g} tau after a transient of {transient:.3g} tau)"
    signals = traj.physics.scene_def.beat_signals(traj)
    counts = [obs.cycles(t, x, transient).count for x in signals]
    if max(counts, default=0) < SETTLED_CYCLES:
        return (
            f"{window} holds fewer than {SETTLED_CYCLES} whole cycles of the beat (it may still be leaving its start)"
        )
    for x in signals:
        amplitudes = obs.cycle_amplitudes(t, x, transient)
        steps = np.diff(amplitudes)
        if amplitudes.size >= 3 and (np.all(steps > 0) or np.all(steps < 0)):
            change = float(amplitudes[-1] / amplitudes[0] - 1.0)
            if abs(change) > SETTLING:
                return (
                    f"the beat is still {'growing' if change > 0 else 'decaying'} in {window} (its cycle "
                    f"amplitudes change steadily by {change:+.2g} over {amplitudes.size} cycles)"
                )
    return None


def needs_estimate(traj: Trajectory, periodic: bool | None) -> bool:
    """Whether a run gets the estimate: judged irregular (periodic False; a window too short to judge already says
    to run longer), noise-free (noise is irregular by design: its statistics are the result), a pivot that does not
    move, and a state that is the angles alone (the pilots start from the recorded angles: not a network's nodes, nor
    angles with the self-aligning units' polarities)."""
    return (
        periodic is False
        and traj.physics.noise == 0
        and traj.head is None
        and traj.nodes is None
        and traj.polarity is None
    )


def estimate(traj: Trajectory, transient: float, numerics: Numerics) -> Sensitivity:
    """Run the two pilots from the state at `transient` (the run's mass ratio and seed) and measure how fast they
    part (module docstring); on a window that does not reach the attractor (`unsettled`), no pilots and no verdict."""
    reason = unsettled(traj, transient)
    if reason is not None:  # no pilots: from a state off the attractor they would measure its approach, not chaos
        amplitude_error, frequency_error = cycle_errors(traj, transient)
        return Sensitivity(None, None, None, amplitude_error, frequency_error, 0.0, reason)
    # start-up time: only irregular runs load the reduced engine
    from .engines.reduced import simulate_reduced

    physics = traj.physics
    k = int(np.searchsorted(traj.t - traj.t[0], transient - 1e-9))
    k = min(k, traj.t.size - 2)
    window = float(traj.t[-1] - traj.t[k])
    spacing = float(traj.t[1] - traj.t[0])
    pilot = max(min(PILOT_TAU, window), 10 * spacing)
    numerics = replace(numerics, sample_dt=spacing, dt=spacing / math.ceil(spacing / 0.1 - 1e-9))
    method = traj.info.get("method") if traj.engine == "reduced" else None  # the run's own method, else automatic
    method = method if method in METHODS else None
    runs = [
        simulate_reduced(physics, numerics, pilot, theta0=traj.theta[k], rtol=rtol, atol=atol, method=method)
        for rtol, atol in PILOT_TOLERANCES
    ]
    rate = separation_rate(runs[0].t, runs[0].theta, runs[1].theta)
    amplitude_error, frequency_error = cycle_errors(traj, transient)
    sensitive = rate > SENSITIVE_RATE
    horizon = math.log(HORIZON_ERROR / 1e-6) / rate if sensitive else None
    return Sensitivity(rate, sensitive, horizon, amplitude_error, frequency_error, pilot)

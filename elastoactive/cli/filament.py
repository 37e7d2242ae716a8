"""`elastoactive filament --S S`: the clamped filament's beat as the limit of a ladder of chains.

The chain of N particles at sigma = S / N^3 discretises the clamped filament under a distributed follower load
S = f L^3 / B (docs/filament.md). This command runs the reduced engine on a ladder of N (default 20, 40, 80, 160),
each rung started from the previous rung's last shape (analysis.filament.resample) and run in chunks of a few
beats until its beat is steady to SETTLE_TOLERANCE, measures the angular frequency omega N^4 (units
B / (zeta L^4)) and the amplitude of Theta = theta_N - theta_1, and extrapolates both to N -> infinity in 1/N
(analysis.filament.richardson, with error estimates). The onset N^3 sigma_c(N) is extrapolated the same way
from the linear operator (analysis.stability.onset) and set beside the continuum's own (analysis.continuum).
A ladder whose coarsest rung does not resolve the bending length L S^(-1/3) is refused before it runs
(check_resolution), and rungs that do not approach their limit monotonically are flagged (converging).

A separate command rather than an option of `run`: it runs several chains and writes no trajectory; `run`
is one chain, one trajectory, one summary.json.

The linear analysis (analysis.stability, analysis.continuum: scipy) and the reduced engine (numba) are imported inside
the functions that run the command, the subcommand's boundary: `elastoactive --help` and the other commands do not
load them.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import asdict, dataclass

import numpy as np

from ..analysis.filament import beat, resample, richardson
from ..core.errors import ParameterError
from ..core.params import DEFAULT_DT, Numerics
from ..reduced.blas import one_blas_thread
from ..scenes import one_pinned
from .options import ladder_argument

DEFAULT_LADDER = (20, 40, 80, 160)
"""The ladder of N: halving 1/N, the finest rung the costliest (~0.5 s per beat at N = 160)."""
SAMPLES_PER_PERIOD = 400
"""Samples per beat period of each rung (analysis.filament.beat's extrema then err by ~1e-10)."""
CHUNK_PERIODS = 4
"""Beat periods per chunk: a rung runs chunk after chunk until two successive chunks agree."""
SETTLE_TOLERANCE = 1e-7
"""Two successive chunks whose period and amplitude agree to this (relative) end a rung."""
MAX_CHUNKS = 12
"""Chunks a rung may take before it is reported as not settled."""
START_AMPLITUDE = 0.5
"""Theta (rad) of the first rung's start: its most unstable mode, scaled to this."""
BEAT_SCALING = 4.0 / 3.0
"""Above the onset the beat quickens like S^(4/3) (the bending length (B / f)^(1/3) sets its time scale): the first
rung's first chunk is planned with the onset's period times (S_c / S)^(4/3); each chunk then measures the period."""
LINKS_PER_BENDING_LENGTH = 1.0
"""Links the coarsest rung must have per bending length L S^(-1/3) (the length over which the follower load bends
the filament): N >= this x S^(1/3). Coarser, the chain does not resolve the bent shape and its beat is not in the 1/N
regime (at S = 1e5 the rung N = 20 curls to a Theta of 7.8 rad against 2.3 at N = 160)."""
MIN_SAMPLES_PER_PERIOD = 40
"""A chunk with fewer samples per period (a planned period far too long) is rerun at the measured period."""


@dataclass(frozen=True)
class Rung:
    """One chain of the ladder."""

    n: int
    sigma: float
    omega: float
    """Angular frequency of the beat in units of B / (zeta L^4) = 1 / (N^4 tau)."""
    amplitude: float
    """Half the peak-to-peak of Theta = theta_N - theta_1, rad."""
    onset: float
    """N^3 sigma_c(N)."""
    chunks: int
    settled: bool
    method: str
    wall_time_s: float


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "filament",
        description="Run the reduced engine on chains of N particles at sigma = S / N^3 and extrapolate the beat "
        "(omega in B / (zeta L^4), amplitude of Theta) and the onset to the continuum filament in 1/N "
        "(docs/filament.md).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--S", dest="S", type=float, required=True, help="follower load f L^3 / B (onset 76.10)")
    ladder_argument(p, DEFAULT_LADDER, count=2, smallest=4)
    p.add_argument("--json", action="store_true", help="print the result as JSON instead of a table")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.set_defaults(func=main)


def _first_shape(n: int, sigma: float):
    """The most unstable mode of the straight chain (real part), scaled to Theta = START_AMPLITUDE."""
    from ..analysis import stability as stab  # the linear operator (scipy)

    lam, vec = np.linalg.eig(stab.linear_operator(n, sigma))
    mode = vec[:, int(np.argmax(lam.real))]
    mode = (mode * np.exp(-1j * np.angle(mode[-1]))).real
    return START_AMPLITUDE * mode / (mode[-1] - mode[0])


def _crossing_period(t, x) -> float | None:
    """A rough period of x from its upward crossings of its mid-range (None with fewer than three): where a chunk's
    planned period was wrong, the next chunk is planned with this one."""

    centred = x - 0.5 * (x.max() + x.min())
    up = t[1:][(centred[:-1] < 0) & (centred[1:] >= 0)]
    return float((up[-1] - up[0]) / (up.size - 1)) if up.size >= 3 else None


def _rung(n: int, S: float, start, progress: bool, period: float | None = None) -> tuple[Rung, object]:
    """Run the chain of n particles at sigma = S / n^3 from the angles `start` until its beat is steady; returns the
    rung and its last angles. `period` (tau): the expected beat period (default: the onset's, quickened like
    S^BEAT_SCALING); each chunk samples the period it expects SAMPLES_PER_PERIOD times, and a chunk that finds its
    period far from the expected one (fewer than MIN_SAMPLES_PER_PERIOD samples, or fewer than three crossings) is
    run again at the period it found."""
    from ..analysis import stability as stab  # the operator (scipy)
    from ..engines.reduced import simulate_reduced  # the reduced engine (numba)

    sigma = S / n**3
    physics = one_pinned.SCENE.physics(n=n, sigma=sigma)  # the clamped chain: the filament's discretisation
    onset, omega_c = stab.onset(n)
    if period is None:
        period = 2 * math.pi / (omega_c if omega_c > 0 else 1.0 / n**4) * min(1.0, n**3 * onset / S) ** BEAT_SCALING
    theta, previous, clock, method = np.asarray(start, dtype=float), None, time.perf_counter(), ""
    settled, chunks = False, 0
    while chunks < MAX_CHUNKS and not settled:
        chunks += 1
        step = period / SAMPLES_PER_PERIOD
        numerics = Numerics(dt=step / math.ceil(step / DEFAULT_DT), sample_dt=step)  # dt: the sample grid's base
        traj = simulate_reduced(physics, numerics, CHUNK_PERIODS * period, theta0=theta)
        method = traj.info["method"]
        signal = traj.theta[:, -1] - traj.theta[:, 0]
        theta = traj.theta[-1].copy()
        found = _crossing_period(traj.t, signal)
        if found is None or found < MIN_SAMPLES_PER_PERIOD * step:  # planned far from the beat: plan again
            period, previous = (CHUNK_PERIODS * period if found is None else found), None
            continue
        b = beat(traj.t, signal)
        period = b.period
        if previous is not None:
            settled = (
                abs(b.period / previous.period - 1) < SETTLE_TOLERANCE
                and abs(b.amplitude / previous.amplitude - 1) < SETTLE_TOLERANCE
            )
        previous = b
    if previous is None:
        raise ParameterError(
            f"--S {S:g}: the chain with N = {n} found no beat in {chunks} chunks of up to "
            f"{CHUNK_PERIODS} planned periods"
        )
    rung = Rung(
        n=n,
        sigma=sigma,
        omega=2 * math.pi / previous.period * n**4,
        amplitude=previous.amplitude,
        onset=n**3 * onset,
        chunks=chunks,
        settled=settled,
        method=method,
        wall_time_s=time.perf_counter() - clock,
    )
    if progress:
        print(
            f"elastoactive: N = {n}: omega = {rung.omega:.6f}, amplitude = {rung.amplitude:.7f} rad "
            f"({chunks} x {CHUNK_PERIODS} beats, {method}, {rung.wall_time_s:.1f} s)",
            file=sys.stderr,
            flush=True,
        )
    return rung, theta


def largest_resolved_S(n: int) -> float:
    """The largest follower load S whose bending length a ladder with coarsest rung n resolves
    (LINKS_PER_BENDING_LENGTH)."""
    return (n / LINKS_PER_BENDING_LENGTH) ** 3


def check_resolution(S: float, ns) -> None:
    """Refuse, before anything runs, a ladder whose coarsest rung does not resolve the bending length at S (one line
    naming --S, the largest S this ladder resolves and the coarsest N that S needs)."""
    coarsest = min(ns)
    if S > largest_resolved_S(coarsest):
        need = math.ceil(LINKS_PER_BENDING_LENGTH * S ** (1 / 3) - 1e-9)
        raise ParameterError(
            f"--S {S:g} is beyond what the ladder resolves: its coarsest chain (N = {coarsest}) has "
            f"{coarsest / S ** (1 / 3):.2g} links per bending length L S^(-1/3) (at least {LINKS_PER_BENDING_LENGTH:g} "
            f"needed), so its beat is not in the 1/N regime; this ladder resolves S up to "
            f"{largest_resolved_S(coarsest):.4g}, or give --ns from N = {need} on (e.g. --ns "
            f"{','.join(str(need * 2**k) for k in range(len(tuple(ns))))})"
        )


def converging(values) -> bool:
    """Whether a ladder's values (coarsest first, halving 1/N or close) approach their limit monotonically, as the
    1/N regime has them: successive differences of one sign, each smaller than the one before."""
    d = [b - a for a, b in zip(values[:-1], values[1:])]
    return all(x * y > 0 and abs(y) < abs(x) for x, y in zip(d[:-1], d[1:]))


def ladder(S: float, ns=DEFAULT_LADDER, progress: bool = False) -> list[Rung]:
    """The rungs of the ladder at follower load S, each started from the previous one's last shape (a ladder that does
    not resolve S is refused first: check_resolution)."""
    from ..analysis import stability as stab  # the operator (scipy)

    ns = tuple(sorted(ns))
    check_resolution(S, ns)
    below = [n for n in ns if S <= n**3 * stab.onset(n)[0]]
    if below:
        raise ParameterError(
            f"S = {S:g} is at or below the onset of the chain with N = {below[0]} (N^3 sigma_c = "
            f"{below[0] ** 3 * stab.onset(below[0])[0]:.4g}): it does not beat; raise --S (the "
            "filament's onset is 76.10) or drop that N from --ns"
        )
    rungs, shape = [], None
    with one_blas_thread():
        for n in ns:
            start = _first_shape(n, S / n**3) if shape is None else resample(shape, n)
            period = 2 * math.pi * n**4 / rungs[-1].omega if rungs else None  # omega N^4 hardly moves along the ladder
            rung, shape = _rung(n, S, start, progress, period)
            rungs.append(rung)
    return rungs


def main(args) -> int:
    from ..analysis.continuum import continuum_critical  # the continuum's onset (scipy)

    if not (math.isfinite(args.S) and args.S > 0):
        raise ParameterError(f"S (follower load f L^3 / B) must be a positive number, got {args.S}")
    clock = time.perf_counter()
    s_c, w_c = continuum_critical()
    if args.S <= s_c:
        raise ParameterError(
            f"S = {args.S:g} is at or below the filament's onset S_c = {s_c:.2f}: the filament "
            "does not beat (short chains still may, below their own onset N^3 sigma_c: "
            "`elastoactive stability one-pinned --n N`); give --S above it"
        )
    check_resolution(args.S, args.ns)
    rungs = ladder(args.S, args.ns, progress=not args.quiet)
    ns = [r.n for r in rungs]
    omega = richardson(ns, [r.omega for r in rungs])
    amplitude = richardson(ns, [r.amplitude for r in rungs])
    onset = richardson(ns, [r.onset for r in rungs])
    wall = time.perf_counter() - clock
    trend = {name: converging(x.values) for name, x in (("omega", omega), ("amplitude", amplitude))}
    if args.json:
        print(
            json.dumps(
                {
                    "S": args.S,
                    "rungs": [asdict(r) for r in rungs],
                    "omega": {**omega._asdict(), "converging": trend["omega"]},
                    "amplitude": {**amplitude._asdict(), "converging": trend["amplitude"]},
                    "onset": onset._asdict(),
                    "continuum_onset": {"S_c": s_c, "omega_c": w_c},
                    "wall_time_s": wall,
                },
                indent=2,
            )
        )
        return 0
    print(f"clamped filament at S = f L^3 / B = {args.S:g}: chains of N at sigma = S / N^3 (reduced engine)")
    print(
        f"{'N':>6} {'sigma':>12} {'omega N^4':>12} {'amplitude':>11} {'N^3 sigma_c':>12} {'method':>13} {'wall s':>7}"
    )
    for r in rungs:
        flag = "" if r.settled else "  (not settled)"
        print(
            f"{r.n:>6} {r.sigma:>12.6g} {r.omega:>12.6f} {r.amplitude:>11.7f} {r.onset:>12.6f} {r.method:>13} "
            f"{r.wall_time_s:>7.2f}{flag}"
        )
    print(f"continuum (Richardson in 1/N over N = {', '.join(map(str, ns))}):")
    print(
        f"  omega     = {omega.value:.4f} +- {omega.error:.2g} B / (zeta L^4)  ({_rel(omega)}){_trend(trend['omega'])}"
    )
    print(
        f"  amplitude = {amplitude.value:.5f} +- {amplitude.error:.2g} rad  ({_rel(amplitude)})"
        f"{_trend(trend['amplitude'])}"
    )
    print(
        f"  onset S_c = {onset.value:.4f} +- {onset.error:.2g}  (the continuum eigenproblem: {s_c:.4f}, "
        f"omega_c = {w_c:.4f})"
    )
    print(f"wall time {wall:.1f} s")
    return 0


def _trend(converges: bool) -> str:
    return "" if converges else "  [rungs not converging monotonically: not the 1/N regime, the error does not hold]"


def _rel(x) -> str:
    return f"{100 * x.error / abs(x.value):.2g}%" if x.value else "n/a"

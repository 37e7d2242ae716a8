"""The automatic numerics of a network run: the step both engines take where the network's dynamics is stepped at a
fixed dt (MuJoCo always; the reduced engine's Euler-Maruyama for noise on the units, terms.unit_noise), and the
record's spacing of a large network (network_sampling: the sample interval left at its default).

Imported by engines.network_mujoco and engines.network_reduced (which MuJoCo's module imports: the rule lives apart
from both so that neither imports the other for it).
"""

from __future__ import annotations

import dataclasses
import math

from ..core.params import DEFAULT_SAMPLE_DT, Numerics, Physics
from ..networks.geometry import turning_scale
from ..terms import turning_rate
from ..terms.base import ALIASING, fastest_term

AUTOMATIC_INTEGRATOR = "Euler"
"""The integrator a network run uses when dt, mass_ratio and integrator are all left at their defaults
(Numerics.automatic). The network's drag is the slide joints' damping, which MuJoCo's Euler integrates implicitly
(its eulerdamp, on by default), exactly as implicitfast does: with no other velocity-dependent force in the model the
two steps are the same, and the trajectories are bit for bit equal (tests/engines/test_network_mujoco.py), but Euler
skips assembling and factoring implicitfast's velocity derivatives: about 30% less per step on the R = 6 lattice
(docs/performance.md)."""
TURN_RESOLUTION = 0.00125
"""dt x Pi that automatic numerics keep below, Pi = sigma / l_a (units k / gamma): the rate at which a unit moving at
its free speed F_a / gamma turns. Both MuJoCo steps are first order; the units' turning sets the error: on the
lattice and trapped-unit validation cases (Pi = 2) the node positions over the first 20 gamma / k are 3.1% and 2.6%
off at dt = 0.0025, 0.77% and 0.66% at dt = 0.000625, halving with dt (docs/performance.md)."""


def network_numerics(physics: Physics, numerics: Numerics, network=None) -> Numerics:
    """The numerics a network run uses: these, or, when they are `automatic`, AUTOMATIC_INTEGRATOR with dt at most
    TURN_RESOLUTION / Pi (a whole fraction of sample_dt; the default dt where that is larger; Pi the fastest unit's
    sigma_u / l_u where the units have their own forces or alignment lengths). network: the one that runs (default the
    scene's, Scene.network; given, e.g. a chain scene's physics run on a given network)."""
    if not numerics.automatic:
        return numerics
    turning = turning_rate(physics)
    if turning > 0:
        network = physics.scene_def.network(physics) if network is None else network
        turning *= turning_scale(network, physics.alignment_length)
    dt = numerics.dt
    if turning > 0:
        dt = min(dt, numerics.sample_dt / math.ceil(numerics.sample_dt * turning / TURN_RESOLUTION - 1e-9))
    return dataclasses.replace(numerics, integrator=AUTOMATIC_INTEGRATOR, dt=dt)


RECORD_BUDGET = 60_000_000
"""Numbers a network run records (samples x (2 per node + 1 per unit)) before network_sampling coarsens a sample
interval left at its default: 480 MB of float64, the R = 18 patch (1027 nodes) over 1000 gamma / k at the default
0.05. Above it the samples, the observables over them and the file cost more than the solve (docs/performance.md,
section 10: 20 001 samples of the 10 267-node patch were 4.9 GB and three times the solve's time)."""


def network_sampling(physics: Physics, numerics: Numerics, duration: float) -> Numerics:
    """These numerics, or, where sample_dt was left at its default and the record would hold more than RECORD_BUDGET
    numbers, a coarser sample_dt: the fewest whole multiples of the default keeping the record within the budget, but
    never so coarse that the fastest term turns more than terms.base.ALIASING rad between samples (the record
    stays unaliased, above the budget then). A given sample_dt is kept as it is."""
    if type(numerics.sample_dt) is not type(DEFAULT_SAMPLE_DT):  # given (a default stays marked as one)
        return numerics
    network = physics.scene_def.network(physics)
    columns = physics.scene_def.record_columns(physics)
    samples = duration / numerics.sample_dt + 1
    if samples * columns <= RECORD_BUDGET:
        return numerics
    step = float(numerics.sample_dt)
    wanted = math.ceil(duration * columns / (RECORD_BUDGET - columns) / step - 1e-9)
    rate, _ = fastest_term(physics)
    rate *= turning_scale(network, physics.alignment_length) if rate > 0 else 1.0
    finest = max(1, math.floor(ALIASING / (rate * step) + 1e-9)) if rate > 0 else wanted
    multiple = max(1, min(wanted, finest))
    if multiple == 1:
        return numerics
    return dataclasses.replace(numerics, sample_dt=multiple * step)

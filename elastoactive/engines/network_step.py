"""The automatic numerics of a network run: the step both engines take where the network's dynamics is stepped at a
fixed dt (MuJoCo always; the reduced engine's Euler-Maruyama for noise on the units, terms.unit_noise).

Imported by engines.network_mujoco and engines.network_reduced (which MuJoCo's module imports: the rule lives apart
from both so that neither imports the other for it).
"""

from __future__ import annotations

import dataclasses
import math

from ..core.params import Numerics, Physics
from ..networks.geometry import turning_scale
from ..terms import turning_rate

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

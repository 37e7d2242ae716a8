"""A periodic force on the tip: F(t) = drive_amplitude sin(2 pi drive_frequency t) along drive_direction, on the
last particle of chain 1 (transverse: the lab's y, across the straight chain; longitudinal: the lab's x, along it).

The reduced model adds it as a node force (elastoactive.engines.node_forces, a law of the time and the positions);
MuJoCo's compiled callback applies it to the tip's site (controllers/follower.c: the site's second user value marks
it, the numeric elastoactive_drive holds (A, omega, d_x, d_y)). Observables: drive_gain and drive_phase, the
tip's displacement along the drive at the drive's frequency over the drive's amplitude and its phase lead
(analysis.response.harmonic_response, over the whole drive periods of the steady window), which below onset the linear
transfer function G(omega) predicts for the transverse drive (docs/outlook.md, section 2).

analysis.response (scipy) is imported inside `measure`, the analysis's boundary: the command line imports the terms
for their parameters.
"""

from __future__ import annotations

import cmath
import math

from ..core.cases import ValidationCase
from ..core.errors import ParameterError
from ..core.observables import Observable
from ..core.parameters import Parameter
from .base import PeriodicForce, Term

DIRECTIONS = ("transverse", "longitudinal")
DIRECTION_VECTORS = {"transverse": (0.0, 1.0), "longitudinal": (1.0, 0.0)}

DRIVE_AMPLITUDE = Parameter(
    "drive_amplitude",
    0.0,
    "amplitude of a periodic force on the tip (C1 / l; 0: no drive)",
    low=0.0,
    title="tip force amplitude, C1 / l",
    units="C1/l",
    quiet_default=True,
)
DRIVE_FREQUENCY = Parameter(
    "drive_frequency",
    0.01,
    "frequency f tau of the tip force (cycles per tau; with --drive-amplitude)",
    low=0.0,
    low_open=True,
    title="tip force frequency f tau",
    units="1/tau",
    needs="drive_amplitude",
    quiet_default=True,
)
DRIVE_DIRECTION = Parameter(
    "drive_direction",
    "transverse",
    "direction of the tip force: transverse (lab y, across "
    "the straight chain) or longitudinal (lab x, along it; with --drive-amplitude)",
    kind=str,
    choices=DIRECTIONS,
    title="tip force direction",
    needs="drive_amplitude",
    quiet_default=True,
)


DRIVE_GAIN = Observable(
    "drive_gain",
    "l^2/C1",
    "tip displacement along the drive at the drive's frequency over the drive's amplitude (null below one period)",
)
DRIVE_PHASE = Observable(
    "drive_phase", "rad", "phase lead of the tip's response over the drive (null below one period)", error="absolute"
)
"""The chain's linear response to the drive (analysis.response.harmonic_response)."""


class TipDrive(Term):
    name = "tip-drive"
    summary = "a periodic force on the tip of chain 1"
    parameters = (DRIVE_AMPLITUDE, DRIVE_FREQUENCY, DRIVE_DIRECTION)
    observables = (DRIVE_GAIN, DRIVE_PHASE)
    measured_at_rest = False  # its observables describe the term acting

    def active(self, physics) -> bool:
        return physics.drive_amplitude > 0

    def check(self, physics) -> None:
        """The drive pushes chain 1's last particle: refused on a scene that holds that particle on a pin (its force
        would go to the pin, not the chain), in both engines."""
        if physics.scene_def.pinned:
            raise ParameterError(
                f"drive_amplitude: the tip drive pushes chain 1's last particle, which scene "
                f"{physics.scene} holds on a pin, so its force would go to the pin, not the chain; "
                "use a scene whose tip is free (e.g. one-pinned)"
            )

    def rate(self, physics) -> float:
        """The drive's angular frequency 2 pi f (the force is read at each step's time)."""
        return 2.0 * math.pi * physics.drive_frequency

    def slower(self, physics, rate: float) -> str:
        return f"drive_frequency <= {rate / (2.0 * math.pi):.2g}"

    def build(self, spec, physics, numerics):
        """The tip's site gets a second user value (1: driven) and the model the numeric elastoactive_drive
        = (A, omega, d_x, d_y) that the compiled callback reads (controllers/follower.c)."""
        prefix = physics.scene_def.chain_prefixes()[0]
        spec.nuser_site = max(spec.nuser_site, 2)
        tip = spec.site(f"{prefix}particle_{physics.n - 1}")
        tip.userdata = [tip.userdata[0], 1.0]
        marker = spec.add_numeric(name="elastoactive_drive")
        marker.data = [
            physics.drive_amplitude,
            2.0 * math.pi * physics.drive_frequency,
            *DIRECTION_VECTORS[physics.drive_direction],
        ]

    def node_forces(self, physics):
        """A PeriodicForce on chain 1's last particle (the reduced engine evaluates it in its compiled right-hand
        side)."""
        x, y = DIRECTION_VECTORS[physics.drive_direction]
        return PeriodicForce(
            physics.n - 1,
            (x * physics.drive_amplitude, y * physics.drive_amplitude),
            2.0 * math.pi * physics.drive_frequency,
        )

    def validation_cases(self, physics):
        """N = 2 at 0.9 sigma_c driven across the chain near its resonance (omega ~ 0.99 / tau; decay time 3.3 tau)."""
        return (
            ValidationCase(
                physics(n=2, sigma=2.7, drive_amplitude=5e-4, drive_frequency=0.157), 80.0, convergence=False
            ),
        )

    def measure(self, traj, transient):
        """drive_gain and drive_phase (rad, the response's lead) over the whole drive periods of the steady window;
        null when the window holds less than one period."""
        physics = traj.physics
        omega = 2.0 * math.pi * physics.drive_frequency
        start = traj.t[0] + transient
        periods = math.floor((traj.t[-1] - start) * physics.drive_frequency)
        if periods < 1:
            return {"drive_gain": None, "drive_phase": None}
        keep = (traj.t >= start) & (traj.t <= start + periods / physics.drive_frequency + 1e-9)
        from ..analysis.response import (  # start-up time: scipy (the CLI imports the terms)
            harmonic_response,
            tip_displacement,
        )

        x = tip_displacement(traj.theta[keep, : physics.n], physics.drive_direction)
        fit = harmonic_response(traj.t[keep], x, omega, physics.drive_amplitude)
        return {"drive_gain": abs(fit.gain), "drive_phase": cmath.phase(fit.gain)}


TERM = TipDrive()

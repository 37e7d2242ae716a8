"""The clamped chain in three dimensions (a kind of its own): N links from a clamp along e_x, free to bend in any
direction, follower forces along the links, lab-frame drag; above onset it whirls (docs/model3d.md).

Its state, Trajectory.theta, is two angles per link: the azimuth phi_k of the link in the xy plane (N columns, the
planar chain's theta for a planar chain) then its elevation psi_k out of the plane (N columns):
t_k = (cos psi cos phi, cos psi sin phi, sin psi). Its engines are elastoactive.reduced.chain3d (reduced) and
elastoactive.mjcf.chain3d (MuJoCo, ball joints); the hooks import them at the engine boundary (inside the hook).
Its beat is the tip's displacement along the major axis of its path across the clamp axis (analysis.motion3d), and it
reports the tip's aspect, the whirl rate, the tip's radius, the bend and the state (rest, beat, whirl, other).

The fluid: with the hydrodynamics term on (bead_radius a / l > 0) the chain's beads interact through the free-space
Rotne-Prager-Yamakawa mobility (elastoactive.hydro.rpy), each bead a sphere of drag gamma = 6 pi mu a = 1. Both engines
then run the chains-in-a-fluid models: the reduced engine elastoactive.reduced.fluid (solve_fluid, one chain at
`bases`, turned by `frame`, `fluid_mobility`), MuJoCo elastoactive.mjcf.cilia (the coupling a background flow on the
drag actuators); the onset, leading eigenvalue and fastest rate are the linear operator's through the fluid
(analysis.stability_fluid). The scene.cilium subclasses share this route and change only the placement (the wall's
normal as the clamp axis, their bases), the mobility (Rotne-Prager-Blake above the wall) and the coupling of their
cilia. With the term off, every run is the lab-frame drag's, bit for bit (reduced.chain3d, mjcf.chain3d).

Its automatic numerics (automatic_numerics): MuJoCo's error on the whirl is first order in dt, with a coefficient that
grows with N and sigma (STEP_ERROR); where the default dt would miss ACCURACY_TARGET, a run whose dt,
mass ratio and integrator are all left at their defaults takes the largest dt (a whole fraction of sample_dt) that meets
it. From core.params.LONG_CHAIN particles on (drag ratio at most 1) it steps as the planar chain's long-chain numerics
do: explicit drag (Euler) with the mass matched to that dt (dt / mass = core.params.LONG_CHAIN_DT_PER_MASS), whose step
skips implicitfast's dense drag derivatives (3N actuators by 3N dofs: O(N^3), 3x the whole step at N = 40) and whose
error on the whirl is implicitfast's at the same dt, of the opposite sign (N = 20, sigma 0.8, dt 0.0025: +0.19% in rate
against -0.20%; N = 40 at the automatic dt 0.00139: +0.33% against -0.34%, the tip radius +0.19% against -0.15%).
"""

from __future__ import annotations

import dataclasses
import math
import time
from typing import TYPE_CHECKING

import numpy as np

from ..analysis import motion3d
from ..core.errors import ParameterError
from ..core.observables import Observable
from ..core.registry import get as scene_named
from ..core.trajectory import Trajectory
from ..core.units import CHAIN, Signal
from .base import Onset, PathView, Scene, ValidationCase

if TYPE_CHECKING:  # typing only: params imports the registry that holds scenes
    from ..core.params import Numerics, Physics

ACCURACY_TARGET = 0.005
"""Relative error of the whirl's (or beat's) frequency and amplitude that the automatic numerics aim at: half the 1%
the engines are held to against each other, the other half left to the measurement of a finite run."""
STEP_ERROR = (0.0515, 1.25, 1.75, 1.0)
"""(c, a, b, d): MuJoCo's relative error on the steady whirl per unit dt (tau), the larger of its frequency's and its
amplitude's, is about c N^a sigma^b / drag_ratio^d. Fitted to the errors measured against Newton's whirl of the
reduced model at N = 7, 12 and 20, sigma 0.3 to 5, drag ratios 0.5 to 2 (implicitfast, mass ratio 1e-4, ball joints;
the error halves with dt: first order), where it exceeds 0.25: the measured errors are 0.77 to 1.44 times the fit's
(docs/model3d.md, section 7)."""

FLUID_STEP_FACTOR = 1.8
"""MuJoCo's first-order error on the whirl with the fluid on, over its error without it at the same dt (a cilium of
N = 7, sigma 1, a/l = 0.2, h = 0.5: -0.165% against -0.091% at dt 0.005, halving with dt in both;
docs/hydrodynamics.md): step_error's factor while the term acts."""
FLUID_TOLERANCES = (1e-6, 1e-8)
"""The reduced engine's (rtol, atol) with the fluid on: a pair of N = 7 on the wall (bead_radius 0.1, sigma 0.8) over
1000 tau beats at f tau = 0.0686127255 with a tip phase difference of -1.5454156 rad at these and -1.5454160 rad at the
chain's 1e-9, 1e-11 (frequency equal to 1e-10), in about a third of the evaluations (10.7k against ~31k per 200 tau)."""
DEGENERATE = 1e-12
"""Relative splitting of the two planes' spectra (analysis.stability_fluid.FluidBranches.splitting) below which the
onset is reported as both planes' together: the symmetric scenes' is round-off, ~1e-15."""

TIP = Signal("y_tip", "y_tip, the tip's displacement along the major axis of its path across the clamp axis", "l")


def load_weights(physics: Physics) -> tuple[float, ...]:
    """The follower force's weight on each particle (1.0 loaded, 0.0 not) as both engines' records take it
    (reduced.chain3d.Chain3D.load, mjcf.chain3d.Chain3DModel.load): empty when every particle is loaded."""
    return () if physics.all_loaded else tuple(float(w) for w in physics.load_mask())


def tangents_of(theta: np.ndarray, n: int) -> np.ndarray:
    """Tangents (..., N, 3) from the recorded angles (..., 2N): azimuths then elevations."""
    phi, psi = theta[..., :n], theta[..., n:]
    return np.stack([np.cos(psi) * np.cos(phi), np.cos(psi) * np.sin(phi), np.sin(psi)], axis=-1)


def angles_of(tangents: np.ndarray) -> np.ndarray:
    """The recorded angles (..., 2N) of tangents (..., N, 3): azimuths unwrapped along the chain and in time."""
    t = tangents / np.linalg.norm(tangents, axis=-1, keepdims=True)
    phi = np.unwrap(np.arctan2(t[..., 1], t[..., 0]), axis=-1)
    if phi.ndim > 1:
        phi = np.unwrap(phi, axis=0)
    psi = np.arcsin(np.clip(t[..., 2], -1.0, 1.0))
    return np.concatenate([phi, psi], axis=-1)


class Clamped3D(Scene):
    name = "clamped-3d"
    summary = "chain clamped at one end, in three dimensions: whirls above sigma_c (the planar onset)"
    base_file = "clamped-3d.xml"
    kind = "chain3d"
    units = CHAIN
    state_units = "1"
    state_name = "tangent"
    mujoco_batched = False
    seeded_start = False
    paced_by_beat = True  # a video shows one beat or turn a second (the tip's beat, beat_signals)
    sized_by_n = True
    builder = "elastoactive.mjcf.chain3d"
    term_parameters = ("n", "sigma", "drag_ratio", "loaded", "bead_radius")
    no_linear_operator = ""
    operator_parameters = ("bead_radius",)
    fluid_mobility = "rpy"
    """The mobility among the beads with the hydrodynamics term on (reduced.fluid.MOBILITIES; MuJoCo's flow): free
    space."""
    frame = np.eye(3)
    """R (3, 3): the lab frame of every chain, lab = base + R chain (the clamp axis e_x becomes R e_x)."""
    min_n = 2
    clamped = True
    """A bending spring holds the first link along e_x (False: a free ball pivot, scenes.pivot3d)."""
    planar_scene = "one-pinned"
    """The planar scene whose straight chain linearises as this one does in each plane (the timestep check's)."""
    file_variables = ("position",)
    observables = (
        Observable("tip_aspect", "1", "minor over major axis of the tip's path (0: a beat in a plane, 1: a whirl)",
                   error="absolute", floor=0.0),
        Observable("whirl_rate", "1/tau", "turning rate of the tip about the clamp axis, cycles per tau (signed)",
                   floor=1e-4),
        Observable("tip_radius", "l", "mean distance of the tip from the clamp axis"),
        Observable("bend", "rad", "mean angle between the first and the last link"),
        Observable("motion_state", "1", "what the chain does (analysis.motion3d.classify)", error="none",
                   categories=("rest", "beat", "whirl", "other")),
    )  # fmt: skip

    def angle_count(self, physics: Physics) -> int:
        return 2 * physics.n

    def beat_signal(self, physics: Physics) -> Signal:
        return TIP

    def check(self, physics: Physics) -> None:
        super().check(physics)
        if physics.bead_radius > 0 and not physics.all_loaded:
            raise ParameterError(
                f"loaded = {physics.loaded}: with bead_radius = {physics.bead_radius:g} every bead carries the "
                "follower force (the fluid's model loads them all)"
            )

    # ------------------------------------------------------------------ the chains in the fluid
    def bases(self, physics: Physics) -> np.ndarray:
        """The chains' anchor points b_c (C, 3), l: one chain clamped at the origin."""
        return np.zeros((1, 3))

    def tip_coupling(self, physics: Physics) -> float:
        """Stiffness of the spring joining neighbouring chains' tips (reduced.fluid.Beds.tip_coupling): none."""
        return 0.0

    def _independent(self, physics: Physics) -> bool:
        """Whether the chains share nothing (no fluid, no spring): each then runs as a chain of its own, with the
        lab-frame drag (reduced.chain3d, mjcf.chain3d)."""
        return physics.bead_radius == 0 and self.tip_coupling(physics) == 0

    def beds(self, physics: Physics):
        """The reduced model's record of the scene's chains (elastoactive.reduced.fluid.Beds): at `bases`, turned by
        `frame`, through `fluid_mobility` with the term on (else the lab-frame drag, "local")."""
        from ..reduced.fluid import Beds  # engine boundary: numba

        fluid = physics.bead_radius > 0
        return Beds(
            physics.n,
            physics.sigma,
            self.bases(physics),
            self.frame,
            mobility=self.fluid_mobility if fluid else "local",
            radius=physics.bead_radius,
            gamma_l=physics.drag_ratio,
            tip_coupling=self.tip_coupling(physics),
            clamped=self.clamped,
        ).checked()

    # ------------------------------------------------------------------ initial state
    def initial_tangents(self, physics: Physics, numerics: Numerics) -> np.ndarray:
        """A non-planar start: seeded static pushes across the axis in y and in z, each of largest angle
        numerics.perturbation."""
        from ..reduced.initial import pushed_chains  # initial imports scipy (start-up time)

        y = pushed_chains(physics.n, 1, numerics.perturbation, numerics.seed)
        z = pushed_chains(physics.n, 1, numerics.perturbation, numerics.seed + 1)
        t = np.column_stack([np.ones(physics.n), np.tan(y), np.tan(z)])
        return t / np.linalg.norm(t, axis=1)[:, None]

    def _start(self, physics: Physics, numerics: Numerics, theta0) -> np.ndarray:
        if theta0 is None:
            return self.initial_tangents(physics, numerics)
        theta0 = np.asarray(theta0, dtype=float)
        if theta0.shape != (2 * physics.n,):
            raise ParameterError(
                f"theta0 must have {2 * physics.n} angles (azimuths, then elevations), got {theta0.shape}"
            )
        return tangents_of(theta0, physics.n)

    def _starts(self, physics: Physics, numerics: Numerics, theta0) -> np.ndarray:
        """Every chain's chain-frame tangents (C, N, 3) at t = 0: here the one chain's."""
        return self._start(physics, numerics, theta0)[None]

    def _times(self, numerics: Numerics, duration: float) -> np.ndarray:
        count = int(math.floor(duration / numerics.sample_dt + 1e-9))
        return numerics.sample_dt * np.arange(count + 1)

    # ------------------------------------------------------------------ engines (the engine boundary)
    def run_reduced(
        self,
        physics: Physics,
        numerics: Numerics,
        duration: float,
        *,
        theta0=None,
        rtol: float = 1e-8,
        atol: float = 1e-10,
        method: str | None = None,
        progress: bool = False,
        **options,
    ) -> Trajectory:
        if not self._independent(physics):
            return self._reduced_coupled(physics, numerics, duration, theta0, rtol, atol, method, progress)
        from ..engines.runner import Meter, solver_budget  # engine boundary: numba and scipy
        from ..reduced.chain3d import Chain3D, solve3d

        if method is not None and method not in self.reduced_methods():
            raise ParameterError(
                f"method: {self.name} integrates by {', '.join(self.reduced_methods())} (or automatic), got {method!r}"
            )
        ts = self._times(numerics, duration)
        refuse = solver_budget(
            physics,
            duration,
            "the reduced engine's",
            start=("perturbation", numerics.perturbation) if theta0 is None else ("start-from", None),
            base_rate=lambda: self.fastest_overdamped_rate(physics),
        )
        chosen = []

        def budget(name, eig):  # the method solve3d runs (its automatic choice too), for the record
            chosen.append(name)
            return refuse(name, eig)

        start = time.perf_counter()
        with Meter(duration, f"reduced {physics.scene}", progress) as meter:
            path = solve3d(
                Chain3D(physics.n, physics.sigma, physics.drag_ratio, self.clamped, load=load_weights(physics)),
                ts,
                self._start(physics, numerics, theta0),
                rtol=rtol,
                atol=atol,
                on_time=meter.at,
                budget=budget,
            )
        info = {"method": chosen[0] if chosen else method, "rtol": rtol, "atol": atol}
        return Trajectory(ts, angles_of(path), physics, "reduced", time.perf_counter() - start, info)

    def _reduced_coupled(self, physics, numerics, duration, theta0, rtol, atol, method, progress) -> Trajectory:
        """The chains sharing the fluid (or a spring) in one reduced model: reduced.fluid.solve_fluid on `beds`."""
        from ..engines.runner import Meter, resume, solver_budget  # engine boundary: numba and scipy
        from ..reduced.fluid import METHODS, solve_fluid

        method = METHODS[0] if method is None else method
        if method not in METHODS:
            raise ParameterError(f"method: {self.name} through the fluid integrates by {' or '.join(METHODS)}, "
                                 f"got {method!r}")  # fmt: skip
        ts = self._times(numerics, duration)
        budget = solver_budget(
            physics,
            duration,
            "the reduced engine's",
            start=("perturbation", numerics.perturbation) if theta0 is None else ("start-from", None),
            base_rate=lambda: self.fastest_overdamped_rate(physics),
        )
        beds = self.beds(physics)
        starts = self._starts(physics, numerics, theta0)
        start = time.perf_counter()
        with Meter(duration, f"reduced {physics.scene}", progress) as meter:
            path = solve_fluid(
                beds, ts, starts, rtol=rtol, atol=atol, method=method, on_time=meter.at, budget=budget,
                loop=lambda call, paused, reached, steps: resume(call, paused, reached, meter, steps),
            )  # fmt: skip
        info = {"method": method, "rtol": rtol, "atol": atol, "mobility": beds.mobility}
        theta = angles_of(path).reshape(ts.size, -1)
        return Trajectory(ts, theta, physics, "reduced", time.perf_counter() - start, info)

    def reduced_tolerances(self, physics: Physics) -> tuple[float, float]:
        """FLUID_TOLERANCES with the fluid on, else the chain's."""
        return FLUID_TOLERANCES if physics.bead_radius > 0 else super().reduced_tolerances(physics)

    def step_error(self, physics: Physics) -> float:
        """MuJoCo's expected relative error on the steady motion per unit dt: STEP_ERROR's c N^a sigma^b /
        drag_ratio^d, FLUID_STEP_FACTOR times larger with the fluid on."""
        c, a, b, d = STEP_ERROR
        error = c * physics.n**a * physics.sigma**b / physics.drag_ratio**d
        return error * FLUID_STEP_FACTOR if physics.bead_radius > 0 else error

    def automatic_numerics(self, physics: Physics, numerics: Numerics) -> Numerics:
        """The numerics a MuJoCo run uses: these when dt, mass ratio or integrator was given; when all three are left
        at their defaults (`automatic`), the default dt, or, where step_error x dt exceeds ACCURACY_TARGET, the
        largest dt that meets it (a whole fraction of sample_dt), as given numerics (so that nothing downstream, the
        pre-flight check or the summary, resolves them again). Never a larger dt than the default: the transient's
        angles are held to the planar chain's accuracy too. A chain of LONG_CHAIN particles or more steps that dt by
        Euler with explicit drag and the mass dt / LONG_CHAIN_DT_PER_MASS, the planar long chain's matched mass
        (core.params.long_chain_numerics), where the drag ratio is at most 1; a larger one would need a mass that
        many times larger for the explicit drag's stability, which the inertial chain's resolution refuses (N = 60,
        sigma 0.8, drag ratio 2), and keeps implicitfast. Chains coupled through the fluid (or a spring) keep the
        given integrator and mass at any N: their coupling rides on the drag actuators (mjcf.cilia), which the long
        chain's explicit-drag numerics do not have."""
        from ..core.params import LONG_CHAIN, LONG_CHAIN_DT_PER_MASS  # params imports the registry that holds scenes

        if not numerics.automatic:
            return numerics
        dt = float(numerics.dt)
        error = self.step_error(physics)
        if error * dt > ACCURACY_TARGET:
            dt = numerics.sample_dt / math.ceil(numerics.sample_dt * error / ACCURACY_TARGET - 1e-9)
        if physics.n < LONG_CHAIN or physics.drag_ratio > 1.0 or not self._independent(physics):
            return dataclasses.replace(numerics, dt=dt)
        return dataclasses.replace(numerics, dt=dt, mass_ratio=dt / LONG_CHAIN_DT_PER_MASS, integrator="Euler")

    def run_mujoco(
        self, physics: Physics, numerics: Numerics, duration: float, *, theta0=None, progress: bool = False, **options
    ) -> Trajectory:
        import mujoco  # engine boundary: MuJoCo

        if not self._independent(physics):
            return self._mujoco_coupled(physics, numerics, duration, theta0, progress)
        # engine boundary: the cost model, the runner and the 3D builder load MuJoCo
        from ..engines.cost import announce_cost, reduced_cost
        from ..engines.runner import Meter, StepChunks, refuse_steps
        from ..mjcf.chain3d import Chain3DModel, simulate3d

        given, numerics = numerics, self.automatic_numerics(physics, numerics)
        ts = self._times(numerics, duration)
        automatic = numerics is not given  # dt for the whirl's accuracy: sigma sets it
        refuse_steps(
            (ts.size - 1) * numerics.steps_per_sample,
            what=f"MuJoCo at dt = {numerics.dt:.3g}" + (" (automatic, for the whirl's accuracy)" if automatic else ""),
            duration=duration,
            cause="sigma" if automatic else "dt",
            value=physics.sigma if automatic else numerics.dt,
            advice="a smaller --sigma" if automatic else "a larger --dt",
        )
        model = Chain3DModel(
            physics.n,
            physics.sigma,
            physics.drag_ratio,
            clamped=self.clamped,
            mass_ratio=numerics.mass_ratio,
            dt=numerics.dt,
            integrator=numerics.integrator,
            load=load_weights(physics),
        )
        meter = Meter(duration, f"mujoco {physics.scene}", progress)
        estimate = []

        def prepared(mj_model, data) -> None:  # the run's estimate, and the reduced engine's where far quicker
            pilot = lambda: reduced_cost(physics, given, duration)  # noqa: E731
            estimate.append(announce_cost(meter, mj_model, data, numerics, ts.size - 1, pilot))

        start = time.perf_counter()
        with meter:
            path = simulate3d(
                model,
                ts,
                self._start(physics, numerics, theta0),
                prepared=prepared,
                step=StepChunks(meter, mujoco.mj_step),
                reached=meter.at,
            )
        wall = time.perf_counter() - start
        info = {"joints": model.joints, "twist_inertia": model.inertia, "twist_damping": model.damping}
        if estimate and estimate[0] is not None:
            info["estimated_wall_s"] = estimate[0].wall_s
        if numerics is not given:
            info["automatic_numerics"] = {
                "integrator": numerics.integrator,
                "dt": float(numerics.dt),
                "mass_ratio": float(numerics.mass_ratio),
                "reason": f"{self.name}: dt for {ACCURACY_TARGET:.1%} on the whirl (Clamped3D.automatic_numerics)",
            }
        return Trajectory(ts, angles_of(path), physics, "mujoco", wall, info)

    def _mujoco_coupled(self, physics, numerics, duration, theta0, progress) -> Trajectory:
        """The chains sharing the fluid (or a spring) in one MuJoCo model (mjcf.cilia: the coupling a background flow
        on the drag actuators from the step before, at the implicit integrator)."""
        from ..engines.runner import Meter, StepChunks, refuse_steps  # engine boundary: MuJoCo
        from ..mjcf.cilia import CiliaModel, simulate_cilia

        given, numerics = numerics, self.automatic_numerics(physics, numerics)
        automatic = numerics is not given  # dt for the whirl's accuracy: sigma sets it
        ts = self._times(numerics, duration)
        refuse_steps(
            (ts.size - 1) * numerics.steps_per_sample,
            what=f"MuJoCo at dt = {numerics.dt:.3g}" + (" (automatic, for the whirl's accuracy)" if automatic else ""),
            duration=duration,
            cause="sigma" if automatic else "dt",
            value=physics.sigma if automatic else numerics.dt,
            advice="a smaller --sigma" if automatic else "a larger --dt",
        )
        chains = CiliaModel(
            physics.n, physics.sigma, self.bases(physics), self.frame, radius=physics.bead_radius,
            flow=self.fluid_mobility, drag_ratio=physics.drag_ratio, tip_coupling=self.tip_coupling(physics),
            mass_ratio=numerics.mass_ratio, dt=numerics.dt, integrator=numerics.integrator, clamped=self.clamped,
        )  # fmt: skip
        prepared = []
        meter = Meter(duration, f"mujoco {physics.scene}", progress)
        start = time.perf_counter()
        with meter:
            path = simulate_cilia(chains, ts, self._starts(physics, numerics, theta0), prepared=prepared.append,
                                  chunked=lambda stepper: StepChunks(meter, stepper), reached=meter.at)  # fmt: skip
        info = {"joints": "ball", "coupling_gain": float(prepared[0].gain), "settle_steps": prepared[0].settle_steps}
        if automatic:
            info["automatic_numerics"] = {
                "integrator": numerics.integrator,
                "dt": float(numerics.dt),
                "mass_ratio": float(numerics.mass_ratio),
                "reason": f"{self.name}: dt for the whirl's accuracy with the coupling "
                f"({type(self).__name__}.automatic_numerics)",
            }
        theta = angles_of(path).reshape(ts.size, -1)
        return Trajectory(ts, theta, physics, "mujoco", time.perf_counter() - start, info)

    def check_timestep(self, physics: Physics, numerics: Numerics, safety: float, accuracy: bool, **options):
        """The planar chain's limits at the numerics the run uses (automatic_numerics): the straight chain's
        linearisation is the planar one twice (analysis.stability3d); the ball joints' twist, an oscillator whose
        inertia scales with dt^2, is stable at any dt (mjcf.chain3d.TWIST_INERTIA_STEPS)."""
        from ..engines.timestep import check_chain_timestep  # engine boundary: the check loads mujoco

        return check_chain_timestep(self.planar(physics), self.automatic_numerics(physics, numerics), safety, accuracy)

    def reduced_methods(self) -> tuple[str, ...]:
        from ..reduced.chain3d import METHODS3D  # engine boundary: numba

        return METHODS3D

    # ------------------------------------------------------------------ trajectory
    def tangents(self, traj: Trajectory) -> np.ndarray:
        return tangents_of(traj.theta, traj.physics.n)

    def positions(self, traj: Trajectory) -> np.ndarray:
        """Shape (T, 1, N, 3), as a planar chain's with (x, y, z): particle i of the one chain in units of l, the sum
        of the first i + 1 tangents from the clamp at the origin (MuJoCo's site particle_i)."""
        return np.cumsum(self.tangents(traj), axis=-2)[:, None]

    def tip(self, traj: Trajectory) -> np.ndarray:
        return self.positions(traj)[:, :, -1, :]

    def centre_of_drag(self, traj: Trajectory) -> np.ndarray:
        return self.positions(traj).mean(axis=-2)

    def state_variables(self, traj: Trajectory) -> tuple[dict, dict]:
        """The tangents, the positions and the tip laid out as a planar chain's, on ``xyz`` in place of ``xy`` (time,
        chain, particle, xyz; time, chain, xyz: one chain)."""
        n, units = traj.physics.n, self.length_units
        coords = {
            "chain": ("chain", np.arange(1), {"long_name": "chain", "description": "chain index, 0-based"}),
            "particle": (
                "particle",
                np.arange(n),
                {"long_name": "particle", "description": "particle index, 0-based (the model's site particle_i)"},
            ),
            "xyz": ("xyz", ["x", "y", "z"], {"long_name": "component", "description": "lab-frame component"}),
        }
        position = self.positions(traj)
        data = {
            "tangent": (
                ("time", "chain", "particle", "xyz"),
                self.tangents(traj)[:, None],
                {"units": "1", "long_name": "link tangent", "description": "unit tangent of each link"},
            ),
            "position": (
                ("time", "chain", "particle", "xyz"),
                position,
                {"units": units, "long_name": "particle position", "description": "lab-frame particle position"},
            ),
            "tip": (
                ("time", "chain", "xyz"),
                position[:, :, -1],
                {"units": units, "long_name": "tip position", "description": "lab-frame position of the last particle"},
            ),
        }
        return coords, data

    def state_difference(self, traj: Trajectory, reference: Trajectory, early: np.ndarray) -> tuple[float, float]:
        n = early.size
        diff = np.abs(self.tangents(traj)[:n][early] - self.tangents(reference)[:n][early]).max()
        return float(diff), 1.0

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        tip = self.tip(traj)[:, 0, 1:]
        lateral = tip - tip.mean(axis=0)
        _, axes = np.linalg.eigh(np.cov(lateral.T))
        return [lateral @ axes[:, 1]]

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float | str]:
        m = motion3d.measure3d(traj.t, self.tangents(traj), transient=transient)
        return {
            "tip_aspect": m.tip_aspect,
            "whirl_rate": m.whirl_rate,
            "tip_radius": m.tip_radius,
            "bend": m.bend,
            "motion_state": m.state,
        }

    # ------------------------------------------------------------------ drawing
    def caption_line(self, physics: Physics) -> str:
        return "   ".join([physics.scene, f"N = {physics.n}", f"σ = {physics.sigma:.3g}", *self.caption(physics)])

    def painter(self, traj: Trajectory, **options):
        from ..render import check_picture  # engine boundary: rendering loads MuJoCo and GL
        from ..render.chain3d import Chain3DPainter

        check_picture(width=options["width"], height=options["height"], trail=options["trail"])
        return Chain3DPainter(traj, **options)

    def tip_views(self, traj: Trajectory, keep: np.ndarray) -> tuple[PathView, ...]:
        """The tip's path across the clamp axis e_x (the yz plane, where a whirl is a circle and a beat a line), then
        in three dimensions."""
        tips = self.tip(traj)[keep]
        return PathView(tips[..., 1:], ("y", "z"), "across the clamp axis"), PathView(tips, ("x", "y", "z"), "3D")

    def draw_shape(self, ax, traj: Trajectory, i: int, labels: list[str]) -> None:
        """The chain projected on the xy plane (dashed: on xz)."""
        p = np.vstack([np.zeros(3), self.positions(traj)[i, 0]])
        ax.plot(p[:, 0], p[:, 1], "-o", ms=4, label="xy")
        ax.plot(p[:, 0], p[:, 2], "--", lw=1, label="xz")
        ax.plot(0, 0, "ks", ms=6)
        ax.legend(fontsize="small")

    # ------------------------------------------------------------------ stability
    def planar(self, physics: Physics) -> Physics:
        """The planar scene's physics (planar_scene) whose straight chain linearises as this one does in each plane:
        the same n, sigma, drag ratio and loaded particles."""
        return scene_named(self.planar_scene).physics(
            n=physics.n, sigma=physics.sigma, drag_ratio=physics.drag_ratio, loaded=physics.loaded
        )

    def onset(self, physics: Physics) -> Onset:
        """The planar onset (analysis.stability3d.onset3d), where the in-plane and out-of-plane pairs cross together:
        the straight chain's operator is the planar one twice, for every particle loaded and for some (the follower
        force acts along the link, the same in both planes), so a partial load's onset is the planar scene's with
        that load. Through the fluid (or chains joined by a spring): the linear operator's (onset_coupled)."""
        from ..analysis.stability3d import onset3d  # start-up time: scipy

        if not self._independent(physics):
            return self.onset_coupled(physics)
        if not physics.all_loaded:
            planar = self.planar(physics)
            onset = planar.scene_def.onset(planar)
            return Onset(onset.sigma_c, onset.omega_c, f"flutter (Hopf), in-plane and out-of-plane pairs together, "
                                                       f"loaded {physics.loaded}")  # fmt: skip
        sigma_c, omega_c = onset3d(physics.n, physics.drag_ratio)
        return Onset(sigma_c, omega_c, "flutter (Hopf), in-plane and out-of-plane pairs together")

    def onset_coupled(self, physics: Physics) -> Onset:
        """The onset of the scene's linear operator through the fluid and the tips' springs
        (analysis.stability_fluid), naming the plane that crosses first, or both together where the symmetry keeps
        them degenerate (a single chain: RPY of collinear beads, RPB along the wall's normal)."""
        from ..analysis.stability_fluid import branches_fluid, linear_operator_fluid, onset_fluid  # scipy

        beds = self.beds(physics)
        sigma_c, omega_c = onset_fluid(beds)
        planes = branches_fluid(linear_operator_fluid(beds, sigma_c))
        through = f" through the fluid (a / l = {physics.bead_radius:g})" if physics.bead_radius > 0 else ""
        if planes.coupling == 0.0 and planes.splitting < DEGENERATE:
            kind = f"flutter (Hopf), in-plane and out-of-plane pairs together{through}"
        else:
            first = "in-plane" if planes.in_plane[0].real >= planes.out_of_plane[0].real else "out-of-plane"
            kind = f"flutter (Hopf), the {first} pair first{through}"
        return Onset(sigma_c, omega_c, kind)

    def leading_eigenvalue(self, physics: Physics, sigma: float) -> complex:
        """The planar scene's (planar_scene: each plane's block of the 3D operator is its operator, so its slowest
        modes, not the 2N x 2N operator's dense eigenvalues, and its own treatment of a free pivot's rigid turn);
        through the fluid (or a spring) the scene's operator's (analysis.stability_fluid)."""
        if not self._independent(physics):
            from ..analysis.stability_fluid import leading_eigenvalue_fluid  # scipy

            return leading_eigenvalue_fluid(self.beds(physics), sigma)
        planar = self.planar(physics)
        return planar.scene_def.leading_eigenvalue(planar, sigma)

    def fastest_overdamped_rate(self, physics: Physics) -> float:
        """The largest |eigenvalue| of the straight chain's 3D linear operator at the physics' sigma, 1/tau: its
        planar block's (analysis.stability3d.fastest_rate3d); a partial load's from the planar scene; through the
        fluid (or a spring) the scene's operator's (analysis.stability_fluid)."""
        if not self._independent(physics):
            from ..analysis.stability_fluid import linear_operator_fluid  # scipy

            lam = np.linalg.eigvals(linear_operator_fluid(self.beds(physics), physics.sigma))
            return float(np.abs(lam).max())
        if not physics.all_loaded:
            planar = self.planar(physics)
            return planar.scene_def.fastest_overdamped_rate(planar)
        from ..analysis.stability3d import fastest_rate3d  # start-up time: scipy

        return fastest_rate3d(physics.n, physics.sigma, self.clamped)

    def stability_report(
        self, physics: Physics, sigma: float | None, onset: Onset | None = None, eigenvalue: complex | None = None
    ) -> list[str]:
        onset = self.onset(physics) if onset is None else onset
        lines = [
            f"{self.name}, N = {physics.n}:",
            f"  onset: {onset.kind} at sigma_c = {onset.sigma_c:.10g}, omega_c = {onset.omega_c:.6g} rad/tau",
        ]
        if sigma is not None:
            lam = self.leading_eigenvalue(physics, sigma) if eigenvalue is None else eigenvalue
            lines.append(
                f"  at sigma = {sigma:g}: growth rate {lam.real:+.6g} /tau ({'unstable' if lam.real > 0 else 'stable'})"
            )
        return lines

    def validation_cases(self) -> tuple[ValidationCase, ...]:
        """N = 7 at sigma = 0.4 (2.5 times the onset): the engines' early tangents agree within 0.23%, amplitude and
        frequency within 0.01% (at sigma = 0.8: 0.67%, 0.08%, 0.03%; docs/model3d.md, section 8)."""
        return (ValidationCase(self.physics(n=7, sigma=0.4), 300.0),)


SCENE = Clamped3D()

"""A cilium on a wall: the clamped 3D chain (scenes.clamped3d) standing on a no-slip wall, its clamp along the wall's
normal e_z, its base (the clamp point, the anchor of link 1) at height h = base_height above the wall z = 0.

The clamped 3D chain's kind, turned: each cilium is a clamped-3d chain in its own frame (clamp axis e_x, the recorded
azimuths and elevations of scenes.clamped3d, regular at the straight state), placed in the lab by the rotation
ROTATION (the chain's x, y, z are the lab's z, x, y) and its base point: particle i of cilium c sits at
b_c + R sum_{k<=i} t_k, b_c = (c d, 0, h). A beat in the chain's xy plane is a beat in the lab's xz plane, across
the wall and along the line of the cilia's bases.

The fluid: with the hydrodynamics term on (bead_radius > 0) the beads of every cilium move through the
Rotne-Prager-Blake mobility above the wall (elastoactive.reduced.fluid), and the cilia of a pair or a row are coupled
only through it (or the tips' spring of cilia-pair). Without the term each particle has its lab-frame drag and the wall
does nothing: a cilium is then a clamped-3d chain, bit for bit (the reduced engine runs each cilium through
reduced.chain3d, MuJoCo through mjcf.chain3d, from the same start), at its base; the cilia of a pair or row without the
term or a spring are independent clamped-3d chains.

Engines: both. Cilia that share nothing (no fluid, no spring) run as clamped-3d chains, each its own model; coupled
cilia take clamped-3d's route through the fluid (scenes.clamped3d: reduced.fluid, and one MuJoCo model,
elastoactive.mjcf.cilia, the fluid carried as a background flow on the beads' drag actuators from the step before,
elastoactive.controllers.hydro, docs/hydrodynamics.md, and the tips' spring as an explicit force beside it, at the
implicit integrator and a dt sized for the whirl's accuracy with the fluid's larger step error,
clamped3d.FLUID_STEP_FACTOR), with the wall's mobility (Rotne-Prager-Blake), the frame ROTATION and the bases here.

Observables: the first cilium's motion (scenes.clamped3d's: tip_aspect, whirl_rate, tip_radius, bend, motion_state,
in its own frame: the tip's path across the wall normal) and pumped_flux, the mean volume flux the cilia pump along
the wall (analysis.cilia.blake_flux: Blake's 6 a sum_i F_x,i h_i in the units gamma = 6 pi mu a = 1; NaN without the
fluid, where there is no viscosity to pump against).
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING

import numpy as np

from ..analysis import cilia as cilia_analysis
from ..analysis import observables
from ..core.errors import ParameterError
from ..core.observables import Observable
from ..core.parameters import Parameter
from ..core.trajectory import Trajectory
from .base import PathView, ValidationCase
from .clamped3d import FLUID_TOLERANCES, Clamped3D, angles_of, tangents_of

__all__ = ["BASE_HEIGHT", "FLUID_TOLERANCES", "PUMPED_FLUX", "ROTATION", "Cilium"]

if TYPE_CHECKING:  # typing only: params imports the registry that holds scenes
    from ..core.params import Numerics, Physics

ROTATION = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
"""lab = R chain: a cilium's clamp axis e_x is the wall's normal e_z, its y the lab's x (along the row), its z the
lab's y."""

BASE_HEIGHT = Parameter(
    "base_height",
    0.5,
    "height h of each cilium's base (its clamp point) above the wall z = 0, in l",
    low=0.0,
    units="l",
    title="base height above the wall",
    symbol="h",
)

FLUX_SAMPLES = 2000
"""The most samples of the steady window whose forces the pumped flux averages (evenly spaced): a mean over many
beats, each sample a dense solve of the beads' forces."""

PUMPED_FLUX = Observable(
    "pumped_flux",
    "l^3/tau",
    "mean volume flux pumped along the wall in +x, through a half-plane across it (Blake's 6 a sum F_x h; NaN "
    "without the fluid)",
    error="absolute",
    floor=0.0,
)


class Cilium(Clamped3D):
    name = "cilium"
    summary = "a 3D chain clamped along the normal of a no-slip wall: beats or whirls; with bead_radius, in the fluid"
    parameters = (BASE_HEIGHT,)
    term_parameters = ("n", "sigma", "drag_ratio", "bead_radius")
    file_variables = ()
    observables = ("tip_aspect", "whirl_rate", "tip_radius", "bend", "motion_state", PUMPED_FLUX)
    fluid_mobility = "rpb"
    frame = ROTATION

    # ------------------------------------------------------------------ the cilia
    def cilia(self, physics: Physics) -> int:
        """How many cilia the scene holds."""
        return 1

    def spacing(self, physics: Physics) -> float:
        """Distance between neighbouring cilia's bases along x (l)."""
        return 0.0

    def bases(self, physics: Physics) -> np.ndarray:
        """The cilia's base points b_c = (c d, 0, h), shape (C, 3)."""
        c = np.arange(self.cilia(physics), dtype=float)
        return np.stack([c * self.spacing(physics), np.zeros_like(c), np.full_like(c, physics.base_height)], axis=1)

    def chain_count(self, physics: Physics) -> int:
        return self.cilia(physics)

    def angle_count(self, physics: Physics) -> int:
        return 2 * physics.n * self.cilia(physics)

    def check(self, physics: Physics) -> None:
        super().check(physics)
        if physics.bead_radius > 0 and physics.base_height + 1.0 <= physics.bead_radius:
            raise ParameterError(
                f"base_height = {physics.base_height:g}: the first bead (at h + 1) must clear the wall by its radius "
                f"bead_radius = {physics.bead_radius:g}"
            )

    # ------------------------------------------------------------------ initial state
    def initial_cilia(self, physics: Physics, numerics: Numerics) -> np.ndarray:
        """Chain-frame tangents (C, N, 3) at t = 0: cilium c pushed as a clamped-3d chain of seed numerics.seed + 2c
        (cilium 0: the clamped-3d start itself)."""
        return np.stack(
            [
                self.initial_tangents(physics, dataclasses.replace(numerics, seed=numerics.seed + 2 * c))
                for c in range(self.cilia(physics))
            ]
        )

    def _starts(self, physics: Physics, numerics: Numerics, theta0) -> np.ndarray:
        if theta0 is None:
            return self.initial_cilia(physics, numerics)
        theta0 = np.asarray(theta0, dtype=float)
        count = self.angle_count(physics)
        if theta0.shape != (count,):
            raise ParameterError(
                f"theta0 must have {count} angles (each cilium's azimuths, then its elevations), got {theta0.shape}"
            )
        return tangents_of(theta0.reshape(self.cilia(physics), 2 * physics.n), physics.n)

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
        if self._independent(physics):  # each cilium a clamped-3d chain, its own run
            starts = self._starts(physics, numerics, theta0)
            runs = [
                super(Cilium, self).run_reduced(
                    physics, numerics, duration, theta0=angles_of(s), rtol=rtol, atol=atol, method=method,
                    progress=progress,
                )
                for s in starts
            ]  # fmt: skip
            return self._joined(runs, physics, "reduced")
        return super().run_reduced(
            physics, numerics, duration, theta0=theta0, rtol=rtol, atol=atol, method=method, progress=progress
        )

    def run_mujoco(
        self, physics: Physics, numerics: Numerics, duration: float, *, theta0=None, progress: bool = False, **options
    ) -> Trajectory:
        if self._independent(physics):  # no fluid, no spring: each cilium clamped-3d's own run
            runs = [
                super(Cilium, self).run_mujoco(physics, numerics, duration, theta0=angles_of(s), progress=progress)
                for s in self._starts(physics, numerics, theta0)
            ]
            return self._joined(runs, physics, "mujoco")
        return super().run_mujoco(physics, numerics, duration, theta0=theta0, progress=progress)

    def _joined(self, runs: list[Trajectory], physics: Physics, engine: str) -> Trajectory:
        """One trajectory of the cilia from each cilium's own run (theta: cilium by cilium)."""
        if len(runs) == 1:
            return Trajectory(runs[0].t, runs[0].theta, physics, engine, runs[0].wall_time_s, runs[0].info)
        theta = np.concatenate([r.theta for r in runs], axis=1)
        wall = sum(r.wall_time_s for r in runs)
        return Trajectory(runs[0].t, theta, physics, engine, wall, {**runs[0].info, "cilia_runs": len(runs)})

    # ------------------------------------------------------------------ trajectory
    def chain_tangents(self, traj: Trajectory) -> np.ndarray:
        """Each cilium's tangents in its own frame (clamp axis e_x), shape (T, C, N, 3)."""
        n, count = traj.physics.n, self.cilia(traj.physics)
        return tangents_of(traj.theta.reshape(len(traj.t), count, 2 * n), n)

    def tangents(self, traj: Trajectory) -> np.ndarray:
        """The first cilium's tangents in its own frame (T, N, 3): what clamped-3d's observables read."""
        return self.chain_tangents(traj)[:, 0]

    def positions(self, traj: Trajectory) -> np.ndarray:
        """Shape (T, C, N, 3): particle i of cilium c in the lab (the wall z = 0, the cilia along x), units of l."""
        return self.bases(traj.physics)[:, None, :] + np.cumsum(self.chain_tangents(traj), axis=-2) @ ROTATION.T

    def centre_of_drag(self, traj: Trajectory) -> np.ndarray:
        return self.positions(traj).mean(axis=-2)

    def state_variables(self, traj: Trajectory) -> tuple[dict, dict]:
        """The lab-frame tangents, positions and tips (time, chain, particle, xyz; time, chain, xyz), one chain a
        cilium."""
        coords, data = super().state_variables(traj)
        count = self.cilia(traj.physics)
        coords["chain"] = ("chain", np.arange(count), {"long_name": "cilium", "description": "cilium index, 0-based"})
        position = self.positions(traj)
        data["tangent"] = (data["tangent"][0], self.chain_tangents(traj) @ ROTATION.T, data["tangent"][2])
        data["position"] = (data["position"][0], position, data["position"][2])
        data["tip"] = (data["tip"][0], position[:, :, -1], data["tip"][2])
        return coords, data

    def state_difference(self, traj: Trajectory, reference: Trajectory, early: np.ndarray) -> tuple[float, float]:
        n = early.size
        diff = np.abs(self.chain_tangents(traj)[:n][early] - self.chain_tangents(reference)[:n][early]).max()
        return float(diff), 1.0

    def beat_signals(self, traj: Trajectory) -> list[np.ndarray]:
        """Each cilium's tip displacement along the major axis of the first cilium's tip path across the wall normal
        (analysis.cilia.tip_signals: one axis for all, so that their phases compare)."""
        return list(cilia_analysis.tip_signals(self.positions(traj)))

    def measure_extra(self, traj: Trajectory, transient: float) -> dict[str, float | str]:
        values = super().measure_extra(traj, transient)
        values["pumped_flux"] = self.pumped_flux(traj, transient)
        return values

    def pumped_flux(self, traj: Trajectory, transient: float) -> float:
        """The steady mean of Blake's flux 6 a sum_i F_x,i z_i, the beads' forces on the fluid from the state
        (reduced.fluid.fluid_forces), over a whole number of its periods (a whirl's flux oscillates about a mean
        that is small against its swing, so a ragged window would bias it); NaN without the fluid."""
        physics = traj.physics
        if not physics.bead_radius > 0:
            return math.nan
        from ..reduced.fluid import fluid_forces  # engine boundary: numba

        keep = np.flatnonzero(traj.t - traj.t[0] >= transient)
        keep = keep[:: max(1, math.ceil(keep.size / FLUX_SAMPLES))]
        tangents = self.chain_tangents(traj)[keep]
        beds = self.beds(physics)
        forces = np.stack([fluid_forces(t, beds) for t in tangents])
        heights = self.positions(traj)[keep][..., 2]
        flux = cilia_analysis.blake_flux(forces[..., 0], heights, physics.bead_radius)
        return observables.whole_period_mean(traj.t[keep], flux, transient=0.0)

    # ------------------------------------------------------------------ drawing
    def painter(self, traj: Trajectory, **options):
        """The first cilium, drawn as a clamped-3d chain in its own frame (clamp axis across the picture)."""
        from ..core.params import Physics  # params imports the registry that holds this class

        first = Physics(scene="clamped-3d", n=traj.physics.n, sigma=traj.physics.sigma)
        shown = Trajectory(traj.t, traj.theta[:, : 2 * traj.physics.n], first, traj.engine, traj.wall_time_s)
        return super().painter(shown, **options)

    def tip_views(self, traj: Trajectory, keep: np.ndarray) -> tuple[PathView, ...]:
        """The tips' paths seen from above (the wall's xy plane), then from the side (xz), then in three dimensions."""
        tips = self.tip(traj)[keep]
        return (
            PathView(tips[..., :2], ("x", "y"), "from above the wall"),
            PathView(tips[..., ::2], ("x", "z"), "from the side"),
            PathView(tips, ("x", "y", "z"), "3D"),
        )

    def draw_shape(self, ax, traj: Trajectory, i: int, labels: list[str]) -> None:
        """The cilia projected on the xz plane (the wall a line at z = 0; dashed: on yz)."""
        positions = self.positions(traj)[i]
        for c, (base, p) in enumerate(zip(self.bases(traj.physics), positions, strict=True)):
            chain = np.vstack([base, p])
            ax.plot(chain[:, 0], chain[:, 2], "-o", ms=4, label=labels[c] if c < len(labels) else None)
            ax.plot(chain[:, 1] + base[0], chain[:, 2], "--", lw=1)
        ax.axhline(0.0, color="k", lw=1)
        if any(labels):  # a single cilium has the one empty label
            ax.legend(fontsize="small")

    def caption_line(self, physics: Physics) -> str:
        parts = [physics.scene, f"N = {physics.n}", f"σ = {physics.sigma:.3g}", *self.caption(physics)]
        if physics.bead_radius > 0:
            parts.append(f"a = {physics.bead_radius:.3g}")
        return "   ".join(parts)

    # ------------------------------------------------------------------ cases
    def validation_cases(self) -> tuple[ValidationCase, ...]:
        """clamped-3d's case, standing on the wall (no fluid: MuJoCo and the reduced engine agree as for it)."""
        return (ValidationCase(self.physics(n=7, sigma=0.4), 300.0),)


SCENE = Cilium()

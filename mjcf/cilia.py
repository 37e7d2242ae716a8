r"""Cilia on a wall as one MuJoCo model: C clamped 3D chains (elastoactive.mjcf.chain3d's, ball joints), each
anchored at its base point b_c with its clamp axis turned by a rotation R, beads coupled through the fluid.

Units l = C1 = gamma = 1 (gamma = 6 pi mu a the drag of one bead). Chain c is chain3d's chain in its own frame
(clamp axis e_x, link k along its body's x axis): its first body sits at b_c turned by R, so particle i of chain c
is at b_c + R sum_{k<=i} t_ck with t_ck its chain-frame tangents (elastoactive.reduced.fluid's convention; a cilium
standing on the wall z = 0 has R e_x = e_z). Names: cilium{c}_segment_{k}, cilium{c}_ball_{k},
cilium{c}_particle_{k}, cilium{c}_drag_long_{k} / _y_{k} / _z_{k} (c, k from 0), clamp_{c}; the stage's floor is the
wall z = 0.

Drag and follower force as chain3d's: three velocity actuators per particle along its site's axes, the follower
force on the longitudinal one's control (-sigma / g). With the fluid (radius > 0) the beads are spheres: all three
actuators have one gain g, and elastoactive.controllers.hydro.FluidCoupling adds the background flow
u = (M - I / g) f of the mobility M (Rotne-Prager-Blake above the wall, or Rotne-Prager-Yamakawa in free space) to
their controls at every step (and the explicit forces of springs between neighbouring cilia's tips, when
tip_coupling > 0). g is the coupling's optimal gain at the start (controllers.hydro.lag_spectrum) unless
given: the beads' motion does not depend on it, the lag's stability does. Without the fluid each cilium is
chain3d's chain (drag ratio gamma_L on the longitudinal actuator), turned and moved.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco
import numpy as np

from ..controllers.hydro import FLOWS, FluidCoupling, lag_spectrum
from ..core.constants import BEAD_RADIUS
from ..core.errors import ParameterError
from . import mjcf_path
from .chain import INTEGRATOR
from .chain3d import BASE_FILE, Chain3DModel, _velocity_actuator, qpos_of_tangents, twist_dofs

INTEGRATORS = ("implicitfast", "implicit")
"""MuJoCo's integrators that split a step (mj_step1, mj_step2) for the coupling and take the drag implicitly."""
AXES = ("long", "y", "z")
"""The drag actuators of a particle, along its site's x (the link), y and z axes."""


@dataclass(frozen=True)
class CiliaModel:
    """What the MuJoCo cilia are built from (units l = C1 = gamma = 1).

    n         particles (links) per cilium
    sigma     follower force F_a l / C1 on every particle
    bases     the cilia's anchors b_c, shape (C, 3), l
    rotation  R (3, 3), orthogonal: lab = b_c + R chain (the clamp axis e_x of every chain becomes R e_x)
    radius    bead radius a / l of the fluid (0: no fluid, each particle its lab-frame drag)
    flow      the mobility with the fluid: 'rpb' (above the no-slip wall z = 0) or 'rpy' (free space)
    gain      the drag actuators' gain g with the fluid (None: the lag's optimal gain at the start)
    drag_ratio  gamma_L of the longitudinal drag without the fluid (1 with it: spheres)
    tip_coupling  stiffness K l^2 / C1 of springs between neighbouring cilia's tips: energy
                K/2 |r_tip,c - r_tip,c+1 - (b_c - b_c+1)|^2 each (reduced.fluid.Beds.tip_coupling), explicit
    clamped   a bending spring holds each chain's first link along its clamp axis (False: a free ball pivot)
    mass_ratio, dt, integrator, twist_damping, twist_inertia   as chain3d.Chain3DModel's
    """

    n: int
    sigma: float
    bases: np.ndarray = field(repr=False)
    rotation: np.ndarray = field(repr=False)
    radius: float = 0.0
    flow: str = "rpb"
    gain: float | None = None
    drag_ratio: float = 1.0
    tip_coupling: float = 0.0
    mass_ratio: float = 1e-4
    dt: float = 0.0025
    integrator: str = "implicitfast"
    twist_damping: float | None = None
    twist_inertia: float | None = None
    clamped: bool = True

    @property
    def chains(self) -> int:
        return int(np.shape(self.bases)[0])

    @property
    def fluid(self) -> bool:
        return self.radius > 0

    @property
    def chain(self) -> Chain3DModel:
        """One cilium as chain3d's record (ball joints): its checks and its twist's inertia and damping."""
        return Chain3DModel(
            self.n, self.sigma, self.drag_ratio, clamped=self.clamped, joints="ball", mass_ratio=self.mass_ratio,
            dt=self.dt, integrator=self.integrator, twist_damping=self.twist_damping,
            twist_inertia=self.twist_inertia,
        )  # fmt: skip

    def checked(self) -> CiliaModel:
        """The record, or ParameterError naming the first field out of range."""
        self.chain.checked()
        bases = np.asarray(self.bases, dtype=float)
        if bases.ndim != 2 or bases.shape[1] != 3 or bases.shape[0] < 1 or not np.all(np.isfinite(bases)):
            raise ParameterError(f"bases must be finite anchor points of shape (C, 3), got shape {bases.shape}")
        rotation = np.asarray(self.rotation, dtype=float)
        if rotation.shape != (3, 3) or not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-12):
            raise ParameterError("rotation must be a 3 x 3 orthogonal matrix")
        if np.linalg.det(rotation) < 0:
            raise ParameterError("rotation must be a proper rotation (determinant +1)")
        if self.integrator not in INTEGRATORS:
            raise ParameterError(f"integrator must be one of {INTEGRATORS} for the cilia, got {self.integrator!r}")
        if not (np.isfinite(self.radius) and self.radius >= 0):
            raise ParameterError(f"radius (bead radius a / l) must be finite and >= 0, got {self.radius}")
        if self.fluid and self.flow not in FLOWS[1:]:
            raise ParameterError(f"flow must be one of {FLOWS[1:]}, got {self.flow!r}")
        if self.fluid and self.drag_ratio != 1.0:
            raise ParameterError(f"drag_ratio: the beads of a fluid are spheres (drag_ratio 1), got {self.drag_ratio}")
        if not (np.isfinite(self.tip_coupling) and self.tip_coupling >= 0):
            raise ParameterError(f"tip_coupling must be finite and >= 0, got {self.tip_coupling}")
        if self.tip_coupling > 0 and self.drag_ratio != 1.0:
            raise ParameterError(
                f"drag_ratio: the tips' spring rides on isotropic drag actuators (drag_ratio 1), got {self.drag_ratio}"
            )
        if self.gain is not None and not (np.isfinite(self.gain) and self.gain > 0):
            raise ParameterError(f"gain (the drag actuators' kv) must be finite and > 0, got {self.gain}")
        if self.fluid and self.flow == "rpb" and not np.all(bases[:, 2] + 1.0 > 0):
            raise ParameterError("bases: every cilium's first bead must be above the wall z = 0")
        return self


def lab_positions(cilia: CiliaModel, tangents: np.ndarray) -> np.ndarray:
    """Particle positions (..., C, N, 3) in the lab of chain-frame tangents (..., C, N, 3)."""
    t = np.asarray(tangents, dtype=float)
    return np.asarray(cilia.bases, dtype=float)[:, None, :] + np.cumsum(t, axis=-2) @ np.asarray(cilia.rotation).T


def resolved_gain(cilia: CiliaModel, tangents0: np.ndarray) -> float:
    """The drag actuators' gain: cilia.gain, else the lag's optimal gain at the start tangents0 (C, N, 3) with the
    fluid, else 1 (the lab-frame drag's)."""
    if cilia.gain is not None:
        return float(cilia.gain)
    if not cilia.fluid:
        return 1.0
    positions = lab_positions(cilia, tangents0)
    return lag_spectrum(positions, cilia.bases, cilia.radius, cilia.flow).optimal_gain


def _quaternion(rotation: np.ndarray) -> np.ndarray:
    q = np.empty(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(rotation, dtype=float).ravel())
    return q


def build_spec(cilia: CiliaModel, gain: float = 1.0) -> mujoco.MjSpec:
    """MjSpec of the cilia (chain3d's base file and pieces): bodies, ball joints, beads, particle sites and their
    drag actuators (gain `gain` on all three with the fluid; drag_ratio and 1 without), clamps at the bases."""
    cilia.checked()
    spec = mujoco.MjSpec.from_file(str(mjcf_path(BASE_FILE)))
    rotation = np.asarray(cilia.rotation, dtype=float)
    quat = _quaternion(rotation)
    clamp_default = spec.find_default("clamp")
    spec.delete(spec.geom("clamp"))
    spec.geom("floor").pos = [0.0, 0.0, 0.0]  # the wall
    segment, link, bead = spec.find_default("segment"), spec.find_default("link"), spec.find_default("bead")
    for c, base in enumerate(np.asarray(cilia.bases, dtype=float)):
        prefix = f"cilium{c}_"
        spec.worldbody.add_geom(name=f"clamp_{c}", default=clamp_default, pos=base - 0.15 * rotation[:, 0], quat=quat)
        parent, pos, orientation = spec.worldbody, base, quat
        for k in range(cilia.n):
            body = parent.add_body(name=f"{prefix}segment_{k}", pos=pos, quat=orientation, childclass="segment")
            stiffness = [0.0 if (k == 0 and not cilia.clamped) else 1.0, 0, 0]
            body.add_joint(name=f"{prefix}ball_{k}", type=mujoco.mjtJoint.mjJNT_BALL, stiffness=stiffness)
            body.add_geom(name=f"{prefix}link_{k}", default=link)
            body.add_geom(name=f"{prefix}bead_{k}", default=bead, mass=cilia.mass_ratio, size=[BEAD_RADIUS, 0, 0])
            body.add_site(name=f"{prefix}particle_{k}", default=segment, userdata=[0.0])
            parent, pos, orientation = body, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]
    gains = (gain, gain, gain) if cilia.fluid else (cilia.drag_ratio, 1.0, 1.0)  # gain 1 without the fluid
    for c in range(cilia.chains):
        for k in range(cilia.n):
            site = f"cilium{c}_particle_{k}"
            for axis, (label, kv) in enumerate(zip(AXES, gains, strict=True)):
                _velocity_actuator(spec, f"cilium{c}_drag_{label}_{k}", site, axis, kv)
    spec.option.timestep = cilia.dt
    spec.option.integrator = INTEGRATOR[cilia.integrator]
    spec.modelname = "cilia"
    return spec


def compile_cilia(cilia: CiliaModel, gain: float = 1.0) -> mujoco.MjModel:
    """The compiled cilia: build_spec's model with each ball joint's twist given chain3d's inertia and damping (as
    chain3d.compile3d)."""
    model = build_spec(cilia, gain).compile()
    twist = twist_dofs(model)
    model.dof_armature[twist] = cilia.chain.inertia
    model.dof_damping[twist] = cilia.chain.damping
    model.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_DAMPER)
    return model


def particle_sites(model: mujoco.MjModel, cilia: CiliaModel) -> np.ndarray:
    """The particle sites' ids, cilium by cilium, particle by particle (C N,)."""
    return np.array([model.site(f"cilium{c}_particle_{k}").id for c in range(cilia.chains) for k in range(cilia.n)])


def drag_actuators(model: mujoco.MjModel, cilia: CiliaModel) -> np.ndarray:
    """The drag actuators' ids (C N, 3): along each particle site's x, y, z."""
    return np.array(
        [
            [model.actuator(f"cilium{c}_drag_{label}_{k}").id for label in AXES]
            for c in range(cilia.chains)
            for k in range(cilia.n)
        ]
    )


def tangents_of(data: mujoco.MjData, model: mujoco.MjModel, cilia: CiliaModel) -> np.ndarray:
    """Chain-frame link tangents (C, N, 3) from the particle sites' positions (after mj_kinematics)."""
    r = data.site_xpos[particle_sites(model, cilia)].reshape(cilia.chains, cilia.n, 3)
    behind = np.concatenate([np.asarray(cilia.bases, dtype=float)[:, None, :], r[:, :-1]], axis=1)
    return (r - behind) @ np.asarray(cilia.rotation, dtype=float)


@dataclass
class PreparedCilia:
    """A model at its start: MuJoCo's model and data, the coupling (None without the fluid) and the gain g."""

    model: mujoco.MjModel
    data: mujoco.MjData
    coupling: FluidCoupling | None
    gain: float
    settle_steps: int = 0

    def stepper(self) -> Callable:
        """What advances the cilia nstep steps: stepper(model, data, nstep) (the coupling, or mujoco.mj_step)."""
        return self.coupling if self.coupling is not None else mujoco.mj_step


def prepare_cilia(cilia: CiliaModel, tangents0: np.ndarray, *, settle: bool = True) -> PreparedCilia:
    """The cilia at rest at chain-frame tangents tangents0 (C, N, 3), the follower controls set; with the fluid or
    the tips' springs, the coupling made (the springs ride on it) and, with the fluid, (settle) its flow and the
    velocities converged to the start's overdamped motion."""
    cilia.checked()
    t0 = np.asarray(tangents0, dtype=float)
    if t0.shape != (cilia.chains, cilia.n, 3):
        raise ParameterError(f"tangents0 must have shape ({cilia.chains}, {cilia.n}, 3), got {t0.shape}")
    gain = resolved_gain(cilia, t0)
    model = compile_cilia(cilia, gain)
    data = mujoco.MjData(model)
    data.qpos[:] = np.concatenate([qpos_of_tangents(cilia.chain, t) for t in t0])
    actuators = drag_actuators(model, cilia)
    data.ctrl[actuators[:, 0]] = -cilia.sigma / (gain if cilia.fluid else cilia.drag_ratio)
    mujoco.mj_forward(model, data)
    if not (cilia.fluid or cilia.tip_coupling > 0):
        return PreparedCilia(model, data, None, gain)
    springs = None
    if cilia.tip_coupling > 0:
        tips = np.arange(cilia.chains) * cilia.n + cilia.n - 1
        bases = np.asarray(cilia.bases, dtype=float)
        springs = (np.column_stack([tips[:-1], tips[1:]]), bases[:-1] - bases[1:], cilia.tip_coupling)
    flow = cilia.flow if cilia.fluid else "identity"  # the spring alone: no flow (u = 0 at the gain 1)
    coupling = FluidCoupling(model, data, particle_sites(model, cilia), actuators, cilia.radius, flow, springs)
    steps = coupling.settle(model, data) if settle and cilia.fluid else 0
    return PreparedCilia(model, data, coupling, gain, steps)


def simulate_cilia(
    cilia: CiliaModel,
    ts: np.ndarray,
    tangents0: np.ndarray,
    *,
    settle: bool = True,
    prepared: Callable[[PreparedCilia], None] | None = None,
    chunked: Callable[[Callable], Callable] | None = None,
    reached: Callable[[float], None] | None = None,
) -> np.ndarray:
    """Chain-frame tangents (len(ts), C, N, 3) of the MuJoCo cilia from tangents0 (C, N, 3), sampled at ts (uniform,
    multiples of dt from ts[0] = 0), coupled through the fluid at every step. Raises RuntimeError when MuJoCo leaves
    finite numbers or a bead goes through the wall.

    Hooks (as chain3d.simulate3d's; none changes the state): prepared(PreparedCilia) once before the first step;
    chunked(stepper) -> step, a function (model, data, nstep) that runs stepper(model, data, k) in chunks (the
    runner's `lambda stepper: StepChunks(meter, stepper)`: the same state, bit for bit); reached(t) after every
    sample."""
    ts = np.asarray(ts, dtype=float)
    sample = ts[1] - ts[0] if ts.size > 1 else cilia.dt
    nstep = int(round(sample / cilia.dt))
    if ts[0] != 0.0 or nstep < 1 or not np.allclose(np.diff(ts), nstep * cilia.dt, rtol=1e-9, atol=1e-12):
        raise ParameterError(f"ts must start at 0 and be evenly spaced by a multiple of dt = {cilia.dt}")
    run = prepare_cilia(cilia, tangents0, settle=settle)
    if prepared is not None:
        prepared(run)
    step = run.stepper() if chunked is None else chunked(run.stepper())
    model, data = run.model, run.data
    out = np.empty((ts.size, cilia.chains, cilia.n, 3))
    out[0] = tangents_of(data, model, cilia)
    for i in range(1, ts.size):
        step(model, data, nstep)
        mujoco.mj_kinematics(model, data)
        out[i] = tangents_of(data, model, cilia)
        if not np.all(np.isfinite(out[i])):
            raise RuntimeError(f"MuJoCo cilia diverged at t = {ts[i]:g} (a smaller dt)")
        if reached is not None:
            reached(float(ts[i]))
    return out

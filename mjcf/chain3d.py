r"""The clamped chain in three dimensions as a MuJoCo model (units l = C1 = gamma_T = 1, so tau = 1).

Mapping (docs/model3d.md, section 5):

  link k                body segment_k (x axis along the link, the particle at (1, 0, 0)), from the clamp at the origin
  joint                 `ball`: one ball joint ball_k, stiffness C = 1 on the whole rotation vector (MuJoCo's ball
                        spring, energy C/2 |rotation angle|^2), or `hinges`: two hinges hinge_k_z then hinge_k_y about
                        the body's z and (turned) y axes, stiffness C each (energy C/2 (a^2 + b^2))
  lab-frame drag        three velocity actuators on particle_k along the site's x (gamma_L = drag ratio), y and z
                        (gamma_T = 1): -(gamma_L t t^T + gamma_T (1 - t t^T)) v, exactly
  follower force        the longitudinal drag actuator's control: its force gamma_L (ctrl - v_x) with ctrl =
                        -w_k sigma / gamma_L is -w_k sigma t - gamma_L (v . t) t, the follower force plus the drag
                        (w_k the particle's load weight: 1 on a loaded particle, 0 on the others), computed
                        by MuJoCo at every stage from the body's own axis (no callback: MuJoCo's site transmission
                        turns it into generalised forces for ball joints and hinges alike)
  twist (ball joints)   a ball joint also turns link k about its own axis; no force of the model does (the particles
                        are on the axis), so the twist only relaxes to where the ball spring is least, zero twist,
                        which is the reduced model's bending energy C/2 phi^2 (docs/model3d.md, section 3). The twist
                        degree of freedom of each ball joint (its rotation about the link's axis relative to the
                        parent: the joint's first dof) gets an inertia twist_inertia (armature) and a damping
                        twist_damping of its own, so the twist is a damped oscillator that MuJoCo steps stably with
                        the explicit ball spring at any dt (twist_inertia ~ C dt^2); neither touches the bending dofs,
                        and both act on the twist's rate relative to the parent, which is ~0 in a steady whirl (every
                        link turning about e_x at one rate): measured, the damping moves the N = 7, sigma = 0.8 whirl's
                        rate by -0.006% per 0.001 (-0.008% at the default)
  mass                  bead of mass m = mass_ratio at the particle (sphere of radius BEAD_RADIUS), as the planar chain

With pairs of hinges there is no twist degree of freedom but the bend is Cardan's: cos(phi) = cos(a) cos(b), so the
spring C/2 (a^2 + b^2) equals C/2 phi^2 only in a plane through a hinge axis (and to second order): the planar chain
exactly, the non-planar one approximately.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np

from ..core.constants import BEAD_RADIUS
from ..core.errors import ParameterError
from . import mjcf_path
from .chain import INTEGRATOR

BASE_FILE = "clamped-3d.xml"
JOINTS = ("ball", "hinges")
TWIST_INERTIA_STEPS = 2.0
"""Default inertia of each ball joint's twist (its armature on the twist dof) in units of C dt^2: the twist oscillates
at sqrt(C / twist_inertia) = 0.71 / dt, inside the stability limit 2 / dt of MuJoCo's explicit spring."""
TWIST_DAMPING_STEPS = 0.5
"""Default damping of each ball joint's twist in units of C dt: damping ratio 0.18 on the twist oscillation (it decays
at 0.125 / dt). Measured on the N = 7, sigma = 0.8 whirl at dt = 0.0025 against the reduced model: frequency -0.03%,
amplitude -0.08% (a rotational drag about each link against the lab, the earlier model, needed 2 C dt for stability
and cost -0.32% in frequency; docs/model3d.md, section 5)."""


@dataclass(frozen=True)
class Chain3DModel:
    """What the MuJoCo 3D chain is built from (units l = C1 = gamma_T = 1)."""

    n: int
    sigma: float
    drag_ratio: float = 1.0
    clamped: bool = True
    joints: str = "ball"
    """'ball' (one ball joint per link) or 'hinges' (two hinges per link)."""
    mass_ratio: float = 1e-4
    dt: float = 0.0025
    integrator: str = "implicitfast"
    twist_damping: float | None = None
    """Damping of each ball joint's twist (torque per twist rate relative to the parent); None: TWIST_DAMPING_STEPS C
    dt."""
    twist_inertia: float | None = None
    """Inertia of each ball joint's twist (its armature); None: TWIST_INERTIA_STEPS C dt^2."""
    load: tuple[float, ...] = ()
    """The follower force's weight on each particle, N numbers >= 0 (1.0 loaded, 0.0 not: particle k carries -load[k]
    sigma t_k); empty: every particle carries it. The reduced model's Chain3D.load."""

    def weights(self) -> np.ndarray:
        """The load's weight on each particle, N numbers (ones when load is empty)."""
        return np.ones(self.n) if len(self.load) == 0 else np.asarray(self.load, dtype=float)

    @property
    def damping(self) -> float:
        """The twist damping in use."""
        return TWIST_DAMPING_STEPS * self.dt if self.twist_damping is None else self.twist_damping

    @property
    def inertia(self) -> float:
        """The twist inertia in use."""
        return TWIST_INERTIA_STEPS * self.dt**2 if self.twist_inertia is None else self.twist_inertia

    def checked(self) -> Chain3DModel:
        """The record, or ParameterError naming the first field out of range."""
        if self.n < 1:
            raise ParameterError(f"n (number of particles N) must be >= 1, got {self.n}")
        if self.joints not in JOINTS:
            raise ParameterError(f"joints must be one of {JOINTS}, got {self.joints!r}")
        if self.integrator not in INTEGRATOR:
            raise ParameterError(f"integrator must be one of {tuple(INTEGRATOR)}, got {self.integrator!r}")
        for name, value in (("drag_ratio", self.drag_ratio), ("mass_ratio", self.mass_ratio), ("dt", self.dt),
                            ("twist_damping", self.damping), ("twist_inertia", self.inertia)):  # fmt: skip
            if not (np.isfinite(value) and value > 0):
                raise ParameterError(f"{name} must be finite and > 0, got {value}")
        if not (np.isfinite(self.sigma) and self.sigma >= 0):
            raise ParameterError(f"sigma must be finite and >= 0, got {self.sigma}")
        if len(self.load) not in (0, self.n):
            raise ParameterError(f"load must hold {self.n} weights (one per particle) or none, got {len(self.load)}")
        if not all(np.isfinite(w) and w >= 0 for w in self.load):
            raise ParameterError(f"load (the particles' weights) must be finite and >= 0, got {self.load}")
        return self


def _velocity_actuator(spec, name: str, site: str, axis: int, kv: float) -> None:
    gear = [0.0] * 6
    gear[axis] = 1.0
    spec.add_actuator(
        name=name,
        target=site,
        trntype=mujoco.mjtTrn.mjTRN_SITE,
        gear=gear,
        gainprm=[kv] + [0] * 9,
        biasprm=[0, 0, -kv] + [0] * 7,
        biastype=mujoco.mjtBias.mjBIAS_AFFINE,
        gaintype=mujoco.mjtGain.mjGAIN_FIXED,
        dyntype=mujoco.mjtDyn.mjDYN_NONE,
    )


def build_spec3d(chain: Chain3DModel) -> mujoco.MjSpec:
    """MjSpec of the 3D chain: its bodies, joints and actuators (compile3d adds the twist's inertia and damping; set the
    controls with `controls`)."""
    chain.checked()
    spec = mujoco.MjSpec.from_file(str(mjcf_path(BASE_FILE)))
    segment = spec.find_default("segment")
    link, bead = spec.find_default("link"), spec.find_default("bead")
    parent, pos = spec.worldbody, [0.0, 0.0, 0.0]
    for k in range(chain.n):
        body = parent.add_body(name=f"segment_{k}", pos=pos, childclass="segment")
        stiffness = [0.0 if (k == 0 and not chain.clamped) else 1.0, 0, 0]
        if chain.joints == "ball":
            body.add_joint(name=f"ball_{k}", type=mujoco.mjtJoint.mjJNT_BALL, stiffness=stiffness)
        else:
            for axis, label in (([0, 0, 1], "z"), ([0, 1, 0], "y")):
                body.add_joint(name=f"hinge_{k}_{label}", default=segment, axis=axis, stiffness=stiffness)
        body.add_geom(name=f"link_{k}", default=link)
        body.add_geom(name=f"bead_{k}", default=bead, mass=chain.mass_ratio, size=[BEAD_RADIUS, 0, 0])
        body.add_site(name=f"particle_{k}", default=segment, userdata=[0.0])  # 0: the callback adds nothing
        parent, pos = body, [1.0, 0.0, 0.0]
    for k in range(chain.n):
        site = f"particle_{k}"
        _velocity_actuator(spec, f"drag_long_{k}", site, 0, chain.drag_ratio)
        _velocity_actuator(spec, f"drag_y_{k}", site, 1, 1.0)
        _velocity_actuator(spec, f"drag_z_{k}", site, 2, 1.0)
    spec.option.timestep = chain.dt
    spec.option.integrator = INTEGRATOR[chain.integrator]
    spec.modelname = "chain3d"
    return spec


def twist_dofs(model: mujoco.MjModel) -> np.ndarray:
    """The twist dof of every ball joint (its first: the rotation about the child link's x axis, its own axis)."""
    balls = np.flatnonzero(model.jnt_type == mujoco.mjtJoint.mjJNT_BALL)
    return model.jnt_dofadr[balls]


def compile3d(chain: Chain3DModel) -> mujoco.MjModel:
    """The compiled 3D chain: build_spec3d's model with, on each ball joint's twist dof only, the armature
    chain.inertia and the damping chain.damping (MuJoCo's passive damping, enabled here; implicit in implicitfast,
    implicit and Euler). MjSpec sets a ball joint's armature and damping on all three of its dofs, hence after
    compiling."""
    model = build_spec3d(chain).compile()
    twist = twist_dofs(model)
    if twist.size:
        model.dof_armature[twist] = chain.inertia
        model.dof_damping[twist] = chain.damping
        model.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_DAMPER)
    return model


def controls(model: mujoco.MjModel, chain: Chain3DModel) -> np.ndarray:
    """The actuators' controls: -w_k sigma / gamma_L on particle k's longitudinal drag actuator (the follower force on
    it, w_k its load weight: chain.weights), 0 on the others."""
    ctrl = np.zeros(model.nu)
    for k, weight in enumerate(chain.weights()):
        ctrl[model.actuator(f"drag_long_{k}").id] = -weight * chain.sigma / chain.drag_ratio
    return ctrl


def _quat_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The unit quaternion of the least rotation taking unit vector a to unit vector b (not antiparallel)."""
    q = np.concatenate([[1.0 + a @ b], np.cross(a, b)])
    return q / np.linalg.norm(q)


def _rotation(q: np.ndarray) -> np.ndarray:
    mat = np.empty(9)
    mujoco.mju_quat2Mat(mat, q)
    return mat.reshape(3, 3)


def qpos_of_tangents(chain: Chain3DModel, tangents: np.ndarray) -> np.ndarray:
    """MuJoCo's qpos for link tangents (N, 3): ball joints at zero twist (each joint the least rotation from its
    parent's axis to its link: the relaxed twist), or the Cardan angles (a, b) of each pair of hinges."""
    tangents = np.asarray(tangents, dtype=float)
    if tangents.shape != (chain.n, 3):
        raise ParameterError(f"tangents must have shape ({chain.n}, 3), got {tangents.shape}")
    frame = np.eye(3)  # the parent's orientation (world from body)
    q = []
    ex = np.array([1.0, 0.0, 0.0])
    for t in tangents / np.linalg.norm(tangents, axis=1)[:, None]:
        local = frame.T @ t
        if chain.joints == "ball":
            quat = _quat_between(ex, local)
            q.extend(quat)
            frame = frame @ _rotation(quat)
        else:
            a = np.arctan2(local[1], local[0])
            b = np.arctan2(-local[2], np.hypot(local[0], local[1]))
            q.extend([a, b])
            ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
            frame = (
                frame
                @ np.array([[ca, -sa, 0], [sa, ca, 0], [0, 0, 1]])
                @ np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
            )
    return np.array(q)


def tangents_of(data: mujoco.MjData, n: int) -> np.ndarray:
    """Link tangents (N, 3) from the particle sites' positions (after mj_kinematics): t_k = r_k - r_{k-1}."""
    r = data.site_xpos[:n]
    return np.diff(r, axis=0, prepend=np.zeros((1, 3)))


def prepare3d(chain: Chain3DModel, tangents0: np.ndarray) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Model and data at rest at the tangents tangents0, with the follower controls set."""
    model = compile3d(chain)
    data = mujoco.MjData(model)
    data.qpos[:] = qpos_of_tangents(chain, tangents0)
    data.ctrl[:] = controls(model, chain)
    mujoco.mj_forward(model, data)
    return model, data


def simulate3d(
    chain: Chain3DModel,
    ts: np.ndarray,
    tangents0: np.ndarray,
    *,
    prepared: Callable[[mujoco.MjModel, mujoco.MjData], None] | None = None,
    step: Callable[[mujoco.MjModel, mujoco.MjData, int], None] | None = None,
    reached: Callable[[float], None] | None = None,
) -> np.ndarray:
    """Tangents (len(ts), N, 3) of the MuJoCo chain from rest at tangents0, sampled at ts (uniform, multiples of dt
    from ts[0] = 0). Raises RuntimeError when MuJoCo leaves finite numbers.

    The engine runner's hooks (engines.runner; none changes the state): prepared(model, data) once before the first
    step (a cost estimate on a copy of the state), step(model, data, nstep) instead of mj_step's nstep steps (in
    chunks that report progress: the same state, bit for bit), reached(t) after every sample."""
    ts = np.asarray(ts, dtype=float)
    sample = ts[1] - ts[0] if ts.size > 1 else chain.dt
    nstep = int(round(sample / chain.dt))
    if ts[0] != 0.0 or nstep < 1 or not np.allclose(np.diff(ts), nstep * chain.dt, rtol=1e-9, atol=1e-12):
        raise ParameterError(f"ts must start at 0 and be evenly spaced by a multiple of dt = {chain.dt}")
    model, data = prepare3d(chain, tangents0)
    if prepared is not None:
        prepared(model, data)
    out = np.empty((ts.size, chain.n, 3))
    out[0] = tangents_of(data, chain.n)
    for i in range(1, ts.size):
        if step is None:
            mujoco.mj_step(model, data, nstep=nstep)
        else:
            step(model, data, nstep)
        mujoco.mj_kinematics(model, data)
        out[i] = tangents_of(data, chain.n)
        if not np.all(np.isfinite(out[i])):
            raise RuntimeError(f"MuJoCo 3D chain diverged at t = {ts[i]:g} (a smaller dt)")
        if reached is not None:
            reached(float(ts[i]))
    return out

"""The one place that turns the paper's dimensionless parameters into a MuJoCo model.

A scene is built from its base MJCF file (mjcf/<scene>.xml): the file supplies the options,
default classes, lights and markers; the chain(s), drag actuators, pin and coupling are
(re)generated here for any N. Mapping (units l = C1 = gamma_T = 1, so tau = 1):

  joint stiffness       1 (chain 1), rho (chain 2); the first hinge of the rotating pin has none
  follower force        site user value sigma on every particle (applied by the C callback)
  lab-frame drag        two velocity actuators per particle site, x (along the pendulum) with
                        kv = gamma_L = drag_ratio and y (across) with kv = gamma_T = 1
  particle mass         bead geom mass = mass_ratio (inertial time m / gamma in units of tau)
  pin (two-pinned)      connect equality: last particle to a world site at (N (1 - delta), 0)
  coupling (pair)       fixed tendon hinge_0(chain 1) - hinge_0(chain 2), stiffness kappa,
                        springlength 0: U_c = kappa/2 (theta_1 - phi_1)^2 exactly
  callback marker       custom numeric elastoactive_follower = (noise amplitude a, seed): the
                        C callback acts only on models that carry it
"""

from __future__ import annotations

import mujoco
import numpy as np

from .initial import buckled_arch
from .mjcf import scene_path
from .params import Numerics, Physics

INTEGRATOR = {
    "Euler": mujoco.mjtIntegrator.mjINT_EULER,
    "RK4": mujoco.mjtIntegrator.mjINT_RK4,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "discrete": mujoco.mjtIntegrator.mjINT_DISCRETE,
}

# The pin is a soft constraint; its time constant is MuJoCo's floor 2 dt (set explicitly, since
# MuJoCo would raise a smaller one silently) and its impedance is close to 1 (nearly hard). With
# the particles' tiny mass the default solimp lets the pin drift by ~1e-2 l (MUJOCO_NOTES.md).
PIN_SOLIMP = (0.9999, 0.999999, 0.001, 0.5, 2.0)


def chain_prefixes(physics: Physics) -> tuple[str, ...]:
    return ("chain1_", "chain2_") if physics.scene == "coupled-pair" else ("",)


def chain_offset(physics: Physics, k: int) -> float:
    """Lateral (y) position of chain k's clamp: side by side, far enough apart to see both."""
    return -float(max(physics.n, 3)) * k


def _add_chain(spec: mujoco.MjSpec, prefix: str, physics: Physics, numerics: Numerics, stiffness: float, y: float):
    segment = spec.find_default("segment")
    link, bead, drag = (spec.find_default(c) for c in ("link", "bead", "drag"))
    parent, pos = spec.worldbody, [0.0, y, 0.0]
    for i in range(physics.n):
        body = parent.add_body(name=f"{prefix}segment_{i}", pos=pos, childclass="segment")
        clamp_spring = 0.0 if (i == 0 and not physics.clamped) else stiffness
        body.add_joint(name=f"{prefix}hinge_{i}", default=segment, stiffness=[clamp_spring, 0, 0])
        body.add_geom(name=f"{prefix}link_{i}", default=link)
        body.add_geom(name=f"{prefix}bead_{i}", default=bead, mass=numerics.mass_ratio)
        body.add_site(name=f"{prefix}particle_{i}", default=segment, userdata=[physics.sigma])
        parent, pos = body, [1.0, 0.0, 0.0]
    for i in range(physics.n):
        site = f"{prefix}particle_{i}"
        for axis, name, gamma in ((0, "long", physics.drag_ratio), (1, "trans", 1.0)):
            gear = [0.0] * 6
            gear[axis] = 1.0
            spec.add_actuator(
                name=f"{prefix}drag_{name}_{i}", default=drag, target=site, trntype=mujoco.mjtTrn.mjTRN_SITE,
                gear=gear, gainprm=[gamma] + [0] * 9, biasprm=[0, 0, -gamma] + [0] * 7,
            )


def build_spec(physics: Physics, numerics: Numerics = Numerics()) -> mujoco.MjSpec:
    """MjSpec of a scene with these parameters (compile it with .compile())."""
    spec = mujoco.MjSpec.from_file(str(scene_path(physics.scene)))
    for element in [*spec.actuators, *spec.keys, *spec.equalities, *spec.tendons]:
        spec.delete(element)
    for prefix in chain_prefixes(physics):
        spec.delete(spec.body(f"{prefix}segment_0"))

    for k, (prefix, stiffness) in enumerate(zip(chain_prefixes(physics), physics.stiffness)):
        _add_chain(spec, prefix, physics, numerics, stiffness, chain_offset(physics, k))

    spec.option.timestep = numerics.dt
    spec.option.integrator = INTEGRATOR[numerics.integrator]
    spec.modelname = physics.scene

    if physics.scene == "two-pinned":
        end = physics.n * (1.0 - physics.delta)
        spec.site("pin").pos = [end, 0.0, 0.0]
        spec.geom("pin_marker").pos = [end, 0.0, 0.0]
        solref = [2.0 * numerics.dt, 1.0]
        spec.add_equality(
            name="pin", type=mujoco.mjtEq.mjEQ_CONNECT, objtype=mujoco.mjtObj.mjOBJ_SITE,
            name1=f"particle_{physics.n - 1}", name2="pin", solref=solref, solimp=list(PIN_SOLIMP),
        )
        arch = buckled_arch(physics.n, physics.delta)
        spec.add_key(name="buckled", qpos=np.diff(arch, prepend=0.0).tolist())
    if physics.scene == "coupled-pair":
        spec.geom("clamp2").pos = [-0.15, chain_offset(physics, 1), 0.0]
        tendon = spec.add_tendon(name="coupling", stiffness=[physics.kappa, 0, 0], springlength=[0.0, 0.0])
        tendon.wrap_joint("chain1_hinge_0", 1.0)
        tendon.wrap_joint("chain2_hinge_0", -1.0)
    spec.numeric("elastoactive_follower").data = [physics.noise, float(numerics.seed)]
    return spec


def build_model(physics: Physics, numerics: Numerics = Numerics()) -> mujoco.MjModel:
    """Compiled MjModel of a scene."""
    return build_spec(physics, numerics).compile()


def relative_angles(physics: Physics, theta: np.ndarray) -> np.ndarray:
    """MuJoCo hinge angles q from absolute angles theta (q_1 = theta_1, q_i = theta_i - theta_{i-1})."""
    theta = np.asarray(theta, dtype=float).reshape(physics.n_chains, physics.n)
    return np.diff(theta, axis=1, prepend=0.0).ravel()


def absolute_angles(physics: Physics, qpos: np.ndarray) -> np.ndarray:
    """Absolute angles theta from hinge angles (works on (..., nq) arrays)."""
    q = np.asarray(qpos, dtype=float)
    shape = q.shape[:-1] + (physics.n_chains, physics.n)
    return np.cumsum(q.reshape(shape), axis=-1).reshape(q.shape)

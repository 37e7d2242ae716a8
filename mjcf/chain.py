"""The one place that turns the paper's dimensionless parameters into a MuJoCo model.

A scene is built from its base MJCF file (mjcf/<scene>.xml, Scene.base_file): the file supplies
the options, default classes, lights and markers; the chain(s) and drag actuators are
(re)generated here for any N, and the scene adds its own elements (Scene.build: a pin, a
coupling). Mapping (units l = C1 = gamma_T = 1, so tau = 1):

  joint stiffness       Scene.stiffness (1 for chain 1, rho for the pair's chain 2); no spring on
                        the first hinge of an unclamped scene (the rotating pin)
  follower force        site user value sigma on every loaded particle (physics.loaded; 0 on the others,
                        which the C callback skips)
  lab-frame drag        two velocity actuators per particle site, x (along the pendulum) with
                        kv = gamma_L = drag_ratio and y (across) with kv = gamma_T = 1
  particle mass         bead geom mass = mass_ratio (inertial time m / gamma in units of tau), a sphere of radius
                        constants.BEAD_RADIUS
  callback marker       custom numeric elastoactive_follower = (noise amplitude a, seed, correlation
                        time tau_c): the C callback acts only on models that carry it; a and tau_c 0 here, the
                        noise term's (elastoactive.terms.noise) when it acts
  terms                 each active term adds its own elements (Term.build, after the scene's): self-contact
                        its capsules (elastoactive.terms.contact)
"""

from __future__ import annotations

import threading

import mujoco
import numpy as np

from ..core.constants import BEAD_RADIUS
from ..core.errors import ParameterError
from ..core.params import Numerics, Physics
from ..core.registry import initial_angles
from ..terms import align_polarities
from . import mjcf_path

INTEGRATOR = {
    "Euler": mujoco.mjtIntegrator.mjINT_EULER,
    "RK4": mujoco.mjtIntegrator.mjINT_RK4,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "discrete": mujoco.mjtIntegrator.mjINT_DISCRETE,
}


def _add_chain(
    spec: mujoco.MjSpec, prefix: str, physics: Physics, numerics: Numerics, stiffness: float, y: float, chain: int = 0
):
    segment = spec.find_default("segment")
    link, bead = (spec.find_default(c) for c in ("link", "bead"))
    parent, pos = spec.worldbody, [0.0, y, 0.0]
    loaded = physics.load_mask()
    for i in range(physics.n):
        body = parent.add_body(name=f"{prefix}segment_{i}", pos=pos, childclass="segment")
        clamp_spring = 0.0 if (i == 0 and not physics.clamped) else stiffness
        body.add_joint(name=f"{prefix}hinge_{i}", default=segment, stiffness=[clamp_spring, 0, 0])
        body.add_geom(name=f"{prefix}link_{i}", default=link)
        body.add_geom(name=f"{prefix}bead_{i}", default=bead, mass=numerics.mass_ratio, size=[BEAD_RADIUS, 0, 0])
        body.add_site(name=f"{prefix}particle_{i}", default=segment, userdata=[physics.sigma if loaded[i] else 0.0])
        parent, pos = body, [1.0, 0.0, 0.0]
    for i in range(physics.n):
        add_drag(spec, f"{prefix}particle_{i}", f"{i}", physics, prefix)


def add_drag(spec: mujoco.MjSpec, site: str, label: str, physics: Physics, prefix: str = "") -> None:
    """One particle's lab-frame drag on `site`: velocity actuators {prefix}drag_long_{label} (along the site's x,
    gamma_L = drag_ratio) and {prefix}drag_trans_{label} (across, gamma_T = 1)."""
    drag = spec.find_default("drag")
    for axis, name, gamma in ((0, "long", physics.drag_ratio), (1, "trans", 1.0)):
        gear = [0.0] * 6
        gear[axis] = 1.0
        spec.add_actuator(
            name=f"{prefix}drag_{name}_{label}",
            default=drag,
            target=site,
            trntype=mujoco.mjtTrn.mjTRN_SITE,
            gear=gear,
            gainprm=[gamma] + [0] * 9,
            biasprm=[0, 0, -gamma] + [0] * 7,
        )


def add_sliding_head(spec: mujoco.MjSpec, physics: Physics, numerics: Numerics) -> None:
    """Free the first pendulum's pivot in the plane: slides head_x, head_y before hinge_0 (qpos = (x_h, y_h, hinge
    angles)), a bead of one particle's mass and a site "head" carrying one particle's drag (the paraboloid's head,
    the free ring's root)."""
    first = spec.body("segment_0")
    spec.delete(spec.joint("hinge_0"))  # the slides go first
    for axis, name in ((0, "head_x"), (1, "head_y")):
        direction = [0.0, 0.0, 0.0]
        direction[axis] = 1.0
        first.add_joint(name=name, type=mujoco.mjtJoint.mjJNT_SLIDE, axis=direction, stiffness=[0, 0, 0])
    first.add_joint(name="hinge_0", default=spec.find_default("segment"), stiffness=[0, 0, 0])
    first.add_geom(name="head_bead", default=spec.find_default("bead"), pos=[0, 0, 0], mass=numerics.mass_ratio)
    first.add_site(name="head", default=spec.find_default("segment"), pos=[0, 0, 0], userdata=[0.0])
    add_drag(spec, "head", "head", physics)  # one particle's drag


_TEMPLATES: dict[tuple, mujoco.MjSpec] = {}
"""A scene's base file parsed, with its template chain(s) and generated elements deleted (_template), by
(base file, chain prefixes)."""
_TEMPLATES_LOCK = threading.Lock()


def _template(scene) -> mujoco.MjSpec:
    """A fresh copy of the scene's base MjSpec without its template elements (what build_spec starts from).
    Parsing the file and deleting the elements costs ~1 ms; it is done once per process and base file, and
    every call gets its own MjSpec.copy() (~15 us), which compiles to the same model, bit for bit
    (tests/sweep/test_sweep.py). Thread-safe (sweeps prepare points on several threads)."""
    path = str(mjcf_path(scene.base_file))
    prefixes = tuple(scene.chain_prefixes())
    key = (path, prefixes)
    with _TEMPLATES_LOCK:
        template = _TEMPLATES.get(key)
        if template is None:
            template = mujoco.MjSpec.from_file(path)
            for element in [*template.actuators, *template.keys, *template.equalities, *template.tendons]:
                template.delete(element)
            for prefix in prefixes:
                template.delete(template.body(f"{prefix}segment_0"))
            _TEMPLATES[key] = template
        return template.copy()


def build_spec(physics: Physics, numerics: Numerics = Numerics()) -> mujoco.MjSpec:
    """MjSpec of a scene with these parameters (compile it with .compile())."""
    scene = physics.scene_def
    if scene.builder != __name__:  # a scene of another kind (a network: nodes on slides) has its own builder
        raise ParameterError(
            f"{scene.name} is a {scene.kind}, not a chain: its MuJoCo model is built by {scene.builder}"
        )
    spec = _template(scene)
    prefixes = scene.chain_prefixes()

    for k, (prefix, stiffness) in enumerate(zip(prefixes, scene.stiffness(physics))):
        _add_chain(spec, prefix, physics, numerics, stiffness, scene.chain_offset(physics, k), k)

    spec.option.timestep = numerics.dt
    spec.option.integrator = INTEGRATOR[numerics.integrator]
    spec.modelname = scene.name
    marker = spec.numeric("elastoactive_follower")  # mjcf/common.xml declares (a, seed); tau_c goes after them
    marker.size = 3
    marker.data = [0.0, float(numerics.seed), 0.0]  # no noise (the noise term sets a and tau_c)
    for term in physics.active_terms():  # the terms' elements on the chains (noise, self-contact, a plug-in's)
        term.build(spec, physics, numerics)
    scene.build(spec, physics, numerics)
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


def head_coordinates(physics: Physics) -> int:
    """Coordinates of qpos before the hinge angles: the scene's moving pivot (the paraboloid's head), or the two
    slides of a term that moves chain 1's clamp point (Term.clamp_motion); 0 when the pivot is fixed."""
    count = physics.scene_def.head_count(physics)
    if count:
        return count
    moving = (term.clamp_motion(physics) for term in physics.active_terms())
    return 2 if any(m is not None and m.translates for m in moving) else 0


def qpos_of(physics: Physics, theta: np.ndarray, head: np.ndarray | None = None) -> np.ndarray:
    """MuJoCo's qpos of a state: the head's position first for a scene with a moving pivot (default: the origin),
    then the hinge angles."""
    q = relative_angles(physics, theta)
    count = head_coordinates(physics)
    if not count:
        return q
    head = np.zeros(count) if head is None else np.asarray(head, dtype=float).reshape(count)
    return np.concatenate([head, q])


def state_of(physics: Physics, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """(absolute angles, head position or None) of qpos (works on (..., nq) arrays)."""
    q = np.asarray(qpos, dtype=float)
    count = head_coordinates(physics)
    if not count:
        return absolute_angles(physics, q), None
    return absolute_angles(physics, q[..., count:]), q[..., :count].copy()


def prepare(physics: Physics, numerics: Numerics, theta0: np.ndarray | None = None, head0: np.ndarray | None = None):
    """Model and data at the initial state (absolute angles theta0, default: seeded perturbation; head0: the head's
    position for a scene with a moving pivot, default the origin)."""
    model = build_model(physics, numerics)
    data = mujoco.MjData(model)
    theta0 = initial_angles(physics, numerics) if theta0 is None else np.asarray(theta0, dtype=float)
    if theta0.shape != (physics.n_angles,):
        raise ParameterError(f"theta0 must have {physics.n_angles} angles, got shape {theta0.shape}")
    data.qpos[:] = qpos_of(physics, theta0, head0)
    for term in physics.active_terms():  # what a term sets in the initial state (a moving clamp's velocity)
        term.start(physics, model, data)
    mujoco.mj_forward(model, data)
    if model.na:  # units that carry a polarity: theirs at t = 0 (self-aligning: the follower direction's)
        align_polarities(model, data)
        mujoco.mj_forward(model, data)
    return model, data

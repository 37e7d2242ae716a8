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
                        time tau_c): the C callback acts only on models that carry it
  noise state           coloured noise (tau_c > 0): nuserdata = 1 + number of particles; mjData.userdata
                        holds (held step + 1, eta of each particle), see controllers/follower.c
  self-contact          (physics.contact) a capsule geom on each link, radius contact_radius, length
                        CONTACT_LENGTH centred on the link; chain k collides only with itself (contype =
                        conaffinity = 2^k), parent-child filtering keeps neighbours apart; frictionless
                        (condim 1) or condim 3 with contact_friction. Softness for the overdamped limit:
                        see contact_solref
"""

from __future__ import annotations

import threading

import mujoco
import numpy as np

from .analysis.reduced.contact import core_span
from .constants import BEAD_RADIUS
from .errors import ParameterError
from .initial import initial_angles
from .mjcf import mjcf_path
from .params import Numerics, Physics

CONTACT_IMPEDANCE = 0.99
"""MuJoCo's constraint impedance d of a self-contact (solimp d0 = d_width = d): the share of the pushing force
the contact cancels within the step; the rest, (1 - d), is left to the contact's reference spring."""
CONTACT_RATE = 0.25
"""Contact spring K_c in units of gamma / dt: the overlap relaxes by about this fraction of itself per step."""


def contact_solref(numerics: Numerics) -> list[float]:
    """solref (-stiffness, -damping) of a self-contact, made for the overdamped limit.

    MuJoCo's soft constraints ask for a reference acceleration a_ref = -b v - k r and produce a force of the
    contact's effective mass times it; with implicit drag that force is then divided by (m + dt gamma), so a
    standard solref (time constant, damping ratio) holds a particle of mass m -> 0 with a force ~ m / dt^2:
    at mass_ratio 1e-4 and dt 0.0025 the capsules pass through each other (overlap ~ 2R, measured). Scaled
    by 1/m, b = gamma / m and k = K_c / m with K_c = CONTACT_RATE gamma / dt, the normal motion of an
    overdamped particle in contact obeys gamma v = (1 - d) F_n - d K_c r: the contact cancels a share d of
    the force pushing in and pulls the overlap r back at rate ~ d K_c / gamma, independently of the mass.
    The overlap then falls like dt (a hard contact in the limit): N = 17, sigma = 0.8, largest overlap
    0.0027 l at dt 0.0025, 0.0010 l at dt 0.00125, the same at mass ratio 1e-4 and 1e-5 (docs/mujoco.md)."""
    mass = numerics.mass_ratio
    return [-CONTACT_RATE / numerics.dt / mass, -1.0 / mass]


INTEGRATOR = {
    "Euler": mujoco.mjtIntegrator.mjINT_EULER,
    "RK4": mujoco.mjtIntegrator.mjINT_RK4,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "discrete": mujoco.mjtIntegrator.mjINT_DISCRETE,
}


def _add_capsule(spec: mujoco.MjSpec, body, name: str, physics: Physics, numerics: Numerics, chain: int) -> None:
    """The link's contact capsule (physics.contact): see the module docstring and contact_solref."""
    radius = physics.contact_radius
    start, end = core_span(radius)  # the reduced model's capsule: CONTACT_LENGTH long, centred on the link
    bits = 1 << chain
    d = CONTACT_IMPEDANCE
    friction = physics.contact_friction
    body.add_geom(name=name, default=spec.find_default("capsule"), fromto=[start, 0, 0, end, 0, 0],
                  size=[radius, 0, 0], contype=bits, conaffinity=bits, condim=3 if friction > 0 else 1,
                  friction=[friction, 0.005, 0.0001], solref=contact_solref(numerics), solimp=[d, d, 0.001, 0.5, 2])


def _add_chain(spec: mujoco.MjSpec, prefix: str, physics: Physics, numerics: Numerics, stiffness: float, y: float,
               chain: int = 0):
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
        if physics.contact:
            _add_capsule(spec, body, f"{prefix}capsule_{i}", physics, numerics, chain)
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
            name=f"{prefix}drag_{name}_{label}", default=drag, target=site, trntype=mujoco.mjtTrn.mjTRN_SITE,
            gear=gear, gainprm=[gamma] + [0] * 9, biasprm=[0, 0, -gamma] + [0] * 7,
        )


_TEMPLATES: dict[tuple, mujoco.MjSpec] = {}
"""A scene's base file parsed, with its template chain(s) and generated elements deleted (_template), by
(base file, chain prefixes)."""
_TEMPLATES_LOCK = threading.Lock()


def _template(scene) -> mujoco.MjSpec:
    """A fresh copy of the scene's base MjSpec without its template elements (what build_spec starts from).
    Parsing the file and deleting the elements costs ~1 ms; it is done once per process and base file, and
    every call gets its own MjSpec.copy() (~15 us), which compiles to the same model, bit for bit
    (tests/test_sweep.py). Thread-safe (sweeps prepare points on several threads)."""
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
    spec = _template(scene)
    prefixes = scene.chain_prefixes()

    for k, (prefix, stiffness) in enumerate(zip(prefixes, scene.stiffness(physics))):
        _add_chain(spec, prefix, physics, numerics, stiffness, scene.chain_offset(physics, k), k)
    if physics.contact:  # the scenes switch these off (mjcf/common.xml): self-contact needs them
        for flag in (mujoco.mjtDisableBit.mjDSBL_CONTACT, mujoco.mjtDisableBit.mjDSBL_FILTERPARENT,
                     mujoco.mjtDisableBit.mjDSBL_CONSTRAINT):
            spec.option.disableflags &= ~int(flag)

    spec.option.timestep = numerics.dt
    spec.option.integrator = INTEGRATOR[numerics.integrator]
    spec.modelname = scene.name
    scene.build(spec, physics, numerics)
    for term in physics.active_terms():  # a plug-in term's elements (the built-in ones are the chain's, above)
        term.build(spec, physics, numerics)
    if physics.noise > 0 and physics.noise_correlation == 0 and physics.noise_calculus != "ito":
        raise ParameterError(
            "MuJoCo applies white noise in the Ito reading only (constant over each step); for the Stratonovich "
            "reading give the noise a short correlation time (--noise-correlation, its Wong-Zakai limit), or use "
            "the reduced engine")
    marker = spec.numeric("elastoactive_follower")  # mjcf/common.xml declares (a, seed); tau_c goes after them
    marker.size = 3
    marker.data = [physics.noise, float(numerics.seed), physics.noise_correlation]
    if physics.noise_correlation > 0:
        spec.nuserdata = 1 + physics.n_angles  # the coloured noise's state (follower.c)
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


def qpos_of(physics: Physics, theta: np.ndarray, head: np.ndarray | None = None) -> np.ndarray:
    """MuJoCo's qpos of a state: the head's position first for a scene with a moving pivot (default: the origin),
    then the hinge angles."""
    q = relative_angles(physics, theta)
    count = physics.scene_def.head_coordinates
    if not count:
        return q
    head = np.zeros(count) if head is None else np.asarray(head, dtype=float).reshape(count)
    return np.concatenate([head, q])


def state_of(physics: Physics, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """(absolute angles, head position or None) of qpos (works on (..., nq) arrays)."""
    q = np.asarray(qpos, dtype=float)
    count = physics.scene_def.head_coordinates
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
    mujoco.mj_forward(model, data)
    return model, data

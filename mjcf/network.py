"""The one place that turns an elastic network of active units (analysis.network.Network) into a MuJoCo model.

The model is generated in code from the base file mjcf/network.xml (its options, default classes and stage; its
example hexagon is deleted), as elastoactive.mjcf.chain generates the chains. Mapping (units k = gamma = a = 1, so time
is in gamma / k):

  free node i           body node_{i} at the node's rest position, with two slide joints node_{i}_x, node_{i}_y
                        (world axes: qpos is the displacement from the rest position) and a site node_{i}
  pinned node i         a site node_{i} on the world body at its rest position (it never moves)
  spring b              spatial tendon spring_{b} between its two nodes' sites, stiffness network.stiffness[b],
                        springlength network.rest_lengths[b]: the exact linear spring -k (|r| - a) r / |r| (a spring
                        between two pinned nodes acts on nothing and is left out)
  harmonic trap         the slide joints' own stiffness network.trap with springref at the node's anchor: the exact
                        isotropic force -trap (x - anchor) (a zero-length tendon would have no direction at zero
                        length)
  lab-frame drag        the slide joints' damping gamma = 1: exactly -gamma v along each world axis, taken implicitly
                        by implicitfast (and implicit, discrete) at no cost beyond the diagonal it adds
  node mass             bead geom mass = mass_ratio (inertial time m / gamma in units of gamma / k)
  active unit on node i the site's first user value F_a = sigma (times the unit's force factor, network.unit_force)
                        and a self-aligning unit on the site (its actuator's dynprm[0] the unit's own l_a where
                        network.unit_alignment_length gives it)
                        (Term.add_unit of the polarity term, the self-aligning term's: an actuator
                        node_{i}_polarity with user dynamics whose activation is the polarity psi_i, its
                        transmission the node's x slide, a pinned node's its site; controllers/follower.c turns
                        psi at (v . n_perp) / l_a and applies F_a (cos psi, sin psi)); every active node has one,
                        also at sigma = 0 (its polarity then turns without a force), so that the state has the same
                        shape at every sigma
  callback marker       custom numeric elastoactive_follower (noise amplitude 0, seed): the compiled callback acts
                        only on models that carry it
"""

from __future__ import annotations

import threading

import mujoco
import numpy as np

from ..core.errors import ParameterError
from ..core.params import Numerics, Physics
from ..networks.geometry import unit_alignment_lengths, unit_forces
from ..terms import polarity_addresses, polarity_term, polarity_terms
from . import mjcf_path
from .chain import INTEGRATOR

BASE_FILE = "network.xml"

_TEMPLATE: list[mujoco.MjSpec] = []
"""network.xml parsed, with its example nodes and springs deleted (what every network starts from)."""
_TEMPLATE_LOCK = threading.Lock()


def _template() -> mujoco.MjSpec:
    """A fresh copy of the base MjSpec without its example network (parsed once per process; thread-safe)."""
    with _TEMPLATE_LOCK:
        if not _TEMPLATE:
            spec = mujoco.MjSpec.from_file(str(mjcf_path(BASE_FILE)))
            for element in [*spec.tendons, *spec.actuators, *spec.keys]:
                spec.delete(element)
            for body in [b for b in spec.worldbody.bodies if b.name.startswith("node_")]:
                spec.delete(body)
            for site in [s for s in spec.worldbody.sites if s.name.startswith("node_")]:
                spec.delete(site)
            _TEMPLATE.append(spec)
        return _TEMPLATE[0].copy()


def free_nodes(network) -> np.ndarray:
    """Indices of the nodes that move (not pinned), in the order of their bodies and of qpos (two per node)."""
    return np.flatnonzero(~np.asarray(network.pinned, dtype=bool))


def check_network(network) -> None:
    """Refuse a network MuJoCo cannot represent as given, naming the field."""
    positions = np.asarray(network.positions, dtype=float)
    count = positions.shape[0]
    if positions.ndim != 2 or positions.shape[1] != 2 or count == 0:
        raise ParameterError(f"network.positions must have shape (P, 2) with P >= 1, got {positions.shape}")
    bonds = np.asarray(network.bonds)
    if bonds.size and (
        bonds.ndim != 2
        or bonds.shape[1] != 2
        or bonds.min() < 0
        or bonds.max() >= count
        or np.any(bonds[:, 0] == bonds[:, 1])
    ):
        raise ParameterError("network.bonds must be (B, 2) pairs of distinct node indices in [0, P)")
    for name in ("rest_lengths", "stiffness"):
        values = np.asarray(getattr(network, name), dtype=float)
        if values.shape != (len(bonds),) or not np.all(np.isfinite(values)) or np.any(values < 0):
            raise ParameterError(f"network.{name} must be {len(bonds)} finite values >= 0, got shape {values.shape}")
    for name in ("pinned", "active"):
        if np.asarray(getattr(network, name)).shape != (count,):
            raise ParameterError(f"network.{name} must have shape ({count},)")
    if np.asarray(network.anchors).shape != (count, 2):
        raise ParameterError(f"network.anchors must have shape ({count}, 2)")
    if not (np.isfinite(network.trap) and network.trap >= 0):
        raise ParameterError(f"network.trap must be a finite stiffness >= 0, got {network.trap}")


def build_network_spec(network, physics: Physics, numerics: Numerics = Numerics()) -> mujoco.MjSpec:
    """MjSpec of a network (compile it with .compile()); physics names the scene and carries the active units'
    parameters, numerics the timestep, integrator, mass ratio and seed."""
    check_network(network)
    spec = _template()
    node, pinned_node, spring = (spec.find_default(c) for c in ("node", "pinned_node", "spring"))
    positions = np.asarray(network.positions, dtype=float)
    anchors = np.asarray(network.anchors, dtype=float)
    pinned = np.asarray(network.pinned, dtype=bool)
    active = np.asarray(network.active, dtype=bool)
    trap = float(network.trap)
    forces = np.zeros(len(positions))
    forces[active] = unit_forces(network, physics.sigma)  # each unit's own (sigma unless the network scales it)
    for i, (x, y) in enumerate(positions):
        force = [float(forces[i])]
        if pinned[i]:
            spec.worldbody.add_site(name=f"node_{i}", default=pinned_node, pos=[x, y, 0.0], userdata=force)
            continue
        body = spec.worldbody.add_body(name=f"node_{i}", pos=[x, y, 0.0], childclass="node")
        for axis, label in ((0, "x"), (1, "y")):
            direction = [0.0, 0.0, 0.0]
            direction[axis] = 1.0
            body.add_joint(
                name=f"node_{i}_{label}",
                default=node,
                axis=direction,
                stiffness=[trap, 0, 0],
                springref=float(anchors[i, axis] - positions[i, axis]),
            )
        body.add_geom(name=f"bead_{i}", default=node, mass=numerics.mass_ratio)
        body.add_site(name=f"node_{i}", default=node, userdata=force)
    for b, (i, j) in enumerate(np.asarray(network.bonds, dtype=int).reshape(-1, 2)):
        if pinned[i] and pinned[j]:
            continue
        tendon = spec.add_tendon(
            name=f"spring_{b}",
            default=spring,
            stiffness=[float(network.stiffness[b]), 0, 0],
            springlength=[float(network.rest_lengths[b])] * 2,
        )
        tendon.wrap_site(f"node_{i}")
        tendon.wrap_site(f"node_{j}")
    units = polarity_term(physics) or polarity_terms()[0]  # the term whose units it carries (Term.add_unit): one always
    passive = forces == 0 if network.unit_force is not None else np.zeros(len(positions), dtype=bool)
    for i in np.flatnonzero(active):  # a free node's unit on its x slide (O(1) per step), a pinned one's on its site
        # a unit given force 0 also on its site: follower.c finds a slide's site by its nonzero force, and a passive
        # unit's polarity still turns with its node
        units.add_unit(spec, f"node_{i}", physics, slide=None if pinned[i] or passive[i] else f"node_{i}_x")
    if network.unit_alignment_length is not None and np.any(active):  # units with their own l_a: the dynprm[0] of
        lengths = unit_alignment_lengths(network, physics.alignment_length)  # their actuators, the last added
        for actuator, length in zip(spec.actuators[-lengths.size :], lengths):
            actuator.dynprm[0] = float(length)

    spec.option.timestep = numerics.dt
    spec.option.integrator = INTEGRATOR[numerics.integrator]
    spec.modelname = physics.scene
    marker = spec.numeric("elastoactive_follower")  # mjcf/common.xml declares (a, seed)
    marker.size = 3
    marker.data = [0.0, float(numerics.seed), 0.0]
    return spec


def build_network_model(network, physics: Physics, numerics: Numerics = Numerics()) -> mujoco.MjModel:
    return build_network_spec(network, physics, numerics).compile()


def node_positions(network, qpos: np.ndarray) -> np.ndarray:
    """Lab positions (..., P, 2) of every node from qpos (..., 2F): pinned nodes at their rest positions."""
    q = np.asarray(qpos, dtype=float)
    free = free_nodes(network)
    rest = np.asarray(network.positions, dtype=float)
    out = np.broadcast_to(rest, q.shape[:-1] + rest.shape).copy()
    out[..., free, :] += q.reshape(q.shape[:-1] + (free.size, 2))
    return out


def qpos_of_positions(network, positions: np.ndarray) -> np.ndarray:
    """qpos (2F,) of node positions (P, 2); refuses pinned nodes away from their rest positions."""
    positions = np.asarray(positions, dtype=float)
    rest = np.asarray(network.positions, dtype=float)
    if positions.shape != rest.shape:
        raise ParameterError(f"node positions must have shape {rest.shape}, got {positions.shape}")
    pinned = np.asarray(network.pinned, dtype=bool)
    if np.any(np.abs(positions[pinned] - rest[pinned]) > 1e-12):
        raise ParameterError("node positions: a pinned node must sit at its rest position")
    return (positions - rest)[free_nodes(network)].ravel()


def polarity_of_units(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """The active units' polarities psi (A,), in node order (the units are built in node order)."""
    return data.act[polarity_addresses(model)].copy()


def set_polarity(model: mujoco.MjModel, data: mujoco.MjData, polarity: np.ndarray) -> None:
    """Write the active units' polarities psi (A,), in node order, into data.act."""
    addresses = polarity_addresses(model)
    polarity = np.asarray(polarity, dtype=float)
    if polarity.shape != addresses.shape:
        raise ParameterError(
            f"polarity must have one angle per active unit, shape {addresses.shape}, got {polarity.shape}"
        )
    data.act[addresses] = polarity

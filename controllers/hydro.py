r"""The hydrodynamic coupling of a MuJoCo model: a background flow at every bead, carried by its drag actuators.

Each bead (a particle site) has three velocity actuators along the site's axes, all of gain kv = g: their force is
g (ctrl_a - v . e_a) along each axis e_a, so with ctrl_a = e_a . u + c_a the bead feels the isotropic drag
g (u - v) in a background flow u, besides whatever the controls c_a carry (the follower force: c = -sigma / g on
the axis along the link). MuJoCo's implicitfast integrator takes the drag's velocity dependence implicitly, so the
self-drag stays implicit at any dt.

Overdamped, the bead's non-drag force f (follower, elastic, constraint) balances the drag, f = g (v - u), and the
mobility M of all beads wants v = M f. Both hold when

    u = (M - I / g) f,

a flow from the forces alone, with no inversion. The coupling takes f from the step before (explicit):

    f_n = g (v_n - u_{n-1}),    u_n = (M(x_n) - I / g) f_n,

v_n and x_n the beads' velocities and positions at the start of step n (after mj_step1), u_{n-1} the flow the last
step was taken in. At its fixed point (a still state, or the limit dt -> 0) the beads move as J^T M^-1 J q' =
J^T F - dU/dq says (docs/hydrodynamics.md). The lag is O(dt), as is MuJoCo's semi-implicit step; measured on a
whirling cilium, converging the flow within every step instead moves the error by less than 5%: the step, not the
lag, sets the error.

Stability of the lag. A change du of the flow moves the beads along the constrained chain's free directions and is
met by the constraint forces along the others (the links' tensions, the space G spans), so the flow iterates as
u_n = -(g M - I) Q u_{n-1} + ..., Q the projector onto the constraint forces. Its spectral radius is
max |g mu - 1| over the generalised eigenvalues mu of (G^T M G, G^T G) (M compressed onto the tensions): the lag is
stable when every 0 < g mu < 2. At g = 1 (the lab-frame drag's gain) that fails where M is large along a chain's
tensions (long straight chains of big beads in free space: mu_max ~ 1 + 3 a ln N / l), and is marginal where a bead
nears the wall (mu -> 0). The gain `optimal_gain` = 2 / (mu_min + mu_max) makes the radius (mu_max - mu_min) /
(mu_max + mu_min) < 1 for every positive definite M; the beads' drag gain changes, their motion does not (the fixed
point is the same for every g).

Cost per step: the flow is M f without M formed (elastoactive.hydro.product: each pair's 3 x 3 block computed once
and used twice), O(n^2); `FluidCoupling` runs mj_step1, the flow and mj_step2 for nstep steps in one compiled loop
that calls MuJoCo's C library directly (no Python per step).
"""

from __future__ import annotations

import glob
import math
import os

import llvmlite.binding as llvm
import mujoco
import numpy as np
from numba import njit, types

from ..core.errors import ParameterError
from ..hydro.blake import check_above_wall, rpb
from ..hydro.product import product_kernel
from ..hydro.rpy import check_radius, rpy

FLOWS = ("identity", "rpy", "rpb")
"""The mobilities a coupling carries, by their code (the index): M = I (the flow vanishes at g = 1: the lab-frame
drag, for the tests), Rotne-Prager-Yamakawa in free space, Rotne-Prager-Blake above a no-slip wall at z = 0."""
IDENTITY, RPY, RPB = range(3)


# --------------------------------------------------------------------------------------------- the flow, O(n^2)
@njit(cache=True)
def flow_kernel(x, f, radius, code, shift, out):
    """out (n, 3) = M(x) f - shift f for beads at x (n, 3) under forces f (n, 3) (out not f), M of FLOWS[code] and
    radius a, never formed (elastoactive.hydro.product's kernel). RPB: every z > 0 (the caller checks)."""
    if code == IDENTITY:
        for i in range(x.shape[0]):
            for p in range(3):
                out[i, p] = (1.0 - shift) * f[i, p]
        return out
    product_kernel(x, radius, f, code == RPB, out)
    for i in range(x.shape[0]):
        for p in range(3):
            out[i, p] -= shift * f[i, p]
    return out


def mobility(positions, radius: float, flow: str) -> np.ndarray:
    """The dense mobility (3n, 3n) the coupling carries: elastoactive.hydro's reference (the identity: 'identity')."""
    x = np.asarray(positions, dtype=float).reshape(-1, 3)
    if flow == "identity":
        return np.eye(3 * len(x))
    return rpy(x, radius) if flow == "rpy" else rpb(x, radius)


def flow(positions, forces, radius: float, flow: str, gain: float = 1.0) -> np.ndarray:
    """u = (M - I / gain) f (n, 3) for beads at positions (n, 3) under forces (n, 3): flow_kernel, checked."""
    code = check_flow(flow)
    x = np.ascontiguousarray(positions, dtype=float).reshape(-1, 3)
    f = np.ascontiguousarray(forces, dtype=float).reshape(-1, 3)
    if f.shape != x.shape:
        raise ParameterError(f"forces must have the positions' shape {x.shape}, got {f.shape}")
    a = check_radius(radius) if code != IDENTITY else 1.0
    if code == RPB:
        check_above_wall(x)
    return flow_kernel(x, f, a, code, 1.0 / check_gain(gain), np.empty_like(x))


def check_flow(name: str) -> int:
    """The code of the mobility `name`; ParameterError naming `flow` otherwise."""
    if name not in FLOWS:
        raise ParameterError(f"flow (the coupling's mobility) must be one of {', '.join(FLOWS)}, got {name!r}")
    return FLOWS.index(name)


def check_gain(gain) -> float:
    g = float(gain)
    if not (math.isfinite(g) and g > 0.0):
        raise ParameterError(f"gain (the drag actuators' kv) must be finite and > 0, got {gain!r}")
    return g


# ------------------------------------------------------------------------------------ the lag's stability
def tension_directions(positions: np.ndarray, bases: np.ndarray) -> np.ndarray:
    """G (3CN, CN): column (c, k) the forces on the beads of a unit tension in link k of chain c (beads (C, N, 3),
    anchors (C, 3)): -t on bead k, +t on bead k - 1 (the anchor takes it for k = 0), t the link's unit tangent."""
    x = np.asarray(positions, dtype=float)
    chains, n = x.shape[:2]
    behind = np.concatenate([np.asarray(bases, dtype=float)[:, None, :], x[:, :-1]], axis=1)
    t = x - behind
    t /= np.linalg.norm(t, axis=-1)[..., None]
    g = np.zeros((chains, n, 3, chains, n))
    for c in range(chains):
        for k in range(n):
            g[c, k, :, c, k] = -t[c, k]
            if k > 0:
                g[c, k - 1, :, c, k] = t[c, k]
    return g.reshape(3 * chains * n, chains * n)


class LagSpectrum:
    """The generalised eigenvalues mu of (G^T M G, G^T G) at one state: M seen along the links' tensions."""

    def __init__(self, mu: np.ndarray):
        self.mu = np.sort(np.asarray(mu, dtype=float))

    @property
    def optimal_gain(self) -> float:
        """g = 2 / (mu_min + mu_max): the smallest spectral radius of the lag."""
        return 2.0 / (self.mu[0] + self.mu[-1])

    def radius(self, gain: float) -> float:
        """The lag's spectral radius max |g mu - 1| at the actuators' gain g (stable below 1)."""
        return float(np.max(np.abs(gain * self.mu - 1.0)))


def lag_spectrum(positions: np.ndarray, bases: np.ndarray, radius: float, flow: str) -> LagSpectrum:
    """The LagSpectrum of chains of beads at positions (C, N, 3) anchored at bases (C, 3) (dense: O((CN)^3), once)."""
    check_flow(flow)
    x = np.asarray(positions, dtype=float)
    g = tension_directions(x, bases)
    m = mobility(x.reshape(-1, 3), radius, flow)
    gram = g.T @ g
    low = np.linalg.cholesky(gram)
    a = np.linalg.solve(low, np.linalg.solve(low, g.T @ m @ g).T)  # L^-1 (G^T M G) L^-T, symmetric
    return LagSpectrum(np.linalg.eigvalsh(0.5 * (a + a.T)))


# ------------------------------------------------------------------------------------- the coupled step
@njit(cache=True)
def flow_controls(xpos, xmat, actvel, sites, actuators, base, radius, code, gain, springs, offsets, stiffness, u, f,
                  x, extra, ctrl):  # fmt: skip
    """One update of the flow after mj_step1: from the sites' positions xpos and frames xmat (MuJoCo's site_xpos,
    site_xmat), the drag actuators' velocities actvel and the flow u (n, 3) the last step was taken in, the forces
    f = g (v - u), the new flow u = (M - I / g) f (in place), the springs' forces `extra` (n, 3) (spring s joins beads
    springs[s] = (i, j): energy stiffness/2 |x_i - x_j - offsets[s]|^2), and the drag actuators' controls
    base + R^T (u + extra / g)."""
    n = sites.shape[0]
    for k in range(n):
        s = sites[k]
        for p in range(3):
            x[k, p] = xpos[s, p]
        for p in range(3):  # v = R v_local, R's columns the site's axes (site_xmat row-major: R[p, a] = xmat[3p + a])
            v = 0.0
            for ax in range(3):
                v += xmat[s, 3 * p + ax] * actvel[actuators[k, ax]]
            f[k, p] = gain * (v - u[k, p])
    flow_kernel(x, f, radius, code, 1.0 / gain, u)
    for k in range(n):
        for p in range(3):
            extra[k, p] = u[k, p]
    for s in range(springs.shape[0]):
        i, j = springs[s, 0], springs[s, 1]
        for p in range(3):
            pull = stiffness / gain * (x[i, p] - x[j, p] - offsets[s, p])
            extra[i, p] -= pull
            extra[j, p] += pull
    for k in range(n):
        s = sites[k]
        for ax in range(3):
            ua = xmat[s, ax] * extra[k, 0] + xmat[s, 3 + ax] * extra[k, 1] + xmat[s, 6 + ax] * extra[k, 2]
            ctrl[actuators[k, ax]] = base[k, ax] + ua


def _load_mujoco() -> bool:
    """Make MuJoCo's C library (the file its Python bindings loaded: the same process-wide copy) known to numba's
    linker, so that compiled code calls mj_step1 and mj_step2 by name; False when the file is not found."""
    folder = os.path.dirname(mujoco.__file__)
    found = sorted(
        glob.glob(os.path.join(folder, "libmujoco.so*")) + glob.glob(os.path.join(folder, "libmujoco*.dylib"))
    )
    if not found:
        return False
    llvm.load_library_permanently(found[0])
    return True


COMPILED_STEPS = _load_mujoco()
"""Whether FluidCoupling steps in compiled code (else from Python: the same steps, slower)."""
_MJ_STEP1 = types.ExternalFunction("mj_step1", types.void(types.uintp, types.uintp))  # (mjModel*, mjData*)
_MJ_STEP2 = types.ExternalFunction("mj_step2", types.void(types.uintp, types.uintp))


@njit(cache=True)
def coupled_steps(nstep, m_ptr, d_ptr, xpos, xmat, actvel, sites, actuators, base, radius, code, gain, springs, offsets,
                  stiffness, u, f, x, extra, ctrl):  # fmt: skip
    """nstep coupled steps in compiled code: MuJoCo's mj_step1, flow_controls, MuJoCo's mj_step2 (m_ptr, d_ptr: the
    model's and data's addresses; the arrays: views of the data's)."""
    for _ in range(nstep):
        _MJ_STEP1(m_ptr, d_ptr)
        flow_controls(xpos, xmat, actvel, sites, actuators, base, radius, code, gain, springs, offsets, stiffness, u, f,
                      x, extra, ctrl)  # fmt: skip
        _MJ_STEP2(m_ptr, d_ptr)


class FluidCoupling:
    """Steps a MuJoCo model with its beads coupled through a mobility: `coupling(model, data, nstep)` in place of
    mujoco.mj_step(model, data, nstep), the same state as mj_step1, `update` and mj_step2 in turn (module docstring).

    sites      the beads' particle sites' ids (n,)
    actuators  their drag actuators' ids (n, 3), along each site's x, y and z axes, all of one gain kv (read from
               the model: the coupling's g)
    radius     the beads' radius a / l (the mobility's; ignored by 'identity')
    flow       one of FLOWS
    springs    optional linear springs between beads: ((i, j) pairs (S, 2) of indices into sites, offsets (S, 3),
               stiffness K): energy K/2 |x_i - x_j - offset|^2 each, its forces explicit, carried by the drag
               actuators' controls as the flow is (the tips' spring of a pair of cilia)

    The controls the model has when the coupling is made (data.ctrl: the follower force) are its base, to which the
    flow is added; the flow starts at zero (the lab-frame drag) unless `settle` finds the start's."""

    def __init__(self, model, data, sites, actuators, radius: float, flow: str, springs=None):
        self.code = check_flow(flow)
        self.flow = flow
        self.sites = np.ascontiguousarray(sites, dtype=np.int64)
        self.actuators = np.ascontiguousarray(actuators, dtype=np.int64).reshape(-1, 3)
        if self.actuators.shape[0] != self.sites.size:
            raise ParameterError(
                f"actuators must hold 3 per site ({self.sites.size} sites), got {self.actuators.shape}"
            )
        gains = model.actuator_gainprm[self.actuators, 0]
        if not np.all(gains == gains.flat[0]) or not np.all(model.actuator_biasprm[self.actuators, 2] == -gains):
            raise ParameterError("actuators: the coupling needs velocity actuators of one gain kv (isotropic drag)")
        self.gain = check_gain(gains.flat[0])
        self.radius = check_radius(radius) if self.code != IDENTITY else 1.0
        self.base = np.ascontiguousarray(data.ctrl[self.actuators], dtype=float)
        n = self.sites.size
        self.u = np.zeros((n, 3))
        self.f = np.zeros((n, 3))
        self._x = np.zeros((n, 3))
        self._extra = np.zeros((n, 3))
        pairs, offsets, stiffness = springs if springs is not None else (np.zeros((0, 2)), np.zeros((0, 3)), 0.0)
        self.springs = np.ascontiguousarray(pairs, dtype=np.int64).reshape(-1, 2)
        self.offsets = np.ascontiguousarray(offsets, dtype=float).reshape(-1, 3)
        self.stiffness = float(stiffness)
        if self.offsets.shape[0] != self.springs.shape[0] or np.any((self.springs < 0) | (self.springs >= n)):
            raise ParameterError(f"springs: pairs of bead indices in [0, {n}) (S, 2) with offsets (S, 3)")
        if not (math.isfinite(self.stiffness) and self.stiffness >= 0):
            raise ParameterError(f"springs: the stiffness must be finite and >= 0, got {stiffness!r}")
        self.compiled = COMPILED_STEPS

    def update(self, model, data) -> None:
        """One update of the flow and the controls from data after mj_step1 (flow_controls)."""
        if self.code == RPB:
            check_above_wall(data.site_xpos[self.sites])
        flow_controls(data.site_xpos, data.site_xmat, data.actuator_velocity, self.sites, self.actuators, self.base,
                      self.radius, self.code, self.gain, self.springs, self.offsets, self.stiffness, self.u, self.f,
                      self._x, self._extra, data.ctrl)  # fmt: skip

    def python_steps(self, model, data, nstep: int = 1) -> None:
        """nstep coupled steps from Python (mj_step1, update, mj_step2): the compiled loop's reference."""
        for _ in range(int(nstep)):
            mujoco.mj_step1(model, data)
            self.update(model, data)
            mujoco.mj_step2(model, data)

    def __call__(self, model, data, nstep: int = 1) -> None:
        """nstep coupled steps (the compiled loop where MuJoCo's library is found, else python_steps)."""
        if not self.compiled:
            self.python_steps(model, data, nstep)
            return
        coupled_steps(int(nstep), model._address, data._address, data.site_xpos, data.site_xmat,
                       data.actuator_velocity, self.sites, self.actuators, self.base, self.radius, self.code,
                       self.gain, self.springs, self.offsets, self.stiffness, self.u, self.f, self._x, self._extra,
                       data.ctrl)  # fmt: skip
        if self.code == RPB and not np.all(data.site_xpos[self.sites, 2] > 0.0):
            raise RuntimeError("a bead went through the wall z = 0 (a smaller dt)")

    def settle(self, model, data, steps: int = 50, tol: float = 1e-6) -> int:
        """Find the flow of the start state: take steps and put the positions and time back after each (the
        velocities carried on), so that the flow and the velocities converge to the overdamped motion at the start
        (geometric, at the lag's spectral radius). Returns the steps taken: at most `steps`, fewer once a step
        changes the flow by less than tol times its largest component."""
        qpos, time = data.qpos.copy(), data.time
        taken = 0
        for taken in range(1, int(steps) + 1):
            before = self.u.copy()
            self.python_steps(model, data, 1)
            data.qpos[:], data.time = qpos, time
            change = np.max(np.abs(self.u - before))
            if taken > 2 and change <= tol * np.max(np.abs(self.u)):  # from rest, the first step's forces vanish
                break
        mujoco.mj_forward(model, data)
        return taken

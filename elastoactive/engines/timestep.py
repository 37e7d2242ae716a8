"""Numerical stability of a MuJoCo scene: limits, pre-flight checks, and divergence causes.

Linearised about a state, the model is M q'' + D q' = f(q), with D the lab-frame drag
(sum over particles of J^T diag(gamma_L, gamma_T) J) and f the springs, coupling and follower
forces. Two time scales bound the timestep:

* overdamped rates lambda = eig(D^-1 df/dq): integrators that treat springs and follower forces
  explicitly (implicitfast, implicit, Euler, RK4) need |1 + dt lambda| < 1 for every decaying
  mode, i.e. dt < min(-2 Re(lambda) / |lambda|^2) ("spring limit").
* inertial rates eig(M^-1 D) ~ gamma / m: Euler and RK4 also treat the drag explicitly and need
  dt < 2 / max rate (RK4: 2.78 / max rate) ("drag limit", set by the particle mass).

implicitfast and implicit take the drag implicitly; discrete takes drag and springs implicitly,
but the follower forces stay explicit in every integrator (they come from the callback).

Stable is not accurate. check_timestep also refuses (accuracy=True, the default) settings that are
stable but measured to be wrong (docs/performance.md, scripts/stability_grid.py):

* resolution: dt * rate <= RESOLUTION (discrete, unpinned: DISCRETE_RESOLUTION), where rate is the fastest
  overdamped rate of the modes the integrator must resolve: every mode for implicitfast, implicit,
  Euler and RK4 (including the growing ones: at sigma >= 10 the straight chain has no decaying mode,
  so the stability limit above is infinite, yet modes grow at up to ~17 sigma N^0.7 / tau); for
  discrete, whose springs are implicit, the growing modes and the follower forces (and every mode
  for the two-pinned chain, whose pin relaxes over 2 dt);
* the pin (two-pinned, all integrators but discrete): dt^3 / mass_ratio <= PIN_DT3_PER_MASS. The pin
  is a soft constraint whose restoring force scales with the particle mass over (2 dt)^2; measured
  on the paper's two-pinned case, its largest violation is about 2 dt^3 / mass_ratio (in l) up to
  ~0.4 l, and the end leaves the pin altogether beyond (11 l at dt = 0.04, m = 1e-4). The bound keeps
  the violation near 0.02 l;
* discrete on long chains: a few probe steps; MuJoCo 4.0's effective-metric solve (M + hD + h^2 K)
  fails to converge from N ~ 30-50 on (mjWARN_INERTIA, residuals up to 1e2) and the run is then
  silently wrong.

The mass ratio is physics, not a numerical setting to refuse. `regime` (elastoactive.engines.regime,
the one criterion: mass_ratio x fastest overdamped rate at the base state vs INERTIA_RESOLUTION = 0.1)
classifies a run:

* overdamped (inside the limit): both engines model the paper's overdamped chain, MuJoCo with a small mass;
  every check above applies as it always did.
* inertial (outside the limit): both engines model the chain with particles of that mass (the reduced
  engine integrates its inertial model), so the mass is no longer refused. The timestep checks then use
  the inertial linearisation M q'' + D q' = F q at the base state instead of the overdamped one:
  - stability: the linearised step of the integrator, S(h) (implicitfast / implicit: v' = (M + hD)^-1
    (M v + hF q), q' = q + h v'; Euler: the same with the drag explicit; RK4: the Taylor polynomial of
    the companion matrix), may have no more eigenvalues |z| > 1 than the chain has growing modes; the
    largest such h (bisection) is the limit;
  - accuracy: dt x inertial_rate <= RESOLUTION, inertial_rate = the fastest eigenvalue |lambda| of the
    quadratic problem (lambda^2 M + lambda D - F) x = 0 that the step must resolve: every mode but the
    drag relaxations: with x a mode's shape, lambda solves m lambda^2 + d lambda + k = 0 (m = x^H M x,
    d = x^H D x, k = -x^H F x), and the drag relaxations are its fast roots, ~ -gamma/m, decaying at least at
    d / 2m and oscillating no faster than they decay. Those are taken implicitly by implicitfast and
    implicit, whose backward-Euler step slaves them exactly to first order however large dt gamma / m is;
    the slow relaxations, the growing modes and every oscillation (the inertial oscillations, sqrt(K/M))
    are explicit in the springs and follower forces, forward-Euler-like with error ~ dt |lambda| / 2.
    For discrete the oscillations are added to its own rates. Measured: at the default dt = 0.0025 the
    paper's cases agree with the inertial reduced model within 0.07% at mass ratios 0.01, 0.5 and 10
    (elastoactive validate --mass-ratio).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import mujoco
import numpy as np

from ..controllers import follower_forces
from ..core.errors import ParameterError
from ..core.params import RESOLUTION, Numerics, Physics
from ..core.surface import settings
from ..mjcf.chain import build_model, prepare
from ..reduced import INERTIA_RESOLUTION  # noqa: F401  (re-exported: the overdamped limit)
from ..terms.base import fastest_term, slower_advice
from .monitor import MAX_STEP_CHANGE
from .regime import regime  # noqa: F401  (re-exported: which physics a mass ratio gives)


def no_log_file() -> None:
    """Stop MuJoCo writing its warnings to MUJOCO_LOG.TXT in the working directory (its default): a run that goes
    bad is detected from data.warning and stopped with the cause (SimulationDiverged), so the file only litters the
    user's folder. Every path that steps a MuJoCo model imports this module (the engines, the pre-flight probe)."""
    config = getattr(mujoco, "MjLogConfig", None)  # MuJoCo >= 4: a process-wide log configuration
    if config is not None:
        settings = config.get()
        if settings.logto_file:
            settings.logto_file = False
            settings.set()


no_log_file()

RK4_STABILITY = 2.785  # real-axis stability interval of classical RK4
EXPLICIT_DRAG = {"Euler": 2.0, "RK4": RK4_STABILITY}

# Accuracy guards (see the module docstring), calibrated on scripts/stability_grid.py and
# `elastoactive accuracy`: at these bounds the paper's cases stay within ~5% (amplitude, frequency)
# and ~10% (transient angles); the project's defaults and the 'fast' preset pass with margin.
DISCRETE_RESOLUTION = 0.03
PIN_DT3_PER_MASS = 0.01
# INERTIA_RESOLUTION (0.1, the overdamped limit) lives with its criterion in elastoactive/reduced/regime.py
INERTIAL_STEP_INTEGRATORS = ("implicitfast", "implicit", "Euler", "RK4")  # linearised step known (module docstring)
PROBE_STEPS = 5


@dataclass(frozen=True)
class StabilityLimits:
    spring_dt: float  # largest stable dt when springs/follower forces are explicit
    drag_dt: float  # largest stable dt when the drag is explicit (Euler); RK4: x 1.39
    follower_dt: float  # largest stable dt with only the follower forces explicit (discrete)
    fastest_rate: float  # largest |lambda| of the overdamped dynamics, 1/tau
    growing_rate: float = 0.0  # largest |lambda| of the growing modes (Re lambda > 0), 1/tau
    follower_rate: float = 0.0  # largest rate of the follower-only (antisymmetric) part, 1/tau
    pinned: bool = False
    # the regime (module docstring): "overdamped" or "inertial", at this mass ratio
    model: str = "overdamped"
    mass_ratio: float = 0.0
    inertia_number: float = 0.0  # mass_ratio x fastest overdamped rate (at the base state)
    inertial_rate: float = 0.0  # inertial regime: fastest mode the step must resolve, 1/tau
    oscillation_rate: float = 0.0  # inertial regime: fastest oscillating mode |lambda|, 1/tau
    inertial_growing_rate: float = 0.0  # inertial regime: fastest growing mode |lambda|, 1/tau
    step_limits: dict = field(default_factory=dict)  # inertial regime: largest stable dt per integrator
    term_rate: float = 0.0  # fastest rate a term imposes (terms.base.fastest_term: a drive's 2 pi f, the units'), 1/tau

    @property
    def inertial(self) -> bool:
        """Outside the overdamped limit: both engines model the inertial chain."""
        return self.model == "inertial"

    def accuracy_rate(self, integrator: str) -> float:
        """Fastest rate the integrator must resolve for an accurate run (see the module docstring), at least the
        fastest rate a term imposes (Term.rate: a prescribed drive, the self-aligning units' turning), which every
        integrator steps explicitly."""
        return max(self._chain_rate(integrator), self.term_rate)

    def _chain_rate(self, integrator: str) -> float:
        if integrator == "discrete" and not self.pinned:
            rate = max(self.growing_rate, self.follower_rate)
            return max(rate, self.oscillation_rate) if self.inertial else rate
        if self.inertial:
            return max(self.inertial_rate, self.oscillation_rate) if integrator == "discrete" else self.inertial_rate
        return self.fastest_rate

    def accuracy_limit(self, integrator: str) -> float:
        """Largest dt that resolves accuracy_rate (RESOLUTION / rate; discrete, unpinned:
        DISCRETE_RESOLUTION / rate)."""
        bound = DISCRETE_RESOLUTION if integrator == "discrete" and not self.pinned else RESOLUTION
        rate = self.accuracy_rate(integrator)
        return bound / rate if rate > 0 else np.inf

    def limit(self, integrator: str) -> float:
        """Largest stable dt for an integrator (linear estimate)."""
        if self.inertial and integrator in self.step_limits:
            return self.step_limits[integrator]
        if integrator == "discrete":
            return self.follower_dt
        dt = self.spring_dt
        if integrator in EXPLICIT_DRAG:
            dt = min(dt, self.drag_dt * EXPLICIT_DRAG[integrator] / 2.0)
        return dt


NEUTRAL = 1e-9
"""Modes with |Re lambda| <= NEUTRAL |lambda| are neutral, not decaying: round-off puts the real part of a
purely imaginary pair (e.g. of two chains on free pins) at +-1e-11, which would otherwise count as a decaying
mode with an explicit limit 2 |Re| / |lambda|^2 ~ 1e-11."""


def _explicit_limit(eigenvalues: np.ndarray) -> float:
    decaying = eigenvalues[eigenvalues.real < -NEUTRAL * np.abs(eigenvalues) - 1e-12]
    if decaying.size == 0:
        return np.inf
    return float(np.min(-2.0 * decaying.real / np.abs(decaying) ** 2))


def linear_operators(model: mujoco.MjModel, data: mujoco.MjData, eps: float = 1e-6):
    """(M, D, F) at data's state: mass matrix, drag matrix and d(force)/dq.

    Forces are read from qfrc_passive (springs, coupling and, with the callback installed, the
    follower forces); the caller installs the callback.
    """
    nv = model.nv
    work = mujoco.MjData(model)
    work.qpos[:] = data.qpos
    work.time = data.time
    mujoco.mj_forward(model, work)
    M = np.zeros((nv, nv))
    mujoco.mj_fullM(model, work, M)
    D = np.zeros((nv, nv))
    jac = np.zeros((3, nv))
    for a in range(model.nu):
        if model.actuator_trntype[a] == mujoco.mjtTrn.mjTRN_JOINT:  # a joint's own drag (the star's turning hub)
            dof = model.jnt_dofadr[model.actuator_trnid[a, 0]]
            D[dof, dof] += -model.actuator_biasprm[a, 2] * model.actuator_gear[a, 0] ** 2
            continue
        site = model.actuator_trnid[a, 0]
        mujoco.mj_jacSite(model, work, jac, None, site)
        axis = work.site_xmat[site].reshape(3, 3) @ model.actuator_gear[a, :3]
        row = axis @ jac
        D += -model.actuator_biasprm[a, 2] * np.outer(row, row)

    def forces(q):
        work.qpos[:] = q
        mujoco.mj_forward(model, work)
        return work.qfrc_passive.copy()

    F = np.zeros((nv, nv))
    q0 = data.qpos.copy()
    for j in range(nv):
        plus, minus = q0.copy(), q0.copy()
        plus[j] += eps
        minus[j] -= eps
        F[:, j] = (forces(plus) - forces(minus)) / (2 * eps)
    return M, D, F


def stability_limits(
    physics: Physics, numerics: Numerics, qpos: np.ndarray | None = None, *, model: mujoco.MjModel | None = None
) -> StabilityLimits:
    """Linear stability limits of the timestep at a state (default: the base state), for the numerics a run
    uses (numerics.for_physics: automatic numerics of a long chain resolved). `model`: the compiled model of
    this physics and numerics if there is one already (model.build_model's; only read), else it is built."""
    numerics = numerics.for_physics(physics)
    model = build_model(physics, numerics) if model is None else model
    data = mujoco.MjData(model)
    if qpos is not None:
        data.qpos[:] = qpos
    elif model.nkey:
        data.qpos[:] = model.key_qpos[0]
    with follower_forces():
        M, D, F = linear_operators(model, data)
    if model.neq:
        # motion tangent to the pin: project onto the null space of the pin's Jacobian
        mujoco.mj_forward(model, data)
        jac = np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, jac, None, model.eq_obj1id[0])
        _, s, vt = np.linalg.svd(jac[:2])
        basis = vt[np.sum(s > 1e-9) :].T
        if basis.shape[1] == 0:  # e.g. N = 2 on two pins: no free motion, nothing to destabilise
            return StabilityLimits(spring_dt=np.inf, drag_dt=np.inf, follower_dt=np.inf, fastest_rate=0.0)
        M, D, F = (basis.T @ X @ basis for X in (M, D, F))
    overdamped = np.linalg.eigvals(np.linalg.solve(D, F))
    inertial = np.linalg.eigvals(np.linalg.solve(M, D)).real
    # follower-only part: remove the symmetric (conservative) part of F
    follower = np.linalg.eigvals(np.linalg.solve(D, 0.5 * (F - F.T)))
    growing = overdamped[overdamped.real > 1e-12]
    reg = regime(physics, numerics)
    extra = {}
    if reg.inertial:
        resolved, oscillating, growing_in = inertial_rates(M, D, F)
        extra = dict(
            inertial_rate=resolved,
            oscillation_rate=oscillating,
            inertial_growing_rate=growing_in,
            step_limits={name: step_limit(M, D, F, name) for name in INERTIAL_STEP_INTEGRATORS},
        )
    return StabilityLimits(
        spring_dt=_explicit_limit(overdamped),
        drag_dt=2.0 / float(np.max(inertial)),
        follower_dt=_explicit_limit(-np.abs(follower.imag) + 0j) if np.any(follower.imag) else np.inf,
        fastest_rate=float(np.max(np.abs(overdamped))),
        growing_rate=float(np.max(np.abs(growing))) if growing.size else 0.0,
        follower_rate=float(np.max(np.abs(follower.imag))) if follower.size else 0.0,
        pinned=bool(model.neq),
        model=reg.model,
        mass_ratio=reg.mass_ratio,
        inertia_number=reg.inertia_number,
        term_rate=fastest_term(physics)[0],
        **extra,
    )


def _companion(M: np.ndarray, D: np.ndarray, F: np.ndarray) -> np.ndarray:
    """A of (q, v)' = A (q, v) for M q'' + D q' = F q."""
    n = M.shape[0]
    return np.block([[np.zeros((n, n)), np.eye(n)], [np.linalg.solve(M, F), -np.linalg.solve(M, D)]])


def inertial_rates(M: np.ndarray, D: np.ndarray, F: np.ndarray) -> tuple[float, float, float]:
    """(fastest |lambda| a step must resolve, fastest |lambda| of a resolved oscillating mode, fastest |lambda| of
    a growing mode) of M q'' + D q' = F q: every eigenvalue but the drag relaxations (module docstring). With x
    the mode's shape, lambda solves m lambda^2 + d lambda + k = 0 for m = x^H M x, d = x^H D x, k = -x^H F x; a drag
    relaxation is the fast root, decaying at least at the drag rate d / 2m and not oscillating faster than
    it decays: -Re lambda >= d / 2m and |Im lambda| <= -Re lambda (a real one: |lambda| >= d / 2m)."""
    n = M.shape[0]
    if n == 0:
        return 0.0, 0.0, 0.0
    lam, vec = np.linalg.eig(_companion(M, D, F))
    scale = max(float(np.max(np.abs(lam))), 1e-300)
    resolved = oscillating = growing = 0.0
    for k, value in enumerate(lam):
        x = vec[:n, k]
        mx, dx = float(np.real(np.conj(x) @ M @ x)), float(np.real(np.conj(x) @ D @ x))
        decay = -value.real
        if decay > 0 and decay * mx >= 0.5 * dx * (1 - 1e-9) and abs(value.imag) <= decay:
            continue  # a drag relaxation
        resolved = max(resolved, abs(value))
        if abs(value.imag) > 1e-9 * scale:
            oscillating = max(oscillating, abs(value))
        if value.real > 1e-12:
            growing = max(growing, abs(value))
    return resolved, oscillating, growing


def step_matrix(M: np.ndarray, D: np.ndarray, F: np.ndarray, h: float, integrator: str) -> np.ndarray:
    """The integrator's linearised step (q, v) -> (q, v) of M q'' + D q' = F q (springs and follower forces F
    explicit everywhere; the drag D implicit in implicitfast and implicit, explicit in Euler; RK4 classical)."""
    n = M.shape[0]
    eye = np.eye(n)
    if integrator in ("implicitfast", "implicit", "Euler"):
        if integrator == "Euler":
            B = np.linalg.inv(M)
            P = eye - h * B @ D
        else:
            B = np.linalg.inv(M + h * D)
            P = B @ M
        BF = h * (B @ F)
        return np.block([[eye + h * BF, h * P], [BF, P]])
    if integrator == "RK4":
        hA = h * _companion(M, D, F)
        S = np.eye(2 * n)
        term = np.eye(2 * n)
        for k in range(1, 5):
            term = term @ hA / k
            S = S + term
        return S
    raise ParameterError(f"no linearised step for integrator {integrator!r}")


def step_limit(M: np.ndarray, D: np.ndarray, F: np.ndarray, integrator: str, ceiling: float = 1.0) -> float:
    """Largest dt whose linearised step (step_matrix) has no more eigenvalues |z| > 1 than the chain has growing
    modes (bisection in log dt; inf when stable up to `ceiling`)."""
    n = M.shape[0]
    if n == 0:
        return np.inf
    lam = np.linalg.eigvals(_companion(M, D, F))
    growing = int(np.sum(lam.real > 1e-7 * max(float(np.max(np.abs(lam))), 1e-300)))

    def stable(h: float) -> bool:
        z = np.abs(np.linalg.eigvals(step_matrix(M, D, F, h, integrator)))
        return int(np.sum(z > 1.0 + 1e-6)) <= growing

    if stable(ceiling):
        return np.inf
    lo, hi = 1e-9, ceiling
    if not stable(lo):
        return 0.0
    for _ in range(60):
        if hi / lo < 1.0 + 1e-4:
            break
        mid = np.sqrt(lo * hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return float(lo)


def _down(x: float) -> float:
    """x rounded down to two significant digits: a suggested bound that passes the check it came from."""
    if not np.isfinite(x) or x <= 0:
        return x
    scale = 10.0 ** (np.floor(np.log10(x)) - 1)
    return float(np.floor(x / scale * (1 - 1e-9)) * scale)  # strictly inside the bound


def _up(x: float) -> float:
    """x rounded up to two significant digits."""
    if not np.isfinite(x) or x <= 0:
        return x
    scale = 10.0 ** (np.floor(np.log10(x)) - 1)
    return float(np.ceil(x / scale * (1 + 1e-9)) * scale)  # strictly inside the bound


def largest_dt(limits: StabilityLimits, numerics: Numerics, accuracy: bool = True) -> float:
    """The largest dt every check passes at this mass ratio and integrator (stability, and with accuracy=True
    the resolution of the fastest rate and the pin's hold): what the error messages suggest."""
    integrator = numerics.integrator
    dt = limits.limit(integrator)
    if accuracy:
        dt = min(dt, limits.accuracy_limit(integrator))
        if limits.pinned and integrator != "discrete":
            dt = min(dt, (PIN_DT3_PER_MASS * numerics.mass_ratio) ** (1 / 3))
    return _down(dt)


SUGGESTION_DIGITS = 3
"""Significant digits of a suggested dt (it must be typed back exactly: the value printed is the value checked)."""
SUGGESTION_TRIES = 4
"""Candidate dt values a suggestion checks, each the next whole fraction of sample_dt down, before giving up."""


def _dividing_steps(dt_max: float, sample_dt: float):
    """dt <= dt_max, largest first, that divide sample_dt into a whole number of steps and print exactly in
    SUGGESTION_DIGITS digits (what Numerics accepts: sample_dt a whole multiple of dt)."""
    if not (np.isfinite(dt_max) and dt_max > 0):
        return
    first = max(1, math.ceil(sample_dt / dt_max - 1e-9))
    for k in range(first, 4 * first + 8):
        dt = float(f"{sample_dt / k:.{SUGGESTION_DIGITS}g}")
        ratio = sample_dt / dt
        if dt <= dt_max and abs(ratio - round(ratio)) <= 1e-9 * ratio:
            yield dt


def passing_setting(physics: Physics, limits: StabilityLimits, numerics: Numerics) -> tuple[float, float] | None:
    """(dt, mass_ratio) that passes every check for this integrator at the run's sample_dt, or None if none is found:
    the largest dt at the run's mass ratio that divides sample_dt, checked (check_timestep) before it is offered.
    The mass is kept: it is physics (outside the overdamped limit both engines model the inertial chain)."""
    tries = 0
    for dt in _dividing_steps(largest_dt(limits, numerics), numerics.sample_dt):
        try:
            check_timestep(physics, replace(numerics, dt=dt), suggest=False)
        except ParameterError:
            tries += 1
            if tries >= SUGGESTION_TRIES:
                return None
            continue
        return dt, float(numerics.mass_ratio)
    return None


def _suggest(physics: Physics, limits: StabilityLimits, numerics: Numerics) -> str:
    setting = passing_setting(physics, limits, numerics)
    if setting is None:
        return ""
    dt, m = setting
    dt, m = float(f"{dt:.{SUGGESTION_DIGITS}g}"), float(f"{m:.6g}")  # as printed: the value typed back is checked
    passing = settings("Numerics", dt=dt, mass_ratio=m, integrator=numerics.integrator)
    return f" (a setting that passes every check: {passing})"


def check_timestep(
    physics: Physics,
    numerics: Numerics,
    safety: float = 1.0,
    accuracy: bool = True,
    *,
    model: mujoco.MjModel | None = None,
    suggest: bool = True,
) -> StabilityLimits:
    """Refuse a timestep beyond the linear stability limit of the chosen integrator and, with
    accuracy=True, settings that are stable but measured to give wrong answers (module docstring). Numerics left
    at their defaults are checked as a run uses them (numerics.for_physics: a long chain's automatic numerics).
    `model`: the run's compiled model if it is built already (stability_limits). A refusal names a setting that
    passes every check (passing_setting), unless suggest=False. The scene's kind checks it (Scene.check_timestep: a
    chain's check_chain_timestep, a network's own linearisation)."""
    return physics.scene_def.check_timestep(physics, numerics, safety, accuracy, model=model, suggest=suggest)


def check_chain_timestep(
    physics: Physics,
    numerics: Numerics,
    safety: float = 1.0,
    accuracy: bool = True,
    *,
    model: mujoco.MjModel | None = None,
    suggest: bool = True,
) -> StabilityLimits:
    """check_timestep of a chain scene (ChainScene.check_timestep)."""
    numerics = numerics.for_physics(physics)
    limits = stability_limits(physics, numerics, model=model)
    dt_max = limits.limit(numerics.integrator)
    if numerics.dt > safety * dt_max:
        cause = (
            f"the inertial chain (mass_ratio = {numerics.mass_ratio:g}, outside the overdamped limit: "
            f"m x rate = {limits.inertia_number:.2g}) is unstable under {numerics.integrator} for larger dt (its "
            f"linearised step at the base state); use dt <= {largest_dt(limits, numerics, accuracy):.2g}"
            if limits.inertial and numerics.integrator in limits.step_limits
            else f"the particle mass: {numerics.integrator} treats the drag explicitly and needs dt < "
            f"{limits.drag_dt * EXPLICIT_DRAG.get(numerics.integrator, 2.0) / 2:.3g} "
            f"at mass_ratio = {numerics.mass_ratio:g}; raise mass_ratio or use integrator implicitfast"
            if numerics.integrator in EXPLICIT_DRAG and dt_max < limits.spring_dt
            else f"the stiffest overdamped mode (rate {limits.fastest_rate:.3g}/tau) is integrated explicitly by "
            f"{numerics.integrator}; use dt <= {largest_dt(limits, numerics, accuracy):.2g}"
            + ("" if numerics.integrator == "discrete" else " or integrator discrete")
        )
        raise ParameterError(
            f"dt = {numerics.dt:g} is above the stability limit {dt_max:.3g} of integrator {numerics.integrator} "
            f"for {_describe(physics)}: {cause}" + (_suggest(physics, limits, numerics) if accuracy and suggest else "")
        )
    if accuracy:
        check_accuracy(physics, numerics, limits, suggest=suggest)
    return limits


def check_accuracy(
    physics: Physics, numerics: Numerics, limits: StabilityLimits | None = None, *, suggest: bool = True
) -> StabilityLimits:
    """Refuse stable settings that are known to give wrong answers: an unresolved fastest rate (of the
    overdamped chain, or of the inertial one outside the overdamped limit), a pin that cannot hold,
    discrete's unconverged solve. A mass ratio outside the overdamped limit is not refused: it makes the
    run inertial (limits.model; both engines model the chain with that mass)."""
    numerics = numerics.for_physics(physics)
    limits = stability_limits(physics, numerics) if limits is None else limits
    integrator, dt, m = numerics.integrator, numerics.dt, numerics.mass_ratio
    rate = limits.accuracy_rate(integrator)
    where = f"for {_describe(physics)}"
    dt_ok = limits.accuracy_limit(integrator)
    if dt > dt_ok and limits.inertial:
        bound = DISCRETE_RESOLUTION if integrator == "discrete" and not limits.pinned else RESOLUTION
        if limits.oscillation_rate > 0 and rate <= limits.oscillation_rate * (1 + 1e-9):
            kind = "an inertial oscillation"
        elif limits.inertial_growing_rate > 0 and rate <= limits.inertial_growing_rate * (1 + 1e-9):
            kind = "a growing mode"
        else:
            kind = "a relaxation"
        raise ParameterError(
            f"dt = {dt:g} does not resolve the inertial chain {where} at mass_ratio = {m:g} (outside the overdamped "
            f"limit, m x rate = {limits.inertia_number:.2g}: both engines model the chain with this mass): its fastest "
            f"resolved mode, {kind}, has rate {rate:.3g}/tau (integrator {integrator}: dt x rate = {dt * rate:.2g} > "
            f"{bound:g}); the run would be inaccurate. Use dt <= {largest_dt(limits, numerics):.2g}"
            + (
                " (the straight chain's active modes grow this fast at high sigma or N)"
                if limits.inertial_growing_rate >= 0.5 * rate and limits.inertial_growing_rate > 20
                else ""
            )
            + (_suggest(physics, limits, numerics) if suggest else "")
        )
    if dt > dt_ok and rate <= limits.term_rate:
        _, term = fastest_term(physics)
        raise ParameterError(
            f"dt = {dt:g} does not resolve the rate {rate:.3g}/tau of the {term.name} term {where} (dt x rate = "
            f"{dt * rate:.2g} > {RESOLUTION:g}: it is stepped explicitly, so the run would be inaccurate or unstable). "
            f"Use dt <= {largest_dt(limits, numerics):.2g}{slower_advice(term, physics, RESOLUTION / dt)}"
            + (_suggest(physics, limits, numerics) if suggest else "")
        )
    if dt > dt_ok:
        bound = DISCRETE_RESOLUTION if integrator == "discrete" and not limits.pinned else RESOLUTION
        raise ParameterError(
            f"dt = {dt:g} does not resolve the fastest overdamped rate {rate:.3g}/tau {where} (integrator "
            f"{integrator}: dt x rate = {dt * rate:.2g} > {bound:g}); the run would be stable but inaccurate. Use dt "
            f"<= {largest_dt(limits, numerics):.2g}"
            + (
                " (the straight chain's active modes grow this fast at high sigma or N)"
                if limits.growing_rate >= 0.5 * rate and limits.growing_rate > 20
                else ""
            )
            + (_suggest(physics, limits, numerics) if suggest else "")
        )
    if limits.pinned and integrator != "discrete" and dt**3 / m > PIN_DT3_PER_MASS:
        raise ParameterError(
            f"the pin cannot hold {where} with dt = {dt:g}, mass_ratio = {m:g} and integrator {integrator}: "
            f"the soft pin's restoring force scales with mass_ratio / (2 dt)^2 and the end drifts off by about "
            f"2 dt^3 / mass_ratio = {2 * dt**3 / m:.2g} l (> {2 * PIN_DT3_PER_MASS:g} l; beyond ~0.4 l it leaves the "
            f"pin altogether). Use integrator discrete, dt <= {largest_dt(limits, numerics):.2g} or mass_ratio >= "
            f"{_up(dt**3 / PIN_DT3_PER_MASS):.2g}"
        )
    if integrator == "discrete":
        residual = _discrete_probe(physics, numerics)
        if residual:
            raise ParameterError(
                f"integrator discrete cannot run {where}: MuJoCo's effective-metric solve (M + h D + h^2 K) did not "
                f"converge in {PROBE_STEPS} probe steps (mjWARN_INERTIA {residual} times; long chains, N >~ 30), so "
                "its accelerations would be wrong. Use integrator implicitfast"
            )
    return limits


def _discrete_probe(physics: Physics, numerics: Numerics) -> int:
    """Number of mjWARN_INERTIA warnings in a few steps of the real model from its initial state."""
    model, data = prepare(physics, numerics)
    with follower_forces():
        mujoco.mj_step(model, data, nstep=PROBE_STEPS)
    return int(data.warning[mujoco.mjtWarning.mjWARN_INERTIA].number)


def _describe(physics: Physics) -> str:
    return ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in physics.relevant().items())


def divergence_cause(
    physics: Physics, numerics: Numerics, time: float, model=None, data=None, *, step_change: float | None = None
) -> str:
    """Message for a run that blew up: what happened and the likely cause. step_change: the state stayed finite but
    one step moved a coordinate this far (rad or l), more than any accurate run does
    (engines.monitor.MAX_STEP_CHANGE)."""
    numerics = numerics.for_physics(physics)
    what = "NaN or |value| > 1e10 in the state"
    if step_change is not None:
        data = None  # the state is finite: its warnings, if any, are not what stopped it
        what = (
            f"one step moved the state by {step_change:.3g} rad or l, where an accurate run moves less than "
            f"{MAX_STEP_CHANGE:g}"
        )
    if data is not None:
        names = {
            mujoco.mjtWarning.mjWARN_BADQACC: "qacc",
            mujoco.mjtWarning.mjWARN_BADQVEL: "qvel",
            mujoco.mjtWarning.mjWARN_BADQPOS: "qpos",
            mujoco.mjtWarning.mjWARN_INERTIA: "the implicit solve (mass matrix not positive definite)",
        }
        bad = [n for w, n in names.items() if data.warning[w].number]
        if bad:
            what = f"NaN or |value| > 1e10 in {', '.join(bad)}"
    head = (
        f"MuJoCo run diverged by t = {time:.4g} tau (checked every few samples; {what}) for {_describe(physics)}, "
        f"dt = {numerics.dt:g}, "
        f"mass_ratio = {numerics.mass_ratio:g}, integrator {numerics.integrator}. "
    )
    try:
        limits = stability_limits(physics, numerics)
    except Exception:  # the diagnosis must not hide the divergence itself
        return head + "Likely cause: dt too large or mass_ratio too small; reduce dt."
    dt_max = limits.limit(numerics.integrator)
    if numerics.integrator in EXPLICIT_DRAG and limits.drag_dt < limits.spring_dt and numerics.dt > 0.5 * dt_max:
        return head + (
            f"Likely cause: mass_ratio too small for dt: {numerics.integrator} treats the drag explicitly "
            f"(stable only for dt < {dt_max:.3g}); use integrator implicitfast or raise mass_ratio."
        )
    if numerics.dt > 0.5 * dt_max:
        return head + (
            f"Likely cause: dt too large: the linear stability limit here is {dt_max:.3g} "
            f"(fastest overdamped rate {limits.fastest_rate:.3g}/tau); reduce dt."
        )
    if step_change is not None:
        return head + (
            "Likely cause: a force stiffer than dt resolves that the pre-flight check, linearised at the "
            "base state, did not see (a term's force away from that state or outside MuJoCo's passive "
            "forces, a term whose rate is not declared: Term.rate); reduce dt."
        )
    return head + (
        "Likely cause: a nonlinear instability or mass_ratio too small (accelerations ~ force / mass "
        "exceed 1e10); reduce dt, raise mass_ratio, or reduce sigma."
    )

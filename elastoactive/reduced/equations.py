r"""The reduced model of the elasto-active chains: its equations (overdamped, and with the particles' inertia),
and where the paper misprints them.

Derivation (virtual work, units l = C1 = gamma_T = 1)
-----------------------------------------------------
Particle i sits at r_i = sum_{j<=i} e_j with e_j = (cos th_j, sin th_j); put n_j = (-sin th_j, cos th_j).
Then dr_i/dth_k = n_k [k <= i] and v_i = dr_i/dt = sum_{j<=i} n_j th'_j.

* Drag on particle i (longitudinal gamma_L along e_i, transverse gamma_T along n_i):
  F^d_i = -(gamma_L e_i e_i^T + gamma_T n_i n_i^T) v_i.  Its generalised force is
  Q^d_k = sum_{i>=k} n_k . F^d_i = -sum_j D_kj th'_j with, using e_i.n_j = sin(th_i - th_j) and
  n_i.n_j = cos(th_i - th_j),

      D_jk = sum_{i >= max(j,k)} [gamma_L sin(th_i - th_j) sin(th_i - th_k)
                                  + gamma_T cos(th_i - th_j) cos(th_i - th_k)],

  symmetric positive definite; isotropic drag gives D_jk = gamma (N - max(j,k) + 1) cos(th_j - th_k).
* Follower force F^a_i = -sigma (1 + eta_i) e_i:
  Q_k = sum_{i>=k} n_k . F^a_i = sigma sum_{i>=k} (1 + eta_i) sin(th_k - th_i).
* Springs: U = c/2 th_1^2 (absent on the rotating pin) + c/2 sum_i (th_{i+1} - th_i)^2 with c = 1 for chain 1
  (theta) and c = rho for chain 2 (phi) of the coupled pair, plus U_c = kappa/2 (th_1 - phi_1)^2.
* Without inertia the virtual work of all forces vanishes for every dth, so

      D(th) th' = f(th) := -dU/dth + Q(th)          [+ G^T mu for the two-pinned chain].

  The pair's D is block diagonal (one block per chain, same sigma and drag); its state is [theta, phi].
* Two-pinned chain: g(th) = (sum cos th_i - N (1 - delta), sum sin th_i) = 0, G = dg/dth (2 x N). The
  index-2 DAE is replaced by its Baumgarte-stabilised index-1 form G th' = -beta g, i.e. each RHS
  evaluation solves the saddle-point system  [[D, G^T], [G, 0]] [th'; lam] = [f; -beta g]  (Schur
  complement: th' = y - X lam with D y = f, D X = G^T, (G X) lam = G y + beta g). Drift off g = 0 decays at
  rate beta (default 10); the largest |g| over the samples is reported by solve.constraint_violation (the engine's
  Trajectory.info["constraint_violation"]).

Solving D th' = f in O(N): articulated drag (kernels.articulated_solve)
---------------------------------------------------------------------
D = J^T W J with J the 2N x N Jacobian of the positions (J_ik = n_k [k <= i]) and W = diag(W_i),
W_i = gamma_L e_i e_i^T + gamma_T n_i n_i^T. Building D costs O(N^2) and factoring it O(N^3), but the
chain structure solves it in O(N), as the articulated-body algorithm solves a chain's dynamics; here
inertia is replaced by drag ("articulated drag"). Write w = th' and v_i = v_{i-1} + n_i w_i (v_0 = 0)
for the particle velocities. Row k of D w = f reads

    n_k . P_k = f_k,    P_k = sum_{i>=k} W_i v_i   (-P_k: the drag on particles k..N, which th_k shifts by n_k dth_k),

and P_k = W_k v_k + P_{k+1}. Suppose P_{k+1} = A_{k+1} v_{k+1} + B_{k+1} (true for k + 1 = N with
A_N = W_N, B_N = 0). Insert v_{k+1} = v_k + n_{k+1} w_{k+1} into row k + 1, with d = n^T A n, all at k + 1:

    w_{k+1} = (f_{k+1} - n.B - (A n).v_k) / d,
    P_{k+1} = (A - A n n^T A / d) v_k + B + A n (f_{k+1} - n.B) / d,

so P_k = A_k v_k + B_k again, with A_k = W_k + A'_{k+1} and
B_k = B_{k+1} + A_{k+1} n_{k+1} (f_{k+1} - n.B_{k+1}) / d_{k+1}.
The downdated A' = A - A n n^T A / d is symmetric with A' n = 0, so in the plane it is rank one:
A' = alpha e e^T with alpha = e^T A' e = det A / (n^T A n). (The subchain beyond a joint turns freely about
it, so moving the joint meets resistance only along the subchain's first link.) Hence one scalar per
joint: with s_k = sin(th_{k+1} - th_k) = e_{k+1}.n_k, c_k = cos(th_{k+1} - th_k), and alpha_{N+1} = 0,

    A_k = W_k + alpha_{k+1} e_{k+1} e_{k+1}^T,    A_k n_k = gamma_T n_k + alpha_{k+1} s_k e_{k+1},
    d_k = n_k^T A_k n_k = gamma_T + alpha_{k+1} s_k^2,
    alpha_k = det A_k / d_k = (gamma_L gamma_T + alpha_{k+1} (gamma_L s_k^2 + gamma_T c_k^2)) / d_k

(isotropic straight chain: alpha_k = N - k + 1, the number of particles k..N). The solve is

  backward, k = N .. 1:  u_k = A_k n_k / d_k,  q_k = (f_k - n_k.B_k) / d_k,  B_{k-1} = B_k + A_k n_k q_k  (B_N = 0),
                         then alpha_k;
  forward,  k = 1 .. N:  w_k = q_k - u_k.v_{k-1},  v_k = v_{k-1} + n_k w_k  (v_0 = 0),

O(1) work and one cosine/sine per joint, no N x N array. It is Gaussian elimination ordered from the tip
(an LDL^T factorisation of D in disguise: the d_k are its pivots); the pivots d_k >= gamma_T > 0 and
alpha_k >= 0, so it needs no pivoting, and it does not lose the ~cond(D) ~ N^2 factor of round-off that
the dense Cholesky solve does. A new right-hand side changes only q and B: the pinned chain's
X = D^-1 G^T rides along as two more right-hand sides (the columns of G^T, (-sin th_i) and (cos th_i), are
n_i . x and n_i . y: the generalised forces of unit forces at the last particle), followed by the same
2 x 2 Schur complement. The pair's D is block diagonal, so each chain is solved on its own (the coupling
is in f only). The analytic Jacobian (implicit methods, stiff cases) stays dense and O(N^3).

N = 2 (isotropic, one pinned end) gives exactly the paper's main-text Eqs. (1)-(2):
  2 th1' + cos(th1 - th2) th2' = th2 - 2 th1 + sigma sin(th1 - th2);  cos(th1 - th2) th1' + th2' = th1 - th2.

With inertia: the exact counterpart of the MuJoCo scenes at a finite mass
--------------------------------------------------------------------------
MuJoCo's chain (mjcf/common.xml) carries all its mass in one bead per particle: a solid sphere of mass
m = mass_ratio (units gamma_T tau) and radius r = 0.14 centred on particle i, rigidly fixed to pendulum i,
so body i also turns with th_i' and has the rotational inertia I = (2/5) m r^2 = m inertia_factor
(ChainSystem.inertia_factor, 0.00784) about the vertical axis; the links are massless. Kinetic energy:

    T = sum_i [ m/2 |v_i|^2 + I/2 th_i'^2 ] = 1/2 th'^T M(th) th',
    M_jk = m sum_{i >= max(j,k)} n_j.n_k + I delta_jk = a_jk cos(th_j - th_k) + I delta_jk,
    a_jk = m (N - max(j,k) + 1)

(1-based; v_i = sum_{j<=i} n_j th_j'). This M is exactly MuJoCo's mass matrix (mj_fullM) after the change
from its relative hinge angles q to the absolute angles th = L q (L lower triangular ones): M_q = L^T M L
(checked to round-off in tests/reduced/test_inertia.py, as are the accelerations below against MuJoCo's qacc).
Lagrange's equations d/dt dT/dth_j' - dT/dth_j = Q_j with dM_kl/dth_j = -a_kl sin(th_k - th_l) (delta_kj - delta_lj):

    d/dt (M th')_j = (M th'')_j - sum_k a_jk sin(th_j - th_k) (th_j' - th_k') th_k',
    dT/dth_j       = -sum_k a_jk sin(th_j - th_k) th_j' th_k',

so the velocity-quadratic (centripetal) terms are

    c_j(th, th') = sum_k a_jk sin(th_j - th_k) th_k'^2 = m n_j . sum_{i >= j} A_i,    A_i = -sum_{k<=i} e_k th_k'^2

(A_i: the centripetal part of particle i's acceleration r_i'' = sum_{k<=i} (n_k th_k'' - e_k th_k'^2); the
bead's spin I th_j' adds no such term, I being constant), and the equations of motion are

    M(th) th'' + c(th, th') + D(th) th' = f(th)          [- G^T lam for the two-pinned chain]

with the same D, springs, follower forces and coupling f as above (the pair: M block diagonal, the
same m on both chains). The state is (th, om = th'); MuJoCo starts at rest, so om(0) = 0. As m -> 0 the
fast modes relax at ~ gamma/m onto D th' = f: the overdamped model is the limit m = 0.

Pins, at the acceleration level: g(th) = 0 gives G th'' + G' th' = 0 with (G' th')_1 = -sum cos th_i th_i'^2,
(G' th')_2 = -sum sin th_i th_i'^2. The index-3 DAE is replaced by its Baumgarte-stabilised index-1 form
g'' + 2 beta g' + beta^2 g = 0 (critically damped drift, rate beta, the same DEFAULT_BETA = 10):

    [[M, G^T], [G, 0]] [th''; lam] = [f - D th' - c; -G' th' - 2 beta G th' - beta^2 g],

solved by the Schur complement: th'' = a0 - X lam with M a0 = f - D th' - c, M X = G^T,
(G X) lam = G a0 + G' th' + 2 beta G th' + beta^2 g.

Cost: the generalised drag D th' and the centripetal terms take O(N) (prefix sums of the particle
velocities and centripetal accelerations, then suffix sums of the particle forces P_i = -W_i v_i - m A_i,
Q_k = n_k . sum_{i >= k} P_i); M is built in O(N^2) and solved by dense Cholesky, O(N^3) (acceptable: the
articulated-body algorithm would make it O(N), as the articulated drag above does for D, but the inertial
runs are of the paper's short chains). Integration: the compiled DOP853 on the doubled state; the system
is stiff only for small m (fast inertial relaxation gamma/m), where solve.py switches to Radau with a
finite-difference Jacobian (kernels.eval_jacobian_inertial). The engine runs this model only outside the
overdamped limit (mass_ratio x fastest overdamped rate > INERTIA_RESOLUTION = 0.1, regime.py),
where gamma/m < 10 x that rate, or on request.

Where the paper's printed equations are wrong (first principles win; checked in tests/reduced/test_reduced.py)
------------------------------------------------------------------------------------------------------
* Appendix C, single chain, equation "i = 1": the drag term reads tau (N th1' + sum_{j>=2} th_j' cos(th1 - th_j));
  the coefficient of th_j' must be (N - j + 1) (= D_1j). The printed form is right only for N = 2 (for
  N >= 3 it misses e.g. the factor 2 = N - j + 1 on th_2' at N = 3; the pair's "i = 1" equations and the
  linear-limit matrix A_ij print the factor correctly, the linear "i = 1" equation again omits it).
* Equation "i = N": the drag sum runs from j = i (= N), i.e. only tau th_N'; it must be sum_{j=1}^{N}
  th_j' cos(th_N - th_j) (row N of D). Same misprint in the pair's and the two-pinned "i = N" equations
  and in the linear limit.
* Supplement, anisotropic drag, N = 2: the printed coefficients (e.g. tau_T/4 (cos 4th1 + 2 cos 2th1 cos 2th2 + 5))
  depend on the absolute angles, so they break the rotation invariance that any drag law defined in the
  pendulum frame has (and that the isotropic limit tau_L = tau_T has). They coincide with the correct
  D = [[tau_T (1 + cos^2 d) + tau_L sin^2 d, tau_T cos d], [tau_T cos d, tau_T]] (d = th1 - th2) at
  th1 = th2 = 0, hence in the linear limit (so the "onset unchanged" claim stands), but not elsewhere:
  at th1 = th2 = pi/4 the printed matrix is half the correct [[2, 1], [1, 1]] tau_T for any tau_L; it is
  not symmetric (at (th1, th2) = (0.3, -0.2): printed D_12 = 0.804, D_21 = 0.990, correct 0.878); and with
  tau_L = tau_T it does not reduce to the isotropic matrix (test_paper_anisotropic_n2_is_wrong).
  Here D_jk above is used for every N.
* The linear-limit matrix A_ij writes the elastic part as tridiag(-1, 2, -1) in every row; the free end
  has K_NN = 1. (With K_NN = 2, sigma_c(7) would be 0.187 instead of 0.157, and N = 2 would lose
  stability through a real eigenvalue at sigma = 3 rather than through a Hopf pair. With the misprinted
  drag rows above, sigma_c(7) would be 0.137.) The paper's sigma_c(7) = 0.15 matches the correct
  equations (0.1575, see analysis.stability), so these are misprints, not errors in its computations.
* N = 2 Landau-Stuart form, z = th1 + i sqrt((1 + mu)/(1 - mu)) th2, mu = sigma - 3: the linear part
  (i + mu) z is right (eigenvalues mu +- i sqrt(1 - mu^2)). The cubic coefficients differ between the
  main text, -(sigma - 5/2) + i (17/4 - sigma) = -1/2 + 5i/4 at sigma = 3, and the supplement,
  -1 - i/8 at mu = 0. Simulating this model near onset (mu = 0.0025 ... 0.01, rtol 1e-11) gives
  mu / <|z|^2> = 0.996, 0.993, 0.985 and (omega - 1) / <|z|^2> = -0.124, -0.122, -0.119, i.e. c -> -1 - i/8:
  the supplement is right, the main text's coefficient is wrong (it would make the limit-cycle radius
  sqrt(2 mu) instead of sqrt(mu) and the frequency rise instead of fall with amplitude).

A free head, a harmonic trap and self-contact (ChainSystem.head_free, trap, contact_radius)
----------------------------------------------------------------------------------------
The same virtual work with more coordinates and forces. Let q be the state: the angles, then (free head) the
head's position h = (x_h, y_h), the pivot of the first pendulum: r_i = h + sum_{k<=i} e_k. Write J_i = dr_i/dq
(2 x dim q: n_k in column k <= i, the identity in the head's columns) and W_i = gamma_L e_i e_i^T +
gamma_T n_i n_i^T. The head is the chain's front piece: it carries one particle's drag, W_h = W(th_0) (gamma_L
along the first pendulum, gamma_T across), and no active force; J_h = dh/dq (the identity in the head's
columns). Then

    D(q) q' = f(q),   D = sum_i J_i^T W_i J_i + J_h^T W_h J_h,
    f = sum_i J_i^T (F^a_i - trap r_i) - J_h^T trap h + sum_{contacts} J_c^T F_c - dU_springs/dq,

with D_jk (angles) as above, D_{k,h} = (sum_{i >= k} W_i) n_k, D_hh = sum_i W_i + W_h. The trap (the small-slope
limit of a paraboloid dish under gravity, stiffness trap = k l^2 / C1) pulls every particle and the head towards
the origin; with a fixed pivot at the origin the head term is zero (the pivot does not move). Contact forces F_c
act at points c = (1 - s) P_{i-1} + s P_i of the links (contact.py: the penalty, the capsules, crossing cores),
so J_c = (1 - s) J_{P_{i-1}} + s J_{P_i} (dc/dth_k = n_k for k < i, s n_i for k = i, the identity for the head).

Why the head needs drag: without W_h, D is singular. The motion dq = (dth_0 = 1, dh = -n_0, the other angles
fixed) moves no particle: dr_i = dh + n_0 dth_0 = 0 for every i, so the first pendulum swings about particle 0
while the head slides, at no drag (q^T D q = 0). A physical head (the chain's front piece) resists it; giving it
one particle's drag is the simplest choice that does, and it is what the MuJoCo scene builds (a body with the
particles' drag at the head). With W_h, q'^T D q' >= |h'|^2 min(gamma) > 0 for any motion of the head, and a
motion with h' = 0 is that of the pinned chain, whose D is positive definite: D > 0.

Energy: U = U_springs + trap/2 (sum |r_i|^2 + |h|^2) + U_contact, and at sigma = 0, dU/dt = -q'^T f = -q'^T D q' <= 0.
Contact forces are internal (equal and opposite, along the line of their points), so with a free head, no trap
and sigma = 0 the drag forces on the whole chain (particles and head) sum to zero, and so do their torques.

With inertia (mass_ratio m > 0) the same coordinates get M q'' + c + D q' = f with M = m sum_i J_i^T J_i + the
beads' rotational inertia m inertia_factor on every angle, plus the head's bead: mass m at the pivot, turning with
the first pendulum (M_hh = m (N + 1) 1 in all, and m inertia_factor more on th_0), as MuJoCo's paraboloid scene
builds it; c = m sum_i J_i^T a_i with the centripetal accelerations a_i = -sum_{k<=i} e_k th_k'^2.

The compiled kernel is kernels.eval_rhs_general (assembles D over all coordinates, O(N^2) plus the O(N^2) contact
pair loop, dense Cholesky); rhs_reference below is its plain-numpy twin (explicit Jacobians J_i).

How these equations are integrated (compiled kernels, DOP853, Radau, Euler-Maruyama): solve.py.
"""

from __future__ import annotations

import numpy as np

from .constraints import pin_jacobian, pin_residual
from .contact import contact_forces
from .system import ChainSystem

__all__ = ["drag_and_forces_reference", "potential_reference", "rhs_inertial_reference", "rhs_reference"]


def _chain_spring_gradient(th, c, clamped):
    """dU/dth of one chain's joint springs (stiffness c; clamped: the spring at the pivot holding th_0 at 0)."""
    grad = np.zeros(th.size)
    if clamped:
        grad[0] += c * th[0]
    bend = np.diff(th)
    grad[:-1] -= c * bend
    grad[1:] += c * bend
    return grad


def _pinned_rates(D, force, theta, beta, delta):
    """The pinned chain's rates from the overdamped Baumgarte saddle point [[D, G^T], [G, 0]] (th', lam) =
    (f, -beta g) (D over the angles theta of the one chain; with more rows, the free ring's head, whose columns of G
    are zero: the constraint holds the last particle relative to the head)."""
    G = pin_jacobian(theta)
    if D.shape[0] > G.shape[1]:
        G = np.hstack([G, np.zeros((2, D.shape[0] - G.shape[1]))])
    M = np.block([[D, G.T], [G, np.zeros((2, 2))]])
    sol = np.linalg.solve(M, np.concatenate([force, -beta * pin_residual(theta, delta)]))
    return sol[: force.size]


def _pinned_accelerations(M, rhs_acc, theta, omega, beta, delta):
    """The pinned chain's accelerations from the inertial saddle point [[M, G^T], [G, 0]] (om', lam) =
    (f - D om - c, -G' om - 2 beta G om - beta^2 g) (no free head: M over the angles theta, rates omega)."""
    G = pin_jacobian(theta)
    gdot_om = -np.array([np.sum(np.cos(theta) * omega**2), np.sum(np.sin(theta) * omega**2)])
    b = -gdot_om - 2.0 * beta * (G @ omega) - beta**2 * pin_residual(theta, delta)
    K = np.block([[M, G.T], [G, np.zeros((2, 2))]])
    return np.linalg.solve(K, np.concatenate([rhs_acc, b]))[: rhs_acc.size]


def rhs_reference(system: ChainSystem, *, beta: float, factor=None):
    """Plain-numpy f(t, theta), written straight from the formulas (for tests and benchmarks).

    factor: optional per-particle force factor (1 + eta_i), default ones. beta: Baumgarte rate (pinned).
    With a free head, a trap or self-contact (system.extended) the state is system.state_size long (the angles,
    then the head) and D, f come from drag_and_forces_reference.
    """
    system = system.typed()
    n = system.n
    nch = system.n_chains
    gl, gt = system.gamma_l, system.gamma_t
    fac = system.force_factors(factor)
    i_idx = np.arange(n)
    # mask[i, j, k] = i >= max(j, k)
    mask = (i_idx[:, None, None] >= i_idx[None, :, None]) & (i_idx[:, None, None] >= i_idx[None, None, :])
    upper = i_idx[None, :] >= i_idx[:, None]  # upper[k, i] = i >= k

    def chain_terms(th, c, a):
        diff = th[:, None] - th[None, :]  # diff[i, j] = th_i - th_j
        s, co = np.sin(diff), np.cos(diff)
        D = np.einsum("ijk,ij,ik->jk", mask, gl * s, s) + np.einsum("ijk,ij,ik->jk", mask, gt * co, co)
        Q = system.sigma * np.sum(upper * a[None, :] * np.sin(th[:, None] - th[None, :]), axis=1)
        return D, Q - _chain_spring_gradient(th, c, system.clamped)

    if system.extended:  # a free head, a trap or self-contact: D and f over every coordinate

        def f_extended(t, y):
            y = np.asarray(y, dtype=float)
            D, force = drag_and_forces_reference(system, y, fac)
            if not system.pinned:
                return np.linalg.solve(D, force)
            return _pinned_rates(D, force, y[: system.n_angles], beta, system.delta)

        return f_extended

    def f(t, theta):
        theta = np.asarray(theta, dtype=float)
        Dfull = np.zeros((n * nch, n * nch))
        force = np.zeros(n * nch)
        for ch in range(nch):
            sl = slice(ch * n, (ch + 1) * n)
            Dfull[sl, sl], force[sl] = chain_terms(theta[sl], system.stiffness(ch), fac[sl])
        if nch == 2:
            force[0] -= system.kappa * (theta[0] - theta[n])
            force[n] += system.kappa * (theta[0] - theta[n])
        if system.closed:  # the ring's last joint (ChainSystem.closed)
            bend = theta[0] + 2.0 * np.pi - theta[n - 1]
            force[0] -= bend
            force[n - 1] += bend
        force -= _star_spring_gradient(system, theta)  # a star's arms on a clamped hub
        if not system.pinned:
            return np.linalg.solve(Dfull, force)
        return _pinned_rates(Dfull, force, theta, beta, system.delta)

    return f


def rhs_inertial_reference(system: ChainSystem, *, beta: float, factor=None):
    """Plain-numpy y' = f(t, y) of the inertial model (system.mass_ratio > 0), y = (theta, omega), written
    straight from the formulas above: M and c from a_jk, D from its sum over particles, f from U and Q. With a free
    head, a trap or self-contact: y = (q, q') over the angles and the head, M, c from the explicit Jacobians."""
    system = system.typed()
    n = system.n
    nch = system.n_chains
    na = n * nch
    m = system.mass_ratio
    gl, gt = system.gamma_l, system.gamma_t
    fac = system.force_factors(factor)
    i_idx = np.arange(n)
    a = m * (n - np.maximum(i_idx[:, None], i_idx[None, :]))  # a_jk = m #{i >= max(j, k)} (0-based)
    mask = (i_idx[:, None, None] >= i_idx[None, :, None]) & (i_idx[:, None, None] >= i_idx[None, None, :])
    upper = i_idx[None, :] >= i_idx[:, None]  # upper[k, i] = i >= k

    if system.extended:
        return _inertial_extended_reference(system, beta, fac)

    def f(t, y):
        y = np.asarray(y, dtype=float)
        theta, omega = y[:na], y[na:]
        M = np.zeros((na, na))
        D = np.zeros((na, na))
        force = np.zeros(na)
        c = np.zeros(na)
        for ch in range(nch):
            sl = slice(ch * n, (ch + 1) * n)
            th, w, cs = theta[sl], omega[sl], system.stiffness(ch)
            diff = th[:, None] - th[None, :]  # th_j - th_k
            M[sl, sl] = a * np.cos(diff) + m * system.inertia_factor * np.eye(n)
            c[sl] = (a * np.sin(diff)) @ (w**2)
            s_, c_ = np.sin(diff), np.cos(diff)
            D[sl, sl] = np.einsum("ijk,ij,ik->jk", mask, gl * s_, s_) + np.einsum("ijk,ij,ik->jk", mask, gt * c_, c_)
            grad = _chain_spring_gradient(th, cs, system.clamped)  # dU/dth
            Q = system.sigma * np.sum(upper * fac[sl][None, :] * np.sin(diff), axis=1)
            force[sl] = Q - grad
        if nch == 2:
            force[0] -= system.kappa * (theta[0] - theta[n])
            force[n] += system.kappa * (theta[0] - theta[n])
        if system.closed:  # the ring's last joint (ChainSystem.closed)
            bend = theta[0] + 2.0 * np.pi - theta[n - 1]
            force[0] -= bend
            force[n - 1] += bend
        force -= _star_spring_gradient(system, theta)  # a star's arms on a clamped hub
        rhs_acc = force - D @ omega - c
        if not system.pinned:
            return np.concatenate([omega, np.linalg.solve(M, rhs_acc)])
        return np.concatenate([omega, _pinned_accelerations(M, rhs_acc, theta, omega, beta, system.delta)])

    return f


def _star_spring_gradient(system: ChainSystem, y: np.ndarray) -> np.ndarray:
    """What a star (ChainSystem.star) adds to dU/dq: its arms' clamp springs refer to alpha_ch + phi (alpha_ch =
    2 pi ch / n_chains, phi = y[n_angles] the hub's angle when hub_free, else 0) instead of 0, and the hub's spring
    hub_stiffness phi^2 / 2: U_star = sum_ch c/2 (th_{ch,0} - alpha_ch - phi)^2 + hub_stiffness phi^2 / 2, less the
    c/2 th_{ch,0}^2 that _chain_spring_gradient already counts. Over n_angles + n_head coordinates."""
    n, nch = system.n, system.n_chains
    grad = np.zeros(system.n_angles + system.n_head)
    if not system.star:
        return grad
    phi = y[system.n_angles] if system.hub_free else 0.0
    for ch in range(nch):
        c = system.stiffness(ch)
        ref = 2.0 * np.pi * ch / nch + phi
        grad[ch * n] -= c * ref
        if system.hub_free:
            grad[system.n_angles] -= c * (y[ch * n] - ref)
    if system.hub_free:
        grad[system.n_angles] += system.hub_stiffness * phi
    return grad


def _chain_geometry(system: ChainSystem, y: np.ndarray, ch: int):
    """(pivots P_{i-1} (N, 2), e (N, 2), nrm (N, 2), head columns or None) of chain ch at the state y."""
    n = system.n
    th = y[ch * n : (ch + 1) * n]
    e = np.stack([np.cos(th), np.sin(th)], axis=1)
    nrm = np.stack([-np.sin(th), np.cos(th)], axis=1)
    head = y[system.n_angles : system.n_angles + 2] if (system.head_free and ch == 0) else np.zeros(2)
    ends = head + np.cumsum(e, axis=0)
    pivots = np.vstack([head, ends[:-1]])
    return pivots, e, nrm


def _node_jacobians(system: ChainSystem, nrm: np.ndarray, ch: int) -> np.ndarray:
    """dP/dq of chain ch's nodes: P_{-1} (the pivot), P_0 .. P_{N-1}; shape (N + 1, 2, dim q)."""
    n = system.n
    nq = system.n_angles + system.n_head
    J = np.zeros((n + 1, 2, nq))
    if system.head_free and ch == 0:
        J[:, :, system.n_angles : system.n_angles + 2] = np.eye(2)
    for i in range(n):
        J[i + 1 :, :, ch * n + i] += nrm[i]
    return J


def _spring_gradient(system: ChainSystem, y: np.ndarray) -> np.ndarray:
    """dU/dq of the joint springs and the pair's coupling spring (zero in the head's columns)."""
    n = system.n
    grad = np.zeros(system.n_angles + system.n_head)
    for ch in range(system.n_chains):
        c = system.stiffness(ch)
        th = y[ch * n : (ch + 1) * n]
        grad[ch * n : (ch + 1) * n] = _chain_spring_gradient(th, c, system.clamped)
    if system.n_chains == 2:
        grad[0] += system.kappa * (y[0] - y[n])
        grad[n] -= system.kappa * (y[0] - y[n])
    if system.closed:  # the ring's last joint (the free ring's angles before its head)
        bend = y[0] + 2.0 * np.pi - y[n - 1]
        grad[0] += bend
        grad[n - 1] -= bend
    return grad + _star_spring_gradient(system, y)


def drag_and_forces_reference(system: ChainSystem, y, factor=None) -> tuple[np.ndarray, np.ndarray]:
    """(D(q), f(q)) over the whole state q (angles, then the free head), plain numpy, from the explicit position
    Jacobians (see "A free head, a harmonic trap and self-contact" above): D = sum_i J_i^T W_i J_i + J_h^T W_h J_h,
    f = sum J^T (active + trap + contact forces) - dU_springs/dq. For any system (the pinned chain's constraint
    force is not in f). factor: the per-particle force factors (1 + eta_i). y: the positions (the inertial model's
    rates, if given after them, are ignored)."""
    system = system.typed()
    y = np.asarray(y, dtype=float).reshape(-1)[: system.n_angles + system.n_head]
    fac = system.force_factors(factor)
    n = system.n
    gl, gt, k = system.gamma_l, system.gamma_t, system.trap
    nq = system.n_angles + system.n_head
    D = np.zeros((nq, nq))
    force = -_spring_gradient(system, y)
    for ch in range(system.n_chains):
        pivots, e, nrm = _chain_geometry(system, y, ch)
        J = _node_jacobians(system, nrm, ch)
        for i in range(n):
            W = gl * np.outer(e[i], e[i]) + gt * np.outer(nrm[i], nrm[i])
            Ji = J[i + 1]
            D += Ji.T @ W @ Ji
            force += Ji.T @ (-system.sigma * fac[ch * n + i] * e[i] - k * (pivots[i] + e[i]))
        if system.head_free and ch == 0:
            W = gl * np.outer(e[0], e[0]) + gt * np.outer(nrm[0], nrm[0])
            D += J[0].T @ W @ J[0]
            force += J[0].T @ (-k * pivots[0])
        if system.contact_radius > 0:
            points, _ = contact_forces(pivots, e, system.contact_radius, system.contact_stiffness)
            for i, s, F in points:
                force += ((1.0 - s) * J[i] + s * J[i + 1]).T @ F
    if system.hub_free:  # a star's hub: its own rotational drag
        D[system.n_angles, system.n_angles] += system.hub_drag
    return D, force


def potential_reference(system: ChainSystem, y) -> float:
    """U(q): joint springs, the pair's coupling, the trap (particles and head) and the contact penalty; at sigma = 0
    the overdamped dynamics never increases it."""
    system = system.typed()
    y = np.asarray(y, dtype=float).reshape(-1)
    n = system.n
    energy = 0.0
    for ch in range(system.n_chains):
        th = y[ch * n : (ch + 1) * n]
        c = system.stiffness(ch)
        energy += 0.5 * c * np.sum(np.diff(th) ** 2) + (0.5 * c * th[0] ** 2 if system.clamped else 0.0)
        pivots, e, _ = _chain_geometry(system, y, ch)
        energy += 0.5 * system.trap * (np.sum((pivots + e) ** 2) + np.sum(pivots[0] ** 2))
        if system.contact_radius > 0:
            energy += contact_forces(pivots, e, system.contact_radius, system.contact_stiffness)[1]
    if system.n_chains == 2:
        energy += 0.5 * system.kappa * (y[0] - y[n]) ** 2
    if system.star:  # the arms' clamp springs refer to alpha_ch + phi; the hub's spring
        phi = y[system.n_angles] if system.hub_free else 0.0
        for ch in range(system.n_chains):
            ref = 2.0 * np.pi * ch / system.n_chains + phi
            energy += 0.5 * system.stiffness(ch) * ((y[ch * n] - ref) ** 2 - y[ch * n] ** 2)
        energy += 0.5 * system.hub_stiffness * phi**2
    return float(energy)


def _inertial_extended_reference(system: ChainSystem, beta: float, fac: np.ndarray):
    """y' of the inertial model with the extended terms, y = (q, q'): M q'' = f - D q' - c with M = m sum_i J_i^T J_i
    + the beads' rotation (m inertia_factor on each angle) + the head's bead (mass m at the pivot, turning with
    th_0), c = m sum_i J_i^T a_i, a_i = -sum_{k <= i} e_k th_k'^2 (the centripetal accelerations), D and f from
    drag_and_forces_reference; the pinned chain's Baumgarte acceleration constraint as in rhs_inertial_reference."""
    n = system.n
    nq = system.n_angles + system.n_head
    m = system.mass_ratio

    def f(t, y):
        y = np.asarray(y, dtype=float)
        q, w = y[:nq], y[nq:]
        D, force = drag_and_forces_reference(system, q, fac)
        M = m * system.inertia_factor * np.diag(np.r_[np.ones(system.n_angles), np.zeros(system.n_head)])
        if system.hub_free:  # a star's hub: a bead's rotational inertia
            M[system.n_angles, system.n_angles] = m * system.inertia_factor
        cgen = np.zeros(nq)
        for ch in range(system.n_chains):
            th, om = q[ch * n : (ch + 1) * n], w[ch * n : (ch + 1) * n]
            _, e, nrm = _chain_geometry(system, q, ch)
            J = _node_jacobians(system, nrm, ch)
            centripetal = -np.cumsum(e * om[:, None] ** 2, axis=0)
            for i in range(n):
                M += m * J[i + 1].T @ J[i + 1]
                cgen += m * J[i + 1].T @ centripetal[i]
            if system.head_free and ch == 0:
                M += m * J[0].T @ J[0]
                M[0, 0] += m * system.inertia_factor
            del th
        rhs_acc = force - D @ w - cgen
        if not system.pinned:
            return np.concatenate([w, np.linalg.solve(M, rhs_acc)])
        return np.concatenate([w, _pinned_accelerations(M, rhs_acc, q[:n], w, beta, system.delta)])

    return f

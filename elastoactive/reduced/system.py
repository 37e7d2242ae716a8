"""The reduced model's description of a system of chains: a typed record, built by each scene.

The compiled kernels read it by field name (numba compiles NamedTuples as typed records). A
scene turns its `Physics` into a `ChainSystem` (Scene.reduced_system); the solver needs nothing
else, so it knows no scene by name.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..core.constants import BEAD_INERTIA_FACTOR, CONTACT_LENGTH  # the models' constants, one place for each
from ..core.errors import ParameterError


class ChainSystem(NamedTuple):
    """One chain, or two chains coupled at their first pendula, in units l = C1 = gamma_T = 1.

    n         particles per chain N
    n_chains  1, or 2 for a coupled pair (state: theta of chain 1, then phi of chain 2)
    clamped   a spring (stiffness c) holds the first pendulum at angle 0; False: a free pin
    pinned    the last particle of chain 1 is held at (N (1 - delta), 0) (two constraints)
    sigma     follower force F_a l / C1 on every particle (the same on both chains)
    gamma_l   longitudinal drag, along each pendulum
    gamma_t   transverse drag, across it (1 in these units)
    kappa     coupling spring kappa/2 (theta_1 - phi_1)^2 between the chains' first pendula
    rho       joint stiffness of chain 2 over chain 1 (chain 1: 1)
    delta     compression of a pinned chain
    mass_ratio      particle mass m / (gamma_T tau); 0: the overdamped model (D th' = f, state th), > 0: the
                    inertial model (M th'' + c + D th' = f, state (th, th'); equations.py)
    inertia_factor  rotational inertia of each particle's body about the vertical axis, over its mass
                    (default: the MuJoCo bead's (2/5) 0.14^2); used only when mass_ratio > 0

    The extended terms (all off by default; with every one off, the kernels run exactly as before they existed,
    bit for bit; with any one on, the overdamped right-hand side is the general dense solve of
    kernels.eval_rhs_general, equations.py):

    head_free          the first pendulum's pivot (the head) slides freely in the plane: the state is
                       (th_0 .. th_{N-1}, x_h, y_h), two more coordinates after the angles. The head carries one
                       particle's drag (gamma_l along e(th_0), gamma_t across) and no active force. Only for one
                       chain with a free pin (n_chains = 1, clamped = False, pinned = False), or the free ring
                       (closed and pinned with delta = 1: the last particle held on the moving head; overdamped only)
    trap               harmonic trap -trap r on every particle and on the head, centred on the pivot's rest
                       position (the origin; each chain's own pivot for a pair), in units k l^2 / C1 (as kappa).
                       With a fixed pivot at the origin the head term does nothing
    contact_radius     radius R of the self-contact capsules (0: no contact), in l; 0 <= R < CONTACT_LENGTH / 2
    contact_stiffness  penalty stiffness K (force K x overlap, units C1 / l^3): U = K/2 max(0, 2R - dist)^2 for
                       each core end of a link against the core of every non-adjacent link (|i - j| >= 2) of the
                       same chain (contact.py: for a single contact, exactly K/2 max(0, 2R - d)^2 of the cores'
                       distance d); must be > 0 when contact_radius > 0
    closed             the chain closes on itself (a ring): a spring of stiffness 1 joins the last link to the first,
                       bent by th_0 + 2 pi - th_{N-1}; with pinned and delta = 1 the last particle is held at the
                       first pendulum's pivot (with head_free: on the moving head, the free ring). Only for one chain
                       on a free pin (n_chains = 1, clamped = False)
    star               the chains are the arms of a star on one hub at the origin (the star scene): chain ch's clamp
                       points at alpha_ch = 2 pi ch / n_chains from the hub, its clamp spring is
                       c (th_{ch,0} - alpha_ch - phi) (phi: the hub's angle, 0 unless hub_free); any number of chains
                       >= 1 (no coupling kappa: the arms interact through the hub only). With a clamped hub the arms are
                       n_chains independent one-pinned chains turned by alpha_ch
    hub_free           the hub turns about the origin: its angle phi is one more coordinate after the angles, with
                       hub_drag phi' = -hub_stiffness phi + sum_ch c (th_{ch,0} - alpha_ch - phi) (overdamped); the
                       hub has no particle. Only with star
    hub_stiffness      the hub's torsional spring to the lab, units C1 (>= 0)
    hub_drag           the hub's rotational drag, units gamma_T l^2 (> 0 with hub_free: phi then has a finite rate);
                       in the inertial model the hub is a bead's rotational inertia m inertia_factor
    The inertial model (mass_ratio > 0) has them too (kernels.eval_rhs_inertial_general); its free head is a bead
    like the particles' (mass m at the pivot, turning with the first pendulum), as MuJoCo's paraboloid scene builds it.
    """

    n: int
    n_chains: int = 1
    clamped: bool = True
    pinned: bool = False
    sigma: float = 0.0
    gamma_l: float = 1.0
    gamma_t: float = 1.0
    kappa: float = 0.0
    rho: float = 1.0
    delta: float = 0.0
    mass_ratio: float = 0.0
    inertia_factor: float = BEAD_INERTIA_FACTOR
    head_free: bool = False
    trap: float = 0.0
    contact_radius: float = 0.0
    contact_stiffness: float = 0.0
    closed: bool = False
    star: bool = False
    hub_free: bool = False
    hub_stiffness: float = 0.0
    hub_drag: float = 0.0

    @property
    def n_angles(self) -> int:
        return self.n * self.n_chains

    @property
    def n_head(self) -> int:
        """Coordinates in the state after the angles: 2 (x_h, y_h) when head_free, 1 (the hub's angle phi) when
        hub_free, else 0."""
        return 2 if self.head_free else (1 if self.hub_free else 0)

    @property
    def extended(self) -> bool:
        """Whether any extended term is on (head_free, trap > 0, contact_radius > 0, hub_free): the overdamped
        right-hand side is then kernels.eval_rhs_general, the Jacobian a finite-difference one."""
        return bool(self.head_free) or self.trap > 0 or self.contact_radius > 0 or bool(self.hub_free)

    @property
    def extensions(self) -> tuple[str, ...]:
        """The extended terms that are on, in words (for a refusal that names them)."""
        named = (
            ("free head", bool(self.head_free)),
            ("trap", self.trap > 0),
            ("self-contact", self.contact_radius > 0),
            ("turning hub", bool(self.hub_free)),
        )
        return tuple(name for name, on in named if on)

    @property
    def inertial(self) -> bool:
        """Whether this is the inertial model (mass_ratio > 0): its state is (theta, omega), 2 n_angles numbers."""
        return self.mass_ratio > 0

    @property
    def state_size(self) -> int:
        """Numbers in the integrated state: n_angles (overdamped), n_angles + 2 with a free head (angles, then
        x_h, y_h); inertial: twice that (positions, then their rates)."""
        positions = self.n_angles + self.n_head
        return 2 * positions if self.mass_ratio > 0 else positions

    def stiffness(self, chain: int) -> float:
        """Joint stiffness of chain `chain` (0 or 1; every arm of a star: 1) in units of C1."""
        return 1.0 if chain == 0 else self.rho

    def typed(self) -> ChainSystem:
        """This record with the field types the compiled kernels are compiled for (int n and n_chains,
        bool clamped, pinned and head_free, float the rest), so that a numpy integer or an integer sigma does
        not compile a second specialisation. The solvers call it on every record they are given; it raises a
        ParameterError for a record the kernels cannot solve."""
        if int(self.n) != self.n or self.n < 1:
            raise ParameterError(f"n (particles per chain) must be an integer >= 1, got {self.n!r}")
        if self.n_chains not in (1, 2) and not (self.star and int(self.n_chains) == self.n_chains >= 1):
            raise ParameterError(f"n_chains must be 1 or 2 (any number >= 1 for a star), got {self.n_chains!r}")
        if self.star and (
            not self.clamped
            or self.pinned
            or self.head_free
            or self.closed
            or self.kappa != 0
            or self.rho != 1
            or self.trap > 0
            or self.contact_radius > 0
        ):
            raise ParameterError(
                "star: the arms are clamped to the hub, unpinned, unit stiffness, without coupling kappa, trap or "
                f"self-contact; got clamped={self.clamped!r}, pinned={self.pinned!r}, head_free={self.head_free!r}, "
                f"closed={self.closed!r}, kappa={self.kappa!r}, rho={self.rho!r}, trap={self.trap!r}, "
                f"contact_radius={self.contact_radius!r}"
            )
        if self.hub_free and not self.star:
            raise ParameterError("hub_free: only the arms of a star (star = True) have a hub")
        if not (self.hub_stiffness >= 0 and np.isfinite(self.hub_stiffness)):
            raise ParameterError(f"hub_stiffness (C1) must be finite and >= 0, got {self.hub_stiffness!r}")
        if self.hub_free and not (self.hub_drag > 0 and np.isfinite(self.hub_drag)):
            raise ParameterError(
                f"hub_drag (gamma l^2) must be finite and > 0 for a turning hub, got {self.hub_drag!r}"
            )
        if self.pinned and self.n_chains != 1:
            raise ParameterError("pinned: only a single chain can be held at both ends")
        if not (self.mass_ratio >= 0 and np.isfinite(self.mass_ratio)):
            raise ParameterError(f"mass_ratio must be finite and >= 0 (0: overdamped), got {self.mass_ratio!r}")
        if not (self.inertia_factor >= 0 and np.isfinite(self.inertia_factor)):
            raise ParameterError(f"inertia_factor must be finite and >= 0, got {self.inertia_factor!r}")
        if self.head_free and (self.n_chains != 1 or self.clamped or (self.pinned and not self.closed)):
            raise ParameterError(
                "head_free: only a single chain on a free pin can slide (n_chains = 1, clamped = False, pinned = False "
                f"unless closed), got n_chains={self.n_chains!r}, clamped={self.clamped!r}, pinned={self.pinned!r}"
            )
        if self.head_free and self.pinned and (self.delta != 1 or self.mass_ratio > 0):
            raise ParameterError(
                "head_free with pinned: the free ring holds its last particle on the moving pivot (delta = 1) in the "
                f"overdamped model only (mass_ratio = 0); got delta={self.delta!r}, mass_ratio={self.mass_ratio!r}"
            )
        if not (self.trap >= 0 and np.isfinite(self.trap)):
            raise ParameterError(f"trap (k l^2 / C1) must be finite and >= 0, got {self.trap!r}")
        if not (0 <= self.contact_radius < CONTACT_LENGTH / 2):
            raise ParameterError(
                f"contact_radius must be >= 0 (0: no contact) and below CONTACT_LENGTH / 2 = {CONTACT_LENGTH / 2} "
                f"(the capsule's core must have a length), got {self.contact_radius!r}"
            )
        if not (self.contact_stiffness >= 0 and np.isfinite(self.contact_stiffness)):
            raise ParameterError(f"contact_stiffness must be finite and >= 0, got {self.contact_stiffness!r}")
        if self.contact_radius > 0 and not self.contact_stiffness > 0:
            raise ParameterError("contact_radius > 0 needs contact_stiffness > 0 (the penalty of an overlap)")
        if self.closed and (
            self.n_chains != 1
            or self.clamped
            or (self.head_free and not self.pinned)
            or self.n < 3
            or self.trap > 0
            or self.contact_radius > 0
        ):
            raise ParameterError(
                "closed: the reduced model's ring is one chain of N >= 3 on a free pin (n_chains = 1, clamped = False; "
                "a free head only with its last particle pinned to it) without a trap or self-contact (use the MuJoCo "
                f"engine for those); got n={self.n!r}, "
                f"n_chains={self.n_chains!r}, clamped={self.clamped!r}, head_free={self.head_free!r}, "
                f"trap={self.trap!r}, contact_radius={self.contact_radius!r}"
            )
        return ChainSystem(
            n=int(self.n),
            n_chains=int(self.n_chains),
            clamped=bool(self.clamped),
            pinned=bool(self.pinned),
            sigma=float(self.sigma),
            gamma_l=float(self.gamma_l),
            gamma_t=float(self.gamma_t),
            kappa=float(self.kappa),
            rho=float(self.rho),
            delta=float(self.delta),
            mass_ratio=float(self.mass_ratio),
            inertia_factor=float(self.inertia_factor),
            head_free=bool(self.head_free),
            trap=float(self.trap),
            contact_radius=float(self.contact_radius),
            contact_stiffness=float(self.contact_stiffness),
            closed=bool(self.closed),
            star=bool(self.star),
            hub_free=bool(self.hub_free),
            hub_stiffness=float(self.hub_stiffness),
            hub_drag=float(self.hub_drag),
        )

    def force_factors(self, factor=None) -> np.ndarray:
        """Per-particle force factors (1 + eta_i) as a float array of n_angles entries (default: ones)."""
        if factor is None:
            return np.ones(self.n_angles)
        fac = np.ascontiguousarray(factor, dtype=float).reshape(-1)
        if fac.size != self.n_angles:
            raise ParameterError(f"factor must have {self.n_angles} entries (one per particle), got {fac.size}")
        return fac

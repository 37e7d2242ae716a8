"""Non-Hermitian linear algebra of the straight clamped chain: mode localisation, the periodic bulk, the
spectrum's sensitivity and transient amplification (docs/outlook.md, section 1).

Pure functions: numbers and arrays in, arrays and typed records out. l = C = gamma = 1, isotropic drag.

The operator in particle displacements. About the straight chain, theta' = A theta (analysis.stability). With
y_k = sum_{j <= k} theta_j the transverse displacement of particle k (y = B theta, B the lower triangular matrix
of ones, D0 = B^T B), the same dynamics read

    y' = M y,   M = B A B^-1 = -B^-T (K - sigma S) B^-1,

a banded matrix (five diagonals) similar to A: the same eigenvalues, eigenvectors in particle displacements, and
the drag metric theta^T D0 theta = |y|^2 becomes the Euclidean one. So M's Hermitian part (M + M^T) / 2 holds
every conservative force and its anti-Hermitian part (M - M^T) / 2 the non-conservative one, and a growth of |y|
can only come from non-normality while the spectrum is stable. Row k of M in the bulk (3 <= k <= N - 2):

    y_k' = -(y_{k+2} - 4 y_{k+1} + 6 y_k - 4 y_{k-1} + y_{k-2})           bending
           - [C_{k+1/2} (y_{k+1} - y_k) - C_{k-1/2} (y_k - y_{k-1})]       links compressed by C = sigma (N - k)
           - sigma (y_k - y_{k-1})                                         particle k's own follower force

with C_{k+1/2} = sigma (N - k) the compression of the link from particle k to k + 1 (the follower forces of the
particles beyond it). The last term is the non-reciprocal one: particle k feels its predecessor, not its
successor. Its anti-Hermitian part, sigma (y_{k-1} - y_{k+1}) / 2, is the same at every k.

The periodic counterpart (ring_operator) freezes the compression at a value T: a circulant whose Bloch symbol, for
y_k ~ exp(i q k), is

    lambda(q) = -(2 - 2 cos q)^2 + T (2 - 2 cos q) - sigma (1 - exp(-i q)),

the chain's exact anti-Hermitian part plus a uniform conservative part. For sigma > 0 the symbol traces a loop
of nonzero winding about the points inside it: the signature of the non-Hermitian skin effect, whose open
counterpart (segment_operator: the same stencil on N sites, no neighbours beyond the ends) piles its slow modes
up at the tip end, within a decay length of about 3 sigma^(-1/3) sites (bending y'''' against the drift sigma y').
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.linalg import eig, expm

from ..core.errors import ParameterError
from .stability import banded_operator

__all__ = [
    "Localisation",
    "Transient",
    "displacement_operator",
    "hermitian_part",
    "bulk_stencil",
    "bulk_symbol",
    "ring_operator",
    "segment_operator",
    "localisation",
    "participation",
    "centre",
    "condition_numbers",
    "winding_number",
    "loop_reference",
    "smallest_singular_values",
    "nonnormality_ratio",
    "decay_length",
    "numerical_abscissa",
    "propagate",
    "worst_gain",
    "transient",
    "kick",
    "angles_from_displacements",
    "displacements",
]


def _check_n(n, least: int = 2) -> int:
    if int(n) != n or int(n) < least:
        raise ParameterError(f"n must be an integer >= {least}, got {n!r}")
    return int(n)


def _check_sigma(sigma) -> float:
    if not math.isfinite(sigma) or sigma < 0:
        raise ParameterError(f"sigma must be finite and >= 0, got {sigma!r}")
    return float(sigma)


# --------------------------------------------------------------------------------------------------
# operators
# --------------------------------------------------------------------------------------------------
def displacement_operator(n: int, sigma: float) -> np.ndarray:
    """M = -B^-T (K - sigma S) B^-1: the straight one-pinned chain's linear operator on the particles' transverse
    displacements y (similar to analysis.stability.linear_operator)."""
    n = _check_n(n)
    b_inv = np.eye(n) - np.eye(n, k=-1)  # B^-1: theta = differences of y
    return -banded_operator(n, _check_sigma(sigma)).toarray() @ b_inv


def hermitian_part(m: np.ndarray) -> np.ndarray:
    """(M + M^T) / 2: the conservative forces (M's non-conservative part is M minus this)."""
    return 0.5 * (m + m.T)


def bulk_stencil(sigma: float, compression: float) -> dict[int, float]:
    """Coefficients c_j of y_k' = sum_j c_j y_{k+j} in a bulk whose links all carry `compression` T:
    bending, the divergence of the links' compressions and the particle's own follower force."""
    s, t = _check_sigma(sigma), float(compression)
    return {-2: -1.0, -1: 4.0 - t + s, 0: -6.0 + 2.0 * t - s, 1: 4.0 - t, 2: -1.0}


def bulk_symbol(q, sigma: float, compression: float) -> np.ndarray:
    """lambda(q) = sum_j c_j exp(i q j) of bulk_stencil (the ring's eigenvalues at q = 2 pi m / N)."""
    q = np.asarray(q, dtype=float)
    return sum(c * np.exp(1j * j * q) for j, c in bulk_stencil(sigma, compression).items())


def _banded(n: int, stencil: dict[int, float], periodic: bool) -> np.ndarray:
    m = np.zeros((n, n))
    rows = np.arange(n)
    for j, c in stencil.items():
        cols = rows + j
        keep = np.ones(n, bool) if periodic else (cols >= 0) & (cols < n)
        np.add.at(m, (rows[keep], cols[keep] % n), c)
    return m


def ring_operator(n: int, sigma: float, compression: float) -> np.ndarray:
    """The bulk stencil on a ring of n particles (a circulant; n >= 5 so that the stencil does not wrap onto itself)."""
    return _banded(_check_n(n, 5), bulk_stencil(sigma, compression), periodic=True)


def segment_operator(n: int, sigma: float, compression: float) -> np.ndarray:
    """The bulk stencil on n sites with open ends (no neighbours beyond them): the ring cut open."""
    return _banded(_check_n(n, 5), bulk_stencil(sigma, compression), periodic=False)


# --------------------------------------------------------------------------------------------------
# where the modes sit
# --------------------------------------------------------------------------------------------------
class Localisation(NamedTuple):
    """Eigenvalues of an operator, sorted by decreasing real part (then imaginary part), and for each mode:"""

    eigenvalues: np.ndarray
    participation: np.ndarray
    """Participation ratio over the number of sites, 1 / (N sum p_k^2) with p = |v|^2 / |v|^2 summed: 1 for a
    plane wave, 1/N for one site."""
    centre: np.ndarray
    """Centre of |v|^2 along the chain, sum k p_k / N (1: the tip end; a uniform mode gives (N + 1) / 2N)."""
    condition: np.ndarray
    """Eigenvalue condition numbers |l| |r| / |l^H r| (left, right eigenvectors): 1 for a normal operator."""


def participation(vectors: np.ndarray) -> np.ndarray:
    """1 / (N sum_k p_k^2) of every column v (p = |v|^2 normalised)."""
    p = np.abs(vectors) ** 2
    p /= p.sum(axis=0)
    return 1.0 / (p.shape[0] * np.sum(p**2, axis=0))


def centre(vectors: np.ndarray) -> np.ndarray:
    """sum_k k p_k / N of every column v (p = |v|^2 normalised, k = 1 .. N)."""
    p = np.abs(vectors) ** 2
    p /= p.sum(axis=0)
    k = np.arange(1, p.shape[0] + 1)
    return (k @ p) / p.shape[0]


def condition_numbers(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """|l| |r| / |l^H r| column by column."""
    overlap = np.abs(np.sum(left.conj() * right, axis=0))
    return np.linalg.norm(left, axis=0) * np.linalg.norm(right, axis=0) / overlap


def localisation(m: np.ndarray) -> Localisation:
    """Eigenvalues, participation ratios, centres and condition numbers of every mode of m."""
    lam, left, right = eig(m, left=True, right=True)
    order = np.lexsort((-lam.imag, -lam.real))
    lam, left, right = lam[order], left[:, order], right[:, order]
    return Localisation(lam, participation(right), centre(right), condition_numbers(left, right))


def decay_length(vector: np.ndarray, lo: float = 0.25, hi: float = 0.75) -> float:
    """Sites over which |v| grows by e toward the tip: 1 / slope of log |v_k| fitted over the sites between the
    fractions lo and hi of the chain (negative: it grows toward the clamp; inf: flat)."""
    v = np.abs(np.asarray(vector))
    n = v.size
    k = np.arange(1, n + 1)
    part = (k > lo * n) & (k <= hi * n)
    if part.sum() < 3 or np.any(v[part] == 0):
        raise ParameterError("decay_length needs at least 3 nonzero sites between lo and hi")
    slope = np.polyfit(k[part], np.log(v[part]), 1)[0]
    return float(1.0 / slope) if slope != 0 else math.inf


# --------------------------------------------------------------------------------------------------
# the periodic spectrum's winding and the open spectrum's sensitivity
# --------------------------------------------------------------------------------------------------
def loop_reference(sigma: float, compression: float) -> complex:
    """A point inside the symbol's loop for sigma > 0: half-way between lambda(0) = 0 and lambda(pi) on the real
    axis (the loop crosses the real axis only at q = 0 and pi, and is open there by sigma |sin q|)."""
    return complex(0.5 * bulk_symbol(math.pi, sigma, compression))


def winding_number(sigma: float, compression: float, z0: complex | None = None) -> int:
    """(1 / 2 pi) times the change of arg(lambda(q) - z0) as q goes once round [0, 2 pi] (z0: loop_reference by
    default), by the argument principle: with beta = exp(i q), beta^2 (lambda - z0) is a polynomial of degree 4,
    so the winding is its number of roots inside the unit circle less 2 (exact however thin the loop). Refused
    when z0 lies on the spectrum of the ring (a root on the unit circle, to 1e-9)."""
    z0 = loop_reference(sigma, compression) if z0 is None else complex(z0)
    c = bulk_stencil(sigma, compression)
    roots = np.roots([c[2], c[1], c[0] - z0, c[-1], c[-2]])
    if np.min(np.abs(np.abs(roots) - 1.0)) < 1e-9:
        raise ParameterError(f"z0 = {z0} lies on the spectrum of the ring: the winding number is not defined there")
    return int(np.sum(np.abs(roots) < 1.0)) - 2


def smallest_singular_values(m: np.ndarray, re: np.ndarray, im: np.ndarray) -> np.ndarray:
    """s_min(z - M) on the grid z = re + i im (shape (len(im), len(re))): z lies in the eps-pseudospectrum where
    this is below eps."""
    n = m.shape[0]
    out = np.empty((len(im), len(re)))
    eye = np.eye(n)
    for i, y in enumerate(im):
        for j, x in enumerate(re):
            out[i, j] = np.linalg.svd((x + 1j * y) * eye - m, compute_uv=False)[-1]
    return out


def nonnormality_ratio(m: np.ndarray, re: np.ndarray, im: np.ndarray) -> float:
    """Largest distance(z, spectrum) / s_min(z - M) over the grid: 1 for a normal operator, and a lower bound on
    how far the spectrum can move under a perturbation of norm eps, in units of eps (grid points on an eigenvalue
    are skipped)."""
    lam = np.linalg.eigvals(m)
    z = np.asarray(re)[None, :] + 1j * np.asarray(im)[:, None]
    dist = np.min(np.abs(z[..., None] - lam), axis=-1)
    off = dist > 0  # a grid point on an eigenvalue has no ratio
    return float(np.max(dist[off] / smallest_singular_values(m, re, im)[off]))


# --------------------------------------------------------------------------------------------------
# transient amplification
# --------------------------------------------------------------------------------------------------
def numerical_abscissa(m: np.ndarray) -> float:
    """Largest eigenvalue of M's Hermitian part: d|y|/dt at t = 0 for the worst y of norm 1. A norm can grow
    transiently (while every eigenvalue decays) only when this is positive."""
    return float(np.linalg.eigvalsh(hermitian_part(m)).max())


def propagate(m: np.ndarray, y0: np.ndarray, times: np.ndarray) -> np.ndarray:
    """y(t) = exp(M t) y0 at every time (rows)."""
    return np.array([expm(m * float(t)) @ y0 for t in np.asarray(times)])


def worst_gain(m: np.ndarray, times: np.ndarray) -> np.ndarray:
    """||exp(M t)||_2 at every time: the largest amplification of any initial disturbance."""
    return np.array([np.linalg.norm(expm(m * float(t)), 2) for t in np.asarray(times)])


class Transient(NamedTuple):
    """How a disturbance's norm and position evolve."""

    gain: np.ndarray
    """|y(t)| / |y(0)| at every time."""
    centre: np.ndarray
    """Centre of y(t)^2 along the chain (fraction of N, as in Localisation.centre)."""
    peak_gain: float
    peak_time: float
    peak_centre: float
    """Where the disturbance sits at the peak."""


def transient(times: np.ndarray, y: np.ndarray) -> Transient:
    """The gain and centre of the displacements y (times, N) relative to the first sample."""
    y = np.asarray(y, dtype=float)
    norm = np.linalg.norm(y, axis=1)
    if norm[0] == 0:
        raise ParameterError("the disturbance is zero at the first time")
    gain = norm / norm[0]
    where = centre(y.T)
    i = int(np.argmax(gain))
    return Transient(gain, where, float(gain[i]), float(np.asarray(times)[i]), float(where[i]))


def kick(n: int, position: float, width: float, amplitude: float) -> np.ndarray:
    """A localised transverse displacement: a Gaussian bump of the particles about position x N (x in (0, 1]),
    of standard deviation width x N particles and height `amplitude` (l)."""
    n = _check_n(n)
    if not 0 < position <= 1:
        raise ParameterError(f"position must be in (0, 1], got {position!r}")
    if not width > 0:
        raise ParameterError(f"width must be > 0, got {width!r}")
    k = np.arange(1, n + 1) / n
    return amplitude * np.exp(-0.5 * ((k - position) / width) ** 2)


def angles_from_displacements(y: np.ndarray) -> np.ndarray:
    """Absolute angles whose particles sit at transverse positions y (exact: sin theta_k = y_k - y_{k-1})."""
    step = np.diff(np.asarray(y, dtype=float), prepend=0.0)
    if np.max(np.abs(step)) >= 1:
        raise ParameterError("neighbouring particles cannot be displaced by a link length or more")
    return np.arcsin(step)


def displacements(theta: np.ndarray) -> np.ndarray:
    """Transverse positions y_k = sum_{j <= k} sin theta_j of the particles (theta: (..., N))."""
    return np.cumsum(np.sin(np.asarray(theta, dtype=float)), axis=-1)

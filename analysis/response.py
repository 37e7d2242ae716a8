"""Linear response of the straight clamped chain to a small periodic force on its tip (docs/outlook.md, section 2).

Pure functions: numbers and arrays in, numbers and typed records out. l = C = gamma = 1, isotropic drag.

A force F on particle N has the generalised force Q_j = F . n_j on every angle (every pendulum carries the tip).
About the straight chain n_j = (-theta_j, 1), so a transverse force F_y enters at linear order as Q = F_y (1, ..,
1), and in particle displacements (analysis.skin: y' = M y, forces B^-T Q) as a force on particle N alone:

    y' = M y + e_N F_y(t),      G(omega) = y_N / F_y = e_N^T (i omega - M)^-1 e_N,

the tip's transfer function (tip displacement over tip force; for F_y = A sin(omega t) the steady tip moves as
|G| A sin(omega t + arg G)). A longitudinal force F_x enters as Q_j = -F_x theta_j: it multiplies the state, a
parametric drive with no linear response about the straight chain.

Below onset the least stable pair lambda = -gamma +- i omega_0 makes |G| resonate at omega ~ omega_0 with a half
width at half maximum (of |G|^2) ~ gamma, which vanishes linearly as sigma -> sigma_c.

Above onset the chain beats, and a weak tip force entrains it. Near the pair lambda, G ~ R / (i omega - lambda) +
c.c. with the residue R = (e_N^T v)(w^T e_N) / (w^T v) (v, w: right and left eigenvectors of M): the pair's
complex amplitude zeta, y_N = zeta + conj(zeta), obeys zeta' = lambda zeta + R F(t) + (nonlinear terms). On the
beat zeta = (a / 2) exp(i phi) (tip amplitude a), and the part of F = A sin(Omega t) that turns with it pushes the
phase at most by |R| A / a per unit time: Adler's locking range, |Omega - omega_beat| <= |R| A / a in angular
frequency (adler_half_width; the beat's non-isochronicity, which widens it by sqrt(1 + alpha^2), is left out).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ..core.errors import ParameterError
from .skin import displacement_operator

__all__ = [
    "Resonance",
    "Harmonic",
    "tip_transfer",
    "resonance",
    "harmonic_response",
    "tip_displacement",
    "tip_residue",
    "adler_half_width",
]


def tip_transfer(n: int, sigma: float, omega) -> np.ndarray:
    """G(omega) = e_N^T (i omega - M)^-1 e_N of the straight one-pinned chain (omega in rad / tau; array in, array
    out)."""
    m = displacement_operator(n, sigma)
    size = m.shape[0]
    tip = np.zeros(size)
    tip[-1] = 1.0
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    out = np.array([np.linalg.solve(1j * w * np.eye(size) - m, tip)[-1] for w in omega])
    return out


class Resonance(NamedTuple):
    """The peak of |G(omega)| and its half width at half maximum of |G|^2 (rad / tau)."""

    omega: float
    gain: float
    low: float
    """omega below the peak where |G|^2 is half its peak (nan when |G|^2 stays above it down to omega = 0)."""
    high: float
    half_width: float
    """(high - low) / 2."""


def resonance(n: int, sigma: float) -> Resonance:
    """The resonance of the tip's gain below onset, from the least stable eigenvalue pair (refused when that is
    real: no resonance)."""
    lam = np.linalg.eigvals(displacement_operator(n, sigma))
    lead = lam[np.argmax(lam.real)]
    if lead.real >= 0:
        raise ParameterError(f"sigma = {sigma:g} is not below the onset of N = {n}: no steady linear response")
    pair = lam[np.abs(lam.imag) > 0]
    if pair.size == 0 or pair[np.argmax(pair.real)].real < lead.real:
        raise ParameterError(f"the least stable mode of N = {n} at sigma = {sigma:g} is real: no resonance")
    w0, gamma = abs(pair[np.argmax(pair.real)].imag), -pair[np.argmax(pair.real)].real

    def gain2(w: float) -> float:
        return float(abs(tip_transfer(n, sigma, w)[0]) ** 2)

    lo = max(0.0, w0 - 3 * gamma)
    best = minimize_scalar(
        lambda w: -gain2(w), bounds=(lo, w0 + 3 * gamma), method="bounded", options={"xatol": 1e-10 * max(w0, 1e-12)}
    )
    peak_w, peak = float(best.x), gain2(float(best.x))
    half = peak / 2.0
    step = max(gamma, 1e-3 * w0)
    high = peak_w + step
    while gain2(high) > half:
        high += step
    high = brentq(lambda w: gain2(w) - half, peak_w, high, xtol=1e-13 * max(w0, 1.0))
    low = float("nan")
    if gain2(0.0) < half:
        low = brentq(lambda w: gain2(w) - half, 0.0, peak_w, xtol=1e-13 * max(w0, 1.0))
    width = (high - low) / 2.0 if math.isfinite(low) else high - peak_w
    return Resonance(peak_w, math.sqrt(peak), float(low), float(high), float(width))


class Harmonic(NamedTuple):
    """The part of a response at the drive's frequency, against the drive A sin(omega t)."""

    gain: complex
    """(p + i q) / A for x ~ c + p sin(omega t) + q cos(omega t): |gain| the amplitude ratio, arg gain the phase
    lead of the response."""
    offset: float
    residual: float
    """RMS of x minus the fit, over the RMS of the fitted oscillation."""


def harmonic_response(t: np.ndarray, x: np.ndarray, omega: float, amplitude: float) -> Harmonic:
    """Least-squares fit of x(t) by c + p sin(omega t) + q cos(omega t) over the samples given (pass whole drive
    periods), against the drive amplitude A."""
    t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
    if amplitude == 0 or not math.isfinite(amplitude):
        raise ParameterError(f"amplitude must be finite and nonzero, got {amplitude!r}")
    if t.size < 4 or omega * (t[-1] - t[0]) < 2 * math.pi:
        raise ParameterError("harmonic_response needs at least one whole drive period of samples")
    basis = np.column_stack([np.ones_like(t), np.sin(omega * t), np.cos(omega * t)])
    coef, *_ = np.linalg.lstsq(basis, x, rcond=None)
    fit = basis @ coef
    swing = math.hypot(coef[1], coef[2]) / math.sqrt(2.0)
    residual = float(np.sqrt(np.mean((x - fit) ** 2)) / swing) if swing > 0 else math.inf
    return Harmonic(complex(coef[1], coef[2]) / amplitude, float(coef[0]), residual)


def tip_displacement(theta: np.ndarray, direction: str = "transverse") -> np.ndarray:
    """The tip's displacement from the straight chain's tip (N l, 0): y_N = sum_j sin theta_j (transverse) or
    x_N - N = sum_j (cos theta_j - 1) (longitudinal); theta: (..., N) one chain's absolute angles."""
    theta = np.asarray(theta, dtype=float)
    if direction == "transverse":
        return np.sin(theta).sum(axis=-1)
    if direction == "longitudinal":
        return (np.cos(theta) - 1.0).sum(axis=-1)
    raise ParameterError(f"direction must be transverse or longitudinal, got {direction!r}")


def tip_residue(n: int, sigma: float) -> complex:
    """R = (e_N^T v)(w^T e_N) / (w^T v) of the eigenvalue pair with the largest real part (its member with positive
    imaginary part): G(omega) ~ R / (i omega - lambda) near it. Refused when that mode is real."""
    m = displacement_operator(n, sigma)
    lam, right = np.linalg.eig(m)
    left = np.linalg.inv(right)  # rows: left eigenvectors with w_k^T v_k = 1
    k = int(np.argmax(lam.real + 1e-12 * np.sign(lam.imag)))
    if lam[k].imag <= 0:
        raise ParameterError(f"the leading mode of N = {n} at sigma = {sigma:g} is real: no beat to entrain")
    return complex(right[-1, k] * left[k, -1])


def adler_half_width(n: int, sigma: float, amplitude: float, tip_amplitude: float) -> float:
    """Adler's locking half width |R| A / a (rad / tau) of a beat with tip amplitude a (half its peak-to-peak, l)
    under the tip force A sin(Omega t)."""
    if not tip_amplitude > 0:
        raise ParameterError(f"tip_amplitude must be > 0, got {tip_amplitude!r}")
    return abs(tip_residue(n, sigma)) * abs(amplitude) / tip_amplitude

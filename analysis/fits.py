"""Fits used by the studies, each returning values with one-standard-error uncertainties.

Errors come from the least-squares covariance (scipy.optimize.curve_fit / the normal equations),
scaled by the residual variance (absolute_sigma=False): they measure how well the data pin the
parameter down under the fitted model, not the model's own error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import curve_fit

__all__ = [
    "Fit",
    "linear_fit",
    "power_law_fit",
    "onset_power_law_fit",
    "square_root_onset_fit",
    "finite_size_fit",
    "exp_oscillation_fit",
    "richardson",
    "crossing",
]


@dataclass(frozen=True)
class Fit:
    """Fitted parameters, their standard errors, the coefficient of determination and the number of points."""

    params: dict
    errors: dict
    r2: float
    n: int
    extra: dict = field(default_factory=dict)

    def __getitem__(self, key: str) -> float:
        return self.params[key]

    def err(self, key: str) -> float:
        return self.errors[key]

    def as_dict(self) -> dict:
        return {"params": dict(self.params), "errors": dict(self.errors), "r2": self.r2, "n": self.n, **self.extra}

    def fmt(self, key: str, digits: int = 4) -> str:
        """'value +/- error' with `digits` significant digits on the value."""
        return f"{self.params[key]:.{digits}g} +/- {self.errors[key]:.2g}"


def _xy(x, y, min_points: int):
    x = np.asarray(x, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    if x.shape != y.shape:
        raise ValueError(f"x and y must have the same length; got {x.size} and {y.size}")
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    if x.size < min_points:
        raise ValueError(f"need at least {min_points} finite points; got {x.size}")
    return x, y


def _r2(y, yfit) -> float:
    ss = float(np.sum((y - y.mean()) ** 2))
    return 1.0 - float(np.sum((y - yfit) ** 2)) / ss if ss > 0 else 1.0


def _lstsq(A: np.ndarray, y: np.ndarray):
    """Coefficients and their covariance (residual-variance scaled) of y ~ A c."""
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    dof = max(y.size - A.shape[1], 1)
    s2 = float(np.sum((y - A @ coef) ** 2)) / dof
    cov = s2 * np.linalg.pinv(A.T @ A)
    return coef, cov


def linear_fit(x, y) -> Fit:
    """y = intercept + slope x (needs 3 points for an error estimate)."""
    x, y = _xy(x, y, 3)
    A = np.column_stack([np.ones_like(x), x])
    c, cov = _lstsq(A, y)
    return Fit(
        {"intercept": c[0], "slope": c[1]},
        {"intercept": math.sqrt(cov[0, 0]), "slope": math.sqrt(cov[1, 1])},
        _r2(y, A @ c),
        x.size,
        {"cov_intercept_slope": float(cov[0, 1])},
    )


def power_law_fit(x, y) -> Fit:
    """y = prefactor x^exponent, by a straight line through (log x, log y); x, y > 0."""
    x, y = _xy(x, y, 3)
    if np.any(x <= 0) or np.any(y <= 0):
        raise ValueError("power_law_fit needs positive x and y")
    f = linear_fit(np.log(x), np.log(y))
    a = math.exp(f["intercept"])
    return Fit(
        {"exponent": f["slope"], "prefactor": a},
        {"exponent": f.err("slope"), "prefactor": a * f.err("intercept")},
        f.r2,
        f.n,
    )


def square_root_onset_fit(x, y) -> Fit:
    """y = sqrt(k (x - onset)) (a supercritical Hopf with exponent 1/2): straight line through (x, y^2).

    onset = -intercept / slope, its error propagated with the intercept-slope covariance.
    """
    x, y = _xy(x, y, 3)
    f = linear_fit(x, y**2)
    b, k = f["intercept"], f["slope"]
    if k == 0:
        raise ValueError("y^2 does not change with x: no onset")
    xc = -b / k
    var = (f.err("intercept") ** 2 + xc**2 * f.err("slope") ** 2 + 2 * xc * f.extra["cov_intercept_slope"]) / k**2
    return Fit({"onset": xc, "k": k}, {"onset": math.sqrt(max(var, 0.0)), "k": f.err("slope")}, f.r2, f.n)


def onset_power_law_fit(x, y, beta0: float = 0.5, correction: bool = False) -> Fit:
    """y = prefactor (x - onset)^beta for x > onset, all three free (scipy curve_fit).

    correction=True fits y = prefactor (x - onset)^beta (1 + c (x - onset)) instead: the leading
    correction away from the onset, so that points further from it can be used without biasing
    beta (needs 5 points). The onset is bounded below min(x) (every point must lie past it).
    Starting guess: the square-root fit. Needs at least 4 points.
    """
    x, y = _xy(x, y, 5 if correction else 4)
    if np.any(y <= 0):
        raise ValueError("onset_power_law_fit needs y > 0 (only points past the onset)")
    span = float(x.max() - x.min())
    if span <= 0:
        raise ValueError("x must not be constant")
    upper = float(x.min()) - 1e-9 * max(1.0, abs(float(x.min())))
    try:
        xc0 = min(square_root_onset_fit(x, y)["onset"], upper - 1e-3 * span)
    except ValueError:
        xc0 = upper - 0.1 * span
    xc0 = max(xc0, upper - 10 * span)
    a0 = float(np.exp(np.mean(np.log(y) - beta0 * np.log(x - xc0))))

    def model(xx, a, xc, beta):
        return a * np.clip(xx - xc, 1e-300, None) ** beta

    p, cov = curve_fit(
        model, x, y, p0=[a0, xc0, beta0], bounds=([0, upper - 100 * span, 0.01], [np.inf, upper, 5.0]), maxfev=20000
    )
    if correction:

        def model_c(xx, a, xc, beta, c):
            return model(xx, a, xc, beta) * (1.0 + c * (xx - xc))

        scale = 1.0 / span
        p, cov = curve_fit(
            model_c,
            x,
            y,
            p0=[*p, 0.0],
            bounds=([0, upper - 100 * span, 0.01, -100 * scale], [np.inf, upper, 5.0, 100 * scale]),
            maxfev=20000,
        )
        err = np.sqrt(np.clip(np.diag(cov), 0, None))
        return Fit(
            {"prefactor": p[0], "onset": p[1], "beta": p[2], "c": p[3]},
            {"prefactor": err[0], "onset": err[1], "beta": err[2], "c": err[3]},
            _r2(y, model_c(x, *p)),
            x.size,
        )
    err = np.sqrt(np.clip(np.diag(cov), 0, None))
    return Fit(
        {"prefactor": p[0], "onset": p[1], "beta": p[2]},
        {"prefactor": err[0], "onset": err[1], "beta": err[2]},
        _r2(y, model(x, *p)),
        x.size,
    )


def finite_size_fit(n, y, order: int = 2) -> Fit:
    """y(N) = limit + b1 / N + ... + b_order / N^order: the N -> infinity limit with its error."""
    n, y = _xy(n, y, order + 2)
    A = np.column_stack([n ** (-k) for k in range(order + 1)])
    c, cov = _lstsq(A, y)
    names = ["limit"] + [f"b{k}" for k in range(1, order + 1)]
    return Fit(dict(zip(names, c)), dict(zip(names, np.sqrt(np.diag(cov)))), _r2(y, A @ c), n.size)


def exp_oscillation_fit(t, x) -> Fit:
    """x(t) = e^{rate (t - t0)} (A cos w (t - t0) + B sin w (t - t0)) + offset, t0 = t[0].

    rate is the real part (1/tau) and w the imaginary part (rad/tau) of the dominant eigenvalue
    when a single complex pair dominates the record; works with as little as one period.
    """
    t, x = _xy(t, x, 8)
    s = t - t[0]
    y = x - x.mean()
    # starting guesses: w from the FFT peak (at least one cycle over the record), rate from the
    # trend of |x| between the two halves
    dt = float(np.median(np.diff(s)))
    spec = np.abs(np.fft.rfft(y * np.hanning(y.size), n=8 * y.size))
    freqs = np.fft.rfftfreq(8 * y.size, dt)
    w0 = 2 * math.pi * max(freqs[1 + int(np.argmax(spec[1:]))], 0.5 / max(s[-1], dt))
    half = y.size // 2
    a1, a2 = np.abs(y[:half]).max(), np.abs(y[half:]).max()
    g0 = math.log(max(a2, 1e-300) / max(a1, 1e-300)) / max(s[half], dt) if a1 > 0 and a2 > 0 else 0.0

    def model(ss, rate, w, A, B, c):
        return np.exp(rate * ss) * (A * np.cos(w * ss) + B * np.sin(w * ss)) + c

    best = None
    for w_try in (w0, 0.7 * w0, 1.4 * w0):
        p0 = [g0, w_try, y[0], 0.0, x.mean()]
        try:
            p, cov = curve_fit(model, s, x, p0=p0, maxfev=20000)
        except RuntimeError:
            continue
        res = float(np.sum((x - model(s, *p)) ** 2))
        if best is None or res < best[0]:
            best = (res, p, cov)
    if best is None:
        raise RuntimeError("exp_oscillation_fit did not converge")
    _, p, cov = best
    err = np.sqrt(np.clip(np.diag(cov), 0, None))
    return Fit(
        {"rate": p[0], "omega": abs(p[1]), "offset": p[4]},
        {"rate": err[0], "omega": err[1], "offset": err[4]},
        _r2(x, model(s, *p)),
        x.size,
    )


def richardson(coarse: float, fine: float, ratio: float = 2.0, order: int = 1) -> float:
    """Extrapolate a quantity computed at step h (coarse) and h / ratio (fine) to h -> 0,
    assuming an error ~ h^order."""
    r = ratio**order
    return (r * fine - coarse) / (r - 1.0)


def crossing(x, y, level: float = 0.0) -> float:
    """First x where y crosses `level` (linear interpolation between samples); nan if it never does."""
    x, y = _xy(x, y, 2)
    d = y - level
    idx = np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) <= 0)
    for i in idx:
        if d[i] == d[i + 1]:
            return float(x[i])
        return float(x[i] - d[i] * (x[i + 1] - x[i]) / (d[i + 1] - d[i]))
    return float("nan")

"""The Greenwood-Williamson functions F_n(h), evaluated to full double precision.

For a Gaussian distribution of summit heights (docs/theory.md, "GW functions")

    F_n(h) = (1/sqrt(2 pi)) * integral_h^inf (s - h)^n exp(-s^2/2) ds
           = Gamma(n+1)/sqrt(2 pi) * exp(-h^2/4) * D_{-n-1}(h)      (D: parabolic cylinder),

with ``dF_n/dh = -n F_{n-1}`` and the recurrence ``F_{n+1}(h) = n F_{n-1}(h) - h F_n(h)``
(integrate ``t^n (h + t) exp(-h t - t^2/2)`` by parts). Here h = (d - mu_s)/sigma is the
separation reduced by the summit-height statistics. For the exponential law of the paper's
eqs. (7)-(10), density (1/sigma) exp(-(z - mu_s)/sigma), ``F_n(h) = Gamma(n+1) exp(-h)``.

Why not the closed forms
------------------------
``F_1 = phi - h F_0`` and the Bessel forms of the half-integer orders subtract nearly equal
numbers once h is a few units large (F_n decays like phi(h) h^(-n-1)); the naive F_1 is off by
~h^4 eps/2 (4e-11 at h = 30). ``scipy.special.pbdv`` is off by up to 3e-9 on [-10, 37]
(measured near h = 5.8, order 3/2) and D_{-n-1}(h) itself overflows for h < -53. This module
instead uses, for the Gaussian law:

* ``|h| < 12``: F_0 = ndtr(-h); F_1 = phi(h) (1 - h sqrt(pi/2) erfcx(h/sqrt 2)) (a scaled
  form: the cancellation costs at most a factor h^2 < 144 on erfcx's rounding); the
  half-integer orders by the substitution s = h + w^2,
  ``F_n(h) = (1/sqrt(2 pi)) integral_{-inf}^{inf} |w|^{2n+1} exp(-(w^2 + h)^2/2) dw``,
  whose integrand is smooth and even (2n+1 is an even integer), so the trapezoidal rule
  converges geometrically; step 0.1 on ``|w| <= 4.6`` is exact to rounding for ``|h| < 12``.
* ``h >= 12``: ``F_n(h) = phi(h) sum_j (-1)^j Gamma(n+2j+1) / (2^j j! h^(n+2j+1))`` from
  expanding exp(-t^2/2) in ``integral_0^inf t^n exp(-h t - t^2/2) dt``; the partial sums of
  exp(-x) bracket it, so the error is below the first omitted term (< 1e-18 relative at h = 12).
  phi(h) is evaluated with h^2 split exactly into two doubles, so no digits are lost in the
  exponent; values underflow gracefully (subnormal, then 0) beyond h ~ 37.5.
* ``h <= -12``: ``F_n(h) = |h|^n sum_j binom(n, 2j) (2j-1)!! h^(-2j)``, the Gaussian
  moments in ``E[(s + |h|)^n]`` (exact for n = 0, 1 up to O(exp(-h^2/2)) < 1e-31; an
  asymptotic series otherwise, truncated where its terms fall below 1e-18 at ``|h| = 12`` and
  checked against mpmath to 1e-15 there).

Accuracy (checked against mpmath in tests/test_gw_functions.py): relative error below 1e-13
for every h in [-10, 37] and every supported order; never NaN, never negative.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from bem.common import checks
from numpy.typing import ArrayLike
from scipy import special

from asperity.common.roots import monotone_root

__all__ = ["GW_ORDERS", "DISTRIBUTIONS", "gw_integral", "log_gw_integral"]

#: Orders n available for the Gaussian height law (any n > -1 for the exponential law).
GW_ORDERS = (-0.5, 0.0, 0.5, 1.0, 1.5)

#: Summit-height distributions understood by every GW-type model.
DISTRIBUTIONS = ("gaussian", "exponential")

_SERIES_THRESHOLD = 12.0       # |h| from which the asymptotic series take over
_UNDERFLOW = 40.0              # F_n(h) < 1e-340 for h > 40: exactly 0 in double precision
_TRAPEZOID_STEP = 0.1
_TRAPEZOID_NODES = np.arange(47) * _TRAPEZOID_STEP          # w = 0 .. 4.6
_TRAPEZOID_BLOCK = 32768                                    # points per block (cache sized)
_LOG_SQRT_TWO_PI = 0.5 * math.log(2.0 * math.pi)
_SQRT_TWO_PI = math.sqrt(2.0 * math.pi)
_SERIES_TOLERANCE = 1e-18      # first omitted term, relative, at |h| = 12


def _upper_series_coefficients(n: float) -> np.ndarray:
    """a_j = (-1)^j Gamma(n+2j+1)/(2^j j!), truncated where |a_J| 12^(-2J) < tolerance a_0."""
    coefficients = []
    for j in range(200):
        log_term = math.lgamma(n + 2 * j + 1) - j * math.log(2.0) - math.lgamma(j + 1)
        coefficients.append((-1.0) ** j * math.exp(log_term))
        if abs(coefficients[-1]) * _SERIES_THRESHOLD ** (-2 * j) < (
                _SERIES_TOLERANCE * abs(coefficients[0])) and j > 0:
            break
    return np.array(coefficients)


def _lower_series_coefficients(n: float) -> np.ndarray:
    """b_j = binom(n, 2j) (2j-1)!!, truncated like the upper series (exact for n = 0, 1)."""
    coefficients = [1.0]
    double_factorial = 1.0
    for j in range(1, 200):
        double_factorial *= 2 * j - 1
        b = float(special.binom(n, 2 * j)) * double_factorial
        coefficients.append(b)
        if abs(b) * _SERIES_THRESHOLD ** (-2 * j) < _SERIES_TOLERANCE:
            break
    return np.array(coefficients)


_UPPER = {n: _upper_series_coefficients(n) for n in GW_ORDERS}
_LOWER = {n: _lower_series_coefficients(n) for n in GW_ORDERS}


# --------------------------------------------------------------------------------------------
# input checks

def _check_distribution(distribution: str) -> str:
    if not isinstance(distribution, str) or distribution not in DISTRIBUTIONS:
        raise ValueError(f"distribution must be one of {DISTRIBUTIONS}, got {distribution!r}")
    return distribution


def _check_order(n: float, distribution: str) -> float:
    order = checks.real_number("n", n)
    if distribution == "exponential":
        if not (np.isfinite(order) and order > -1.0):
            raise ValueError(f"n must be finite and > -1 for exponential heights, got {n!r}")
        return order
    if order not in GW_ORDERS:
        raise ValueError(f"n must be one of {GW_ORDERS} for Gaussian heights, got {n!r}")
    return order


def _check_reduced_separation(h: ArrayLike, name: str = "h") -> np.ndarray:
    values = checks.real_array(name, h, finite=False)
    if np.isnan(values).any():
        raise ValueError(f"{name} must not contain NaN")
    return values


# --------------------------------------------------------------------------------------------
# the three regions of the Gaussian law

def _square_split(h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """h*h = p + e exactly (Dekker's product; valid for |h| < 1e150)."""
    c = 134217729.0 * h
    high = c - (c - h)
    low = h - high
    p = h * h
    e = ((high * high - p) + 2.0 * high * low) + low * low
    return p, e


def _gaussian_density(h: np.ndarray) -> np.ndarray:
    """phi(h) = exp(-h^2/2)/sqrt(2 pi) to a few ulp (the exponent is split exactly)."""
    p, e = _square_split(h)
    return np.exp(-0.5 * p) * (np.exp(-0.5 * e) / _SQRT_TWO_PI)


def _upper_sum(n: float, h: np.ndarray) -> np.ndarray:
    """sum_j a_j h^(-2j) (Horner in 1/h^2), h >= 12."""
    u = (1.0 / h) ** 2
    total = np.zeros_like(h)
    for a in _UPPER[n][::-1]:
        total = total * u + a
    return total


def _lower_sum(n: float, x: np.ndarray) -> np.ndarray:
    """sum_j b_j x^(-2j), x = -h >= 12."""
    u = (1.0 / x) ** 2
    total = np.zeros_like(x)
    for b in _LOWER[n][::-1]:
        total = total * u + b
    return total


def _upper_value(n: float, h: np.ndarray) -> np.ndarray:
    out = np.zeros_like(h)
    finite = h <= _UNDERFLOW
    x = h[finite]
    p, e = _square_split(x)
    with np.errstate(under="ignore"):
        out[finite] = np.exp(-0.5 * p) * (
            _upper_sum(n, x) * x ** (-n - 1.0) * np.exp(-0.5 * e) / _SQRT_TWO_PI)
    return out


def _upper_log(n: float, h: np.ndarray) -> np.ndarray:
    out = np.full_like(h, -np.inf)
    finite = np.isfinite(h)
    x = h[finite]
    with np.errstate(over="ignore"):                  # h > 1e154: log F_n = -inf
        out[finite] = (-0.5 * x * x - _LOG_SQRT_TWO_PI - (n + 1.0) * np.log(x)
                       + np.log(_upper_sum(n, x)))
    return out


def _lower_log(n: float, h: np.ndarray) -> np.ndarray:
    x = -h
    out = np.empty_like(h)
    finite = np.isfinite(x)
    out[finite] = n * np.log(x[finite]) + np.log(_lower_sum(n, x[finite]))
    out[~finite] = np.inf if n > 0 else (0.0 if n == 0 else -np.inf)
    return out


def _lower_value(n: float, h: np.ndarray) -> np.ndarray:
    x = -h
    out = np.empty_like(h)
    finite = np.isfinite(x)
    with np.errstate(over="ignore"):
        out[finite] = x[finite] ** n * _lower_sum(n, x[finite])
    out[~finite] = np.inf if n > 0 else (1.0 if n == 0 else 0.0)
    return out


def _central_values(orders: Sequence[float], h: np.ndarray) -> list[np.ndarray]:
    """F_n(h) for |h| < 12 and each order; half-integer orders share one set of exponentials."""
    results: dict[float, np.ndarray] = {}
    half_integer = [n for n in orders if n not in (0.0, 1.0)]
    if 0.0 in orders or 1.0 in orders:
        tail = special.ndtr(-h)
        results[0.0] = tail
        if 1.0 in orders:
            density = _gaussian_density(h)
            positive = h > 0
            first = np.empty_like(h)
            first[~positive] = density[~positive] - h[~positive] * tail[~positive]
            hp = h[positive]
            scaled = 1.0 - hp * (math.sqrt(math.pi / 2.0) * special.erfcx(hp / math.sqrt(2.0)))
            first[positive] = density[positive] * scaled
            results[1.0] = first
    if half_integer:
        w = _TRAPEZOID_NODES
        weights = np.array([w ** (2.0 * n + 1.0) for n in half_integer]).T   # (nodes, orders)
        weights[0, :] *= 0.5                                   # w = 0 counted once in +-w
        weights *= 2.0 * _TRAPEZOID_STEP / _SQRT_TWO_PI
        w2 = w * w
        values = np.zeros((len(half_integer), h.size))
        term = np.empty(min(h.size, _TRAPEZOID_BLOCK))
        # Node by node over cache-sized blocks: every point sums its terms in the same order,
        # so equal h give bit-identical F_n wherever they sit in the array (a BLAS product
        # does not guarantee that).
        for start in range(0, h.size, _TRAPEZOID_BLOCK):
            block = h[start:start + _TRAPEZOID_BLOCK]
            t = term[:block.size]
            for node in range(w.size):
                np.add(block, w2[node], out=t)
                np.multiply(t, t, out=t)
                t *= -0.5
                np.exp(t, out=t)
                for k in range(len(half_integer)):
                    values[k, start:start + block.size] += weights[node, k] * t
        for k, n in enumerate(half_integer):
            results[n] = values[k]
    return [results[n] for n in orders]


def _gaussian(orders: Sequence[float], h: np.ndarray, *, log: bool) -> list[np.ndarray]:
    """F_n(h) (or log F_n(h)) for Gaussian heights: series in both tails, quadrature between."""
    upper_tail, lower_tail = (_upper_log, _lower_log) if log else (_upper_value, _lower_value)
    flat = h.ravel()
    outputs = [np.empty_like(flat) for _ in orders]
    upper = flat >= _SERIES_THRESHOLD
    lower = flat <= -_SERIES_THRESHOLD
    middle = ~(upper | lower)
    central = _central_values(orders, flat[middle]) if middle.any() else None
    for k, n in enumerate(orders):
        outputs[k][upper] = upper_tail(n, flat[upper])
        outputs[k][lower] = lower_tail(n, flat[lower])
        if central is not None:
            outputs[k][middle] = np.log(central[k]) if log else central[k]
    return [out.reshape(h.shape) for out in outputs]


# --------------------------------------------------------------------------------------------
# the public functions and their batched internal forms

def gw_integrals(orders: Sequence[float], h: np.ndarray, distribution: str = "gaussian"
                 ) -> list[np.ndarray]:
    """F_n(h) for several orders at once (h already checked); shares work between orders."""
    if distribution == "exponential":
        with np.errstate(over="ignore"):
            return [np.exp(math.lgamma(n + 1.0) - h) for n in orders]
    return _gaussian(orders, h, log=False)


def log_gw_integrals(orders: Sequence[float], h: np.ndarray, distribution: str = "gaussian"
                     ) -> list[np.ndarray]:
    """log F_n(h) for several orders at once (h already checked); finite where F_n underflows."""
    if distribution == "exponential":
        return [math.lgamma(n + 1.0) - h for n in orders]
    return _gaussian(orders, h, log=True)


def gw_integral(n: float, h: ArrayLike, distribution: str = "gaussian") -> np.ndarray:
    """The Greenwood-Williamson function F_n(h) (docs/theory.md, eq. T6; paper Section 2).

    ``F_n(h) = integral_h^inf (s - h)^n phi*(s) ds`` for the standardised summit-height
    density phi*: F_0 is the fraction of summits in contact, F_1 gives the real area,
    F_3/2 the load and F_1/2 the stiffness of GW theory.

    Parameters
    ----------
    n : float
        Order. Gaussian heights: one of ``GW_ORDERS`` = (-1/2, 0, 1/2, 1, 3/2). Exponential
        heights: any n > -1.
    h : array_like
        Reduced separation (d - mu_s)/sigma [-]. Any shape; +-inf allowed, NaN is not.
    distribution : {"gaussian", "exponential"}
        ``"gaussian"``: standard normal phi*. ``"exponential"``: the paper's eq. (7) law
        phi*(s) = exp(-s) taken over all s (the usual model of the upper tail), so that
        F_n(h) = Gamma(n+1) exp(-h) for every h (eqs. (8)-(10) then hold exactly).

    Returns
    -------
    numpy.ndarray or numpy.float64
        F_n(h) [-], same shape as h; relative error < 1e-13 on [-10, 37] (see the module
        docstring), smoothly underflowing to 0 beyond h ~ 37.5, +inf where the exact value
        overflows (h -> -inf for n > 0). Never NaN, never negative.

    Raises
    ------
    ValueError
        If ``n`` is not an available order, ``h`` contains NaN, or ``distribution`` is unknown.
    """
    distribution = _check_distribution(distribution)
    order = _check_order(n, distribution)
    values = _check_reduced_separation(h)
    return gw_integrals((order,), values, distribution)[0][()]


def log_gw_integral(n: float, h: ArrayLike, distribution: str = "gaussian") -> np.ndarray:
    """Natural logarithm of :func:`gw_integral`, finite where F_n itself underflows.

    Same parameters as :func:`gw_integral`. For h >= 12 (Gaussian) it is
    ``-h^2/2 - ln sqrt(2 pi) + ln(sum_j a_j h^(-n-2j-1))``, so it stays accurate far beyond
    the underflow of F_n (used to invert very small loads). Error: a few units in the last
    place of log F_n (about 1e-13 absolute at h = 37, where log F_n ~ -690).
    """
    distribution = _check_distribution(distribution)
    order = _check_order(n, distribution)
    values = _check_reduced_separation(h)
    return log_gw_integrals((order,), values, distribution)[0][()]


def inverse_log_gw_integral(n: float, log_value: np.ndarray, distribution: str = "gaussian"
                            ) -> tuple[np.ndarray, np.ndarray]:
    """The reduced separation h with ``log F_n(h) = log_value`` (n > 0), elementwise.

    ``log_value = -inf`` gives ``h = +inf``. Gaussian: F_n is strictly decreasing and
    log-concave, so Newton's iteration on ``log F_n(h) - log_value`` is monotone once it is to
    the right of the root; the bracket comes from ``F_n(h) <= F_n(0) exp(-h^2/2)`` for h >= 0
    and ``F_n(-x) >= x^n`` (n >= 1, Jensen) or ``>= (x/2)^n / 2`` (0 < n < 1) for x > 0.

    Returns ``(h, converged)``.
    """
    target = np.asarray(log_value, dtype=float)
    if distribution == "exponential":
        return math.lgamma(n + 1.0) - target, np.ones(target.shape, dtype=bool)
    if not n > 0:
        raise ValueError(f"n must be > 0 to invert F_n, got {n!r}")
    flat = target.ravel()
    h = np.full(flat.shape, np.inf)
    converged = np.ones(flat.shape, dtype=bool)
    finite = np.isfinite(flat)
    if np.any(flat == np.inf):
        raise ValueError("the value to invert must be finite")
    if finite.any():
        goal = flat[finite]
        log_at_zero = math.log(float(gw_integrals((n,), np.zeros(1))[0][0]))
        light = goal < log_at_zero
        with np.errstate(over="ignore"):
            if n >= 1:
                far = np.exp(goal / n)
            else:
                far = 2.0 * np.exp((goal + math.log(2.0)) / n)
        if not np.all(np.isfinite(far)):
            raise ValueError("the value to invert is too large (F_n overflows)")
        lower = np.where(light, 0.0, -far)
        upper = np.where(light, np.sqrt(2.0 * np.maximum(log_at_zero - goal, 0.0)), 0.0)
        start = np.where(light, upper, lower)
        ratio_orders = (n - 1.0, n) if (n - 1.0) in GW_ORDERS else None
        if ratio_orders is None:
            raise ValueError(f"n - 1 must be an available order to invert F_n, got n = {n!r}")

        def function(x, index):
            log_lower, log_value_n = log_gw_integrals(ratio_orders, x)
            return log_value_n - goal[index], -n * np.exp(log_lower - log_value_n)

        root, ok, _ = monotone_root(function, lower, upper, start, increasing=False)
        h[finite] = root
        converged[finite] = ok
    return h.reshape(target.shape), converged.reshape(target.shape)

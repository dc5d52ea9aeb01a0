"""The kernels of Persson's theory: I(x) of the mean gap (docs/theory.md, eq. P6) and g(x) of
the stiffness (P8), with the correction factor gamma of Yang & Persson (2008).

Both :mod:`asperity.spectral.persson` (the theory) and :mod:`asperity.spectral.persson_gaps` (its gap
distribution) integrate them over the spectrum; they live here so that neither imports the other.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import chebyshev, laguerre, legendre
from numpy.typing import ArrayLike
from scipy import special

from bem.common.checks import points, real_number

__all__ = ["YANG_PERSSON_GAMMA", "separation_kernel"]

#: The correction factor gamma of Yang & Persson (2008); gamma = 1 is Persson (2007).
YANG_PERSSON_GAMMA = 0.42

_SWITCH = 4.0                     # J: Chebyshev interpolant below, E1 minus a tail above
_LAGUERRE_NODES, _LAGUERRE_WEIGHTS = laguerre.laggauss(24)


def _tail(x: np.ndarray) -> np.ndarray:
    """R(x) = integral_x^inf (1 - erf^2) exp(-t^2) dt/t for x >= 4 (Gauss-Laguerre in t^2)."""
    s = _LAGUERRE_NODES[np.newaxis, :]
    y2 = x[:, np.newaxis] ** 2 + 0.5 * s
    y = np.sqrt(y2)
    inner = special.erfcx(y) * (2.0 - special.erfc(y)) / (4.0 * y2)
    return np.exp(-2.0 * x**2) * (inner @ _LAGUERRE_WEIGHTS)


def _j_by_quadrature(x: np.ndarray) -> np.ndarray:
    """J(x) = integral_x^inf erf(t)^2 exp(-t^2) dt/t for 0 <= x <= 4: 96-point Gauss-Legendre
    on [x, x + 6] (a sum of positive terms: no cancellation) plus the closed-form tail."""
    nodes, weights = legendre.leggauss(96)
    t = x[:, np.newaxis] + 3.0 * (nodes + 1.0)
    safe = np.where(t > 0, t, 1.0)
    f = np.where(t > 0, special.erf(safe) ** 2 * np.exp(-safe**2) / safe, 0.0)
    end = x + 6.0
    return 3.0 * (f @ weights) + 0.5 * special.exp1(end**2) - _tail(end)


def _build_j() -> chebyshev.Chebyshev:
    """Chebyshev interpolant of ln J on [0, 4] (J falls from 0.6 to 1e-8 there; interpolating
    its logarithm keeps the relative error at rounding level)."""
    # coefficients fall to the quadrature's noise (~5e-14) by degree 35: keep 41 terms
    return chebyshev.Chebyshev.interpolate(lambda x: np.log(_j_by_quadrature(np.asarray(x))),
                                           90, domain=[0.0, _SWITCH]).truncate(41)


_J = _build_j()


def separation_kernel(x: ArrayLike, gamma: float = YANG_PERSSON_GAMMA) -> np.ndarray:
    """I(x) = integral_x^inf (dt/t) [gamma + 3 (1 - gamma) erf(t)^2] exp(-t^2), eq. (P6).

    ``(gamma/2) E1(x^2) + 3 (1 - gamma) J(x)``; +inf at x = 0. Relative accuracy ~1e-13.
    """
    return _separation_kernel(points("x", x, non_negative=True, allow_infinity=True),
                              real_number("gamma", gamma, minimum=0.0, exclusive=True,
                                          maximum=1.0))


def _separation_kernel(x: np.ndarray, gamma: float) -> np.ndarray:
    """:func:`separation_kernel` of checked arguments (x >= 0 as a float array)."""
    flat = x.ravel()
    with np.errstate(divide="ignore", over="ignore"):
        e1 = special.exp1(flat**2)
        tiny = flat < 1e-8          # x^2 may underflow: E1(z) = -euler_gamma - ln z + O(z)
        e1[tiny] = -np.euler_gamma - 2.0 * np.log(flat[tiny])
    j = np.empty_like(flat)
    low = flat < _SWITCH
    j[low] = np.exp(_J(flat[low]))
    j[~low] = 0.5 * e1[~low] - _tail(flat[~low])
    return (0.5 * gamma * e1 + 3.0 * (1.0 - gamma) * j).reshape(x.shape)


def _stiffness_kernel(x: np.ndarray, gamma: float) -> np.ndarray:
    """g(x) = [gamma + 3 (1 - gamma) erf(x)^2] exp(-x^2) = -x dI/dx."""
    return (gamma + 3.0 * (1.0 - gamma) * special.erf(x) ** 2) * np.exp(-x * x)

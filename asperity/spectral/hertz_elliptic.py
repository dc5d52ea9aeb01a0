"""Hertz contact of an elliptic paraboloid with a flat: area and load against approach.

Johnson, *Contact Mechanics* (1985), section 4.2 (docs/theory.md, section "Bush-Gibson-Thomas
theory", eq. S9). A summit ``z = w - (kappa_1 x^2 + kappa_2 y^2)/2`` with principal curvatures
``kappa_1 >= kappa_2 > 0`` pressed by ``w`` [length] makes an elliptic contact of semi-axes
``a >= b`` (a along the direction of the smaller curvature). With the eccentricity
``e^2 = m = 1 - b^2/a^2`` and the complete elliptic integrals K(m), E(m) (parameter m), the
curvature ratio fixes m,

    lambda = kappa_2 / kappa_1 = (K - E) / (E / (1 - m) - K),

and the area and load follow in the form of a sphere of the geometric-mean radius
``R_e = 1/sqrt(kappa_1 kappa_2)`` corrected by two factors of lambda alone:

    A = pi R_e w f_A(lambda),          f_A = 2 sqrt(1 - m) (K - E) / (m K sqrt(lambda))
    P = (4/3) E* R_e^(1/2) w^(3/2) f_P(lambda),   f_P = pi (K - E)^(1/2) / (sqrt(2 m) K^(3/2) lambda^(1/4))

with ``f_A = f_P = 1`` at lambda = 1 (Hertz's sphere) and ``dP/dw = 3P/(2w)``. Setting both
factors to 1 is Greenwood's simplified elliptic model (Wear 261, 2006).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy import special

from bem.common import checks

__all__ = ["hertz_elliptic_factors", "eccentricity_parameter"]

#: Bisection steps on log(-log(1 - m)): ample for double precision over the whole range.
_STEPS = 200


def _integrals(m: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """K, E and K - E at m, given also p = 1 - m = b^2/a^2 (each without cancellation), so
    that they are accurate near m = 0 and m = 1."""
    k = special.ellipkm1(p)
    e = special.ellipe(m)
    # K - E = (pi/4) m (1 + 3m/8 + 15m^2/64 + 175 m^3/1024 + ...) for small m (no cancellation)
    small = m < 1e-3
    series = 0.25 * math.pi * m * (1.0 + m * (3.0 / 8.0 + m * (15.0 / 64.0
                                                               + m * 175.0 / 1024.0)))
    return k, e, np.where(small, series, k - e)


def _ratio(m: np.ndarray, p: np.ndarray) -> np.ndarray:
    """lambda(m) = (K - E) / (E/(1 - m) - K), given also p = 1 - m."""
    k, e, k_minus_e = _integrals(m, p)
    # E/(1-m) - K = (E - K + m K)/(1-m) = (m K - (K - E)) / p
    return k_minus_e * p / (m * k - k_minus_e)


def _solve(lam: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(m, 1 - m) with lambda(m) = lam, each computed without cancellation."""
    lo = np.full(lam.shape, math.log(1e-18))     # m ~ 1e-18: lambda = 1 to rounding
    hi = np.full(lam.shape, math.log(700.0))     # 1 - m ~ exp(-700): lambda ~ 1e-300
    for _ in range(_STEPS):
        mid = 0.5 * (lo + hi)
        y = np.exp(mid)                          # y = -log(1 - m)
        larger = _ratio(-np.expm1(-y), np.exp(-y)) > lam                 # still too round: m must grow
        lo = np.where(larger, mid, lo)
        hi = np.where(larger, hi, mid)
    y = np.exp(0.5 * (lo + hi))                  # y = -log(1 - m)
    return -np.expm1(-y), np.exp(-y)


def eccentricity_parameter(ratio: ArrayLike) -> np.ndarray:
    """The parameter m = e^2 of the Hertz contact ellipse of curvature ratio lambda in (0, 1).

    Bisection on ``log(-log(1 - m))`` (lambda decreases as m grows), elementwise.
    """
    return _solve(np.asarray(ratio, dtype=float))[0]


def hertz_elliptic_factors(ratio: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Area and load factors ``(f_A, f_P)`` of the elliptic Hertz contact (module docstring).

    Parameters
    ----------
    ratio : array_like
        Curvature ratio lambda = kappa_min / kappa_max, in (0, 1] [-].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        f_A and f_P [-], each of the shape of ``ratio`` (both 1 at lambda = 1).
    """
    lam = checks.real_array("ratio", ratio)
    if np.any(lam <= 0) or np.any(lam > 1):
        raise ValueError("ratio must lie in (0, 1] (smaller over larger principal curvature)")
    round_ = lam >= 1.0 - 1e-15
    safe = np.where(round_, 0.5, lam)
    m, p = _solve(safe)
    k, _, k_minus_e = _integrals(m, p)
    f_area = 2.0 * np.sqrt(p) * k_minus_e / (m * k * np.sqrt(safe))
    f_load = math.pi * np.sqrt(k_minus_e) / (np.sqrt(2.0 * m) * k**1.5 * safe**0.25)
    return np.where(round_, 1.0, f_area), np.where(round_, 1.0, f_load)

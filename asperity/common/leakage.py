"""Leakage predictions of the theories: effective hydraulic apertures of gap distributions.

docs/theory.md, section "Gas-tightness and leakage", eqs. (L1)-(L5).

The quantity is the effective hydraulic aperture h_eff [length] of the gap between the rigid
plane and the surface, defined by the Reynolds flow rate through a square of side L (width W)
under a pressure drop dp, ``Q = W h_eff^3 dp / (12 mu L)`` (L1): a uniform gap h gives h, a gap
sealed by a percolating contact gives 0. The leak rate itself is proportional to h_eff^3.

Effective medium (Bruggeman 1935; used for contact leakage by Lorenz & Persson 2010 and Dapp,
Lucke, Persson & Muser 2012): the local Reynolds conductance is g^3, and an inclusion of
conductance g^3 in a homogeneous medium of conductance c = h_eff^3 must, on average, not disturb
the flow. For isotropic two-dimensional flow this is (L2)::

    integral P(g) (g^3 - c) / (g^3 + k c) dg = 0,      k = a_c / (1 - a_c)

with the contact fraction f0 as a weight at g = 0. The plain 2-D Bruggeman medium has k = 1: its
contact percolates, and the flow stops, at f0 = a_c = 1/2. A general k moves the threshold to
a_c (the same form as a lattice's effective medium with its coordination number), which is how a
measured percolation threshold (about 0.42 for elastic self-affine contacts) can be built in.
The left side decreases strictly in c, so it has exactly one root when f0 < a_c and none
(h_eff = 0) when f0 >= a_c (L3).

What each model feeds into (L2) is the subject of :func:`rigid_gaussian_aperture` (asperity
models: the rigid gap at a separation, L5) and :mod:`asperity.spectral.persson_gaps` (Persson).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable

import numpy as np
from numpy.polynomial import legendre
from numpy.typing import ArrayLike
from scipy import special

from bem.common.checks import points, real_array, real_number
from bem.common.warnings import ConvergenceWarning

from asperity.common.roots import monotone_root

__all__ = ["BRUGGEMAN_CRITICAL_AREA", "effective_medium_aperture", "effective_medium_density",
           "log_aperture_error", "rigid_gaussian_aperture", "two_phase_aperture"]

#: Contact-area fraction at which the plain 2-D Bruggeman medium stops conducting.
BRUGGEMAN_CRITICAL_AREA = 0.5

# The open part of a Gaussian gap distribution, in the heights z (units of their rms): 8-point
# Gauss-Legendre on 16 panels geometric in the gap t - z from 1e-6 to 1 (plus [0, 1e-6]),
# where the conductance g^3 changes fastest near the seal, and 16 equal panels from
# min(t - 1, 10) down to z = -10 (the normal density is below 1e-22 beyond +-10). Within 1e-10 relative of adaptive
# quadrature (tests/test_leakage_theory.py).
_NODES, _WEIGHTS = legendre.leggauss(8)
_NEAR_GAPS = np.concatenate(([0.0], np.geomspace(1e-6, 1.0, 17)))
_BULK = np.linspace(0.0, 1.0, 17)
_LOWEST = -10.0


def _depolarisation(critical_area: float) -> float:
    """k = a_c / (1 - a_c) of eq. (L2) for a threshold a_c in (0, 1)."""
    a_c = real_number("critical_area", critical_area, minimum=0.0, exclusive=True,
                      maximum=1.0, exclusive_maximum=True)
    return a_c / (1.0 - a_c)


def effective_medium_aperture(gaps: ArrayLike, weights: ArrayLike | None = None, *,
                              contact_fraction: ArrayLike = 0.0,
                              critical_area: float = BRUGGEMAN_CRITICAL_AREA) -> np.ndarray:
    """Effective hydraulic aperture h_eff [length] of gap distributions, eq. (L2).

    Parameters
    ----------
    gaps : array_like, shape (..., M)
        Gap samples g >= 0 [length] of each distribution along the last axis (zeros count as
        contact). A 1-D array is one distribution.
    weights : array_like, optional
        Weights >= 0 of the samples, broadcast against ``gaps`` (default equal). Per
        distribution they are scaled to add up to ``1 - contact_fraction``.
    contact_fraction : array_like
        Fraction f0 in [0, 1] of the area in contact (a weight at g = 0) besides zero samples;
        broadcast against the leading axes of ``gaps`` and ``weights`` (numpy's rule).
    critical_area : float
        Contact fraction a_c in (0, 1) at which the medium stops conducting (k = a_c/(1 - a_c));
        the plain Bruggeman medium has 1/2.

    Returns
    -------
    ndarray, the broadcast leading shape
        h_eff = c^(1/3), c the root of (L2); exactly 0 where the contact fraction (with zero
        samples) reaches a_c. Found by Newton's method on ln c in the bracket (L3), safeguarded
        by bisection; a distribution where it fails is warned (:class:`bem.ConvergenceWarning`).
    """
    k = _depolarisation(critical_area)
    g = real_array("gaps", gaps, minimum=0.0)
    if g.ndim == 0 or g.shape[-1] == 0:
        raise ValueError(f"gaps must have at least one sample along the last axis, got shape "
                         f"{g.shape}")
    w = np.ones(g.shape) if weights is None else real_array("weights", weights, minimum=0.0)
    f0 = real_array("contact_fraction", contact_fraction, minimum=0.0)
    try:
        w = np.broadcast_to(w, np.broadcast_shapes(g.shape, w.shape))
        leading = np.broadcast_shapes(w.shape[:-1], f0.shape)
    except ValueError:
        raise ValueError(f"weights {w.shape} and contact_fraction {f0.shape} must broadcast "
                         f"against the gaps {g.shape} (samples along the last axis)") from None
    g = np.broadcast_to(g, leading + g.shape[-1:])
    w, f0 = np.broadcast_to(w, g.shape), np.broadcast_to(f0, leading)
    total = w.sum(axis=-1)
    if np.any(f0 > 1.0) or np.any((total <= 0) & (f0 < 1.0)):
        raise ValueError("contact_fraction must be <= 1, and weights must not all vanish where "
                         "it is below 1")
    shape = g.shape[:-1]
    g, w = g.reshape(-1, g.shape[-1]), w.reshape(-1, g.shape[-1])
    f0, total = f0.ravel(), total.ravel()
    with np.errstate(invalid="ignore", divide="ignore"):
        w = w * ((1.0 - f0) / np.where(total > 0, total, 1.0))[:, None]
    # Gaps in units of the largest per distribution: c in (0, 1] whatever the length unit.
    # A gap whose cube underflows there (below 1e-100 of the largest) conducts nothing.
    scale = g.max(axis=1)
    sigma = (g / np.where(scale > 0, scale, 1.0)[:, None]) ** 3
    open_gap = sigma > 0
    w_open = np.where(open_gap, w, 0.0)
    sealed = f0 + np.sum(np.where(open_gap, 0.0, w), axis=1)      # contact fraction f0
    drive = (1.0 - sealed) - sealed / k                           # (L2) at c -> 0+
    out = np.zeros(g.shape[0])
    flows = drive > 0
    if flows.any():
        out[flows] = scale[flows] * np.cbrt(_root(sigma[flows], w_open[flows], sealed[flows],
                                                  drive[flows], k))
    return out.reshape(shape)


def _root(sigma: np.ndarray, w: np.ndarray, sealed: np.ndarray, drive: np.ndarray,
          k: float) -> np.ndarray:
    """The root c of (L2) per row (rows that conduct), Newton on ln c inside (L3)."""
    open_part = np.where(sigma > 0, sigma, np.inf)
    lower = drive / ((1.0 + k) * np.sum(w / open_part, axis=1))   # (L2) >= 0 below it
    upper = np.sum(w * sigma, axis=1) / (1.0 - sealed)            # (L2) <= 0 above it
    lo, hi = np.log(lower) - 1e-9, np.log(upper) + 1e-9

    def function(log_c: np.ndarray, index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        c = np.exp(log_c)[:, None]
        s, weight = sigma[index], w[index]
        denominator = s + k * c
        value = np.sum(weight * (s - c) / denominator, axis=1) - sealed[index] / k
        slope = -np.sum(weight * s / denominator**2, axis=1) * (1.0 + k) * c[:, 0]
        return value, slope

    log_c, converged, _ = monotone_root(function, lo, hi, 0.5 * (lo + hi), increasing=False)
    if not converged.all():
        warnings.warn(f"effective-medium aperture: {int(np.count_nonzero(~converged))} of "
                      f"{converged.size} distributions did not converge", ConvergenceWarning,
                      stacklevel=3)
    return np.exp(log_c)


def effective_medium_density(density: Callable[[np.ndarray], ArrayLike], grid: ArrayLike, *,
                             contact_fraction: float = 0.0,
                             critical_area: float = BRUGGEMAN_CRITICAL_AREA) -> float:
    """h_eff [length] of a gap density P(g) given as a callable, by the trapezoidal rule on
    ``grid`` (increasing gaps >= 0 [length] covering the density's support), eq. (L2).

    The density's values on the grid are scaled so that the open part carries
    ``1 - contact_fraction``; the rule's error is that of the trapezoidal rule on the grid.
    """
    grid = real_array("grid", grid, ndim=1, min_size=2, minimum=0.0)
    if np.any(np.diff(grid) <= 0):
        raise ValueError("grid must be strictly increasing")
    values = real_array("density", np.broadcast_to(density(grid), grid.shape), minimum=0.0)
    spacing = np.diff(grid)
    weights = values * (np.concatenate((spacing, [0.0])) + np.concatenate(([0.0], spacing))) / 2
    return float(effective_medium_aperture(grid, weights, contact_fraction=contact_fraction,
                                           critical_area=critical_area))


def rigid_gaussian_aperture(separation: ArrayLike, height_rms: float, *,
                            critical_area: float = BRUGGEMAN_CRITICAL_AREA) -> np.ndarray:
    """h_eff [length] of the rigid gap ``g = max(d - z, 0)`` over Gaussian heights, eq. (L5).

    Parameters
    ----------
    separation : array_like
        d [length] from the mean plane of the heights (any shape; +inf gives +inf).
    height_rms : float
        Standard deviation s >= 0 of the heights z ~ N(0, s^2) [length]; s = 0 (a flat
        surface) gives the uniform gap max(d, 0).
    critical_area : float
        Threshold a_c of the effective medium (L2).

    Returns
    -------
    ndarray
        h_eff, the shape of ``separation``: s times a function of t = d/s alone, 0 where the
        bearing fraction ``P(z > d) = erfc(t/sqrt 2)/2`` reaches a_c (t <= 0 for a_c = 1/2),
        and d (1 + O(s^2/d^2)) far from contact. The open part is integrated by composite
        Gauss-Legendre in z (256 nodes), within 1e-10 relative of adaptive quadrature.
    """
    d = points("separation", separation, allow_infinity=True)
    s = real_number("height_rms", height_rms, minimum=0.0)
    k = _depolarisation(critical_area)
    if s == 0:                                   # a flat surface: a uniform gap, or contact
        return np.where(d > 0, d, 0.0)
    t = (d / s).ravel()
    out = np.where(np.isinf(t), np.inf, 0.0)
    bearing = special.ndtr(-t)
    # at threshold or beyond: h_eff = 0 (L3); far away: the rule below still applies
    work = np.isfinite(t) & ((1.0 - bearing) - bearing / k > 0)
    if work.any():
        tw = t[work][:, None]
        top = np.minimum(tw - 1.0, -_LOWEST)        # no weight between z = 10 and t - 1
        bulk = top + (np.minimum(_LOWEST, top) - top) * _BULK
        edges = np.concatenate((tw - _NEAR_GAPS, bulk), axis=1)
        left, width = edges[:, :-1, None], np.diff(edges, axis=1)[:, :, None]
        width[:, _NEAR_GAPS.size - 1] = 0.0          # the step from the near to the bulk panels
        z = (left + 0.5 * width * (_NODES + 1.0)).reshape(tw.shape[0], -1)
        weights = (0.5 * np.abs(width) * _WEIGHTS).reshape(z.shape) * np.exp(-0.5 * z * z)
        out[work] = s * effective_medium_aperture(tw - z, weights, contact_fraction=bearing[work],
                                                  critical_area=critical_area)
    return out.reshape(d.shape)


def two_phase_aperture(mean_gap: ArrayLike, area_fraction: ArrayLike, *,
                       critical_area: float = BRUGGEMAN_CRITICAL_AREA) -> np.ndarray:
    """h_eff [length] of a two-phase medium: contact on ``area_fraction`` a, one open gap
    elsewhere, with the given mean gap u (contact counted as 0), eq. (L4)::

        h_eff^3 = (u / (1 - a))^3 (1 - a / a_c),      0 for a >= a_c

    a closed form from the mean gap and the contact area alone (not the closed form of Wang &
    Muser 2020, whose constants could not be checked; docs/theory.md).
    """
    u = points("mean_gap", mean_gap, non_negative=True, allow_infinity=True)
    a = real_array("area_fraction", area_fraction, minimum=0.0)
    if np.any(a > 1.0):
        raise ValueError("area_fraction must be in [0, 1]")
    a_c = 1.0 / (1.0 + 1.0 / _depolarisation(critical_area))
    with np.errstate(divide="ignore", invalid="ignore"):
        open_gap = u / (1.0 - a)
        return np.where(a < a_c, open_gap * np.cbrt(np.clip(1.0 - a / a_c, 0.0, None)), 0.0)


def log_aperture_error(model: ArrayLike, reference: ArrayLike) -> np.ndarray:
    """The recommended leakage error, ``ln(h_model / h_reference)`` = ln(Q_model/Q_ref) / 3
    (docs/theory.md, eq. L7): 0 where both are sealed, NaN where only one is."""
    got, want = np.asarray(model, dtype=float), np.asarray(reference, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        error = np.log(got / want)
    return np.where((got == 0) & (want == 0), 0.0, np.where(np.isfinite(error), error, np.nan))


"""Per-surface verdicts: does a model hold on single surfaces, not only on average?

The verdict on the mean (:mod:`validation.judge.verdicts`) says whether the *mean* error over
realizations lies within the tolerance. A user applying a model to one surface needs the share
of surfaces whose own error lies within it. With the errors of one model, quantity and load
point over n realizations (mean ``m``, sample standard deviation ``s``) taken as a normal sample,
and ``b`` the reference band (docs/theory.md, "Per-surface validity", eqs. T35-T37):

* **holds per surface** where, with confidence ``gamma`` (95 %), at least a share ``P`` (90 %) of
  surfaces have ``|error| <= tol``: the two-sided normal tolerance interval
  ``m ± k2 s`` (content P, confidence gamma; :func:`two_sided_factor`), widened by ``b``, lies
  inside ``[-tol, tol]``; the band is at most a quarter of the tolerance and every realization
  converged (as for the mean);
* **fails per surface** where, with confidence gamma, more than ``1 - P`` (10 %) of surfaces
  miss: the lower confidence bound ``m + kq s`` of the upper ``P`` quantile, less ``b``,
  exceeds ``tol`` (or, mirrored, the upper bound of the lower quantile, plus ``b``, is below
  ``-tol``); ``kq`` is the exact noncentral-t factor (:func:`quantile_bound_factor`);
* **undecided** otherwise (also with fewer than 3 finite errors or an unknown band).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special, stats

from validation.judge.verdicts import (FAILS, HOLDS, REFERENCE_ACCURACY, REFERENCE_BAND,
                                 TOO_FEW_REALIZATIONS, UNCONVERGED, UNDECIDED)

__all__ = [
    "CONTENT",
    "SurfaceInterval",
    "classify_per_surface",
    "howe_factor",
    "quantile_bound_factor",
    "surface_interval",
    "surface_reasons",
    "two_sided_factor",
]

#: Share of surfaces that must lie within the tolerance for "holds per surface".
CONTENT = 0.90
#: Fewest finite errors for a per-surface verdict (the interval needs a scatter estimate with
#: at least two degrees of freedom to be finite for every content and confidence used here).
MIN_COUNT = 3
# Gauss-Legendre nodes on [0, 1] for the integral over the sample mean (eq. T35).
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(96)
_NODES, _WEIGHTS = 0.5 * (_NODES + 1.0), 0.5 * _WEIGHTS


def _check(content: float, confidence: float, count: int) -> None:
    for name, value in (("content", content), ("confidence", confidence)):
        if not 0.0 < value < 1.0:
            raise ValueError(f"{name} must be in (0, 1), got {value!r}")
    if isinstance(count, bool) or int(count) != count or count < 2:
        raise ValueError(f"count must be an integer >= 2, got {count!r}")


def _half_content_width(x: np.ndarray, content: float) -> np.ndarray:
    """r(x) with Phi(x + r) - Phi(x - r) = content: the half-width of the interval about x that
    holds the share ``content`` of a standard normal population (Newton, vectorised)."""
    r = np.full(x.shape, stats.norm.ppf(0.5 + content / 2.0)) + np.abs(x)
    for _ in range(60):
        f = special.ndtr(x + r) - special.ndtr(x - r) - content
        step = f / (stats.norm.pdf(x + r) + stats.norm.pdf(x - r))
        r = r - step
        if np.all(np.abs(step) < 1e-14 * r):
            break
    return r


@functools.lru_cache(maxsize=512)
def two_sided_factor(count: int, content: float = CONTENT, confidence: float = 0.95) -> float:
    """Exact two-sided normal tolerance factor k2 (eq. T35).

    ``[m - k2 s, m + k2 s]`` holds at least the share ``content`` of a normal population with
    probability ``confidence``, for the mean ``m`` and sample standard deviation ``s`` of
    ``count`` observations: k2 solves

        gamma = 2 sqrt(n / 2 pi) \\int_0^inf P(chi2_nu >= nu r(x)^2 / k^2) exp(-n x^2 / 2) dx

    with nu = n - 1 and r(x) of ``Phi(x + r) - Phi(x - r) = P`` (Odeh 1978; Krishnamoorthy &
    Mathew 2009, eq. 2.3.6). The integral runs over |x| <= 10 / sqrt(n) by Gauss-Legendre.
    """
    _check(content, confidence, count)
    n, nu = int(count), int(count) - 1
    span = 10.0 / np.sqrt(n)
    x = span * _NODES
    weight = 2.0 * span * _WEIGHTS * np.sqrt(n / (2.0 * np.pi)) * np.exp(-0.5 * n * x**2)
    r2 = _half_content_width(x, content) ** 2

    def coverage(k: float) -> float:
        return float(np.sum(weight * stats.chi2.sf(nu * r2 / k**2, nu))) - confidence

    upper = howe_factor(n, content, confidence) * 2.0 + 1.0
    return float(optimize.brentq(coverage, 1e-6, upper, xtol=1e-12))


def howe_factor(count: int, content: float = CONTENT, confidence: float = 0.95) -> float:
    """Howe's (1969) approximation of :func:`two_sided_factor`:
    ``k2 ~ z_{(1+P)/2} sqrt(nu (1 + 1/n) / chi2_{1-gamma, nu})``, a check of the exact factor."""
    _check(content, confidence, count)
    nu = count - 1
    return float(stats.norm.ppf(0.5 + content / 2.0)
                 * np.sqrt(nu * (1.0 + 1.0 / count) / stats.chi2.ppf(1.0 - confidence, nu)))


@functools.lru_cache(maxsize=512)
def quantile_bound_factor(count: int, content: float = CONTENT, confidence: float = 0.95
                          ) -> float:
    """Factor kq of the lower confidence bound ``m + kq s`` of the ``content`` quantile
    ``mu + z_P sigma`` of a normal population (eq. T36):
    ``kq = t'_{1-gamma}(nu, z_P sqrt(n)) / sqrt(n)``, t' the noncentral t quantile, so that
    ``P(m + kq s <= mu + z_P sigma) = gamma`` exactly."""
    _check(content, confidence, count)
    root = np.sqrt(count)
    return float(stats.nct.ppf(1.0 - confidence, count - 1, stats.norm.ppf(content) * root)
                 / root)


def _factors(count: np.ndarray, content: float, confidence: float, which) -> np.ndarray:
    out = np.full(count.shape, np.nan)
    for n in np.unique(count[count >= MIN_COUNT]):
        out[count == n] = which(int(n), content, confidence)
    return out


@dataclass(frozen=True)
class SurfaceInterval:
    """Per-point normal tolerance interval and quantile bounds of single-surface errors."""

    low: np.ndarray        # m - k2 s: with confidence gamma, at least P of surfaces above ...
    high: np.ndarray       # m + k2 s: ... and below (NaN with fewer than MIN_COUNT errors)
    upper_tail: np.ndarray  # m + kq s: confidence-gamma lower bound of the upper P quantile
    lower_tail: np.ndarray  # m - kq s: confidence-gamma upper bound of the lower P quantile
    content: float = CONTENT
    confidence: float = 0.95


def surface_interval(mean: np.ndarray, std: np.ndarray, count: np.ndarray, *,
                     content: float = CONTENT, confidence: float = 0.95,
                     floor: float | np.ndarray = -np.inf) -> SurfaceInterval:
    """Tolerance interval (eq. T35) and quantile bounds (eq. T36) per load point.

    Parameters
    ----------
    mean, std : array, shape (points,)
        Mean and sample standard deviation of the finite errors per point (as
        :class:`validation.judge.verdicts.ErrorInterval` holds them).
    count : int array, shape (points,)
        Number of finite errors per point.
    content, confidence : float
        Share of surfaces P and confidence gamma, both in (0, 1).
    floor : float or array
        The least error any surface can have: -1 for a relative error (a model's area or
        stiffness is never negative), -inf otherwise. The interval's lower end is raised to it
        (the normal approximation knows no bound); no verdict changes, since a tolerance below 1
        is never met at -1.
    """
    mean, std = np.asarray(mean, dtype=float), np.asarray(std, dtype=float)
    count = np.asarray(count, dtype=int)
    _check(content, confidence, 2)
    k2 = _factors(count, content, confidence, two_sided_factor)
    kq = _factors(count, content, confidence, quantile_bound_factor)
    return SurfaceInterval(np.maximum(mean - k2 * std, floor), mean + k2 * std, mean + kq * std,
                           mean - kq * std, content, confidence)


def classify_per_surface(interval: SurfaceInterval, band: np.ndarray, tolerance: float, *,
                         complete: np.ndarray | None = None) -> np.ndarray:
    """Per-surface verdict per load point (module docstring; eq. T37).

    Parameters
    ----------
    interval : SurfaceInterval
        From :func:`surface_interval`.
    band : array, shape (points,) or scalar
        Reference band per point (>= 0); NaN means unknown and leaves the point undecided.
    tolerance : float
        Error bound (> 0), relative or in units of sigma.
    complete : bool array, shape (points,), optional
        Where every realization converged (default everywhere); elsewhere no "holds".
    """
    if not tolerance > 0:
        raise ValueError(f"tolerance must be > 0, got {tolerance!r}")
    high = np.asarray(interval.high, dtype=float)
    band = np.broadcast_to(np.asarray(band, dtype=float), high.shape)
    complete = np.ones(high.shape, bool) if complete is None else np.asarray(complete, bool)
    known = np.isfinite(band) & np.isfinite(high)
    with np.errstate(invalid="ignore"):
        holds = (known & (interval.low - band >= -tolerance) & (high + band <= tolerance)
                 & (band <= REFERENCE_ACCURACY * tolerance) & complete)
        fails = known & ((interval.upper_tail - band > tolerance)
                         | (interval.lower_tail + band < -tolerance))
    verdict = np.full(high.shape, UNDECIDED, dtype="<U9")
    verdict[holds] = HOLDS
    verdict[fails] = FAILS
    return verdict


def surface_reasons(interval: SurfaceInterval, band: np.ndarray, tolerance: float, *,
                    count: np.ndarray, complete: np.ndarray | None = None) -> np.ndarray:
    """Why each point is undecided per surface ("" where it holds or fails per surface), in the
    words of :func:`validation.judge.verdicts.undecided_reasons`:

    * ``UNCONVERGED``: no finite error there, or the point would hold per surface but a
      realization did not converge;
    * ``REFERENCE_BAND``: the point would be decided against an exact reference (band 0) but
      the band is not estimated or above a quarter of the tolerance;
    * ``TOO_FEW_REALIZATIONS``: otherwise: fewer than :data:`MIN_COUNT` errors, or the tolerance
      interval and the quantile bounds straddle the tolerance.

    ``count`` is the number of finite errors per point.
    """
    verdict = classify_per_surface(interval, band, tolerance, complete=complete)
    undecided = verdict == UNDECIDED
    exact = classify_per_surface(interval, np.zeros(verdict.shape), tolerance)
    if_complete = classify_per_surface(interval, band, tolerance)
    reasons = np.full(verdict.shape, "", dtype=f"<U{len(TOO_FEW_REALIZATIONS)}")
    reasons[undecided] = TOO_FEW_REALIZATIONS
    reasons[undecided & (exact != UNDECIDED)] = REFERENCE_BAND
    reasons[undecided & ((if_complete == HOLDS) | (np.asarray(count) == 0))] = UNCONVERGED
    return reasons

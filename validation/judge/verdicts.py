"""Verdicts with uncertainty: does a model hold at a load point, fail there, or is it undecided?

Pure functions of error arrays; no curves, no I/O.

At each load point k the errors ``e[r, k]`` of one model in one quantity over the realizations
r that converged give

* the mean error ``m_k`` and its 95 % confidence interval over realizations (Student t):
  ``m_k ± h_k`` with ``h_k = t_{0.975, n_k - 1} s_k / sqrt(n_k)``, ``s_k`` the sample standard
  deviation and ``n_k`` the number of finite errors (``h_k = inf`` for ``n_k < 2``);
* the reference band ``b_k >= 0``: the reference's own error at that point, in the same
  measure as the error (relative, or in units of sigma for separation).

The interval widened by the band, ``[m_k - h_k - b_k, m_k + h_k + b_k]``, decides:

* **holds** where it lies inside ``[-tol, tol]``, the reference resolves the question
  (``b_k <= tol / 4``, the reference-accuracy rule) and every realization converged;
* **fails** where it lies wholly outside ``[-tol, tol]`` and the band is known;
* **undecided** otherwise (interval straddles a bound, too few realizations, the reference
  band is above a quarter of the tolerance or was not estimated (NaN: an unknown band is
  never taken as zero), or no converged realization).

**One surface** (a scene of one realization: one measured scan, ``tiles = 1``) is not a
population: the BEM solves that very surface, so its error ``e_k`` is known but for the
reference band ``b_k``, and realization statistics do not apply (:func:`one_surface_verdicts`):

* **holds** where ``|e_k| + b_k <= tol``;
* **fails** where ``|e_k| - b_k > tol``;
* **undecided** only where the band straddles the tolerance (reason :data:`REFERENCE_BAND`),
  or where the band or the error is unknown (NaN: not estimated, or :data:`UNCONVERGED`).

A validity range is the longest contiguous run of points that hold.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from bem.common import checks
# the verdict names and their confidence are shared with the plan of realizations below the
# judge, so they are defined at the bottom (validation.common.verdicts) and exported here too
from validation.common.verdicts import CONFIDENCE, FAILS, HOLDS, UNDECIDED

__all__ = [
    "CONFIDENCE",
    "FAILS",
    "HOLDS",
    "REFERENCE_ACCURACY",
    "REFERENCE_BAND",
    "SYMBOLS",
    "TOO_FEW_REALIZATIONS",
    "UNCONVERGED",
    "UNDECIDED",
    "ErrorInterval",
    "ValidityRange",
    "classify",
    "confidence_interval",
    "one_surface_reasons",
    "one_surface_verdicts",
    "reference_band",
    "true_runs",
    "undecided_reasons",
    "validity_range",
    "verdict_counts",
    "verdict_range",
    "verdict_strip",
]

#: Why a point is undecided (:func:`undecided_reasons`), in the report's words.
REFERENCE_BAND, TOO_FEW_REALIZATIONS, UNCONVERGED = ("reference band", "too few realizations",
                                                     "unconverged")
#: One character per verdict, for tables and figures.
SYMBOLS = {HOLDS: "✔", FAILS: "✘", UNDECIDED: "?"}
#: A point is undecided where the reference band exceeds this fraction of the tolerance.
REFERENCE_ACCURACY = 0.25


@dataclass(frozen=True)
class ErrorInterval:
    """Mean error and its confidence interval over realizations, per load point."""

    mean: np.ndarray        # (k,) mean over the finite errors (NaN where none)
    half_width: np.ndarray  # (k,) t quantile x standard error (inf where fewer than 2)
    std: np.ndarray         # (k,) sample standard deviation (NaN where fewer than 2)
    count: np.ndarray       # (k,) number of finite errors (realizations that count)
    confidence: float = CONFIDENCE

    @property
    def low(self) -> np.ndarray:
        return self.mean - self.half_width

    @property
    def high(self) -> np.ndarray:
        return self.mean + self.half_width


def confidence_interval(errors: np.ndarray, confidence: float = CONFIDENCE) -> ErrorInterval:
    """Student-t confidence interval of the mean error over realizations, point by point.

    Parameters
    ----------
    errors : array, shape (realizations, points)
        Errors per realization and load point; NaN (unconverged, undefined) entries are left out.
    confidence : float
        Two-sided confidence level, 0 < confidence < 1.

    Returns
    -------
    ErrorInterval
        ``mean ± t_{(1+confidence)/2, n-1} s / sqrt(n)`` per point.
    """
    errors = np.atleast_2d(np.asarray(errors, dtype=float))
    if errors.ndim != 2:
        raise ValueError("errors must be a (realizations, points) array")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    finite = np.isfinite(errors)
    count = finite.sum(axis=0)
    filled = np.where(finite, errors, 0.0)
    safe = np.maximum(count, 1)
    mean = np.where(count > 0, filled.sum(axis=0) / safe, np.nan)
    squares = np.where(finite, (errors - mean) ** 2, 0.0).sum(axis=0)
    std = np.where(count > 1, np.sqrt(squares / np.maximum(count - 1, 1)), np.nan)
    quantile = stats.t.ppf(0.5 + confidence / 2.0, np.maximum(count - 1, 1))
    half_width = np.where(count > 1, quantile * np.nan_to_num(std) / np.sqrt(safe), np.inf)
    return ErrorInterval(mean, half_width, std, count, confidence)


def reference_band(absolute_errors: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """The reference's own error per point, in the error measure of the comparison.

    The band is the mean over realizations of ``|absolute error| / scale``: ``scale`` is the
    reference value itself for relative measures (area, conductance, stiffness) and sigma for
    separation (broadcast over points). NaN entries are left out; a point without any finite
    entry has a NaN band (treated as unknown, so it cannot hold).

    Parameters
    ----------
    absolute_errors : array, shape (realizations, points)
        Absolute error estimates of the reference, in the units of the field.
    scale : array, broadcastable to (realizations, points)
        Reference values (relative measure) or sigma per realization, shape (realizations, 1).
    """
    absolute_errors = np.atleast_2d(np.asarray(absolute_errors, dtype=float))
    scale = np.broadcast_to(np.asarray(scale, dtype=float), absolute_errors.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        measure = np.where(scale != 0, np.abs(absolute_errors) / np.abs(scale), np.nan)
    finite = np.isfinite(measure)
    count = finite.sum(axis=0)
    total = np.where(finite, measure, 0.0).sum(axis=0)
    return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def classify(interval: ErrorInterval, band: np.ndarray, tolerance: float, *,
             complete: np.ndarray | None = None) -> np.ndarray:
    """Verdict per load point: ``"holds"``, ``"fails"`` or ``"undecided"`` (module docstring).

    Parameters
    ----------
    interval : ErrorInterval
        Mean error and confidence half-width per point.
    band : array, shape (points,) or scalar
        Reference band per point (>= 0; NaN means not estimated: the point is undecided).
    tolerance : float
        Error bound (> 0), relative or in units of sigma.
    complete : bool array, shape (points,), optional
        Where every realization converged (default: everywhere). Elsewhere a point can fail
        but not hold.
    """
    if not tolerance > 0:
        raise ValueError(f"tolerance must be > 0, got {tolerance!r}")
    mean = np.asarray(interval.mean, dtype=float)
    band = np.broadcast_to(np.asarray(band, dtype=float), mean.shape)
    complete = np.ones(mean.shape, bool) if complete is None else np.asarray(complete, bool)
    widened = interval.half_width + band
    low, high = mean - widened, mean + widened
    with np.errstate(invalid="ignore"):
        # NaN (unknown) means or bands make both comparisons false: undecided
        fails = (low > tolerance) | (high < -tolerance)
        resolved = band <= REFERENCE_ACCURACY * tolerance
        holds = (low >= -tolerance) & (high <= tolerance) & resolved & complete
    verdict = np.full(mean.shape, UNDECIDED, dtype="<U9")
    verdict[holds] = HOLDS
    verdict[fails] = FAILS
    return verdict


def undecided_reasons(interval: ErrorInterval, band: np.ndarray, tolerance: float, *,
                      complete: np.ndarray | None = None) -> np.ndarray:
    """Why each undecided point is undecided ("" where a point holds or fails).

    * :data:`UNCONVERGED`: no realization converged there, or the point would hold but a
      realization did not converge;
    * :data:`REFERENCE_BAND`: the point would be decided against an exact reference (band 0)
      but the band is not estimated or above a quarter of the tolerance (a finer reference
      grid decides it);
    * :data:`TOO_FEW_REALIZATIONS`: otherwise: the confidence interval straddles a bound, or
      fewer than two realizations give one (more realizations decide it).
    """
    verdict = classify(interval, band, tolerance, complete=complete)
    undecided = verdict == UNDECIDED
    exact = classify(interval, np.zeros(np.shape(verdict)), tolerance)
    if_complete = classify(interval, band, tolerance)
    reasons = np.full(verdict.shape, "", dtype=f"<U{len(TOO_FEW_REALIZATIONS)}")
    reasons[undecided] = TOO_FEW_REALIZATIONS
    reasons[undecided & (exact != UNDECIDED)] = REFERENCE_BAND
    reasons[undecided & ((if_complete == HOLDS) | (np.asarray(interval.count) == 0))] = UNCONVERGED
    return reasons


def one_surface_verdicts(error: np.ndarray, band: np.ndarray, tolerance: float) -> np.ndarray:
    """Verdict per point on one surface, from its error and the reference band alone.

    ``"holds"`` where ``|error| + band <= tolerance``, ``"fails"`` where
    ``|error| - band > tolerance``, ``"undecided"`` otherwise: where the band straddles the
    tolerance, or where the error or the band is NaN (unknown: never taken as zero). No
    realization statistics and no reference-accuracy rule: the only open thing about one
    surface is the reference's own error (module docstring).

    Parameters
    ----------
    error : array_like
        The model's error on this surface per point, in the comparison's measure (relative, in
        units of sigma, or the log ratio); NaN where unconverged or unreachable.
    band : array_like
        Reference band per point (>= 0), broadcast against ``error``; NaN: not estimated.
    tolerance : float
        Error bound (> 0), in the measure of ``error``.

    Returns
    -------
    ndarray of str
        One of ``"holds"``, ``"fails"``, ``"undecided"`` per point, the shape of ``error``
        broadcast with ``band``.
    """
    if not tolerance > 0:
        raise ValueError(f"tolerance must be > 0, got {tolerance!r}")
    error, band = np.broadcast_arrays(np.asarray(error, dtype=float),
                                      np.asarray(band, dtype=float))
    size = np.abs(error)
    with np.errstate(invalid="ignore"):
        # NaN in either makes both comparisons false: undecided
        holds = size + band <= tolerance
        fails = size - band > tolerance
    verdict = np.full(error.shape, UNDECIDED, dtype="<U9")
    verdict[holds] = HOLDS
    verdict[fails] = FAILS
    return verdict


def one_surface_reasons(error: np.ndarray, band: np.ndarray, tolerance: float) -> np.ndarray:
    """Why each point of one surface is undecided ("" where it holds or fails):
    :data:`UNCONVERGED` where the error is unknown (a solver did not converge, or the model did
    not reach the load), else :data:`REFERENCE_BAND` (the band straddles the tolerance or was
    not estimated: a finer reference decides it). Never :data:`TOO_FEW_REALIZATIONS`."""
    verdict = one_surface_verdicts(error, band, tolerance)
    error = np.broadcast_to(np.asarray(error, dtype=float), verdict.shape)
    reasons = np.full(verdict.shape, "", dtype=f"<U{len(TOO_FEW_REALIZATIONS)}")
    undecided = verdict == UNDECIDED
    reasons[undecided] = REFERENCE_BAND
    reasons[undecided & np.isnan(error)] = UNCONVERGED
    return reasons


def verdict_counts(verdicts: np.ndarray) -> dict[str, int]:
    """How many points hold, fail and are undecided."""
    verdicts = np.asarray(verdicts)
    return {name: int(np.count_nonzero(verdicts == name)) for name in (HOLDS, FAILS, UNDECIDED)}


def verdict_strip(verdicts: np.ndarray) -> str:
    """The verdicts as one character per point, from low to high load, e.g. ``✘✘??✔✔``."""
    return "".join(SYMBOLS[str(v)] for v in np.asarray(verdicts))


@dataclass(frozen=True)
class ValidityRange:
    """Where a model holds: the longest contiguous run of load points that hold."""

    tolerance: float
    first: int | None            # index of the first load point of the range (None: nowhere)
    last: int | None             # index of the last load point of the range
    load_min: float = float("nan")
    load_max: float = float("nan")
    area_fraction_min: float = float("nan")
    area_fraction_max: float = float("nan")
    points: int = 0              # load points in the range
    total: int = 0               # load points compared

    @property
    def holds_anywhere(self) -> bool:
        return self.first is not None

    def describe(self, load_format: str = ".2e") -> str:
        """Human-readable range in contact-area fraction, the load beside it, e.g.
        ``area 0.02 % – 5.1 % (Load 1.00e-05 – 3.20e-03)`` (the load alone where the area
        fraction is unknown)."""
        if not self.holds_anywhere:
            return "nowhere"
        area = np.isfinite(self.area_fraction_min)
        if self.first == self.last:
            load = f"Load {self.load_min:{load_format}}"
            return (f"only at area {100 * self.area_fraction_min:.3g} % ({load})" if area
                    else f"only at {load}")
        load = f"Load {self.load_min:{load_format}} – {self.load_max:{load_format}}"
        text = (f"area {100 * self.area_fraction_min:.3g} % – "
                f"{100 * self.area_fraction_max:.3g} % ({load})" if area else load)
        return text + (" [whole range]" if self.points == self.total else "")


def true_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """The runs of consecutive true entries of a 1-D mask as (first, last) index pairs, last
    included, in order: ``[(0, 1), (4, 4)]`` for ``[1, 1, 0, 0, 1]``."""
    edges = np.diff(np.concatenate(([0], np.asarray(mask, dtype=np.int8), [0])))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return [(int(a), int(b)) for a, b in zip(starts, stops)]


def verdict_range(loads: np.ndarray, holds: np.ndarray, tolerance: float,
                  area_fraction: np.ndarray | None = None) -> ValidityRange:
    """Longest contiguous run of points where ``holds`` is true (ties: the lower-load run).

    Parameters
    ----------
    loads : array, shape (k,)
        Load points, increasing.
    holds : bool array, shape (k,)
        Where the model holds (e.g. ``verdicts == HOLDS``).
    tolerance : float
        The tolerance the verdicts were taken at (recorded in the range).
    area_fraction : array, shape (k,), optional
        Reference area fraction per point, to report the area range too.
    """
    loads = checks.real_array("loads", loads, ndim=1, finite=False)
    holds = np.asarray(holds, dtype=bool)
    if holds.shape != loads.shape:
        raise ValueError(f"loads and holds must be 1-D arrays of one length, got shapes "
                         f"{loads.shape} and {holds.shape}")
    if area_fraction is not None:
        area_fraction = checks.real_array("area_fraction", area_fraction, finite=False)
        if area_fraction.shape != loads.shape:
            raise ValueError(f"area_fraction must have the length of loads {loads.shape}, got "
                             f"shape {area_fraction.shape}")
    _increasing(loads)
    runs = true_runs(holds)
    if not runs:
        return ValidityRange(tolerance, None, None, total=loads.size)
    # max takes the first (lowest-load) of the longest runs
    first, last = max(runs, key=lambda run: run[1] - run[0])
    area_min = area_max = float("nan")
    if area_fraction is not None:
        area_min, area_max = float(area_fraction[first]), float(area_fraction[last])
    return ValidityRange(tolerance, first, last, float(loads[first]), float(loads[last]),
                         area_min, area_max, last - first + 1, loads.size)


def validity_range(loads: np.ndarray, errors: np.ndarray, tolerance: float,
                   area_fraction: np.ndarray | None = None) -> ValidityRange:
    """Longest contiguous run of points where the point estimate ``|errors| <= tolerance``.

    The range of a single error curve without its uncertainty (NaN counts as not holding);
    reports use :func:`classify` and :func:`verdict_range` instead. The loads must not
    decrease (a ValueError naming ``loads`` says to sort them). Where the model holds
    nowhere, ``first`` is None and the bounds are NaN (``describe()`` says "nowhere"); the area
    bounds are NaN without ``area_fraction``. No load points at all is a ValueError naming
    ``loads``: a range over nothing states nothing.
    """
    errors = checks.real_array("errors", errors, finite=False)
    tolerance = checks.positive("tolerance", tolerance)
    loads = checks.real_array("loads", loads, ndim=1, min_size=1)
    if errors.shape != loads.shape:
        raise ValueError(f"loads and errors must be 1-D arrays of one length, got shapes "
                         f"{loads.shape} and {errors.shape}")
    if area_fraction is not None:
        area_fraction = checks.real_array("area_fraction", area_fraction, ndim=1)
    _increasing(loads)
    with np.errstate(invalid="ignore"):
        holds = np.abs(errors) <= tolerance
    return verdict_range(loads, holds, tolerance, area_fraction)


def _increasing(loads: np.ndarray) -> None:
    """A range is a run of neighbouring loads: loads (those known) must not decrease."""
    known = loads[np.isfinite(loads)]
    if np.any(np.diff(known) < 0):
        raise ValueError("loads must increase along the points (a validity range is a run of "
                         "neighbouring loads): sort them, with their errors and area fractions, "
                         "e.g. order = numpy.argsort(loads)")

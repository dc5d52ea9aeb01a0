"""Errors of a model against the reference at equal load, and the ranges where a model holds.

Error measures (at equal total load W, realization by realization):

* area and conductance (and stiffness, contacts): relative error ``q_model / q_reference - 1``;
* separation: ``(d_model - d_reference) / sigma`` with sigma the standard deviation of the
  summit heights of that realization (the paper's unit of separation).

A model *holds* at a load when the magnitude of its mean error over realizations is within the
tolerance. :func:`validity_range` returns the longest contiguous run of load points where it
holds, with the load and area-fraction ranges it spans.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bem.curve import ContactCurve

__all__ = ["RELATIVE_QUANTITIES", "ABSOLUTE_QUANTITIES", "curve_errors", "converged_points",
           "validity_range",
           "ValidityRange", "ErrorSummary", "summarise_errors"]

#: Quantities compared by relative error.
RELATIVE_QUANTITIES = ("area", "conductance", "stiffness", "contacts")
#: Quantities compared by absolute error in units of sigma.
ABSOLUTE_QUANTITIES = ("separation",)


def curve_errors(model: ContactCurve, reference: ContactCurve, sigma: float,
                 quantities: tuple[str, ...], *, load_rtol: float = 1e-6) -> dict[str, np.ndarray]:
    """Errors of ``model`` against ``reference`` at the same loads.

    Parameters
    ----------
    model, reference : ContactCurve
        Curves on the same load points (checked to ``load_rtol``).
    sigma : float
        Standard deviation of the summit heights [length], the unit of separation errors.
    quantities : tuple of str
        Which errors to compute; quantities missing from either curve are skipped.

    Returns
    -------
    dict of str to ndarray
        One error array per quantity (NaN where the reference value is zero or where either
        curve's solver did not converge).
    """
    if model.load.shape != reference.load.shape or not np.allclose(
            model.load, reference.load, rtol=load_rtol, atol=0.0):
        raise ValueError("model and reference curves must be evaluated at the same loads")
    errors: dict[str, np.ndarray] = {}
    # A point that either solver did not converge at says nothing: its errors are NaN (and so
    # count as not holding).
    unconverged = ~(converged_points(model) & converged_points(reference))
    for name in quantities:
        if name in ABSOLUTE_QUANTITIES:
            errors[name] = (model.separation - reference.separation) / sigma
        elif name in RELATIVE_QUANTITIES:
            got, want = getattr(model, name), getattr(reference, name)
            if got is None or want is None:
                continue
            with np.errstate(divide="ignore", invalid="ignore"):
                errors[name] = np.where(want != 0, got / np.where(want != 0, want, 1.0) - 1.0, np.nan)
    for name in errors:
        errors[name] = np.where(unconverged, np.nan, errors[name])
    return errors


def converged_points(curve: ContactCurve) -> np.ndarray:
    """Boolean array: where the curve's solver converged (all True for closed-form models)."""
    flags = curve.extras.get("converged")
    if flags is None:
        return np.ones(curve.load.shape, dtype=bool)
    return np.broadcast_to(np.asarray(flags, dtype=bool), curve.load.shape)


@dataclass(frozen=True)
class ValidityRange:
    """Where a model holds: the contiguous load points with ``|mean error| <= tolerance``."""

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
        """Human-readable range, e.g. ``Load 1.0e-05 - 3.2e-03 (area 0.02 % - 5.1 %)``."""
        if not self.holds_anywhere:
            return "nowhere"
        if self.first == self.last:
            text = f"only at {self.load_min:{load_format}}"
            if np.isfinite(self.area_fraction_min):
                text += f" (area {100 * self.area_fraction_min:.3g} %)"
            return text
        text = f"{self.load_min:{load_format}} – {self.load_max:{load_format}}"
        if np.isfinite(self.area_fraction_min):
            text += f" (area {100 * self.area_fraction_min:.3g} % – {100 * self.area_fraction_max:.3g} %)"
        if self.points == self.total:
            text += " [whole range]"
        return text


def validity_range(loads: np.ndarray, errors: np.ndarray, tolerance: float,
                   area_fraction: np.ndarray | None = None) -> ValidityRange:
    """Longest contiguous run of load points where ``|errors| <= tolerance``.

    Parameters
    ----------
    loads : array, shape (k,)
        Load points, increasing (any unit; the paper's Load = W/(E* L^2) in reports).
    errors : array, shape (k,)
        Mean error at each load point (NaN counts as not holding).
    tolerance : float
        Error bound (> 0).
    area_fraction : array, shape (k,), optional
        Reference area fraction at each load point, to report the area range too.

    Ties between runs of equal length go to the run at lower load.
    """
    loads = np.asarray(loads, dtype=float)
    errors = np.asarray(errors, dtype=float)
    if loads.shape != errors.shape or loads.ndim != 1:
        raise ValueError("loads and errors must be 1-D arrays of one length")
    if not tolerance > 0:
        raise ValueError(f"tolerance must be > 0, got {tolerance!r}")
    with np.errstate(invalid="ignore"):
        holds = np.abs(errors) <= tolerance
    best_first, best_length, start = None, 0, None
    for index, ok in enumerate(np.append(holds, False)):
        if ok and start is None:
            start = index
        elif not ok and start is not None:
            if index - start > best_length:
                best_first, best_length = start, index - start
            start = None
    if best_first is None:
        return ValidityRange(tolerance, None, None, total=loads.size)
    last = best_first + best_length - 1
    area_min = area_max = float("nan")
    if area_fraction is not None:
        area_fraction = np.asarray(area_fraction, dtype=float)
        area_min, area_max = float(area_fraction[best_first]), float(area_fraction[last])
    return ValidityRange(tolerance, best_first, last, float(loads[best_first]), float(loads[last]),
                         area_min, area_max, best_length, loads.size)


@dataclass(frozen=True)
class ErrorSummary:
    """Mean and scatter over realizations of one model's error in one quantity."""

    quantity: str
    mean: np.ndarray      # shape (points,)
    std: np.ndarray       # sample standard deviation over realizations (0 for one)
    count: int            # realizations


def summarise_errors(quantity: str, per_realization: list[np.ndarray]) -> ErrorSummary:
    """Mean and sample standard deviation over realizations (ignoring NaN entries)."""
    stack = np.vstack(per_realization)
    finite = np.isfinite(stack)
    count = finite.sum(axis=0)
    filled = np.where(finite, stack, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(count > 0, filled.sum(axis=0) / np.maximum(count, 1), np.nan)
        deviation = np.where(finite, stack - mean, 0.0)
        std = np.where(count > 1, np.sqrt((deviation**2).sum(axis=0) / np.maximum(count - 1, 1)), 0.0)
    return ErrorSummary(quantity, mean, std, stack.shape[0])


# --------------------------------------------------------------------------------------------
# a whole D value of a scene

#: Quantities that have a validity range (the load path itself is not compared). Contact
#: counts are not among them: the BEM counts connected contact patches, the asperity models
#: asperities in contact, which are different things once spots merge.
COMPARED_QUANTITIES = ("area", "separation", "conductance", "stiffness")


@dataclass(frozen=True)
class ModelComparison:
    """One model, one quantity: error statistics and validity ranges at each tolerance."""

    model: str
    quantity: str
    summary: ErrorSummary
    ranges: tuple[ValidityRange, ...]
    unconverged: int = 0  # (realization, load) points where the model or the BEM did not converge


@dataclass(frozen=True)
class Comparison:
    """All models against the reference for one surface family (one D) of a scene.

    ``load`` is the paper's dimensionless Load = W/(E* L^2) of the path; ``area_fraction`` the
    reference's mean area fraction at each load; ``reference_error`` the boundary-element
    reference's own error per quantity and load (grid n against 2n on one realization: relative,
    or in units of sigma for separation), empty when not estimated.
    """

    D: float
    load: np.ndarray
    area_fraction: np.ndarray
    models: dict[tuple[str, str], ModelComparison]
    reference_error: dict[str, np.ndarray]

    def reference_error_max(self, quantity: str) -> float:
        values = self.reference_error.get(quantity)
        if values is None or not np.any(np.isfinite(values)):
            return float("nan")
        return float(np.nanmax(np.abs(values)))


def _per_point_reference_error(results, reference_model: str,
                                quantities: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The reference's own error per load from its curves' ``<quantity>_error`` extras: the
    largest over the realizations, relative (separation: in units of sigma); {} without them."""
    out: dict[str, np.ndarray] = {}
    for name in quantities:
        per_realization = []
        for result in results:
            curve = result.curves[reference_model]
            error, value = curve.extras.get(f"{name}_error"), getattr(curve, name)
            if error is None or value is None:
                break
            scale = result.sigma if name == "separation" else np.abs(value)
            with np.errstate(divide="ignore", invalid="ignore"):
                per_realization.append(np.where(scale > 0, np.asarray(error) / scale, np.nan))
        else:
            if per_realization:
                out[name] = np.max(per_realization, axis=0)
    return out


def compare_realizations(results, reference=None, *, tolerances=(0.05, 0.2),
                         reference_model: str = "bem") -> Comparison:
    """Compare every model with the reference over the realizations of one D.

    Parameters
    ----------
    results : list of validation.runner.RealizationResult
        Realizations of one surface family; each holds a curve per model.
    reference : RealizationResult, optional
        The same family on a grid twice as fine (reference only), for the reference's own error.
    tolerances : tuple of float
        Error levels for the validity ranges.

    Notes
    -----
    Errors are averaged over realizations point by point. On a load path every realization
    has the same loads; on a separation path (``loads.quantity = "separation"``) the loads of
    point k differ between realizations, and ``load`` is that of the first realization: read
    such a comparison as one per separation point.
    """
    if not results:
        raise ValueError("no realizations to compare")
    first = results[0]
    if reference_model not in first.curves:
        raise ValueError(f"the results hold no {reference_model!r} reference curve")
    ref0 = first.curves[reference_model]
    length = first.task.surface.L
    load = ref0.load / (ref0.e_star * length**2)
    area_fraction = np.mean([r.curves[reference_model].area_fraction for r in results], axis=0)
    quantities = tuple(q for q in COMPARED_QUANTITIES if q in first.task.quantities)
    models: dict[tuple[str, str], ModelComparison] = {}
    for model in first.curves:
        if model == reference_model:
            continue
        per_quantity: dict[str, list[np.ndarray]] = {}
        unconverged = sum(int(np.count_nonzero(~(converged_points(r.curves[model])
                                                  & converged_points(r.curves[reference_model]))))
                          for r in results)
        for result in results:
            errors = curve_errors(result.curves[model], result.curves[reference_model],
                                  result.sigma, quantities)
            for name, values in errors.items():
                per_quantity.setdefault(name, []).append(values)
        for name, arrays in per_quantity.items():
            summary = summarise_errors(name, arrays)
            ranges = tuple(validity_range(load, summary.mean, tol, area_fraction) for tol in tolerances)
            models[(model, name)] = ModelComparison(model, name, summary, ranges, unconverged)
    reference_error = _per_point_reference_error(results, reference_model, quantities)
    if reference is not None:
        coarse = next((r for r in results if r.task.seed == reference.task.seed), first)
        fine_curve = reference.curves[reference_model]
        coarse_curve = coarse.curves[reference_model]
        if np.allclose(fine_curve.load, coarse_curve.load, rtol=1e-6, atol=0):
            reference_error = curve_errors(coarse_curve, fine_curve, coarse.sigma, quantities)
    return Comparison(D=first.task.D, load=load, area_fraction=area_fraction, models=models,
                      reference_error=reference_error)

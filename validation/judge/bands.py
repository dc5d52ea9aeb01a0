"""The reference band of a compared field: the reference's own error in the comparison's
measure (relative, in units of sigma, or of ln h_eff), from its per-point estimates, and the
part of it that is the reference method's own error (docs/theory.md, T32 and T50).

Two bands per field: the band one surface carries (the estimates ``<field>_error``: the
discretisation's and the mirror method's bound), for the verdicts per surface and on one
surface; and the band of the mean over realizations, in which the method's bound is replaced by
its bias (``<field>_error - <field>_method_error + <field>_method_bias``): the method's scatter
from surface to surface is in each realization's error, so the confidence interval of the mean
holds it already (eq. T50)."""

from __future__ import annotations

import numpy as np

from validation.judge.errors import ABSOLUTE_QUANTITIES, LOG_QUANTITIES, field_values
from validation.judge.verdicts import reference_band

__all__ = ["BAND_PARTS", "NOT_ESTIMATED", "method_band"]

#: Band source of a reference field without error estimates (its band is NaN).
NOT_ESTIMATED = "not estimated"

#: The bands of a field: the one one surface carries, the mean's, and their method parts
#: (the mirror method's bound and bias; eq. T50).
BAND_PARTS = ("surface", "mean", "bound", "bias")


def _estimate(extras, field_name: str, part: str):
    """The per-point estimate of ``part`` (:data:`BAND_PARTS`) of one curve, or None."""
    total = extras.get(f"{field_name}_error")
    if part == "bound":
        return extras.get(f"{field_name}_method_error")
    if part == "bias":
        return extras.get(f"{field_name}_method_bias")
    if part == "surface" or total is None:
        return total
    bound = extras.get(f"{field_name}_method_error")
    bias = extras.get(f"{field_name}_method_bias")
    if bound is None:
        return total
    total, bound = np.asarray(total, dtype=float), np.asarray(bound, dtype=float)
    bias = np.zeros(bound.shape) if bias is None else np.asarray(bias, dtype=float)
    # an infinite bound (the stiffness of a closed contact) leaves the estimate infinite
    finite = np.isfinite(bound)
    return np.where(finite, total - np.where(finite, bound, 0.0) + np.where(finite, bias, 0.0),
                    total)


def _band(results, field_name: str, reference_model: str,
          part: str = "surface") -> tuple[np.ndarray, str]:
    """Reference band of one field per point, and where it came from.

    Per-point estimates of every realization, when present (``part``: "surface", the estimate
    ``extras[field + "_error"]`` one surface carries; "mean", the same with the method's bound
    replaced by its bias; "bound" and "bias", those method parts alone): the mean over
    realizations of |error| in the comparison's measure. Otherwise NaN, "not estimated": an
    unknown band is never taken as zero (every verdict against it is undecided).
    """
    curves = [r.curves[reference_model] for r in results]
    points = curves[0].load.shape
    estimates = [_estimate(c.extras, field_name, part) for c in curves]
    if all(e is not None for e in estimates):
        absolute = np.vstack([np.asarray(e, dtype=float) for e in estimates])
        if field_name in LOG_QUANTITIES:
            return (_log_band(absolute, np.vstack([field_values(c, field_name) for c in curves])),
                    f"per-point estimates, {len(curves)} realization(s)")
        if field_name in ABSOLUTE_QUANTITIES:
            scale = np.array([[r.sigma] for r in results])
        else:
            scale = np.vstack([field_values(c, field_name) for c in curves])
        return reference_band(absolute, scale), f"per-point estimates, {len(curves)} realization(s)"
    return np.full(points, np.nan), NOT_ESTIMATED


def _log_band(absolute: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Reference band in the log-ratio measure (L7): the mean over realizations of e_h / h, the
    first-order change of ln h; 0 where the reference is sealed with a zero estimate, infinite
    where it is sealed but its estimate is not (its state is then unknown, so nothing holds).
    NaN estimates are left out; a point without any is NaN (unknown)."""
    absolute = np.abs(absolute)
    with np.errstate(divide="ignore", invalid="ignore"):
        measure = np.where(reference > 0, absolute / np.where(reference > 0, reference, 1.0),
                           np.where(absolute == 0, 0.0, np.inf))
    measure = np.where(np.isnan(absolute), np.nan, measure)
    known = ~np.isnan(measure)
    total = np.where(known, measure, 0.0).sum(axis=0)
    return np.where(known.any(axis=0), total / np.maximum(known.sum(axis=0), 1), np.nan)


def method_band(results, field_name: str, reference_model: str,
                part: str = "bound") -> np.ndarray:
    """The part of the reference band of ``field_name`` that is the reference method's own
    error, in the comparison's measure: zero where the reference has none. A finer grid cannot
    narrow it.

    ``part``: "bound", the mirror method's bound (extras ``<field>_method_error``), in the band
    one surface carries; "bias", its bias (``<field>_method_bias``), in the band of the mean
    (eq. T50)."""
    if part not in ("bound", "bias"):
        raise ValueError(f"part must be 'bound' or 'bias', got {part!r}")
    band, _ = _band(results, field_name, reference_model, part=part)
    return np.nan_to_num(band, nan=0.0)

"""Errors of one model curve against the reference curve of the same realization, point by
point at equal load: the error measures, the points both reached and converged at, and the
disagreements about sealing. Pure functions of curves; the statistics over realizations and the
verdicts are in :mod:`validation.judge.compare`.

Error measures (at equal total load W, realization by realization):

* area and conductance (and stiffness, contacts): relative error ``q_model / q_reference - 1``;
* separation (and the mean gap): ``(d_model - d_reference) / sigma`` with sigma the standard
  deviation of the summit heights of that realization (the paper's unit of separation);
* leakage (the effective hydraulic aperture h_eff): the logarithm of the ratio,
  ``ln(h_model / h_reference) = ln(Q_model / Q_reference) / 3`` (docs/theory.md, eq. L7),
  0 where both are sealed (h_eff = 0). Where only one of them is sealed the ratio is 0 or
  infinite and the error undefined: the point is a *disagreement about sealing*, left out of the
  error statistics (NaN, never 0) and counted (:func:`sealing_disagreements`). It decides the
  verdict instead: a disagreement the reference resolves (its own error estimate cannot turn
  its value into the model's sealed or open state) is an error beyond any tolerance, so the
  point fails; one it does not resolve leaves the point undecided.
"""

from __future__ import annotations

import numpy as np

from asperity.common.leakage import log_aperture_error
from bem.common import checks
from bem.common.curve import CURVE_QUANTITIES, ContactCurve

__all__ = [
    "ABSOLUTE_QUANTITIES",
    "LOAD_RTOL",
    "LOG_QUANTITIES",
    "RELATIVE_QUANTITIES",
    "converged_points",
    "curve_errors",
    "field_values",
    "pairwise_errors",
    "reached_points",
    "sealing_disagreements",
]

#: Quantities compared by relative error.
RELATIVE_QUANTITIES = ("area", "conductance", "stiffness", "contacts")
#: Quantities compared by absolute error in units of sigma.
ABSOLUTE_QUANTITIES = ("separation", "mean_gap")
#: Quantities compared by the logarithm of the ratio (eq. L7): the leakage h_eff.
LOG_QUANTITIES = ("leakage",)
#: Largest relative difference between a model's load and the reference's at one point for
#: the two to be compared (both solve for the same load; far beyond any solver tolerance).
LOAD_RTOL = 1e-6

def field_values(curve: ContactCurve, name: str) -> np.ndarray | None:
    """A quantity of a curve by name: a curve field, else an extra (``None`` when absent)."""
    value = getattr(curve, name) if name in CURVE_QUANTITIES else curve.extras.get(name)
    return None if value is None else np.asarray(value, dtype=float)


def converged_points(curve: ContactCurve) -> np.ndarray:
    """Boolean array: where the curve's solver converged (all True for closed-form models)."""
    flags = curve.extras.get("converged")
    if flags is None:
        return np.ones(curve.load.shape, dtype=bool)
    return np.broadcast_to(np.asarray(flags, dtype=bool), curve.load.shape)


def reached_points(model: ContactCurve, reference: ContactCurve, *,
                   load_rtol: float = LOAD_RTOL) -> np.ndarray:
    """Boolean array: where ``model`` reached the reference's load (to ``load_rtol``). A model
    that cannot carry a load (an unconverged solve ending at another load, a load beyond what
    it can reach) is not compared there: its point is *unreachable*, never an error.

    Raises
    ------
    ValueError
        When the two curves do not have the same number of points.
    """
    if model.load.shape != reference.load.shape:
        raise ValueError(f"model and reference curves must have the same load points, got "
                         f"{model.load.shape} and {reference.load.shape}")
    with np.errstate(invalid="ignore"):
        return np.abs(model.load - reference.load) <= load_rtol * np.abs(reference.load)


def curve_errors(model: ContactCurve, reference: ContactCurve, sigma: float,
                 quantities: tuple[str, ...], *, load_rtol: float = LOAD_RTOL,
                 reference_fields: dict[str, str] | None = None) -> dict[str, np.ndarray]:
    """Errors of ``model`` against ``reference`` at the same loads.

    Parameters
    ----------
    model, reference : ContactCurve
        Curves on the same load points; a point where the model's load differs from the
        reference's by more than ``load_rtol`` (relative) is unreachable
        (:func:`reached_points`): NaN error. Curves that share no load at all are refused
        (ValueError): no error is defined between them.
    sigma : float
        Standard deviation of the summit heights [length], the unit of separation errors.
    quantities : tuple of str
        Which errors to compute; quantities missing from either curve are skipped.
    reference_fields : dict, optional
        Reference field per quantity where it differs from the quantity (default identity).

    Returns
    -------
    dict of str to ndarray
        One error array per quantity (NaN where the reference value is zero for a relative
        error, where only one of the two is sealed for the leakage, where either curve's solver did
        not converge, or where the model did not reach the reference's load).
    """
    for name, curve in (("model", model), ("reference", reference)):
        if not isinstance(curve, ContactCurve):
            raise checks.InputTypeError(f"{name} must be a bem.ContactCurve, got "
                                        f"{type(curve).__name__}")
    sigma, quantities = checks.curve_error_arguments(
        sigma, quantities, ABSOLUTE_QUANTITIES + RELATIVE_QUANTITIES + LOG_QUANTITIES)
    load_rtol = checks.non_negative("load_rtol", load_rtol)
    reached = reached_points(model, reference, load_rtol=load_rtol)
    if reached.size and not reached.any():
        raise ValueError(f"model and reference share no load: at every point the model's load "
                         f"differs from the reference's by more than load_rtol = {load_rtol:g} "
                         f"(relative), so no error is defined; compare curves solved at the "
                         f"same loads (the model's at_load(reference.load))")
    return _errors(model, reference, sigma, quantities, reached, reference_fields)


def _errors(model: ContactCurve, reference: ContactCurve, sigma: float,
            quantities: tuple[str, ...], reached: np.ndarray,
            reference_fields: dict[str, str] | None) -> dict[str, np.ndarray]:
    """:func:`curve_errors` of checked arguments; a point not ``reached`` is NaN."""
    fields = reference_fields or {}
    unconverged = ~(converged_points(model) & converged_points(reference) & reached)
    errors: dict[str, np.ndarray] = {}
    for name in quantities:
        got, want = field_values(model, name), field_values(reference, fields.get(name, name))
        if got is None or want is None:
            continue
        with np.errstate(divide="ignore", invalid="ignore"):
            if name in ABSOLUTE_QUANTITIES:
                error = (got - want) / sigma
            elif name in LOG_QUANTITIES:
                error = log_aperture_error(got, want)
            else:
                error = np.where(want != 0, got / np.where(want != 0, want, 1.0) - 1.0, np.nan)
        # a point that either solver did not converge at says nothing
        errors[name] = np.where(unconverged, np.nan, error)
    return errors


def sealing_disagreements(model: ContactCurve, reference: ContactCurve,
                          reference_field: str = "leakage") -> tuple[np.ndarray, np.ndarray]:
    """Where exactly one of two curves is sealed (leakage h_eff = 0), and which of those
    disagreements the reference resolves.

    Parameters
    ----------
    model, reference : ContactCurve
        Curves on the same load points, both with their ``leakage`` (else no disagreement).
    reference_field : str
        The reference's field compared with the model's leakage.

    Returns
    -------
    disagree, resolved : ndarray of bool
        Per point: one of the two is sealed and the other not (points where either solver did
        not converge, or the model did not reach the reference's load, excluded); and, among those, the points where the reference's own error
        estimate ``extras[field + "_error"]`` (absolute, h_eff units; taken as 0 when absent)
        cannot change its state: it is sealed with a zero estimate, or open by more than the
        estimate (``h > error``).
    """
    got, want = field_values(model, "leakage"), field_values(reference, reference_field)
    shape = reference.load.shape
    if got is None or want is None:
        return np.zeros(shape, dtype=bool), np.zeros(shape, dtype=bool)
    counted = (converged_points(model) & converged_points(reference)
               & reached_points(model, reference))
    disagree = counted & ((got == 0) != (want == 0))
    estimate = reference.extras.get(f"{reference_field}_error")
    error = np.zeros(shape) if estimate is None else np.abs(np.asarray(estimate, dtype=float))
    with np.errstate(invalid="ignore"):
        certain = np.where(want == 0, error == 0, want > error)   # NaN estimate: uncertain
    return disagree, disagree & certain


def pairwise_errors(results, model: str, reference_model: str, quantities: tuple[str, ...],
                    reference_fields: dict[str, str] | None = None) -> dict[str, np.ndarray]:
    """Errors of one model against another over realizations: quantity -> (realizations, k)."""
    stacked: dict[str, list[np.ndarray]] = {}
    for result in results:
        # a model that reaches none of the reference's loads is not compared anywhere (NaN)
        curve, reference = result.curves[model], result.curves[reference_model]
        errors = _errors(curve, reference, result.sigma, quantities,
                         reached_points(curve, reference), reference_fields)
        for name, values in errors.items():
            stacked.setdefault(name, []).append(values)
    return {name: np.vstack(arrays) for name, arrays in stacked.items()}

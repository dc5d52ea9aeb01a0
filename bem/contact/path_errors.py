"""Discretisation-error estimates of a load path (:func:`bem.contact_curve` with
``error_estimate=True``) from the same path on half the grid (docs/theory.md, eq. T32).
"""

from __future__ import annotations

import numpy as np

from bem.common.curve import ContactCurve

__all__ = ["ERROR_FACTOR", "PERIMETER_COEFFICIENT_UNCERTAINTY", "error_estimates"]


#: Safety factor f of :func:`error_estimates` on ``|Q_N - Q_(N/2)|`` (docs/guide/benchmarks.md,
#: "Accuracy of the reference"): twice the first-order Richardson estimate, the smallest factor that bounded the
#: error of area, stiffness, separation and mean gap against converged values in the mesh study
#: of benchmarks/bench_area.py (WM, D = 2.05-2.95, N = 256 and 512).
ERROR_FACTOR = 2.0
#: Uncertainty of the perimeter coefficient alpha over surfaces (fits on WM surfaces of
#: D = 2.05 ... 2.95 spread by this much about bem.contact.area.PERIMETER_COEFFICIENT): the area error
#: is at least this times h times the staircase perimeter.
PERIMETER_COEFFICIENT_UNCERTAINTY = 0.015

_ERROR_QUANTITIES = ("area", "separation", "contacts", "stiffness", "conductance", "leakage")


def error_estimates(fine: ContactCurve, coarse: ContactCurve, spacing: float) -> dict[str, np.ndarray]:
    """Per-point discretisation-error estimates of a curve from the same path on half the grid
    (docs/theory.md, eq. T32).

    For a quantity converging as ``Q_N = Q + c h^p`` the error of the fine grid is
    ``|Q_N - Q_(N/2)| / (2^p - 1)``, which is ``|Q_N - Q_(N/2)|`` at first order (the order of
    every quantity here). The estimate is ``f |Q_N - Q_(N/2)|`` with ``f =``
    :data:`ERROR_FACTOR`, which also covers convergence that is not yet monotone; for the area
    at least ``delta_alpha h P`` (P the staircase perimeter, extras ``staircase_perimeter``, and
    delta_alpha = :data:`PERIMETER_COEFFICIENT_UNCERTAINTY`), because the perimeter
    estimator's residual error can vanish on both grids by chance.

    Parameters
    ----------
    fine, coarse : ContactCurve
        The path on the grid of spacing h and on every second point (spacing 2h).
    spacing : float
        h [length].

    Returns
    -------
    dict of str to numpy.ndarray
        ``<quantity>_error`` [units of the quantity], absolute, for ``area``, ``separation``,
        ``mean_gap`` and those of ``contacts``, ``stiffness``, ``conductance`` and ``leakage``
        both curves hold.
    """
    out = {}
    for name in _ERROR_QUANTITIES:
        a, b = getattr(fine, name), getattr(coarse, name)
        if a is not None and b is not None:   # equal, infinite too (full contact): no error
            with np.errstate(invalid="ignore"):
                out[f"{name}_error"] = ERROR_FACTOR * np.where(a == b, 0.0, np.abs(a - b))
    out["mean_gap_error"] = ERROR_FACTOR * np.abs(
        np.asarray(fine.extras["mean_gap"]) - np.asarray(coarse.extras["mean_gap"]))
    floor = PERIMETER_COEFFICIENT_UNCERTAINTY * spacing * np.asarray(
        fine.extras["staircase_perimeter"])
    out["area_error"] = np.maximum(out["area_error"], floor)
    return out

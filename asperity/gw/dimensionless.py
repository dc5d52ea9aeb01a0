"""The paper's dimensionless quantities.

Two families of dimensionless forms appear in Ciavarella, Greenwood & Paggi (2008):

* Section 2 (theory, Figs. 1-3): the nominal pressure ``p_bar = p_nom / (eta E* R^(1/2)
  sigma^(3/2))`` (eq. 3) and the interaction parameter ``C = eta sqrt(A R sigma)`` (eq. 4);
  the improved theory reads ``p_bar = (4/3) F_3/2(d/sigma + m C p_bar)``, so for given m the
  curves depend on C only.
* Section 4 (comparisons, docs/theory.md eq. T4): Area = A_real/L^2, Load = W/(E* L^2),
  Separation = d/sigma, Conductance = -2 dLoad/dSeparation = 2 S sigma/(E* L^2).

The curves of Figs. 1-3 themselves are :func:`asperity.gw.reduced_curves.interaction_curves`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bem.common import checks
from bem.common.checks import frozen_array as _frozen
from numpy.typing import ArrayLike

from bem.common.curve import ContactCurve

__all__ = ["DimensionlessCurve", "dimensionless", "dimensionless_pressure",
           "interaction_parameter"]


def _positive(name: str, value) -> float:
    """A finite real number > 0 in the supported magnitude range (powers of it stay finite)."""
    return checks.supported_magnitude(name, checks.positive(name, value))











@dataclass(frozen=True, eq=False)
class DimensionlessCurve:
    """A contact curve in the paper's Section 4 variables (all [-], read-only arrays).

    Attributes
    ----------
    separation : d / sigma
    load : W / (E* L^2)
    area : A_real / L^2
    conductance : 2 S sigma / (E* L^2) = -2 dLoad/dSeparation, or None if the curve has no
        stiffness

    Raises
    ------
    ValueError
        Fields of different shapes, NaN or -inf entries (+inf is allowed: out of contact);
        a :class:`TypeError` for strings, None or objects where numbers are due.
    """

    separation: np.ndarray
    load: np.ndarray
    area: np.ndarray
    conductance: np.ndarray | None = None

    def __post_init__(self) -> None:
        checks.record_arrays(self, ("separation", "load", "area", "conductance"),
                             optional=("conductance",), allow_infinity=True)



def dimensionless(curve: ContactCurve, sigma: float, length: float) -> DimensionlessCurve:
    """Convert a :class:`bem.ContactCurve` to the paper's Area, Load, Separation, Conductance.

    Parameters
    ----------
    curve : ContactCurve
        Any model's curve (uses its separation, load, area, stiffness and e_star).
    sigma : float
        Standard deviation of the summit heights sigma [length] (the paper's unit of
        separation).
    length : float
        Sample length L [length]; the nominal area is L^2.
    """
    if not isinstance(curve, ContactCurve):
        raise checks.InputTypeError(f"curve must be a bem.ContactCurve, got "
                                    f"{type(curve).__name__}")
    sigma = _positive("sigma", sigma)
    length = _positive("length", length)
    scale = curve.e_star * length ** 2
    conductance = None
    if curve.stiffness is not None:
        conductance = _frozen(2.0 * curve.stiffness * sigma / scale)
    elif curve.conductance is not None:  # conductance = 2 S / E*, a length
        conductance = _frozen(curve.conductance * sigma / length ** 2)
    return DimensionlessCurve(separation=_frozen(curve.separation / sigma),
                              load=_frozen(curve.load / scale),
                              area=_frozen(curve.area / length ** 2),
                              conductance=conductance)


def dimensionless_pressure(mean_pressure: ArrayLike, density: float, radius: float,
                           sigma: float, e_star: float) -> np.ndarray:
    """p_bar = p_nom / (eta E* R^(1/2) sigma^(3/2)), the paper's eq. (3) [-].

    ``mean_pressure`` p_nom = W/A [pressure]; density eta [1/length^2]; radius R and sigma
    [length]; e_star E* [pressure].
    """
    reference = (_positive("density", density) * _positive("e_star", e_star)
                 * math.sqrt(_positive("radius", radius)) * _positive("sigma", sigma) ** 1.5)
    return checks.real_array("mean_pressure", mean_pressure) / reference


def interaction_parameter(density: float, radius: float, sigma: float, area: float) -> float:
    """C = eta sqrt(A R sigma) = sqrt(N eta R sigma), the paper's eq. (4) [-].

    density eta [1/length^2], radius R [length], sigma [length], nominal area A [length^2].
    With eta R sigma ~ 0.05, C ~ sqrt(N/20): C = 5 for 500 summits, C = 50 for 50,000.
    """
    return (_positive("density", density)
            * math.sqrt(_positive("area", area) * _positive("radius", radius)
                        * _positive("sigma", sigma)))

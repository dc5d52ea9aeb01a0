"""The paper's dimensionless quantities, and the curves of its Figs. 1-3.

Two families of dimensionless forms appear in Ciavarella, Greenwood & Paggi (2008):

* Section 2 (theory, Figs. 1-3): the nominal pressure ``p_bar = p_nom / (eta E* R^(1/2)
  sigma^(3/2))`` (eq. 3) and the interaction parameter ``C = eta sqrt(A R sigma)`` (eq. 4);
  the improved theory reads ``p_bar = (4/3) F_3/2(d/sigma + m C p_bar)``, so for given m the
  curves depend on C only.
* Section 4 (comparisons, docs/theory.md eq. T4): Area = A_real/L^2, Load = W/(E* L^2),
  Separation = d/sigma, Conductance = -2 dLoad/dSeparation = 2 S sigma/(E* L^2).

Example (the paper's Figs. 1-3 for C = 5 and C = 50)::

    import matplotlib.pyplot as plt
    from asperity import interaction_curves
    fig, (ax1, ax2) = plt.subplots(1, 2)
    for c in (5.0, 50.0):
        k = interaction_curves(c)
        ax1.semilogy(k.separation, k.gw_pressure, k.separation, k.improved_pressure)
        ax2.semilogy(k.separation, k.effective_stiffness, k.separation, k.improved_stiffness)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bem import checks
from bem.checks import frozen_array as _frozen
from bem.checks import non_negative as _non_negative
from numpy.typing import ArrayLike

from bem.curve import ContactCurve

__all__ = ["DimensionlessCurve", "dimensionless", "dimensionless_pressure",
           "interaction_parameter", "InteractionCurves", "interaction_curves"]


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
    """

    separation: np.ndarray
    load: np.ndarray
    area: np.ndarray
    conductance: np.ndarray | None = None


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


@dataclass(frozen=True, eq=False)
class InteractionCurves:
    """The curves of the paper's Figs. 1-3 (Gaussian summit heights), all [-].

    Separations are reduced by the summit statistics, ``(d - mu_s)/sigma`` (the paper's d/sigma
    with d measured from the mean summit height); pressures are p_bar (eq. 3); stiffnesses are
    ``-dp_bar/d(separation)`` = S / (N E* R^(1/2) sigma^(1/2)).

    Attributes
    ----------
    interaction_parameter, m : float
        C and the interaction factor m.
    separation : d/sigma.
    effective_separation : d1/sigma of the improved theory at d.
    gw_pressure : p_bar of GW theory at d (Figs. 1-2, "without interaction").
    improved_pressure : p_bar of the improved theory at d (Figs. 1-2, "with interaction").
    effective_stiffness : -dp_bar/d(d1/sigma) at the improved state, the paper's "GW stiffness
        dW/dd1" of Fig. 3 (= 2 F_1/2(d1/sigma)).
    improved_stiffness : -dp_bar/d(d/sigma), the true stiffness dW/dd of Fig. 3
        (series compliance, = effective / (1 + m C effective)).
    gw_stiffness : -dp_bar/d(d/sigma) of plain GW theory at d (= 2 F_1/2(d/sigma)).
    """

    interaction_parameter: float
    m: float
    separation: np.ndarray
    effective_separation: np.ndarray
    gw_pressure: np.ndarray
    improved_pressure: np.ndarray
    effective_stiffness: np.ndarray
    improved_stiffness: np.ndarray
    gw_stiffness: np.ndarray


def interaction_curves(interaction_parameter: float, *, m: float = 1.0,
                       separation: ArrayLike | None = None) -> InteractionCurves:
    """Figs. 1-3 of the paper from C and m: GW and improved-GW p_bar and stiffness vs d/sigma.

    Parameters
    ----------
    interaction_parameter : float
        C = eta sqrt(A R sigma) >= 0 (eq. 4); the paper uses C = 5 (Fig. 1) and 50 (Fig. 2).
    m : float
        Interaction factor >= 0 (the paper: 1).
    separation : array_like, optional
        Reduced separations d/sigma; default 201 points from -1 to 4.

    Notes
    -----
    Evaluated with :class:`ImprovedGreenwoodWilliamson` in units where eta = R = sigma = A =
    E* = 1 and the product m C carried by m (the reduced equations depend on m C only), so the
    exact solve of eq. (2) is the library's one implementation.
    """
    from asperity.greenwood_williamson import ImprovedGreenwoodWilliamson

    c = _non_negative("interaction_parameter", interaction_parameter)
    m = _non_negative("m", m)
    checks.supported_magnitude("interaction_parameter * m", c * m)
    h = (np.linspace(-1.0, 4.0, 201) if separation is None
         else checks.separations("separation", separation))
    model = ImprovedGreenwoodWilliamson(1.0, 1.0, 1.0, m=m * c)
    improved = model.at_separation(h)
    plain = model.greenwood_williamson.at_separation(h)
    return InteractionCurves(
        interaction_parameter=c, m=m, separation=_frozen(h),
        effective_separation=_frozen(improved.extras["effective_separation"]),
        gw_pressure=_frozen(plain.load), improved_pressure=_frozen(improved.load),
        effective_stiffness=_frozen(improved.extras["gw_stiffness"]),
        improved_stiffness=_frozen(improved.stiffness),
        gw_stiffness=_frozen(plain.stiffness))

"""The curves of the paper's Figs. 1-3: GW and improved GW in reduced variables.

For Gaussian summit heights the improved theory reads ``p_bar = (4/3) F_3/2(d/sigma + m C p_bar)``
(Ciavarella, Greenwood & Paggi 2008, eqs. 2-4, :mod:`asperity.gw.dimensionless`), so for given m the
curves depend on the interaction parameter C only.

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

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from asperity.gw.greenwood_williamson import ImprovedGreenwoodWilliamson
from bem.common import checks
from bem.common.checks import frozen_array as _frozen
from bem.common.checks import non_negative as _non_negative

__all__ = ["InteractionCurves", "interaction_curves"]


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

    def __post_init__(self) -> None:
        for name in ("interaction_parameter", "m"):
            object.__setattr__(self, name, _non_negative(name, getattr(self, name)))
        checks.record_arrays(self, ("separation", "effective_separation", "gw_pressure",
                                    "improved_pressure", "effective_stiffness",
                                    "improved_stiffness", "gw_stiffness"), allow_infinity=True)


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

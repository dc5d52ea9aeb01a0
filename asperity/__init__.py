"""Asperity models of rough contact: Greenwood-Williamson (GW), improved GW with uniform
interaction, the discrete asperity model with first-order interaction, Holm-Greenwood
constriction resistance, and summit detection on a height map.

Conventions (docs/theory.md): separation d from the rigid plane to the mean plane of the surface
heights; summit heights have mean mu_s above that plane and standard deviation sigma; loads are
total forces W on the nominal area A; every model returns a :class:`bem.ContactCurve`.
"""

from bem.common.curve import ContactCurve

__all__ = ["ContactCurve"]

# GW functions, GW and improved GW theory, Holm-Greenwood resistance, dimensionless forms.
from asperity.common.gw_functions import DISTRIBUTIONS, GW_ORDERS, gw_integral, log_gw_integral  # noqa: E402
from asperity.gw.greenwood_williamson import GreenwoodWilliamson, ImprovedGreenwoodWilliamson  # noqa: E402
from asperity.common.holm_greenwood import holm_greenwood  # noqa: E402
from asperity.gw.dimensionless import (  # noqa: E402
    DimensionlessCurve, dimensionless, dimensionless_pressure, interaction_parameter)
from asperity.gw.reduced_curves import InteractionCurves, interaction_curves  # noqa: E402

__all__ += ["gw_integral", "log_gw_integral", "GW_ORDERS", "DISTRIBUTIONS",
            "GreenwoodWilliamson", "ImprovedGreenwoodWilliamson", "holm_greenwood",
            "dimensionless", "DimensionlessCurve", "dimensionless_pressure",
            "interaction_parameter", "interaction_curves", "InteractionCurves"]

# Summits of a height map and the discrete asperity model with first-order interaction.
from asperity.gw.summits import Summits, find_summits  # noqa: E402
from asperity.gw.summit_arrays import summits_from_arrays, summits_to_arrays  # noqa: E402
from asperity.discrete.model import DISCRETE_QUANTITIES, DiscreteAsperityModel, ValidityWarning  # noqa: E402
from asperity.discrete.interaction import PointForceInteraction  # noqa: E402

__all__ += ["Summits", "find_summits", "summits_to_arrays", "summits_from_arrays",
            "DiscreteAsperityModel", "ValidityWarning", "DISCRETE_QUANTITIES",
            "PointForceInteraction"]

# Persson's theory from the power spectral density of the surface.
from asperity.spectral.persson import PERSSON_QUANTITIES, Persson, separation_kernel  # noqa: E402
from asperity.spectral.spectrum import IsotropicSpectrum, radial_power_spectrum  # noqa: E402

__all__ += ["Persson", "PERSSON_QUANTITIES", "separation_kernel", "IsotropicSpectrum",
            "radial_power_spectrum"]

# Spectral asperity theories: Nayak's summit statistics from the moments m0, m2, m4 (GW from
# the spectrum, McCool 1986) and Bush-Gibson-Thomas theory of elliptic summits.
from asperity.spectral.spectral_summits import (  # noqa: E402
    SpectralMoments, SpectralSummits, spectral_moments, spectral_summits)
from asperity.spectral.hertz_elliptic import hertz_elliptic_factors  # noqa: E402
from asperity.spectral.bush_gibson_thomas import BushGibsonThomas  # noqa: E402

__all__ += ["SpectralMoments", "SpectralSummits", "spectral_moments", "spectral_summits",
            "hertz_elliptic_factors", "BushGibsonThomas"]

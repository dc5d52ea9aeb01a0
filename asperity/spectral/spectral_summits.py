"""Summit statistics of an isotropic Gaussian surface from its spectral moments.

Random-process theory of rough surfaces (Nayak 1971; McCool 1986; docs/theory.md, section
"Spectral summit statistics", eqs. S1-S7): an isotropic Gaussian surface is described, as far
as its summits go, by three numbers, the **profile** spectral moments

    m0 = <z^2>,   m2 = <(dz/dx)^2>,   m4 = <(d^2z/dx^2)^2>                          (S1)

of one straight profile (any direction: the surface is isotropic). m2 is the mean square slope
of a profile, *half* the mean square gradient of the surface (h'_rms^2 = 2 m2), and m4 the
mean square curvature of a profile. With Nayak's bandwidth parameter ``alpha = m0 m4 / m2^2``
(>= 3/2 for every isotropic surface) the summits (points higher than every neighbour of the
continuous surface) have

* density ``eta = m4 / (6 pi sqrt(3) m2)``                     [1/length^2]   (S3)
* mean height ``mu_s = 4 sqrt(m0 / (pi alpha))`` above the mean plane of the heights  (S4)
* height variance ``sigma_s^2 = (1 - c/alpha) m0``, ``c = 16/pi - 3 sqrt(3) + 1 = 0.8968``  (S5)
* mean curvature (the average of the two principal curvatures, averaged over all summits)
  ``(8/3) sqrt(m4/pi)``, whose inverse is McCool's GW radius ``R = 0.375 sqrt(pi/m4)``  (S6)

These are the parameters of "GW from the spectrum" (McCool 1986): GW (or improved GW) theory
with a Gaussian summit-height law of mean mu_s and standard deviation sigma_s.

Two estimators of the moments, one definition (S1)
--------------------------------------------------
* From a height map, :func:`spectral_moments`: central finite differences along x and along y,
  averaged over the two directions (eq. S2; the values :func:`validation.surface_statistics`
  reports). They see the surface as the 8-neighbour summit finder sees it: a mode of
  wavevector q along x enters m2 with the factor ``(sin(q h)/(q h))^2`` and m4 with
  ``(sin(q h/2)/(q h/2))^4``.
* From a power spectral density (:class:`asperity.IsotropicSpectrum`, convention eq. P1),
  :meth:`SpectralMoments.from_spectrum`: ``m_n = integral d^2q q_x^n C(q)``, i.e.
  ``m0 = 2 pi M1``, ``m2 = pi M3``, ``m4 = (3 pi/4) M5`` with ``M_k = integral q^k C dq``
  (the continuous surface's moments, no sampling attenuation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from bem.common import checks

__all__ = ["SUMMIT_VARIANCE_CONSTANT", "MINIMUM_BANDWIDTH", "SpectralMoments", "SpectralSummits",
           "spectral_moments", "spectral_summits"]

#: c of eq. (S5), ``16/pi - 3 sqrt(3) + 1`` (McCool's 0.8968).
SUMMIT_VARIANCE_CONSTANT = 16.0 / math.pi - 3.0 * math.sqrt(3.0) + 1.0

#: The smallest bandwidth alpha = m0 m4 / m2^2 of an isotropic surface (a ring spectrum).
MINIMUM_BANDWIDTH = 1.5


@dataclass(frozen=True)
class SpectralMoments:
    """Profile spectral moments of an isotropic surface, eq. (S1).

    Parameters
    ----------
    m0 : float
        Mean square height about the mean plane [length^2].
    m2 : float
        Mean square slope of a profile [-] (half the mean square gradient of the surface).
    m4 : float
        Mean square curvature of a profile [1/length^2].
    """

    m0: float
    m2: float
    m4: float

    def __post_init__(self) -> None:
        for name in ("m0", "m2", "m4"):
            value = checks.supported_magnitude(name, checks.positive(name, getattr(self, name)))
            object.__setattr__(self, name, value)

    @property
    def alpha(self) -> float:
        """Nayak's bandwidth parameter ``m0 m4 / m2^2`` [-]."""
        return self.m0 * self.m4 / self.m2**2

    @property
    def rms_height(self) -> float:
        """sqrt(m0) [length]."""
        return math.sqrt(self.m0)

    @property
    def rms_gradient(self) -> float:
        """h'_rms = sqrt(2 m2), the rms of ``|grad z|`` (both directions) [-]."""
        return math.sqrt(2.0 * self.m2)

    @classmethod
    def from_spectrum(cls, spectrum) -> "SpectralMoments":
        """The moments of a continuous isotropic surface of PSD C(q) (convention eq. P1).

        ``m0 = 2 pi M1``, ``m2 = pi M3``, ``m4 = (3 pi / 4) M5``, ``M_k = integral q^k C dq``
        over the spectrum's band (``spectrum.moment(k)``): the angular averages of
        ``q_x^0, q_x^2, q_x^4`` over a ring are ``1, q^2/2, 3 q^4/8``.
        """
        from asperity.spectral.spectrum import IsotropicSpectrum

        if not isinstance(spectrum, IsotropicSpectrum):
            raise TypeError(f"spectrum must be an asperity.IsotropicSpectrum, got "
                            f"{type(spectrum).__name__}")
        return cls(2.0 * math.pi * spectrum.moment(1), math.pi * spectrum.moment(3),
                   0.75 * math.pi * spectrum.moment(5))

    def summits(self) -> "SpectralSummits":
        """Nayak's summit statistics of these moments (:func:`spectral_summits`)."""
        return spectral_summits(self.m0, self.m2, self.m4)


def height_derivatives(z: np.ndarray, spacing: float, *, periodic: bool = False
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Central finite differences z_x, z_y, z_xx, z_yy of a checked height map, eq. (S2).

    ``z_x = (z[j+1] - z[j-1]) / (2 h)`` along the columns (x), ``z_y`` along the rows (y),
    ``z_xx = (z[j+1] - 2 z[j] + z[j-1]) / h^2``; over the interior points (rows and columns
    1..n-2), or over all points with wrap-around when ``periodic``. The one place the project
    differentiates a height map (:func:`spectral_moments`, ``validation.surface_statistics``).
    """
    if periodic:
        right, left = np.roll(z, -1, axis=1), np.roll(z, 1, axis=1)
        up, down = np.roll(z, -1, axis=0), np.roll(z, 1, axis=0)
        centre = z
    else:
        right, left = z[1:-1, 2:], z[1:-1, :-2]
        up, down = z[2:, 1:-1], z[:-2, 1:-1]
        centre = z[1:-1, 1:-1]
    return ((right - left) / (2.0 * spacing), (up - down) / (2.0 * spacing),
            (right - 2.0 * centre + left) / spacing**2, (up - 2.0 * centre + down) / spacing**2)


def spectral_moments(heights: ArrayLike, spacing: float, *, periodic: bool = False
                     ) -> SpectralMoments:
    """Profile moments of a height map by central finite differences, eq. (S2).

    ``m0 = <z^2>`` over all points (heights about their mean);
    ``m2 = (<z_x^2> + <z_y^2>)/2`` with ``z_x = (z[i+1] - z[i-1]) / (2 h)``;
    ``m4 = (<z_xx^2> + <z_yy^2>)/2`` with ``z_xx = (z[i+1] - 2 z[i] + z[i-1]) / h^2``;
    derivatives over the interior points (rows and columns 1..n-2), or over all points with
    wrap-around when ``periodic``. These are the moments of ``validation.surface_statistics``.

    Parameters
    ----------
    heights : array_like
        Height map [length], 2-D, at least 3 x 3, finite.
    spacing : float
        Grid step h [length], > 0.
    periodic : bool
        The map is one period of a periodic surface.

    Returns
    -------
    SpectralMoments
    """
    z = checks.height_map("heights", heights)
    checks.supported_magnitude("max |heights|", float(np.max(np.abs(z))))
    h = checks.supported_magnitude("spacing", checks.positive("spacing", spacing))
    periodic = checks.flag("periodic", periodic)
    z = z - z.mean()
    m0, m2, m4 = profile_moments(z, *height_derivatives(z, h, periodic=periodic))
    for name, value in (("m2", m2), ("m4", m4)):
        if not value > 0.0:
            raise ValueError(f"heights: the map is flat to finite differences ({name} = 0)")
    try:
        return SpectralMoments(m0, m2, m4)
    except ValueError as error:   # a moment beyond the supported range: say which input
        raise ValueError(f"heights and spacing give spectral moments outside the supported "
                         f"range ({error}); rescale the length unit") from None


def profile_moments(z: np.ndarray, z_x: np.ndarray, z_y: np.ndarray, z_xx: np.ndarray,
                    z_yy: np.ndarray) -> tuple[float, float, float]:
    """m0 = <z^2>, m2 = (<z_x^2> + <z_y^2>)/2, m4 = (<z_xx^2> + <z_yy^2>)/2, eq. (S2), of heights
    about their mean and their :func:`height_derivatives` (the profile moments averaged over the
    x and y directions)."""
    return (float(np.mean(z * z)),
            0.5 * (float(np.mean(z_x * z_x)) + float(np.mean(z_y * z_y))),
            0.5 * (float(np.mean(z_xx * z_xx)) + float(np.mean(z_yy * z_yy))))


@dataclass(frozen=True)
class SpectralSummits:
    """Nayak's summit statistics of an isotropic Gaussian surface (McCool's GW parameters).

    Build it with :func:`spectral_summits`. All lengths in the unit of the moments.

    Attributes
    ----------
    m0, m2, m4 : float
        The profile moments (S1) [length^2], [-], [1/length^2].
    alpha : float
        Nayak's bandwidth m0 m4 / m2^2 [-] (>= 3/2).
    density : float
        Summit density eta, eq. (S3) [1/length^2].
    mean : float
        Mean summit height mu_s above the mean plane of the heights, eq. (S4) [length].
    sigma : float
        Standard deviation of the summit heights, eq. (S5) [length].
    radius : float
        McCool's GW radius, the inverse of the summits' mean curvature, eq. (S6) [length].
    """

    m0: float
    m2: float
    m4: float
    alpha: float = field(init=False)
    density: float = field(init=False)
    mean: float = field(init=False)
    sigma: float = field(init=False)
    radius: float = field(init=False)

    def __post_init__(self) -> None:
        moments = SpectralMoments(self.m0, self.m2, self.m4)
        alpha = moments.alpha
        if not alpha >= MINIMUM_BANDWIDTH * (1.0 - 1e-12):
            raise ValueError(f"m4: the bandwidth alpha = m0 m4 / m2^2 must be >= 1.5 for an "
                             f"isotropic surface, got alpha = {alpha:.6g}")
        set_ = lambda name, value: object.__setattr__(self, name, value)  # noqa: E731
        for name in ("m0", "m2", "m4"):
            set_(name, getattr(moments, name))
        set_("alpha", alpha)
        set_("density", moments.m4 / (6.0 * math.pi * math.sqrt(3.0) * moments.m2))
        set_("mean", 4.0 * math.sqrt(moments.m0 / (math.pi * alpha)))
        set_("sigma", math.sqrt((1.0 - SUMMIT_VARIANCE_CONSTANT / alpha) * moments.m0))
        set_("radius", 0.375 * math.sqrt(math.pi / moments.m4))

    @property
    def moments(self) -> SpectralMoments:
        """The moments as a :class:`SpectralMoments`."""
        return SpectralMoments(self.m0, self.m2, self.m4)

    def greenwood_williamson(self, area: float, *, e_star: float = 1.0):
        """GW theory with these summits ("GW from the spectrum", McCool 1986).

        Gaussian summit heights of mean :attr:`mean` and standard deviation :attr:`sigma`,
        radius :attr:`radius`, density :attr:`density`, on the nominal area ``area``
        [length^2], composite modulus ``e_star`` [pressure]; the heights' rms sqrt(m0) sets the
        rigid gap of its ``leakage``. Returns an
        :class:`asperity.GreenwoodWilliamson`.
        """
        from asperity.gw.greenwood_williamson import GreenwoodWilliamson

        return GreenwoodWilliamson(self.density, self.radius, self.sigma, mean=self.mean,
                                   e_star=e_star, area=area, height_rms=math.sqrt(self.m0))

    def improved_greenwood_williamson(self, area: float, m: float = 1.0, *,
                                      e_star: float = 1.0):
        """Improved GW theory (uniform interaction, factor ``m``) with these summits."""
        from asperity.gw.greenwood_williamson import ImprovedGreenwoodWilliamson

        return ImprovedGreenwoodWilliamson(self.density, self.radius, self.sigma,
                                           mean=self.mean, e_star=e_star, area=area, m=m,
                                           height_rms=math.sqrt(self.m0))


def spectral_summits(m0: float, m2: float, m4: float) -> SpectralSummits:
    """Nayak's summit statistics and McCool's GW parameters from the profile moments.

    Parameters
    ----------
    m0 : float
        Mean square height [length^2].
    m2 : float
        Mean square slope of a profile [-] (h'_rms^2 / 2).
    m4 : float
        Mean square curvature of a profile [1/length^2].

    Returns
    -------
    SpectralSummits
        ``alpha = m0 m4 / m2^2``, ``density = m4 / (6 pi sqrt(3) m2)``,
        ``mean = 4 sqrt(m0 / (pi alpha))``, ``sigma = sqrt((1 - 0.8968/alpha) m0)``,
        ``radius = 0.375 sqrt(pi / m4)`` (docs/theory.md, eqs. S3-S6).

    Raises
    ------
    ValueError, TypeError
        A moment that is not a finite number > 0, or alpha < 3/2 (no isotropic surface has
        such moments).

    Examples
    --------
    >>> s = spectral_summits(1.0, 1.0, 10.0)
    >>> round(s.alpha, 6), round(s.density, 6)
    (10.0, 0.306293)
    """
    return SpectralSummits(m0, m2, m4)

"""Height, slope and curvature statistics of a sampled height map, whatever made it (a
Weierstrass-Mandelbrot or self-affine surface, a measured scan): rms values and Nayak's spectral
moments by central finite differences.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from asperity.spectral.spectral_summits import height_derivatives, profile_moments
from bem.common import checks

__all__ = ["surface_statistics", "SurfaceStatistics"]


@dataclass(frozen=True)
class SurfaceStatistics:
    """Statistics of a sampled height map (see :func:`surface_statistics`): real numbers >= 0,
    ``nayak`` possibly +inf; a :class:`ValueError` or :class:`TypeError` naming the field
    otherwise."""

    rms_height: float
    rms_gradient: float
    rms_curvature: float
    m0: float
    m2: float
    m4: float
    nayak: float

    def __post_init__(self) -> None:
        for name in ("rms_height", "rms_gradient", "rms_curvature", "m0", "m2", "m4"):
            object.__setattr__(self, name, checks.non_negative(name, getattr(self, name)))
        object.__setattr__(self, "nayak", checks.non_negative_or_infinite("nayak", self.nayak))


def surface_statistics(heights: np.ndarray, spacing: float, *, periodic: bool = False
                       ) -> SurfaceStatistics:
    """Height, slope and curvature statistics of a height map.

    Derivatives are central finite differences: ``z_x = (z[i+1] - z[i-1]) / (2 dx)`` and
    ``z_xx = (z[i+1] - 2 z[i] + z[i-1]) / dx^2`` over the interior points (rows and columns
    1..n-2), or over all points with wrap-around when ``periodic``.

    Returns
    -------
    SurfaceStatistics
        * ``rms_height`` = sqrt(m0), heights about their mean [length];
        * ``rms_gradient`` = sqrt(<z_x^2 + z_y^2>) [-];
        * ``rms_curvature`` = sqrt(<((z_xx + z_yy)/2)^2>), the rms mean curvature [1/length];
        * Nayak's profile spectral moments, averaged over the x and y directions:
          ``m0 = <z^2>``, ``m2 = (<z_x^2> + <z_y^2>)/2``, ``m4 = (<z_xx^2> + <z_yy^2>)/2``;
        * ``nayak`` = m0 m4 / m2^2 (bandwidth parameter alpha); +inf where the differences
          vanish but the heights do not (a checkerboard, whose central differences are 0).

    Raises
    ------
    ValueError
        A flat map (all heights equal): its rms height, gradient and curvature are 0, but
        Nayak's parameter m0 m4 / m2^2 = 0/0 has no value, and no statistic of the roughness
        exists; the message says so. Also heights that are not a finite 2-D map of at least
        3 x 3 points, or a spacing that is not > 0 (a :class:`TypeError` for strings, None
        or objects).
    """
    heights = checks.height_map("heights", heights)
    checks.supported_magnitude("max |heights|", float(np.max(np.abs(heights))))
    spacing = checks.supported_magnitude("spacing", checks.positive("spacing", spacing))
    periodic = checks.flag("periodic", periodic)
    if np.all(heights == heights.flat[0]):
        raise ValueError("heights is flat (all heights equal): its rms height, gradient and "
                         "curvature are 0 and Nayak's parameter m0 m4 / m2^2 is undefined (0/0)")

    z = heights - heights.mean()
    z_x, z_y, z_xx, z_yy = height_derivatives(z, spacing, periodic=periodic)
    m0, m2, m4 = profile_moments(z, z_x, z_y, z_xx, z_yy)
    mean_curvature = 0.5 * (z_xx + z_yy)
    return SurfaceStatistics(
        rms_height=math.sqrt(m0),
        rms_gradient=math.sqrt(2.0 * m2),
        rms_curvature=math.sqrt(float(np.mean(mean_curvature * mean_curvature))),
        m0=m0,
        m2=m2,
        m4=m4,
        nayak=m0 * m4 / m2**2 if m2 > 0 else math.inf,
    )

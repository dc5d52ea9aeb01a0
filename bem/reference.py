"""Analytic reference solutions of frictionless normal contact (docs/theory.md, "Analytic checks").

These are the closed forms the boundary-element solver is tested against; they are shared by the
tests and by users who want to check a model on a known case. All functions take physical
inputs: lengths in any consistent unit, pressures and moduli in one unit (that of ``e_star``),
forces in pressure x length^2.

Contents
--------
* :func:`love_pixel_displacement`: Love's (1929) surface displacement under uniform pressure on
  a rectangle, in the asinh form that is finite everywhere (the pixel kernel of the operator,
  defined in :mod:`bem.elastic.kernel`).
* :data:`UNIFORM_SQUARE_MEAN_DEFLECTION`: mean deflection of a uniformly loaded square, in units
  of p L / E* (0.9464020, the ``m`` of the improved GW theory).
* :func:`hertz`: sphere on a flat (Hertz): contact radius, approach, peak pressure, pressure and
  surface displacement profiles.
* :func:`westergaard`: periodic 1-D sinusoid (Westergaard): contact fraction and mean gap.
* :func:`bisinusoid_area_low_load`, :func:`bisinusoid_area_high_load`: the
  Johnson-Greenwood-Higginson asymptotes for ``z = Delta cos(2 pi x / lambda) cos(2 pi y / lambda)``.
* :func:`flat_punch_stiffness`: rigid flat circular punch, ``S = 2 E* a``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bem.common.checks import positive as _positive
from bem.elastic.kernel import love_pixel_displacement

__all__ = [
    "love_pixel_displacement",
    "UNIFORM_SQUARE_MEAN_DEFLECTION",
    "UNIFORM_SQUARE_CENTRE_DEFLECTION",
    "HertzSolution",
    "hertz",
    "WestergaardSolution",
    "westergaard",
    "bisinusoid_area_low_load",
    "bisinusoid_area_high_load",
    "flat_punch_stiffness",
]

#: Mean deflection over a uniformly loaded square of side L, in units of p L / E*:
#: ``(4/pi) [ln(1 + sqrt 2) - (sqrt 2 - 1)/3]`` (docs/theory.md, "Love's pixel kernel").
UNIFORM_SQUARE_MEAN_DEFLECTION = 4.0 / math.pi * (math.log(1.0 + math.sqrt(2.0))
                                                  - (math.sqrt(2.0) - 1.0) / 3.0)

#: Deflection at the centre of a uniformly loaded square of side L, in units of p L / E*:
#: ``4 ln(1 + sqrt 2) / pi``.
UNIFORM_SQUARE_CENTRE_DEFLECTION = 4.0 * math.log(1.0 + math.sqrt(2.0)) / math.pi


@dataclass(frozen=True)
class HertzSolution:
    """Hertz contact of a rigid sphere of radius R on an elastic half-space (or the equivalent).

    Attributes
    ----------
    load : float
        Normal force P [force].
    radius : float
        Sphere radius R [length].
    e_star : float
        Composite modulus E* [pressure].
    contact_radius : float
        ``a = (3 P R / (4 E*))^(1/3)`` [length].
    approach : float
        Rigid-body approach (penetration) ``delta = a^2 / R`` [length].
    peak_pressure : float
        ``p0 = 3 P / (2 pi a^2)`` [pressure].
    """

    load: float
    radius: float
    e_star: float
    contact_radius: float
    approach: float
    peak_pressure: float

    @property
    def contact_area(self) -> float:
        """``pi a^2`` [length^2]."""
        return math.pi * self.contact_radius**2

    @property
    def stiffness(self) -> float:
        """Normal stiffness ``dP/d delta = 2 E* a`` [force/length]."""
        return 2.0 * self.e_star * self.contact_radius

    def pressure(self, r) -> np.ndarray:
        """``p(r) = p0 sqrt(1 - r^2/a^2)`` inside the contact, 0 outside [pressure]."""
        r = np.asarray(r, dtype=float)
        inside = np.clip(1.0 - (r / self.contact_radius) ** 2, 0.0, None)
        return self.peak_pressure * np.sqrt(inside)

    def displacement(self, r) -> np.ndarray:
        """Surface displacement u(r) into the body [length].

        Inside (r <= a): ``u = delta - r^2/(2R)``; outside:
        ``u = p0/(2 a E*) [(2a^2 - r^2) asin(a/r) + a sqrt(r^2 - a^2)]`` (docs/theory.md, eq. T28).
        """
        r = np.abs(np.asarray(r, dtype=float))
        a = self.contact_radius
        outside = r > a
        safe_r = np.where(outside, r, 2.0 * a)
        outer = (self.peak_pressure / (2.0 * a * self.e_star)
                 * ((2.0 * a * a - safe_r**2) * np.arcsin(a / safe_r)
                    + a * np.sqrt(safe_r**2 - a * a)))
        inner = self.approach - r**2 / (2.0 * self.radius)
        return np.where(outside, outer, inner)


def hertz(load: float, radius: float, e_star: float = 1.0) -> HertzSolution:
    """Hertz solution for force ``load`` on a sphere of radius ``radius`` (docs/theory.md, eq. T27).

    R = E* = P = 1 gives a = 0.908560, delta = 0.825482, p0 = 0.578407.
    """
    load = _positive("load", load)
    radius = _positive("radius", radius)
    e_star = _positive("e_star", e_star)
    a = (3.0 * load * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return HertzSolution(load=load, radius=radius, e_star=e_star, contact_radius=a,
                         approach=a * a / radius, peak_pressure=3.0 * load / (2.0 * math.pi * a * a))


@dataclass(frozen=True)
class WestergaardSolution:
    """Periodic contact of ``z = Delta cos(2 pi x / lambda)`` with a rigid flat (Westergaard).

    Attributes
    ----------
    psi : float
        Mean pressure over the full-contact pressure, ``p_mean / p*`` [-], 0 < psi <= 1.
    full_contact_pressure : float
        ``p* = pi E* Delta / lambda`` [pressure].
    contact_fraction : float
        Contact width over wavelength, ``(2/pi) asin(sqrt psi)`` [-].
    mean_gap : float
        ``Delta (1 - psi + psi ln psi)`` [length]: the mean gap, which equals the separation
        from the rigid plane to the mean plane of the (deformed) periodic surface.
    """

    psi: float
    full_contact_pressure: float
    contact_fraction: float
    mean_gap: float


def westergaard(mean_pressure: float, *, amplitude: float, wavelength: float,
                e_star: float = 1.0) -> WestergaardSolution:
    """Westergaard solution for the 1-D sinusoid at mean pressure ``mean_pressure``.

    Parameters
    ----------
    mean_pressure : float
        Nominal (mean) pressure [pressure], 0 < p_mean <= p*.
    amplitude : float
        Delta [length] (half the peak-to-valley height).
    wavelength : float
        lambda [length].
    e_star : float
        Composite modulus [pressure].
    """
    amplitude = _positive("amplitude", amplitude)
    wavelength = _positive("wavelength", wavelength)
    e_star = _positive("e_star", e_star)
    mean_pressure = _positive("mean_pressure", mean_pressure)
    p_star = math.pi * e_star * amplitude / wavelength
    psi = mean_pressure / p_star
    if psi > 1.0:
        raise ValueError(f"mean_pressure must be <= p* = {p_star!r} (full contact), got {mean_pressure!r}")
    return WestergaardSolution(
        psi=psi,
        full_contact_pressure=p_star,
        contact_fraction=2.0 / math.pi * math.asin(math.sqrt(psi)),
        mean_gap=amplitude * (1.0 - psi + psi * math.log(psi)),
    )


def bisinusoid_area_low_load(psi):
    """JGH low-load asymptote ``A / lambda^2 = pi (3 psi / (8 pi))^(2/3)`` for the bisinusoid.

    ``psi = p_mean / p*`` with ``p* = sqrt(2) pi E* Delta / lambda`` (docs/theory.md, eq. T30).
    """
    psi = _load_ratio(psi)
    return math.pi * (3.0 * psi / (8.0 * math.pi)) ** (2.0 / 3.0)


def bisinusoid_area_high_load(psi):
    """JGH near-full-contact asymptote ``A / lambda^2 = 1 - (3/(2 pi)) (1 - psi)``."""
    psi = _load_ratio(psi)
    return 1.0 - 3.0 / (2.0 * math.pi) * (1.0 - psi)


def _load_ratio(psi) -> np.ndarray:
    psi = np.asarray(psi, dtype=float)
    if not np.all((psi >= 0.0) & (psi <= 1.0)):  # also catches NaN
        raise ValueError("psi = p_mean / p* must lie in [0, 1] (full contact at psi = 1)")
    return psi


def flat_punch_stiffness(radius: float, e_star: float = 1.0) -> float:
    """Normal stiffness ``S = 2 E* a`` of a rigid flat circular punch of radius a [force/length]."""
    return 2.0 * _positive("e_star", e_star) * _positive("radius", radius)

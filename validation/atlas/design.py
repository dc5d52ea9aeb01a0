"""The design of the error atlas: which surfaces it solves, and the scene of each.

The atlas samples the surface descriptors a user can read off a scan before any solve
(:func:`validation.surface_descriptors`): the Hurst exponent H, the magnification (rolloff
to short-cutoff wavelength, which sets Nayak's bandwidth alpha) and the shape of the height
distribution. Its design points are space-filling (a Latin hypercube, :mod:`scipy.stats.qmc`):

* Gaussian self-affine surfaces, H in [0.3, 0.9] and magnification 4 to 128 (uniform in its
  logarithm), with the short cutoff at the grid's Nyquist wavelength 2 L/n and the rolloff
  ``magnification`` times longer, flat up to L;
* plateau-honed surfaces, the same two descriptors and the heights above a quantile q in
  [0.6, 0.95] cut flat (``[surface] plateau``): non-Gaussian heights with negative skewness.

Every point is a scene of :data:`REALIZATIONS` periodic surfaces (``window = 1``) on an
``n x n`` grid, rms slope 0.1, loaded along the check's default path: twelve nominal pressures
p / (E* h'_rms) from 5e-4 to 0.15, logarithmic (:data:`validation.check.request.DEFAULT_PRESSURES`),
with the check's interface models against the periodic boundary-element reference.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.stats import qmc

from validation.check.request import CHECK_TOLERANCE, DEFAULT_COUNT, DEFAULT_PRESSURES, \
    INTERFACE_MODELS
from validation.scenes.reader import parse_scene
from validation.scenes.scene import Scene

__all__ = ["ATLAS_GRID", "ATLAS_POINTS", "atlas_design", "ATLAS_QUANTITIES", "ATLAS_SLOPE", "DesignPoint", "REALIZATIONS",
           "atlas_scene", "design", "design_array"]

#: Grid points per side of every atlas surface.
ATLAS_GRID = 256
#: Realizations (seeds) per design point.
REALIZATIONS = 4
#: rms slope of every atlas surface (the loads scale with it: p / (E* h'_rms) is what counts).
ATLAS_SLOPE = 0.1
#: The quantities the atlas compares (the check's names).
ATLAS_QUANTITIES = ("area", "separation", "stiffness")
#: Design points the computed atlas solves: Gaussian and plateau-honed (all of :func:`design`'s).
ATLAS_POINTS = (40, 8)
#: Ranges of the design: H, log2 of the magnification, the plateau quantile.
HURST_RANGE = (0.3, 0.9)
LOG2_MAGNIFICATION_RANGE = (2.0, 7.0)
PLATEAU_RANGE = (0.6, 0.95)


@dataclass(frozen=True)
class DesignPoint:
    """One surface kind of the atlas.

    Attributes
    ----------
    index : int
        Its number in the design (also the seed block of its realizations).
    hurst : float
        Hurst exponent H [-].
    magnification : float
        Rolloff over short-cutoff wavelength [-].
    plateau : float or None
        Quantile above which the heights are cut flat; None: Gaussian heights.
    """

    index: int
    hurst: float
    magnification: float
    plateau: float | None = None

    @property
    def name(self) -> str:
        """The scene's name (``atlas-007``)."""
        return f"atlas-{self.index:03d}"


def design(gaussian: int = 40, honed: int = 8, *, seed: int = 0) -> tuple[DesignPoint, ...]:
    """The atlas' design points: ``gaussian`` Gaussian and ``honed`` plateau-honed surfaces,
    each set a scrambled Latin hypercube over the ranges of the module docstring.

    Raises
    ------
    ValueError
        For counts below 0 (or 1 for ``gaussian``).
    """
    if isinstance(gaussian, bool) or not isinstance(gaussian, int) or gaussian < 1:
        raise ValueError(f"gaussian must be an integer >= 1, got {gaussian!r}")
    if isinstance(honed, bool) or not isinstance(honed, int) or honed < 0:
        raise ValueError(f"honed must be an integer >= 0, got {honed!r}")
    low = [HURST_RANGE[0], LOG2_MAGNIFICATION_RANGE[0], PLATEAU_RANGE[0]]
    high = [HURST_RANGE[1], LOG2_MAGNIFICATION_RANGE[1], PLATEAU_RANGE[1]]
    points = []
    for count, dimensions in ((gaussian, 2), (honed, 3)):
        if count == 0:
            continue
        unit = qmc.LatinHypercube(d=dimensions, seed=seed + dimensions).random(count)
        scaled = qmc.scale(unit, low[:dimensions], high[:dimensions])
        for row in scaled:
            points.append(DesignPoint(len(points), round(float(row[0]), 4),
                                      round(float(2.0 ** row[1]), 3),
                                      round(float(row[2]), 4) if dimensions == 3 else None))
    return tuple(points)


def atlas_design() -> tuple[DesignPoint, ...]:
    """The design points of the computed atlas (:data:`ATLAS_POINTS`: the first of each of
    :func:`design`'s hypercubes, whose rows come in random order)."""
    points = design()
    gaussian = [p for p in points if p.plateau is None][:ATLAS_POINTS[0]]
    honed = [p for p in points if p.plateau is not None][:ATLAS_POINTS[1]]
    return tuple(gaussian + honed)


def atlas_scene(point: DesignPoint, *, n: int = ATLAS_GRID,
                realizations: int = REALIZATIONS) -> Scene:
    """The scene of one design point (module docstring)."""
    spacing = 1.0 / n
    short_cutoff = 2.0 * spacing
    rolloff = min(1.0, point.magnification * short_cutoff)
    low, high = (p * ATLAS_SLOPE for p in DEFAULT_PRESSURES)
    surface = {"family": "self-affine", "hurst": point.hurst, "rms_slope": ATLAS_SLOPE,
               "rolloff": rolloff, "short_cutoff": short_cutoff, "window": 1, "L": 1.0, "n": n}
    if point.plateau is not None:
        surface["plateau"] = point.plateau
    data = {"name": point.name,
            "title": f"Error atlas: H = {point.hurst:g}, magnification {point.magnification:g}"
                     + ("" if point.plateau is None else f", plateau at q = {point.plateau:g}"),
            "surface": surface,
            "realizations": {"count": realizations, "seed": 1000 * point.index},
            "material": {"e_star": 1.0},
            "loads": {"quantity": "load", "min": low, "max": high, "count": DEFAULT_COUNT,
                      "spacing": "log"},
            "models": {"use": list(INTERFACE_MODELS)},
            "quantities": {"use": ["area", "load", "separation", "stiffness"]},
            "bem": {"tol": CHECK_TOLERANCE},
            "tolerances": {"levels": [0.05, 0.2]}}
    return parse_scene(data, source=f"{point.name} (atlas design)")


def design_array(points: tuple[DesignPoint, ...]) -> np.ndarray:
    """(H, log10 magnification, plateau or 1) of each point, shape (points, 3)."""
    return np.array([[p.hurst, np.log10(p.magnification), 1.0 if p.plateau is None
                      else p.plateau] for p in points])

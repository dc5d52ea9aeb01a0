"""The design of the error atlas: which surfaces it solves, and the scene of each.

The atlas samples the surface descriptors a user can read off a scan before any solve
(:func:`validation.surface_descriptors`): the Hurst exponent H, the magnification (rolloff
to short-cutoff wavelength, which sets Nayak's bandwidth alpha) and the shape of the height
distribution. Its design points are space-filling (a Latin hypercube, :mod:`scipy.stats.qmc`):

* Gaussian self-affine surfaces, H in [0.3, 0.9] and magnification 4 to 128 (uniform in its
  logarithm), with the short cutoff at the grid's Nyquist wavelength 2 L/n and the rolloff
  ``magnification`` times longer, flat up to L;
* plateau-honed surfaces, the same two descriptors and the heights above a quantile q in
  [0.6, 0.95] cut flat (``[surface] plateau``): non-Gaussian heights with negative skewness;
* periodic Weierstrass-Mandelbrot surfaces (eq. T52; gamma = 1.5, M = 10), D in [2.05, 2.95]
  (H = 3 - D) and n_max from 4 to 11 (a magnification gamma^n_max of 5 to 87, the shortest
  wavelength at least 2.9 grid steps on 256 points): a spectrum of discrete lines whose longest wave spans
  the period, the paper's surfaces.

Every point is a scene of :data:`REALIZATIONS` periodic surfaces (``window = 1``) on an
``n x n`` grid, rms slope 0.1, loaded along the check's default path: twelve nominal pressures
p / (E* h'_rms) from 5e-4 to 0.15, logarithmic (:data:`validation.check.request.DEFAULT_PRESSURES`),
with the check's interface models against the periodic boundary-element reference, area,
separation, stiffness and leakage (the effective hydraulic aperture).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.stats import qmc

from validation.check.request import CHECK_TOLERANCE, DEFAULT_COUNT, DEFAULT_PRESSURES, \
    INTERFACE_MODELS
from validation.scenes.reader import parse_scene
from validation.scenes.scene import Scene

__all__ = ["ATLAS_GRID", "ATLAS_POINTS", "ATLAS_QUANTITIES", "ATLAS_SLOPE", "DesignPoint",
           "REALIZATIONS", "atlas_design", "atlas_scene", "design"]

#: Grid points per side of every atlas surface.
ATLAS_GRID = 256
#: Realizations (seeds) per design point.
REALIZATIONS = 4
#: rms slope of every atlas surface (the loads scale with it: p / (E* h'_rms) is what counts).
ATLAS_SLOPE = 0.1
#: The quantities the atlas compares (the check's names).
ATLAS_QUANTITIES = ("area", "separation", "stiffness", "leakage")
#: Design points the computed atlas solves: Gaussian, plateau-honed and WM (all of
#: :func:`design`'s).
ATLAS_POINTS = (40, 8, 12)
#: Ranges of the design: H, log2 of the magnification, the plateau quantile.
HURST_RANGE = (0.3, 0.9)
LOG2_MAGNIFICATION_RANGE = (2.0, 7.0)
PLATEAU_RANGE = (0.6, 0.95)
#: Ranges of the WM design: D and n_max (integer, inclusive); gamma and M are fixed.
WM_D_RANGE = (2.05, 2.95)
WM_N_MAX_RANGE = (4, 11)
WM_GAMMA, WM_RIDGES = 1.5, 10


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
    family : {"self-affine", "wm"}
        The generator; for "wm", H = 3 - D and the magnification is gamma^n_max.
    """

    index: int
    hurst: float
    magnification: float
    plateau: float | None = None
    family: str = "self-affine"

    @property
    def n_max(self) -> int:
        """A WM point's n_max (the magnification is gamma^n_max)."""
        return round(np.log(self.magnification) / np.log(WM_GAMMA))

    @property
    def name(self) -> str:
        """The scene's name (``atlas-007``)."""
        return f"atlas-{self.index:03d}"


def design(gaussian: int = 40, honed: int = 8, wm: int = 12, *,
           seed: int = 0) -> tuple[DesignPoint, ...]:
    """The atlas' design points: ``gaussian`` Gaussian, ``honed`` plateau-honed and ``wm`` WM
    surfaces, each set a scrambled Latin hypercube over the ranges of the module docstring.

    Raises
    ------
    ValueError
        For counts below 0 (or 1 for ``gaussian``).
    """
    if isinstance(gaussian, bool) or not isinstance(gaussian, int) or gaussian < 1:
        raise ValueError(f"gaussian must be an integer >= 1, got {gaussian!r}")
    for name, count in (("honed", honed), ("wm", wm)):
        if isinstance(count, bool) or not isinstance(count, int) or count < 0:
            raise ValueError(f"{name} must be an integer >= 0, got {count!r}")
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
    if wm:
        unit = qmc.LatinHypercube(d=2, seed=seed + 10).random(wm)
        low, high = WM_N_MAX_RANGE
        for d, level in qmc.scale(unit, [WM_D_RANGE[0], low], [WM_D_RANGE[1], high + 1]):
            points.append(DesignPoint(len(points), round(3.0 - float(d), 4),
                                      round(WM_GAMMA ** min(int(level), high), 3),
                                      family="wm"))
    return tuple(points)


def atlas_design() -> tuple[DesignPoint, ...]:
    """The design points of the computed atlas (:data:`ATLAS_POINTS`: the first of each of
    :func:`design`'s hypercubes, whose rows come in random order)."""
    points = design()
    gaussian = [p for p in points if p.plateau is None and p.family != "wm"][:ATLAS_POINTS[0]]
    honed = [p for p in points if p.plateau is not None][:ATLAS_POINTS[1]]
    wm = [p for p in points if p.family == "wm"][:ATLAS_POINTS[2]]
    return tuple(gaussian + honed + wm)


def atlas_scene(point: DesignPoint, *, n: int = ATLAS_GRID,
                realizations: int = REALIZATIONS) -> Scene:
    """The scene of one design point (module docstring)."""
    low, high = (p * ATLAS_SLOPE for p in DEFAULT_PRESSURES)
    if point.family == "wm":
        # the shortest wavelength L / gamma^n_max at least 2.9 grid steps on a coarser grid too
        n_max = min(point.n_max, int(np.log(n / 2.9) / np.log(WM_GAMMA)))
        surface = {"family": "wm", "D": round(3.0 - point.hurst, 4), "rms_slope": ATLAS_SLOPE,
                   "gamma": WM_GAMMA, "M": WM_RIDGES, "n_max": n_max, "L": 1.0, "n": n,
                   "periodic": True}
        title = f"Error atlas: WM D = {surface['D']:g}, n_max {n_max}"
    else:
        spacing = 1.0 / n
        short_cutoff = 2.0 * spacing
        surface = {"family": "self-affine", "hurst": point.hurst, "rms_slope": ATLAS_SLOPE,
                   "rolloff": min(1.0, point.magnification * short_cutoff),
                   "short_cutoff": short_cutoff, "window": 1, "L": 1.0, "n": n}
        title = f"Error atlas: H = {point.hurst:g}, magnification {point.magnification:g}"
        if point.plateau is not None:
            surface["plateau"] = point.plateau
            title += f", plateau at q = {point.plateau:g}"
    data = {"name": point.name, "title": title,
            "surface": surface,
            "realizations": {"count": realizations, "seed": 1000 * point.index},
            "material": {"e_star": 1.0},
            "loads": {"quantity": "load", "min": low, "max": high, "count": DEFAULT_COUNT,
                      "spacing": "log"},
            "models": {"use": list(INTERFACE_MODELS)},
            "quantities": {"use": ["area", "load", "separation", "stiffness", "leakage"]},
            "bem": {"tol": CHECK_TOLERANCE},
            "tolerances": {"levels": [0.05, 0.2]}}
    return parse_scene(data, source=f"{point.name} (atlas design)")

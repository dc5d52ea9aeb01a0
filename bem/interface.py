"""The interface reference: a surface's contact as an unbounded interface (docs/theory.md, 8.10).

The non-periodic reference (:class:`bem.BoundaryElementModel`, ``periodic=False``) presses the
L x L window, as a whole, into a half-space: a *finite nominal contact*, whose separation
contains the window's own sink ``m p L / E*`` and whose stiffness is capped near ``E*/L``
(docs/theory.md, T47-T48). Persson's theory, GW, Bush-Gibson-Thomas and the discrete model
without interaction describe instead an *interface* of unbounded nominal extent, per unit area,
with zero mean elastic displacement: the periodic problem (Pastewka et al., PRE 87 (2013)
062809, showed that the sub-linear stiffness of non-periodic solutions is this finite-size
effect). :class:`InterfaceModel` solves that problem for a height map in one of two ways:

* ``extension="periodic"``: the map *is* one period of a periodic surface (a self-affine
  surface from the generator without a window, a WM surface with ``periodic=True``): the
  periodic half-space on the map itself.
* ``extension="mirror"``: any other window (a measured scan, a WM surface of eq. (11), a window
  of a larger surface): its even (mirror) extension, 2N x 2M points of period twice the map, solved on the
  periodic half-space. The extension is continuous across the map's edges (no height step, only
  a slope kink along the mirror lines), its height and slope distributions are the map's, and
  its power spectrum is the one :func:`asperity.spectral.spectrum.power_spectrum_2d` gives the map with
  ``window="mirror"`` (Persson's theory is computed from the same spectrum). By symmetry the
  pressure and displacement of the extension are even too, so its period is solved on the map
  itself: the half-space operator of the quadrant is a product of type-II cosine transforms
  (:class:`bem.HalfSpace` with ``mirror``), the extension's periodic solution per copy at a
  quarter of its points (equal to the solve of the extension to 1e-11, tested). Loads, areas,
  stiffness and contacts are the map's; the contact edges and patches do not wrap around, and
  the leakage, the extension's periodic Reynolds flow, is the map's own non-periodic flow
  (inlet and outlet edges, closed sides: the mirror lines are isobars across the flow and
  closed along it).

On the periodic half-space the mean displacement is zero, so the separation d (rigid plane to
the mean plane of the heights) equals the mean gap: the interface's mean gap u-bar.

The mirror method has an error of its own (its kinks, and its period 2L instead of the
unbounded surface's), measured against the periodic solution of periodic self-affine surfaces
(``benchmarks/bench_interface.py``; docs/theory.md, eq. T50) per contact-area fraction: a small
*bias* (:data:`MIRROR_BIAS`, the 95 % confidence bound of the mean signed error over surfaces)
and a larger scatter from surface to surface, held by the *bound* (:data:`MIRROR_BOUND`, what
one surface carries); relative for area and stiffness, in units of the rms height for
separation and mean gap (:func:`mirror_error`). With ``error_estimate`` the bound is added to
the per-point error estimates, so that the reference band of one surface holds the method's
error as well as the discretisation's; the bias is kept beside it for the verdicts on the mean
over realizations, whose intervals hold the scatter already.
"""

from __future__ import annotations

from dataclasses import replace
from types import MappingProxyType
from typing import Any, Iterable

import numpy as np
from numpy.typing import ArrayLike

from bem.common import checks
from bem.common.curve import CURVE_QUANTITIES, ContactCurve
from bem.model import BoundaryElementModel, check_points

__all__ = ["EXTENSIONS", "MIRROR_BIAS", "MIRROR_BOUND", "MIRROR_FRACTIONS", "MIRROR_PARTS",
           "InterfaceModel", "NominalContactModel", "method_error", "mirror_error",
           "mirror_extension"]

#: How a height map becomes one period of the interface: the map itself, or its mirror image.
EXTENSIONS = ("periodic", "mirror")

#: Contact-area fractions the mirror method's error is tabulated at: the geometric centres of
#: the calibration's bins, edged at 0.3, 1, 3, 10 and 30 % (the periodic solution's fraction).
MIRROR_FRACTIONS = (0.0055, 0.0173, 0.0548, 0.173)

# The tables below are the envelope of three calibrations, the mirror method against the
# periodic solution of the same surface, 256^2, rms slope 0.1, 14 mean pressures 1.5e-4 to
# 2.5e-2 E* (about 0.25-32 % contact): ``python benchmarks/bench_interface.py --n 256 --seeds 32``
# (periodic self-affine surfaces, H = 0.3, 0.5, 0.8, rolloff L/4, seeds 0-31 each),
# ``python benchmarks/bench_interface.py --n 256 --seeds 16 --rolloff 1`` (the same without a
# rolloff: the longest waves span the map, as in a scan that does not show its rolloff; seeds
# 0-15 each) and ``python benchmarks/bench_interface.py --hurst "" --wm 2.05,2.5,2.95 --seeds 24``
# (periodic WM surfaces, eq. T52, seeds 0-23 each). Per bin the largest over each family
# member and each family's pooled surfaces (a scene's realizations share one H or D, and the
# bias depends on it). The surfaces whose longest waves span the map set every entry: the WM
# surfaces most of the area's and the light contacts', the self-affine ones without a rolloff
# the stiffness's at 3-30 % contact (up to 37 % off on one surface at H 0.8) and the mean
# gap's bias; with a rolloff at L/4 the mirror image's kinks weigh less (area bias <= 1.5 %,
# stiffness bound <= 12 %). Relative for area and stiffness (the conductance is the stiffness
# times 2/E*), in units of the map's rms height for separation and mean gap (the interface's
# separation is its mean gap). Docs: docs/theory.md, eq. T50.

#: The mirror method's bias per bin of :data:`MIRROR_FRACTIONS`: the 95 % confidence bound
#: |mean| + t s / sqrt(n) of the mean over the calibration's surfaces of each surface's signed
#: error in the bin (n = 32 per H with a rolloff, 16 without, 24 per D): what a verdict on the
#: mean over realizations must allow. The signed means: area +0.4 to +1.9 %, mean gap -0.004 to
#: -0.054 h_rms, stiffness -7 to +8 % (negative at light contact, positive at heavy).
MIRROR_BIAS = MappingProxyType({
    "area": (0.0262, 0.0182, 0.0171, 0.0135),
    "mean_gap": (0.0564, 0.0678, 0.0695, 0.0446),
    "stiffness": (0.0879, 0.0686, 0.0658, 0.1132),
})

#: The mirror method's bound per bin of :data:`MIRROR_FRACTIONS`: the larger of 1.25 times the
#: largest |error| of one surface measured in the bin and the one-sided 95 %/95 % normal
#: tolerance limit of the surfaces' largest |error| there: what one surface carries. The
#: largest measured: area 11.0, 8.2, 6.1, 5.0 % (WM); mean gap 0.128, 0.129, 0.152, 0.117
#: h_rms; stiffness 21.7, 30.9 (WM), 26.4, 36.7 % (self-affine without a rolloff, H 0.8).
MIRROR_BOUND = MappingProxyType({
    "area": (0.1381, 0.1022, 0.0763, 0.0619),
    "mean_gap": (0.1594, 0.1615, 0.1905, 0.1457),
    "stiffness": (0.2712, 0.3859, 0.3299, 0.4587),
})

#: The quantity whose table each estimated field takes.
_TABLE_OF = MappingProxyType({"area": "area", "separation": "mean_gap", "mean_gap": "mean_gap",
                              "stiffness": "stiffness", "conductance": "stiffness"})
#: The parts of the mirror method's error: the bias (the mean's) and the bound (one surface's).
MIRROR_PARTS = ("bias", "bound")


def mirror_error(quantity: str, area_fraction: ArrayLike, part: str = "bound") -> np.ndarray:
    """The mirror method's error (eq. T50) at contact-area fractions ``area_fraction``.

    Piecewise linear in ln(fraction) between the table's points (:data:`MIRROR_FRACTIONS`),
    constant beyond them (also at zero contact).

    Parameters
    ----------
    quantity : {"area", "separation", "mean_gap", "stiffness", "conductance"}
        The field: relative for area, stiffness and conductance, in units of the map's rms
        height for separation and mean gap.
    area_fraction : array_like
        The interface's contact-area fraction A/A0 per point, in [0, 1].
    part : {"bound", "bias"}
        :data:`MIRROR_BOUND` (what one surface carries) or :data:`MIRROR_BIAS` (what the mean
        over realizations carries).

    Returns
    -------
    numpy.ndarray
        The error, of the shape of ``area_fraction``.
    """
    name = checks.choice("quantity", quantity, tuple(_TABLE_OF))
    table = (MIRROR_BOUND if checks.choice("part", part, MIRROR_PARTS) == "bound"
             else MIRROR_BIAS)[_TABLE_OF[name]]
    fraction = np.asarray(area_fraction, dtype=float)
    if np.any(fraction < 0) or np.any(fraction > 1) or np.any(np.isnan(fraction)):
        raise ValueError("area_fraction must lie in [0, 1]")
    log = np.log(np.maximum(fraction, 1e-300))
    return np.interp(log, np.log(MIRROR_FRACTIONS), table)


def mirror_extension(heights: ArrayLike) -> np.ndarray:
    """The even extension of a height map: 2N x 2M points, period twice the map's.

    ``out[:N, :M]`` is the map, ``out[:N, M:]`` its mirror image in x, ``out[N:, :]`` the
    mirror image in y of the upper half, so that ``out[j, i] == out[2N-1-j, i] ==
    out[j, 2M-1-i]``: each mirror line lies half a pixel beyond the map's edge (the cosine
    extension of a type-II DCT).
    """
    z = np.asarray(heights, dtype=float)
    if z.ndim != 2:
        raise ValueError(f"heights must be a 2-D array, got shape {z.shape}")
    return np.block([[z, z[:, ::-1]], [z[::-1, :], z[::-1, ::-1]]])


class InterfaceModel(BoundaryElementModel):
    """The boundary-element reference of the unbounded interface (module docstring).

    Parameters
    ----------
    heights : array_like
        Heights z[j, i] [length] on an N x M grid.
    spacing : float
        Grid step h [length].
    extension : {"mirror", "periodic"}
        ``"periodic"``: the map is one period of a periodic surface; ``"mirror"`` (default): its
        even extension is.
    **options
        Keywords of :func:`bem.contact_curve` (``e_star``, ``tol``, ``max_iter``,
        ``error_estimate``, ...), except ``periodic`` and ``mirror``, which this model sets.

    Loads, areas, contacts and stiffness refer to the map's own nominal area ``N M h^2``. With
    ``error_estimate`` and the mirror extension, every ``<quantity>_error`` extra also holds
    the mirror method's bound, with ``<quantity>_method_error`` (the bound) and
    ``<quantity>_method_bias`` (its bias) beside it (:func:`method_error`, eq. T50). Extra
    ``extension``: the method, for the record.
    """

    name = "bem_interface"

    def __init__(self, heights: ArrayLike, spacing: float, *, extension: str = "mirror",
                 **options: Any) -> None:
        for name in ("periodic", "mirror"):
            if name in options:
                raise TypeError(f"options must not set {name}: the interface is solved on the "
                                f"periodic half-space (extension says how the map becomes a "
                                f"period)")
        self.extension = checks.choice("extension", extension, EXTENSIONS)
        # the mirror extension's period is solved on the map itself, by cosine transforms
        # (bem.HalfSpace mirror): its solution per copy, at a quarter of its points
        super().__init__(heights, spacing, periodic=True, mirror=self.extension == "mirror",
                         **options)

    def __repr__(self) -> str:
        return (f"{type(self).__name__}(heights of shape {self.heights.shape}, "
                f"spacing={self.spacing!r}, extension={self.extension!r}, "
                f"options={self.options!r})")

    def _solve(self, values: np.ndarray, keyword: str, quantities) -> ContactCurve:
        """The path of :class:`bem.BoundaryElementModel` on the periodic half-space, with the
        method (and its bound) in the extras; d is the interface's mean gap."""
        return self._scaled(super()._solve(values, keyword, quantities))

    def _scaled(self, curve: ContactCurve) -> ContactCurve:
        """The curve with the method and, for the mirror extension, its error bound added."""
        extras = dict(curve.extras)
        extras["extension"] = self.extension
        if self.extension == "mirror":
            rms = np.full(curve.load.shape, float(np.std(self.heights)))
            extras["window_rms_height"] = rms
            extras.update(method_error(curve, extras, rms))
        return replace(curve, extras=extras)


def method_error(curve: ContactCurve, extras, rms_height, index=None) -> dict:
    """The per-point error estimates ``extras[<quantity>_error]`` with the mirror method's
    bound in them (eq. T50), and its two parts beside them.

    At each point the bound and the bias (:func:`mirror_error` at the curve's contact-area
    fraction) are scaled to the quantity: relative ones times ``|quantity|``, height-like ones times
    the map's rms height. ``<quantity>_error`` holds the discretisation's estimate plus the
    bound (the band one surface carries); ``<quantity>_method_error`` the bound alone (what a
    finer grid cannot narrow) and ``<quantity>_method_bias`` the bias (what the verdicts on the
    mean over realizations carry instead of the bound).

    Parameters
    ----------
    curve : ContactCurve
        The interface's curve (its area fraction and quantities).
    extras : mapping
        Its extras, with the estimates ``<quantity>_error`` [the quantity's unit].
    rms_height : array_like
        The map's rms height [length], per point or one.
    index : array_like of int, optional
        Only at those points (the others unchanged); a bound already in an estimate there is
        replaced, not added twice.

    Returns
    -------
    dict
        ``<quantity>_error``, ``<quantity>_method_error`` and ``<quantity>_method_bias`` of
        every quantity with an estimate.
    """
    out = {}
    points = slice(None) if index is None else np.asarray(index, dtype=int)
    fraction = np.clip(np.nan_to_num(np.asarray(curve.area_fraction, dtype=float)), 0.0, 1.0)
    for name in _TABLE_OF:
        key = f"{name}_error"
        height_like = name in ("separation", "mean_gap")
        value = None if height_like else getattr(curve, name, None)
        if key not in extras or (not height_like and value is None):
            continue
        total = np.array(extras[key], dtype=float)
        scale = np.asarray(rms_height if height_like else np.abs(np.asarray(value, dtype=float)),
                           dtype=float)
        parts = {part: np.broadcast_to(mirror_error(name, fraction, part) * scale, total.shape)
                 for part in MIRROR_PARTS}
        method = np.array(extras.get(f"{name}_method_error", np.zeros(total.shape)), dtype=float)
        bias = np.array(extras.get(f"{name}_method_bias", np.zeros(total.shape)), dtype=float)
        total[points] += parts["bound"][points] - method[points]
        method[points] = parts["bound"][points]
        bias[points] = parts["bias"][points]
        out[key], out[f"{name}_method_error"], out[f"{name}_method_bias"] = total, method, bias
    return out


class NominalContactModel(InterfaceModel):
    """The interface reference of a finite nominal contact: a square of side ``nominal_size``
    pressed as a whole (docs/theory.md, eq. T49).

    Under the mean pressure p the nominal square sinks as a uniformly loaded patch, by
    ``m p L_n / E*`` on average (``m`` = :data:`bem.reference.UNIFORM_SQUARE_MEAN_DEFLECTION`
    = 0.946, Timoshenko & Goodier; the uniform term of the improved GW theory), and the
    interface and the patch act as springs in series. From the interface solution (d_i, K_i):

        d = d_i - m p L_n / E*,      1/K = 1/K_i + m L_n / E*   (K = S / A0 per unit area),

    the rigid plane nearer the far-field mean plane by the sink (as improved GW's
    ``d = d1 - m p sqrt(A) / E*``), while the gap field, and with it area, mean gap u-bar and
    leakage, is the interface's. The map is a sample of the interface inside the nominal
    contact (``nominal_size`` at least the map's side); its error estimates are the interface's
    carried through these relations (the sink is exact for a uniform mean pressure).

    Parameters
    ----------
    heights, spacing, extension, **options
        As :class:`InterfaceModel`.
    nominal_size : float
        Side L_n [length] of the square nominal contact, at least the map's side.
    """

    name = "bem_nominal"

    def __init__(self, heights: ArrayLike, spacing: float, *, nominal_size: float,
                 **options: Any) -> None:
        super().__init__(heights, spacing, **options)
        side = float(np.sqrt(self.heights.size)) * self.spacing
        self.nominal_size = checks.positive("nominal_size", nominal_size)
        if self.nominal_size < side * (1 - 1e-9):
            raise ValueError(f"nominal_size must be at least the map's side (its points per "
                             f"side times spacing) {side:.6g}, got {nominal_size!r}")

    def at_separation(self, separation: ArrayLike, *,
                      quantities: Iterable[str] = CURVE_QUANTITIES) -> ContactCurve:
        """Contact at separations d [length] of the nominal square (any shape): each point's
        load is the root of ``d(W) = d`` (Brent's method on the load path of :meth:`at_load`,
        monotone in W), then its curve is that load's."""
        from scipy.optimize import brentq

        values = check_points("separation", separation)
        first = float(np.max(self.heights))      # first contact: no load, no sink
        loads = np.zeros(values.shape)
        e_star = float(self.options.get("e_star", 1.0))
        scale = self.heights.size * self.spacing**2 * e_star * 1e-3   # p = 1e-3 E*

        def excess(load: float, target: float) -> float:
            return float(self.at_load(load, quantities=("area",)).separation) - target

        for index in np.ndindex(values.shape):
            target = float(values[index])
            if target >= first:
                continue
            high = scale
            while excess(high, target) > 0.0:
                high *= 4.0
                if high > 1e12 * scale:        # p > 1e9 E*: no contact problem of this kind
                    raise ValueError(f"separation {target!r} is below what any supported load "
                                     f"reaches (a mean pressure of 1e9 E* leaves it above)")
            loads[index] = brentq(excess, 0.0, high, xtol=1e-14 * high, rtol=1e-13,
                                  args=(target,))
        return self.at_load(loads, quantities=quantities)

    def _scaled(self, curve: ContactCurve) -> ContactCurve:
        from bem.reference import UNIFORM_SQUARE_MEAN_DEFLECTION

        interface = super()._scaled(curve)
        e_star = interface.e_star
        compliance = UNIFORM_SQUARE_MEAN_DEFLECTION * self.nominal_size / e_star   # per unit area
        sink = np.asarray(interface.mean_pressure) * compliance
        extras = dict(interface.extras)
        extras["nominal_sink"] = sink
        fields = {"separation": interface.separation - sink}
        if interface.stiffness is not None:
            area = interface.nominal_area
            own = interface.stiffness / area                        # K_i per unit area
            # 1/K = 1/K_i + m L_n/E*; full contact (K_i infinite): the square's own 1/compliance
            with np.errstate(invalid="ignore"):
                series = np.where(np.isinf(own), 1.0 / compliance,
                                  own / (1.0 + own * compliance))
            ratio = 1.0 / (1.0 + own * compliance) ** 2              # dK/dK_i
            fields["stiffness"] = series * area
            if interface.conductance is not None:
                fields["conductance"] = 2.0 * series * area / e_star
            for name in ("stiffness", "conductance"):
                for key in (f"{name}_error", f"{name}_method_error", f"{name}_method_bias"):
                    if key in extras:
                        extras[key] = np.asarray(extras[key]) * ratio
        return replace(interface, extras=extras, **fields)

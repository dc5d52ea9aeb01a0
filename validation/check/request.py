"""One measured scan, one question: the scene that answers it.

``python -m validation check SCAN`` asks which theory to trust on *this* surface. The scan is
read once (:func:`validation.read_topography`, plane removed) to choose what the user left out:

* the length unit of the answer: nm, um or mm, whichever makes the rms height a number from 1
  to 1000;
* the nominal pressures, when none are given: p / E* from ``5e-4`` to ``0.15`` times the rms
  slope, twelve points, logarithmic. With A / A0 ≈ κ p / (E* h′_rms), κ ≈ 2 (Persson; Hyun
  et al.), that spans real contact-area fractions from about 0.1 % to about 30 %: light to heavy
  contact.

The scene is one realization of the whole scan (``tiles = 1``): every model and the
boundary-element reference see the same surface, and the verdicts are those of one surface
(holds where ``|error| + band`` ≤ tolerance). Where the reference band decides a cell, the
reference is solved again on the scan interpolated to twice its grid (``[bem] max_grid = 2N``,
:func:`validation.run.finer_sample.interpolated_scan`) for scans up to :data:`MAX_REFINED_SIDE`
pixels. The scene is written as a TOML file beside the report, so the same answer can be
recomputed with ``python -m validation report check.toml`` and edited like any scene.
"""

from __future__ import annotations

import math
import pathlib
from dataclasses import dataclass

import numpy as np

from bem.reference import UNIFORM_SQUARE_MEAN_DEFLECTION
from validation.check.units import PressureRange, length_unit_for
from validation.surfaces.topography import Topography, read_topography
from validation.surfaces.statistics import surface_statistics
from validation.surfaces.units import LENGTH_UNITS, readable

__all__ = ["CHECK_TOLERANCE", "CheckRequest", "DEFAULT_PRESSURES", "INTERFACE_MODELS", "MAX_REFINED_SIDE",
           "NOMINAL_MODELS", "QUANTITIES", "scene_text"]

#: Default nominal pressures as multiples of E* times the rms slope (light to heavy contact).
DEFAULT_PRESSURES = (5e-4, 0.15)
#: Default number of nominal pressures.
DEFAULT_COUNT = 12
#: Largest scan side whose reference is refined onto the 2N interpolation (a 4096² non-periodic
#: solve needs an 8192² FFT: several GB).
MAX_REFINED_SIDE = 1024
#: Solver tolerance (T25) of the check's reference: its error, at most c_s tol = 1e-6 (eq. T40,
#: c_s = 0.1), is 1 % of a band of 1e-4, below any band a scan's reference has (its
#: discretisation band, and for the interface its mirror bound, are 1e-3 and more); the scenes'
#: 1e-8 costs 17 % more products of the half-space on a 512^2 scan and changes no decision.
CHECK_TOLERANCE = 1e-5
#: The models of the interface frame, the check's answer by default (a scan samples an
#: interface larger than itself), with their reference (docs/theory.md 8.10).
INTERFACE_MODELS = ("gw", "discrete_no_interaction", "persson", "gw_spectral", "bgt",
                    "bem_interface")
#: The models a nominal contact size adds: the finite frame of that square, improved GW with
#: its uniform term and the interface reference with the square's bulk sink.
NOMINAL_MODELS = ("improved_gw", "improved_gw_spectral", "bem_nominal")
#: Quantities the check compares: everything a tribologist asks of a contact. The normal
#: stiffness is the check's word for what an ensemble report calls the conductance (Barber's
#: analogy: conductance = 2 S / E*, the same relative error).
QUANTITIES = ("area", "load", "separation", "stiffness", "contacts", "leakage")


@dataclass(frozen=True)
class CheckRequest:
    """What the user asked: the scan, how to read it, E* and the pressures.

    Attributes
    ----------
    path : pathlib.Path
        The height file (any format :func:`validation.read_topography` reads).
    e_star : float or None
        Effective modulus E* [Pa]; None: pressures are in units of E*.
    pressures : PressureRange or None
        Nominal pressures; None: the default range from the scan's rms slope.
    short_cutoff : str or None
        Short-wavelength cutoff as the scene key writes it (``"20 nm"``), or None.
    fill : str or None
        ``"mean"`` or ``"interpolate"`` for missing points, or None (missing points refused).
    physical_size : str, (str, str) or None
        For a file that does not state its size: its width, or (width, height), with units
        (``"10 um"``, ``("10 um", "7.8 um")``).
    file_unit : str or None
        For a file that does not state its height unit (``"nm"``).
    tiles : int
        1: the whole scan; k²: also the scan cut into k x k tiles, as a second reading of how
        the answer varies across the scan.
    resample : str or None
        ``"finer"`` or ``"coarser"`` for pixels that are not square, or None (refused).
    nominal_size : float or None
        Side [m] of the user's square nominal contact (a seal's width), at least the scan's:
        adds the finite frame of that square; None: the interface frame alone.
    models : tuple of str or None
        The models to compare (registry names; each frame's reference is added); None: those
        of :data:`INTERFACE_MODELS`, and of :data:`NOMINAL_MODELS` with a nominal size.
    scratch : bool
        True when ``path`` is a copy the library call wrote of a height array (a report written
        from it keeps its own copy).
    device : str
        Where the reference's contact problems are solved, ``"cpu"`` or ``"gpu"``
        (:mod:`bem.elastic.device`; the scene's ``[bem] device``).
    """

    path: pathlib.Path
    e_star: float | None = None
    pressures: PressureRange | None = None
    short_cutoff: str | None = None
    fill: str | None = None
    physical_size: str | tuple[str, str] | None = None
    file_unit: str | None = None
    tiles: int = 1
    resample: str | None = None
    nominal_size: float | None = None
    models: tuple[str, ...] | None = None
    scratch: bool = False
    device: str = "cpu"

    @property
    def name(self) -> str:
        """The scan's file name (``scan.npy`` for an array: its name in the report's folder)."""
        return "scan.npy" if self.scratch else self.path.name

    def read(self, unit: str = "m") -> Topography:
        """The scan as the scene will read it (plane removed), lengths in ``unit``."""
        options = {key: value for key, value in (("fill", self.fill), ("resample", self.resample),
                                                 ("short_cutoff", self.short_cutoff))
                   if value is not None}
        return read_topography(self.path, physical_size=self.physical_size,
                               file_unit=self.file_unit, height_unit=unit, detrend="plane",
                               square="keep", **options)

    def unit(self, scan_in_metres: Topography) -> str:
        """The length unit of the answer (nm, um, mm) from the scan's rms height."""
        return length_unit_for(float(np.std(scan_in_metres.heights)))

    def _is_plane(self, scan: Topography) -> bool:
        """Whether the scan is a plane to rounding (what its mean plane leaves is below 1e-9
        of its own rms height, e.g. a tilted plane of integers)."""
        options = {key: value for key, value in (("fill", self.fill), ("resample", self.resample))
                   if value is not None}
        raw = read_topography(self.path, physical_size=self.physical_size,
                              file_unit=self.file_unit, height_unit=scan.unit, detrend=None,
                              square="keep", **options)
        return float(np.std(scan.heights)) <= 1e-9 * float(np.std(raw.heights))

    def rms_slope(self, scan: Topography) -> float:
        """The scan's rms slope h'_rms.

        Raises
        ------
        ValueError
            For a scan that is a plane (nothing rough is left to press).
        """
        slope = surface_statistics(scan.heights, scan.spacing).rms_gradient
        if not slope > 0 or self._is_plane(scan):
            raise ValueError(f"{self.name}: the scan is flat after removing its mean plane "
                             f"(rms slope 0): there is no rough contact to check")
        return slope

    def loads(self, scan: Topography) -> tuple[float, float, int]:
        """(lowest, highest p / E*, count) of the scene's load path.

        Raises
        ------
        ValueError
            For a scan that is a plane (nothing rough is left to press).
        """
        slope = self.rms_slope(scan)
        if self.pressures is not None:
            low, high = self.pressures.dimensionless(self.e_star)
            return low, high, self.pressures.count
        return DEFAULT_PRESSURES[0] * slope, min(DEFAULT_PRESSURES[1] * slope, 0.5), DEFAULT_COUNT


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return '"' + str(value).replace("\\", "\\\\").replace('"', '\\"') + '"'


def _table(name: str | None, entries: dict) -> list[str]:
    lines = [f"[{name}]"] if name else []
    return lines + [f"{key} = {_toml(value)}" for key, value in entries.items() if value is not None]


def scene_text(request: CheckRequest, name: str, *, tiles: int = 1) -> str:
    """The TOML scene that answers ``request`` on the whole scan (``tiles = 1``) or on its
    ``tiles`` tiles; reads the scan once to fill in the defaults.

    Raises
    ------
    ValueError
        For a scan that cannot be read (the reader's message), a flat scan, or pressures that
        need E* (the message names the option).
    """
    metres = request.read("m")
    unit = request.unit(metres)
    scan = request.read(unit)
    low, high, count = request.loads(scan)
    rows, columns = scan.heights.shape
    side = max(rows, columns) // math.isqrt(tiles)
    e_star = ("E* not given: pressures in units of E*" if request.e_star is None
              else f"E* = {request.e_star:.6g} Pa")
    description = (f"The whole scan {request.name} ({rows} x {columns} pixels, spacing "
                   f"{readable(scan.spacing, 4)} {unit}) as one surface"
                   + (f", cut into {tiles} tiles" if tiles > 1 else "")
                   + f"; {e_star}; Load = p / E*.")
    lines = _table(None, {"name": name, "title": f"Your surface: {request.name}"
                          + (f", {tiles} tiles" if tiles > 1 else ""),
                          "description": description})
    lines += [""] + _table("surface", {
        "family": "file", "path": str(request.path.resolve()), "unit": unit,
        "detrend": "plane", "square": "keep", "tiles": tiles, "fill": request.fill,
        "short_cutoff": request.short_cutoff, "resample": request.resample,
        "physical_size": request.physical_size,
        "file_unit": request.file_unit})
    lines += [""] + _table("material", {"e_star": 1.0, "physical_e_star": request.e_star})
    lines += ["# the scene runs in units of E* (loads are p / E*); physical_e_star [Pa] is the E* "
              "of the report's physical units"]
    lines += [""] + _table("loads", {"quantity": "load", "min": low, "max": high, "count": count,
                                     "spacing": "log" if count > 1 else None})
    models = request.models or (INTERFACE_MODELS + (NOMINAL_MODELS if request.nominal_size
                                                    is not None else ()))
    nominal = None if request.nominal_size is None else request.nominal_size / LENGTH_UNITS[unit]
    # improved GW's uniform term with the square's own mean deflection, the m of the
    # reference's sink (bem.NominalContactModel), so that it is judged on its asperity part
    m = None if nominal is None else round(UNIFORM_SQUARE_MEAN_DEFLECTION, 7)
    lines += [""] + _table("models", {"use": list(models), "nominal_size": nominal, "m": m})
    lines += [""] + _table("quantities", {"use": list(QUANTITIES)})
    refined = side <= MAX_REFINED_SIDE and tiles == 1
    lines += [""] + _table("bem", {"tol": CHECK_TOLERANCE,
                                   "max_grid": 2 * side if refined else None,
                                   "device": None if request.device == "cpu" else request.device})
    return "\n".join(lines) + "\n"


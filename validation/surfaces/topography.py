"""Measured height maps from instrument files, as heights z[j, i] and a grid spacing.

:func:`read_topography` reads the file (:mod:`validation.surfaces.formats`: text matrices and
``.npy`` built in, every other format through SurfaceTopography, the optional extra), converts
its units (:mod:`validation.surfaces.units`), puts it on square pixels, crops it, removes its
plane, fills its missing points when asked and cuts its short wavelengths when asked
(:func:`validation.surfaces.cutoff.short_wavelength_cutoff`).
"""

from __future__ import annotations

import math
import pathlib
from dataclasses import dataclass

import numpy as np

from bem.common import checks
from bem.common.checks import choice, file_path, frozen_array, optional_integer, positive
from validation.surfaces.cutoff import check_cutoff, short_wavelength_cutoff
from validation.surfaces.formats import load_map
from validation.surfaces.resample import RESAMPLE, resample_square
from validation.surfaces.units import LENGTH_UNITS, length_in, parse_length, unit_factor

__all__ = ["LENGTH_UNITS", "MIN_SIDE", "Topography", "read_topography", "write_gwyddion_ascii"]

#: Fewest pixels along each side of a map: the smallest tile a scene solves
#: (:data:`validation.surfaces.spec.MIN_TILE`), whose summits and BEM band mean something.
MIN_SIDE = 32


@dataclass(frozen=True)
class Topography:
    """A measured height map, ready for the contact models.

    Attributes
    ----------
    heights : numpy.ndarray
        Read-only heights [unit], indexed ``heights[j, i]`` (row j = y, column i = x).
    spacing : float
        Grid spacing [unit], equal along x and y.
    physical_size : tuple of float
        (width along x, height along y) [unit] of the returned map: ``shape[::-1] * spacing``.
    unit : str
        Length unit of heights, spacing and size (a key of :data:`LENGTH_UNITS`).
    source : str
        The file and the reader that read it.
    filled : int
        Points of the file's map that were missing and filled (``fill``): of the map as
        cropped, or of the file's grid when its pixels were resampled to squares.

    Raises
    ------
    ValueError
        Heights that are not a finite 2-D map, a spacing or size that is not > 0, an unknown
        unit; a :class:`TypeError` for strings, None or objects where numbers are due. The
        message names the field.
    """

    heights: np.ndarray
    spacing: float
    physical_size: tuple[float, float]
    unit: str
    source: str
    filled: int = 0

    def __post_init__(self) -> None:
        checks.record_arrays(self, ("heights",), ndim=2)
        object.__setattr__(self, "spacing", positive("spacing", self.spacing))
        size = self.physical_size
        if (isinstance(size, (str, bytes)) or not isinstance(size, (tuple, list))
                or len(size) != 2):
            raise checks.InputTypeError(f"physical_size must be a pair (width, height) of "
                                        f"lengths > 0, got {size!r}")
        object.__setattr__(self, "physical_size", tuple(
            positive(f"physical_size[{index}]", value) for index, value in enumerate(size)))
        choice("unit", self.unit, LENGTH_UNITS)
        if not isinstance(self.source, str):
            raise checks.InputTypeError(f"source must be a str, got {type(self.source).__name__}")
        object.__setattr__(self, "filled", checks.integer("filled", self.filled, minimum=0))


def _physical_size(value) -> tuple[tuple[float, str | None], tuple[float, str | None]]:
    if isinstance(value, (tuple, list)):
        if len(value) != 2:
            raise ValueError(f"physical_size must be a length or (width, height), got {value!r}")
        return parse_length("physical_size", value[0]), parse_length("physical_size", value[1])
    side = parse_length("physical_size", value)
    return side, side


def _detrend(heights: np.ndarray, valid: np.ndarray, detrend: str | None) -> np.ndarray:
    if detrend is None:
        return heights
    if detrend == "mean":
        return heights - heights[valid].mean()
    rows, columns = np.indices(heights.shape, dtype=float)
    basis = np.stack((np.ones(valid.sum()), columns[valid], rows[valid]), axis=1)
    coefficients, *_ = np.linalg.lstsq(basis, heights[valid], rcond=None)
    return heights - (coefficients[0] + coefficients[1] * columns + coefficients[2] * rows)


def _fill(heights: np.ndarray, valid: np.ndarray, fill: str) -> np.ndarray:
    """Missing points filled with the mean of the valid ones, or interpolated: piecewise linear
    on a Delaunay triangulation of the valid points next to a missing one (within two pixels:
    the rest of the map cannot change a gap's values, and a 500^2 map with a few holes is
    triangulated in milliseconds, not a minute), nearest valid value outside their hull or
    when they span no triangle (the nearest valid point of a missing one always borders a
    missing point)."""
    if fill == "mean":
        return np.where(valid, heights, heights[valid].mean())
    from scipy.interpolate import griddata
    from scipy.ndimage import binary_dilation
    from scipy.spatial import QhullError

    border = binary_dilation(~valid, structure=np.ones((3, 3), dtype=bool), iterations=2) & valid
    points = np.argwhere(border)
    missing = np.argwhere(~valid)
    try:
        values = griddata(points, heights[border], missing, method="linear")
    except QhullError:          # fewer than 3 valid points, or all of them on one line
        values = np.full(len(missing), np.nan)
    outside = ~np.isfinite(values)
    if outside.any():
        values[outside] = griddata(points, heights[border], missing[outside], method="nearest")
    filled = heights.copy()
    filled[~valid] = values
    return filled


def read_topography(
    path: str | pathlib.Path,
    *,
    physical_size: float | str | tuple | None = None,
    height_unit: str = "m",
    detrend: str | None = "plane",
    fill: str | None = None,
    square: str = "crop",
    file_unit: str | None = None,
    channel: int | None = None,
    reader: str = "auto",
    resample: str | None = None,
    short_cutoff: float | str | None = None,
) -> Topography:
    """Read a measured height map into heights [height_unit] and a grid spacing.

    Parameters
    ----------
    path : str or path-like
        The file. ``.npy`` and plain-text matrices are read built in (row = y, column = x),
        every other format through SurfaceTopography (optional extra ``[topography]``): the
        built-in reader is tried first for the suffixes ``.npy``, ``.txt``, ``.csv``, ``.asc``,
        ``.dat`` and ``.tsv``, SurfaceTopography first for any other, then the other one (a
        Zygo MetroPro ``.dat`` is read by SurfaceTopography; a text matrix of two or three
        columns is taken for a list of x, (y,) z points and left to it as well).
    physical_size : float, str or (width, height), optional
        Size of the whole map along x and y, required exactly when the file does not state
        it. Numbers are in ``height_unit``; strings carry their unit (``"10 um"``). A single
        value means a square map. Giving it for a file that states its size is an error.
    height_unit : str
        Unit of the returned heights, spacing and size (default metres); one of
        :data:`LENGTH_UNITS` (m, mm, µm/um, nm, Å/A, ...).
    detrend : {"plane", "mean", None}
        Subtract the least-squares plane ``a + b x + c y`` (default), the mean, or nothing.
        Fitted over the valid points of the returned (cropped) map.
    fill : {None, "mean", "interpolate"}
        Missing points (NaN in the file, masked points of an instrument file): an error by
        default; filled with the mean of the valid heights, or interpolated (piecewise linear
        inside the valid points' hull, nearest valid value outside) when asked.
    square : {"crop", "keep"}
        A non-square map is cropped to its largest centred square (default), or kept
        rectangular (every contact model takes N x M grids of square pixels).
    file_unit : str, optional
        Unit of the numbers in a file that states none (``.npy``, bare text); required then.
    channel : int, optional
        Channel index for multi-channel instrument files (default: the reader's default).
        SurfaceTopography stores arrays as [x, y]; they are transposed to [y, x] here (so an
        ``.npy`` read with ``reader="surfacetopography"`` comes back transposed).
    reader : {"auto", "builtin", "surfacetopography"}
        Both in turn (default, see ``path``), or only the built-in reader or SurfaceTopography's.
    resample : {None, "finer", "coarser"}
        Pixels that are not square (dx != dy) are an error by default; with this option the
        map is resampled onto square pixels of the finer or the coarser of the two spacings,
        along the one axis whose spacing changes, keeping the physical size to within half a
        new pixel (:func:`validation.surfaces.resample.resample_square`: a cubic spline at the new
        centres, or its mean over each new pixel). Effect on the spectrum (docs/theory.md,
        "7.6 Measured maps: non-square pixels and rectangular maps"): refining adds no
        wavevectors beyond the old Nyquist pi/dy and attenuates those just below it (to 0.49
        in amplitude at pi/dy); coarsening removes the band above the new Nyquist pi/h, and
        the pixel mean damps but does not remove its folding back. Missing points are filled
        first (``fill``); square pixels are left as they are.
    short_cutoff : float or str, optional
        Remove every wavelength shorter than this from the returned map, last (after the
        crop, the detrending and the filling): a number in ``height_unit`` or a string with
        its unit (``"20 nm"``), at least two pixels and shorter than the map's shorter side.
        A sharp circular low-pass of the map's mirror extension that keeps its plane
        (:func:`validation.surfaces.cutoff.short_wavelength_cutoff`, which says what it does
        to the spectrum and to the rms height and slope). Default: the map as measured.

    Returns
    -------
    Topography
        Frozen dataclass (heights, spacing, physical_size, unit, source).

    Raises
    ------
    ValueError
        Line scans, maps of fewer than :data:`MIN_SIDE` pixels along a side, maps without a
        valid point, missing data without ``fill``, missing size or unit, pixels that are not
        square (without ``resample``), unknown units or options, a ``short_cutoff`` out of
        range, files that no reader reads (corrupted or truncated: the message names each
        reader tried and its reason).
    ImportError
        An instrument format without the ``[topography]`` extra installed.
    """
    path = file_path("path", path)
    if not path.is_file():
        raise ValueError(f"path must be an existing file, got {str(path)!r}")
    for name, value, allowed in (("detrend", detrend, ("plane", "mean", None)),
                                 ("fill", fill, (None, "mean", "interpolate")),
                                 ("square", square, ("crop", "keep")),
                                 ("reader", reader, ("auto", "builtin", "surfacetopography")),
                                 ("resample", resample, (None, *RESAMPLE))):
        choice(name, value, allowed)
    optional_integer("channel", channel, minimum=0)
    out_factor = unit_factor("height_unit", height_unit)
    if file_unit is not None:
        unit_factor("file_unit", file_unit)
    user_size = None if physical_size is None else _physical_size(physical_size)
    cutoff = None if short_cutoff is None else length_in("short_cutoff", short_cutoff,
                                                         height_unit)

    heights, size, unit, source = load_map(path, reader, channel)
    if size is not None and user_size is not None:
        raise ValueError(f"{path} states its physical size; leave physical_size out")
    # everything the file lacks is said at once
    missing = [(what, name, example) for what, name, example, absent in (
        ("its height unit", "file_unit", "'nm'", unit is None and file_unit is None),
        ("its physical size", "physical_size", "'10 um'", size is None and user_size is None))
        if absent]
    if missing:
        raise ValueError(f"{path} does not state {' or '.join(m[0] for m in missing)}: pass "
                         + " and ".join(f"{name}, e.g. {example}" for _, name, example in missing))
    unit = file_unit if unit is None else unit
    file_factor = unit_factor(f"the height unit in {path}", unit)
    width, height = ((v * (LENGTH_UNITS[u] / out_factor if u else 1.0) for v, u in user_size)
                     if size is None else
                     (v * unit_factor(f"the size unit in {path}", u or unit) / out_factor
                      for v, u in size))
    rows, columns = heights.shape
    spacing, spacing_y = width / columns, height / rows
    square_pixels = math.isclose(spacing, spacing_y, rel_tol=1e-6)
    if min(rows, columns) < (MIN_SIDE if square_pixels or resample is None else 4):
        _too_small(path, heights.shape)     # (a cubic spline resamples 4 points or more)
    if not square_pixels:
        if resample is None:
            raise ValueError(f"{path}: pixels are not square (dx = {spacing:g}, dy = "
                             f"{spacing_y:g} {height_unit}); pass resample='finer' or "
                             "'coarser' to resample the map onto square pixels")
        filled = int(np.count_nonzero(~np.isfinite(heights)))
        heights, spacing = resample_square(_clean(heights, None, fill, path), spacing,
                                           spacing_y, resample)
    heights = _crop(heights) if square == "crop" else heights
    if min(heights.shape) < MIN_SIDE:
        _too_small(path, heights.shape)
    if square_pixels:
        filled = int(np.count_nonzero(~np.isfinite(heights)))
    heights = _clean(heights, detrend, fill, path)
    heights *= file_factor / out_factor
    if cutoff is not None:
        heights = short_wavelength_cutoff(heights, spacing,
                                          check_cutoff("short_cutoff", cutoff, spacing,
                                                       heights.shape, height_unit))
    return Topography(heights=frozen_array(heights), spacing=spacing,
                      physical_size=(heights.shape[1] * spacing, heights.shape[0] * spacing),
                      unit=height_unit, source=f"{path} ({source})", filled=filled)


def _too_small(path: pathlib.Path, shape: tuple[int, int]) -> None:
    raise ValueError(f"{path}: a map of {shape[0]} x {shape[1]} points; the contact models need "
                     f"at least {MIN_SIDE} x {MIN_SIDE}")


def _crop(heights: np.ndarray) -> np.ndarray:
    """The largest centred square of a map."""
    rows, columns = heights.shape
    side = min(rows, columns)
    top, left = (rows - side) // 2, (columns - side) // 2
    return heights[top:top + side, left:left + side]


def _clean(heights: np.ndarray, detrend: str | None, fill: str | None, path) -> np.ndarray:
    """Detrended over the valid points, missing points filled as asked (a new array)."""
    valid = np.isfinite(heights)
    if not valid.any():
        raise ValueError(f"{path}: no valid height in the map")
    if not valid.all() and fill is None:
        raise ValueError(f"{path}: {np.count_nonzero(~valid)} of {valid.size} points are "
                         "missing (NaN or masked): pass fill='mean' or fill='interpolate'")
    heights = _detrend(heights, valid, detrend)
    return heights.copy() if valid.all() else _fill(heights, valid, fill)


def write_gwyddion_ascii(path: str | pathlib.Path, heights: np.ndarray, spacing: float, *,
                         unit: str = "m", size_unit: str | None = None, channel: str = "Height"
                         ) -> pathlib.Path:
    """Write heights[j, i] [unit] as a Gwyddion ASCII matrix with its informational header.

    The header states ``Width`` and ``Height`` (columns and rows times ``spacing`` [unit]) in
    ``size_unit`` (default ``unit``; Gwyddion itself writes values in m and sizes in µm) and
    the ``Value units``, so :func:`read_topography` needs no extra argument.
    """
    heights = np.asarray(heights, dtype=float)
    if heights.ndim != 2:
        raise ValueError(f"heights must be a 2-D array, got shape {heights.shape}")
    spacing = positive("spacing", spacing)
    size_unit = unit if size_unit is None else size_unit
    scale = unit_factor("unit", unit) / unit_factor("size_unit", size_unit)
    rows, columns = heights.shape
    header = (f"Channel: {channel}\nWidth: {columns * spacing * scale:.6g} {size_unit}\n"
              f"Height: {rows * spacing * scale:.6g} {size_unit}\nValue units: {unit}")
    path = pathlib.Path(path)
    np.savetxt(path, heights, fmt="%.6e", delimiter="\t", header=header, comments="# ",
               encoding="utf-8")
    return path

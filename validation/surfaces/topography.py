"""Measured height maps from instrument files, as heights z[j, i] and a grid spacing.

Built in (no extra dependency): ``.npy`` arrays and plain-text matrices (``.txt``, ``.csv``,
``.asc``, ``.dat``, ``.tsv``: whitespace- or comma-separated, or whitespace-separated with
decimal commas; ``#`` comment lines), including
Gwyddion's "ASCII data matrix" export with its informational header::

    # Channel: Height
    # Width: 10.000 µm
    # Height: 10.000 µm
    # Value units: m

With the optional extra ``pip install "asperity-validation[topography]"`` every other format
that SurfaceTopography (ContactEngineering) reads (AFM ``.di``, ``.ibw``, ``.x3p``, ``.opd``,
``.plu``, ``.sur``, ``.gwy``, netCDF, ...) is read through its reader.
"""

from __future__ import annotations

import math
import pathlib
import re
import warnings
from dataclasses import dataclass

import numpy as np

from bem import checks
from bem.checks import choice, file_path, frozen_array, optional_integer, positive
from validation.surfaces.resample import RESAMPLE, resample_square

__all__ = ["LENGTH_UNITS", "Topography", "read_topography", "write_gwyddion_ascii"]

#: Metres per unit, for every spelling accepted in files and arguments.
LENGTH_UNITS: dict[str, float] = {
    "m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "micron": 1e-6,
    "nm": 1e-9, "A": 1e-10, "\u00c5": 1e-10, "\u212b": 1e-10, "angstrom": 1e-10, "pm": 1e-12,
}
TEXT_SUFFIXES = (".txt", ".csv", ".asc", ".dat", ".tsv")
_HEADER = re.compile(r"^#\s*([^:]+?)\s*:\s*(.*?)\s*$")


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


def _unit_factor(name: str, unit: str) -> float:
    if not isinstance(unit, str) or unit.strip() not in LENGTH_UNITS:
        raise ValueError(f"{name} must be a length unit, one of {sorted(set(LENGTH_UNITS))}, "
                         f"got {unit!r}")
    return LENGTH_UNITS[unit.strip()]


def _length(name: str, value: float | str) -> tuple[float, str | None]:
    """A length as (number, unit or None): ``2.5`` or ``"10 µm"``."""
    if isinstance(value, str):
        match = re.fullmatch(r"\s*([-+0-9.,eE]+)\s*(\S+)\s*", value.replace(",", "."))
        if match is None:
            raise ValueError(f"{name} must be a number or 'number unit' like '10 um', got {value!r}")
        unit = match.group(2)
        _unit_factor(f"the unit of {name}", unit)
        try:
            number = float(match.group(1))
        except ValueError:
            raise ValueError(f"{name} must be a number or 'number unit' like '10 um', "
                             f"got {value!r}") from None
        return positive(name, number), unit
    return positive(name, value), None


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _read_text(path: pathlib.Path) -> tuple[np.ndarray, tuple | None, str | None, str]:
    """Plain-text matrix; header keys Width/Height/Value units (Gwyddion ASCII) are honoured."""
    header: dict[str, str] = {}
    first_data = ""
    with path.open(encoding="utf-8", errors="replace") as stream:
        for line in stream:
            match = _HEADER.match(line)
            if match:
                header[match.group(1).lower()] = match.group(2)
            elif line.strip() and not line.lstrip().startswith("#"):
                first_data = line
                break
    delimiter, decimal_comma = None, False
    if "," in first_data:                   # "1.5, 2.5" separates; "1,5\t2,5" is a decimal comma
        delimiter = "," if all(_is_number(field) for field in first_data.split(",")) else None
        decimal_comma = delimiter is None
    try:
        with path.open(encoding="utf-8", errors="replace") as stream:
            lines = (line.replace(",", ".") for line in stream) if decimal_comma else stream
            heights = np.loadtxt(lines, comments="#", delimiter=delimiter, ndmin=2)
    except ValueError as error:
        raise ValueError(f"{path}: not a numeric matrix ({error})") from None
    unit = header.get("value units")
    size = None
    if "width" in header or "height" in header:
        if not ("width" in header and "height" in header):
            raise ValueError(f"{path}: the header gives only one of Width and Height")
        size = (_length("Width", header["width"]), _length("Height", header["height"]))
    reader = "Gwyddion ASCII" if {"width", "height", "value units"} <= set(header) else "text"
    return heights, size, unit, reader


def _read_surfacetopography(path: pathlib.Path, channel: int | None
                            ) -> tuple[np.ndarray, tuple | None, str | None, str]:
    """Heights[j, i] through SurfaceTopography's reader (its arrays are [x, y]: transposed).

    Size and unit that the file does not state come back as None; read_topography applies
    the caller's.
    """
    try:
        from SurfaceTopography import open_topography
    except ImportError:
        raise ImportError(f"reading {path.suffix or path.name!r} files needs the optional extra: "
                          "pip install 'asperity-validation[topography]' (SurfaceTopography)"
                          ) from None
    try:
        reader = open_topography(str(path))
    except Exception as error:  # noqa: BLE001 -- the readers' exception types vary by format
        raise ValueError(f"{path}: SurfaceTopography cannot read it ({error})") from None
    try:
        if channel is not None and not 0 <= channel < len(reader.channels):
            raise ValueError(f"channel must index one of the {len(reader.channels)} channels "
                             f"of {path}, got {channel!r}")
        info = reader.default_channel if channel is None else reader.channels[channel]
        if len(info.nb_grid_pts) != 2:
            raise ValueError(f"{path}: a line scan ({info.nb_grid_pts} points), not a height map")
        arguments: dict = {"channel_index": info.index}
        if info.physical_sizes is None:
            arguments["physical_sizes"] = (1.0, 1.0)    # placeholder, replaced by the caller's
        if info.unit is None:
            arguments["unit"] = "m"                     # placeholder, replaced by file_unit
        try:
            topography = reader.topography(**arguments)
        except Exception as error:  # noqa: BLE001
            raise ValueError(f"{path}: SurfaceTopography cannot read it ({error})") from None
        if topography.dim != 2 or not topography.is_uniform:
            raise ValueError(f"{path}: not a uniform 2-D height map (line scan or scattered "
                             "points)")
        heights = np.array(np.ma.filled(np.ma.asarray(topography.heights(), dtype=float),
                                        np.nan).T)      # a copy: the file may be memory-mapped
        (width, height), unit = topography.physical_sizes, topography.unit
        del topography                                  # release the mapping before closing
    finally:
        with warnings.catch_warnings():  # scipy's netCDF warns that the reader keeps a mapping
            warnings.filterwarnings("ignore", "Cannot close a netcdf_file", RuntimeWarning)
            reader.close()
    size = None if info.physical_sizes is None else ((float(width), None), (float(height), None))
    unit = None if info.unit is None else unit
    return heights, size, unit, f"SurfaceTopography, channel {info.name!r}"


def _physical_size(value) -> tuple[tuple[float, str | None], tuple[float, str | None]]:
    if isinstance(value, (tuple, list)):
        if len(value) != 2:
            raise ValueError(f"physical_size must be a length or (width, height), got {value!r}")
        return _length("physical_size", value[0]), _length("physical_size", value[1])
    side = _length("physical_size", value)
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
    if fill == "mean":
        return np.where(valid, heights, heights[valid].mean())
    from scipy.interpolate import griddata

    points = np.argwhere(valid)
    missing = np.argwhere(~valid)
    values = griddata(points, heights[valid], missing, method="linear")
    outside = ~np.isfinite(values)
    if outside.any():
        values[outside] = griddata(points, heights[valid], missing[outside], method="nearest")
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
) -> Topography:
    """Read a measured height map into heights [height_unit] and a grid spacing.

    Parameters
    ----------
    path : str or path-like
        The file. ``.npy`` and plain-text matrices are read built in (row = y, column = x);
        any other suffix through SurfaceTopography (optional extra ``[topography]``).
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
        Force the built-in reader or SurfaceTopography's.
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

    Returns
    -------
    Topography
        Frozen dataclass (heights, spacing, physical_size, unit, source).

    Raises
    ------
    ValueError
        Line scans, missing data without ``fill``, missing size or unit, pixels that are not
        square (without ``resample``), unknown units or options, unreadable files.
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
    out_factor = _unit_factor("height_unit", height_unit)
    if file_unit is not None:
        _unit_factor("file_unit", file_unit)
    user_size = None if physical_size is None else _physical_size(physical_size)

    heights, size, unit, source = _load(path, reader, channel)
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
    file_factor = _unit_factor(f"the height unit in {path}", unit)
    width, height = ((v * (LENGTH_UNITS[u] / out_factor if u else 1.0) for v, u in user_size)
                     if size is None else
                     (v * _unit_factor(f"the size unit in {path}", u or unit) / out_factor
                      for v, u in size))
    rows, columns = heights.shape
    spacing, spacing_y = width / columns, height / rows
    if not math.isclose(spacing, spacing_y, rel_tol=1e-6):
        if resample is None:
            raise ValueError(f"{path}: pixels are not square (dx = {spacing:g}, dy = "
                             f"{spacing_y:g} {height_unit}); pass resample='finer' or "
                             "'coarser' to resample the map onto square pixels")
        heights, spacing = resample_square(_clean(heights, None, fill, path), spacing,
                                           spacing_y, resample)
    heights = _clean(_crop(heights) if square == "crop" else heights, detrend, fill, path)
    heights *= file_factor / out_factor
    return Topography(heights=frozen_array(heights), spacing=spacing,
                      physical_size=(heights.shape[1] * spacing, heights.shape[0] * spacing),
                      unit=height_unit, source=f"{path} ({source})")


def _load(path: pathlib.Path, reader: str, channel: int | None
          ) -> tuple[np.ndarray, tuple | None, str | None, str]:
    """Heights[j, i] as stored, the size and unit the file states (or None), the reader."""
    suffix = path.suffix.lower()
    if reader == "builtin" or (reader == "auto" and suffix in (".npy",) + TEXT_SUFFIXES):
        if suffix == ".npy":
            try:
                heights, size, unit, source = np.load(path, allow_pickle=False), None, None, "npy"
            except ValueError as error:
                raise ValueError(f"{path}: not a numeric .npy array ({error})") from None
        else:
            heights, size, unit, source = _read_text(path)
    else:
        heights, size, unit, source = _read_surfacetopography(path, channel)
    heights = np.asarray(heights)
    if not (np.issubdtype(heights.dtype, np.integer) or np.issubdtype(heights.dtype, np.floating)):
        raise ValueError(f"{path}: heights must be real numbers, got dtype {heights.dtype}")
    if heights.ndim != 2 or min(heights.shape) < 2:
        raise ValueError(f"{path}: a line scan or single point (shape {heights.shape}), "
                         "not a height map")
    return heights.astype(float), size, unit, source


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
    scale = _unit_factor("unit", unit) / _unit_factor("size_unit", size_unit)
    rows, columns = heights.shape
    header = (f"Channel: {channel}\nWidth: {columns * spacing * scale:.6g} {size_unit}\n"
              f"Height: {rows * spacing * scale:.6g} {size_unit}\nValue units: {unit}")
    path = pathlib.Path(path)
    np.savetxt(path, heights, fmt="%.6e", delimiter="\t", header=header, comments="# ",
               encoding="utf-8")
    return path

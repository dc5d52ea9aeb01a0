"""Reading a height-map file: the built-in readers and SurfaceTopography's, tried in turn.

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
``.plu``, ``.sur``, ``.gwy``, MetroPro ``.dat``, netCDF, ...) is read through its reader.

:func:`load_map` tries the built-in reader first for the built-in suffixes and SurfaceTopography
first for any other, then the other one: a Zygo MetroPro ``.dat`` is not a text matrix and is
read by SurfaceTopography; a ``.hgt`` text matrix that SurfaceTopography does not take is read
as text. When both fail, the error names both attempts.
"""

from __future__ import annotations

import contextlib
import logging
import pathlib
import re
import warnings
from typing import Iterator

import numpy as np

from validation.surfaces.units import parse_length

__all__ = ["TEXT_SUFFIXES", "BUILTIN_SUFFIXES", "load_map"]

TEXT_SUFFIXES = (".txt", ".csv", ".asc", ".dat", ".tsv")
#: Suffixes the built-in reader is tried on first.
BUILTIN_SUFFIXES = (".npy",) + TEXT_SUFFIXES
_HEADER = re.compile(r"^#\s*([^:]+?)\s*:\s*(.*?)\s*$")
#: Longest part of a reader's own message quoted in ours.
_QUOTE = 240

#: A map as the file holds it: heights[j, i], ((width, unit), (height, unit)) or None, the
#: height unit or None, and the reader that read it.
Loaded = tuple[np.ndarray, tuple | None, str | None, str]


class _Unreadable(ValueError):
    """This reader cannot parse the file (another one may: ``elsewhere``; False for a text
    file that is not a matrix of numbers, which SurfaceTopography does not make a map of
    either, so that its absence is not the user's problem)."""

    def __init__(self, message: str, *, elsewhere: bool = True) -> None:
        super().__init__(message)
        self.elsewhere = elsewhere


def _quote(error: BaseException) -> str:
    """A reader's message, its first line only, printable and at most :data:`_QUOTE` long."""
    text = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
    text = "".join(c if c.isprintable() else "?" for c in text)
    return text if len(text) <= _QUOTE else text[:_QUOTE] + "..."


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _read_npy(path: pathlib.Path) -> Loaded:
    try:
        heights = np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError) as error:
        raise _Unreadable(f"not a numeric .npy array ({_quote(error)})") from None
    if not isinstance(heights, np.ndarray):
        raise _Unreadable("an .npz archive, not a .npy array")
    return heights, None, None, "npy"


def _read_text(path: pathlib.Path) -> Loaded:
    """Plain-text matrix; header keys Width/Height/Value units (Gwyddion ASCII) are honoured.
    Three columns are taken for a list of points (x, y, z) and left to SurfaceTopography,
    which reads those; two for a profile (x, z), refused: a height matrix so narrow is of no
    use anyway."""
    with path.open("rb") as stream:
        if b"\0" in stream.read(4096):
            raise _Unreadable("a binary file, not a text matrix")
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
    if not first_data:
        raise _Unreadable("no numbers in it (an empty file)", elsewhere=False)
    fields = [f for f in re.split(r"[\s;]+|,(?=\s*[-+.\d])|,\s*$", first_data.strip()) if f]
    if fields and not any(_is_number(f) or _is_number(f.replace(",", ".")) for f in fields):
        raise _Unreadable(f"its first line is not numbers ({first_data.strip()[:40]!r}...): a "
                          f"header row? Remove it, or start it with '#'", elsewhere=False)
    delimiter, decimal_comma = None, False
    if "," in first_data:                   # "1.5, 2.5" separates; "1,5\t2,5" is a decimal comma
        delimiter = "," if all(_is_number(field) for field in first_data.split(",")) else None
        decimal_comma = delimiter is None
    try:
        with path.open(encoding="utf-8", errors="replace") as stream:
            lines = (line.replace(",", ".") for line in stream) if decimal_comma else stream
            heights = np.loadtxt(lines, comments="#", delimiter=delimiter, ndmin=2)
    except ValueError as error:
        raise _Unreadable(f"not a numeric matrix ({_quote(error)})", elsewhere=False) from None
    if heights.shape[1] == 2:
        raise ValueError(f"{path}: two numbers per row, a profile (a line scan: positions and "
                         f"heights) or a map two points wide: not a height map; a map needs at "
                         f"least 32 x 32 points")
    if heights.shape[1] == 3:
        raise _Unreadable(f"3 columns of {heights.shape[0]} numbers: a list of points (x, y, "
                          "z), not a height matrix")
    unit = header.get("value units")
    size = None
    if "width" in header or "height" in header:
        if not ("width" in header and "height" in header):
            raise ValueError(f"{path}: the header gives only one of Width and Height")
        size = (parse_length("Width", header["width"]), parse_length("Height", header["height"]))
    reader = "Gwyddion ASCII" if {"width", "height", "value units"} <= set(header) else "text"
    return heights, size, unit, reader


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """While SurfaceTopography tries its readers: the Igor reader's library logs the whole data
    block of a file it fails on (megabytes of bytes on stderr); its logger is silenced."""
    logger = logging.getLogger("igor2")
    level = logger.level
    logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        logger.setLevel(level)


def _open_surfacetopography(path: pathlib.Path):
    """SurfaceTopography's reader of the file; for a file no reader recognises, the error of
    the readers its suffix names (a truncated ``.di``: "File is not large enough to contain all
    data buffers"), else that none does."""
    try:
        from SurfaceTopography import open_topography
    except ImportError:
        raise ImportError(f"reading {path.suffix or path.name!r} files needs the optional extra: "
                          "pip install 'asperity-validation[topography]' (SurfaceTopography)"
                          ) from None
    from SurfaceTopography.IO import readers

    with _quiet():
        try:
            return open_topography(str(path))
        except Exception as error:  # noqa: BLE001 -- the readers' exception types vary by format
            if type(error).__name__ != "CannotDetectFileFormat":
                raise _Unreadable(_quote(error)) from None
        suffix = path.suffix.lower().lstrip(".")
        formats = [r.format() for r in readers if suffix and (suffix == r.format() or suffix in
                   getattr(r, "file_extensions", lambda: ())())]
        reasons = []
        for name in formats:
            try:
                return open_topography(str(path), format=name)
            except Exception as error:  # noqa: BLE001
                reasons.append(f"as {name}: {_quote(error)}")
    raise _Unreadable("none of its formats recognises it"
                      + (f" ({'; '.join(reasons)})" if reasons else ""))


def _read_surfacetopography(path: pathlib.Path, channel: int | None) -> Loaded:
    """Heights[j, i] through SurfaceTopography's reader (its arrays are [x, y]: transposed).

    Size and unit that the file does not state come back as None; read_topography applies
    the caller's.
    """
    reader = _open_surfacetopography(path)
    try:
        if not reader.channels:                         # a header cut before its first channel
            raise _Unreadable(f"its {reader.format()} reader finds no channel in it")
        if channel is not None and not 0 <= channel < len(reader.channels):
            raise ValueError(f"channel must index one of the {len(reader.channels)} channels "
                             f"of {path}, got {channel!r}")
        info = reader.default_channel if channel is None else reader.channels[channel]
        if len(info.nb_grid_pts) != 2:
            raise ValueError(f"{path}: read as a line scan ({info.nb_grid_pts[0]} points), not a "
                             f"height map; a map needs at least 32 x 32 points (a text file of "
                             f"two numbers per row reads as a profile: positions and heights)")
        arguments: dict = {"channel_index": info.index}
        if info.physical_sizes is None:
            arguments["physical_sizes"] = (1.0, 1.0)    # placeholder, replaced by the caller's
        if info.unit is None:
            arguments["unit"] = "m"                     # placeholder, replaced by file_unit
        try:
            topography = reader.topography(**arguments)
            heights = np.array(np.ma.filled(np.ma.asarray(topography.heights(), dtype=float),
                                            np.nan).T)  # a copy: the file may be memory-mapped
        except Exception as error:  # noqa: BLE001
            raise _Unreadable(f"its {reader.format()} reader recognises it but cannot read its "
                              f"data ({_quote(error)})") from None
        if topography.dim != 2 or not topography.is_uniform:
            raise ValueError(f"{path}: not a uniform 2-D height map (line scan or scattered "
                             "points)")
        (width, height), unit = topography.physical_sizes, topography.unit
        del topography                                  # release the mapping before closing
    finally:
        with warnings.catch_warnings():  # scipy's netCDF warns that the reader keeps a mapping
            warnings.filterwarnings("ignore", "Cannot close a netcdf_file", RuntimeWarning)
            reader.close()
    size = None if info.physical_sizes is None else ((float(width), None), (float(height), None))
    unit = None if info.unit is None else unit
    return heights, size, unit, f"SurfaceTopography, {reader.format()}, channel {info.name!r}"


def _builtin(path: pathlib.Path, channel: int | None) -> Loaded:
    return _read_npy(path) if path.suffix.lower() == ".npy" else _read_text(path)


_ATTEMPTS = {"builtin": ("as text", _builtin),
             "surfacetopography": ("with SurfaceTopography", _read_surfacetopography)}


def load_map(path: pathlib.Path, reader: str = "auto", channel: int | None = None) -> Loaded:
    """Heights[j, i] as the file stores them, the size and unit it states (or None), and the
    reader that read it.

    ``reader="auto"`` tries the built-in reader first for :data:`BUILTIN_SUFFIXES` and
    SurfaceTopography first otherwise, then the other; ``"builtin"`` or ``"surfacetopography"``
    only that one.

    Raises
    ------
    ValueError
        When no reader reads it (naming each attempt and why it failed), or what was read is a
        line scan, a single point, or not real numbers.
    ImportError
        When the built-in reader fails and SurfaceTopography, the optional extra, is missing.
    """
    if reader == "auto":
        order = (("builtin", "surfacetopography") if path.suffix.lower() in BUILTIN_SUFFIXES
                 else ("surfacetopography", "builtin"))
    else:
        order = (reader,)
    failures, missing, elsewhere = [], None, False
    for name in order:
        what, attempt = _ATTEMPTS[name]
        if name == "builtin" and path.suffix.lower() == ".npy":
            what = "as a .npy array"
        try:
            heights, size, unit, source = attempt(path, channel)
            break
        except _Unreadable as error:
            failures.append(f"{what}: {error}")
            elsewhere = elsewhere or error.elsewhere
        except ImportError as error:
            missing = error
    else:
        if missing is not None and not elsewhere and path.suffix.lower() in BUILTIN_SUFFIXES:
            # a text file that is no matrix of numbers: the extra would not read it either
            raise ValueError(f"{path}: cannot read it as a height map ({'; '.join(failures)})")
        if missing is not None:   # the extra first: what the user has to do
            tried = (f" (the built-in reader, tried too: {'; '.join(failures)})" if failures
                     else "")
            raise ImportError(f"{path}: {missing}{tried}") from None
        raise ValueError(f"{path}: cannot read it as a height map ({'; '.join(failures)})")
    heights = np.asarray(heights)
    if not (np.issubdtype(heights.dtype, np.integer) or np.issubdtype(heights.dtype, np.floating)):
        raise ValueError(f"{path}: heights must be real numbers, got dtype {heights.dtype}")
    if heights.size == 0:
        raise ValueError(f"{path}: no heights in it (an empty file)")
    if heights.ndim != 2 or min(heights.shape) < 2:
        raise ValueError(f"{path}: a line scan or single point (shape {heights.shape}), "
                         "not a height map")
    return heights.astype(float), size, unit, source

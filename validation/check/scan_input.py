"""The scan a check is given, as the file its scene reads: a height file as it is, a
:class:`validation.Topography` or a height array written to ``.npy`` under a name from its
content (the same array is the same file, so the cache knows it), with its size as the scene
writes it (one length for a square map, [width, height] for a rectangular one).

A height array is checked here, where its user still knows it as an array: complex, non-numeric,
too small or infinite heights, and missing points without ``fill``, are refused saying what they
are, never naming the copy in the cache.
"""

from __future__ import annotations

import hashlib
import math
import os
import pathlib
import re
import tempfile

import numpy as np

from validation.check.units import parse_length, unitless
from validation.surfaces.topography import MIN_SIDE, Topography
from validation.surfaces.units import LENGTH_UNITS

__all__ = ["SCRATCH_NAME", "scan_source", "size_text"]

#: The name of a height array's copy in the cache (messages name the array instead).
SCRATCH_NAME = re.compile(r"[^\s'\"]*scan-[0-9a-f]{20}\.npy")


def _scratch_scan(heights: np.ndarray, cache_dir: str | None) -> pathlib.Path:
    """A height array [m] kept as ``.npy`` under a name from its content (the same array is
    the same file, so the cache knows it)."""
    heights = np.ascontiguousarray(heights, dtype=float)
    digest = hashlib.sha256(heights.tobytes() + str(heights.shape).encode()).hexdigest()[:20]
    folder = pathlib.Path(cache_dir) / "scans" if cache_dir else \
        pathlib.Path(tempfile.gettempdir()) / "asperity-validation-scans"
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"scan-{digest}.npy"
    if not path.exists():
        np.save(path, heights)
    return path


def size_text(width: float, height: float) -> str | tuple[str, str]:
    """A size [m] as the scene writes it: one length for a square map, else [width, height]."""
    if math.isclose(width, height, rel_tol=1e-12):
        return f"{width!r} m"
    return (f"{width!r} m", f"{height!r} m")


def _spacing(spacing) -> float:
    """A height array's pixel size [m]: a number in metres or a string with its unit."""
    if spacing is None:
        raise ValueError("a height array needs its spacing: spacing=1e-9 (metres) or "
                         "spacing='1nm'")
    pixel, has_unit = parse_length("spacing", spacing)
    if isinstance(spacing, str) and not has_unit:
        raise unitless("spacing", spacing)
    if not pixel > 0:
        raise ValueError(f"spacing must be a positive length, got {spacing!r}")
    return pixel


def _array_heights(scan: np.ndarray, fill) -> np.ndarray:
    """A height array as a real 2-D float map, refused with what it is (never a file's name):
    complex, not numbers, not 2-D, too small, infinite, or missing points without ``fill``."""
    heights = np.asarray(scan)
    described = f"shape {heights.shape} of {heights.dtype}"
    if np.iscomplexobj(heights):
        raise ValueError(f"scan as an array must hold real heights, got complex numbers "
                         f"({described}): pass its real part (or its modulus) if that is the "
                         f"height")
    if heights.ndim != 2 or not np.issubdtype(heights.dtype, np.number):
        raise ValueError(f"scan as an array must be a 2-D map of heights, got {described}")
    if min(heights.shape) < MIN_SIDE:
        raise ValueError(f"scan as an array is a map of {heights.shape[0]} x {heights.shape[1]} "
                         f"points; the contact models need at least {MIN_SIDE} x {MIN_SIDE}")
    heights = heights.astype(float)
    infinite = np.isinf(heights)
    if infinite.any():
        raise ValueError(f"scan as an array holds {int(infinite.sum())} infinite height(s) "
                         f"(of {heights.size}): heights must be finite (NaN marks a missing "
                         f"point)")
    missing = int(np.isnan(heights).sum())
    if missing == heights.size:
        raise ValueError(f"scan as an array has no valid height: all {heights.size} are NaN")
    if missing and fill is None:
        raise ValueError(f"scan as an array has {missing} of {heights.size} points missing "
                         f"(NaN): pass fill='mean' or fill='interpolate'")
    return heights


def scan_source(scan, spacing, file_unit, physical_size, fill, cache_dir):
    """(path, physical_size, file_unit, scratch) of a path, a Topography or a height array;
    a size is one length (square) or (width, height)."""
    if isinstance(scan, (str, os.PathLike)):
        if spacing is not None:
            raise ValueError("spacing is for a height array; a file states its size (or give "
                             "physical_size)")
        return pathlib.Path(scan), physical_size, file_unit, False
    if isinstance(scan, Topography):
        metres = LENGTH_UNITS[scan.unit]
        size = size_text(*(side * metres for side in scan.physical_size))
        return _scratch_scan(scan.heights * metres, cache_dir), size, "m", True
    if isinstance(scan, np.ndarray):
        if physical_size is not None:
            raise ValueError("physical_size is for a file that does not state its size; a "
                             "height array's size is its spacing times its shape")
        heights = _array_heights(scan, fill)
        pixel = _spacing(spacing)
        if file_unit and file_unit not in LENGTH_UNITS:
            raise ValueError(f"file_unit must be one of {', '.join(LENGTH_UNITS)}, got "
                             f"{file_unit!r}")
        scale = LENGTH_UNITS[file_unit] if file_unit else 1.0
        rows, columns = heights.shape
        return (_scratch_scan(heights * scale, cache_dir), size_text(pixel * columns, pixel * rows),
                "m", True)
    raise TypeError(f"scan must be a file path, a Topography or a 2-D height array, got "
                    f"{type(scan).__name__}")



"""Surface families of a scene: one height maker and one cache identity per family.

A scene's ``[surface] family`` says how realization ``k`` of it is made:

* ``"wm"``: a Weierstrass-Mandelbrot surface (:func:`validation.wm_surface`), seed ``k``
  (with ``periodic``: its wave vectors on the period's lattice, the map one period of it);
* ``"self-affine"``: a Gaussian self-affine surface (:func:`validation.self_affine_surface`),
  seed ``k``, cut as a non-periodic window from a periodic surface ``window`` times larger per
  side (the BEM solves non-periodic windows, as for a measured map);
* ``"file"``: tile ``k`` of a measured height map read once by
  :func:`validation.read_topography`; ``tiles = k^2`` cuts it into k x k non-overlapping
  tiles, row by row (square tiles of a cropped map, rectangular ones of a map kept whole),
  each of an even number of pixels along both sides (:func:`tile_side`).

Every maker returns heights on the task's ``n x n`` grid of side ``L`` (a measured map's tiles
may be rectangular: :attr:`validation.scenes.scene.SurfaceSpec.grid`). For WM and self-affine
surfaces ``slope_grid`` is the grid on which ``rms_slope`` fixes the amplitude, so that grids of
several sizes (a mesh-convergence study) sample the *same* continuous surface; the runner uses
the task's own grid (the BEM's per-point error estimate subsamples the same heights).
:func:`surface_identity` is what the cache keys hash for the surface: its parameters, or, for
a measured map, the SHA-256 of the file's bytes (never its path) and how it is read and tiled.
"""

from __future__ import annotations

import functools
import hashlib
import pathlib
from typing import Callable

import numpy as np

from validation.surfaces.self_affine import self_affine_surface
from validation.surfaces.statistics import surface_statistics
from validation.surfaces.wm import wm_surface
from validation.surfaces.topography import Topography, read_topography

__all__ = ["surface_heights", "surface_identity", "read_map", "tile", "tile_side", "file_digest"]


@functools.lru_cache(maxsize=16)
def _digest(path: str, modified: int, size: int) -> str:
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def file_digest(path: str) -> str:
    """SHA-256 of a file's bytes (read again whenever its modification time or size change)."""
    status = pathlib.Path(path).stat()
    return _digest(str(path), status.st_mtime_ns, status.st_size)


@functools.lru_cache(maxsize=8)
def _read(path: str, digest: str, physical_size, unit: str, detrend: str | None,
          file_unit: str | None, resample: str | None = None, square: str = "crop",
          options: tuple = (), short_cutoff: float | str | None = None) -> Topography:
    return read_topography(path, physical_size=physical_size, height_unit=unit, detrend=detrend,
                           file_unit=file_unit, resample=resample, square=square,
                           short_cutoff=short_cutoff, **dict(options))


def read_map(surface) -> Topography:
    """The measured map of a ``"file"`` surface as :func:`validation.read_topography` reads it
    (heights and spacing in ``surface.unit``, its short wavelengths cut when the scene asks,
    the scene's other reader keywords passed on), read once per process and per file
    content."""
    s = surface
    return _read(s.path, file_digest(s.path), s.physical_size, s.unit,
                 None if s.detrend == "none" else s.detrend, s.file_unit,
                 None if s.resample == "none" else s.resample, s.square, s.read_options,
                 s.short_cutoff)


def tile(heights: np.ndarray, tiles: int, index: int,
         shape: tuple[int, int] | None = None) -> np.ndarray:
    """Tile ``index`` (row by row) of the ``k x k`` non-overlapping tiles of a map,
    ``tiles = k^2``; each of ``shape`` = (rows, columns) pixels (default ``rows // k`` x
    ``columns // k``, the whole cell; a scene uses :func:`tile_side` along each axis) from the
    top-left corner of its cell, mean removed (the mean plane of the tile, as for every surface
    of a scene)."""
    per_side = round(tiles ** 0.5)
    cell = tuple(side // per_side for side in heights.shape)
    shape = cell if shape is None else tuple(shape)
    if len(shape) != 2 or not all(0 < s <= c for s, c in zip(shape, cell)):
        raise ValueError(f"shape must be (rows, columns) within the {cell[0]} x {cell[1]}-pixel "
                         f"cells of {tiles} tiles of a {heights.shape[0]} x {heights.shape[1]}"
                         f"-pixel map, got {shape!r}")
    row, column = divmod(index, per_side)
    top, left = row * cell[0], column * cell[1]
    part = np.array(heights[top:top + shape[0], left:left + shape[1]])
    return part - part.mean()


def tile_side(pixels: int, tiles: int) -> int:
    """Pixels of the tiles of a scene along one side of a map of ``pixels`` along it (applied to
    its rows and to its columns): ``pixels // k`` for ``tiles = k^2``, made even by dropping
    the last row (column) of an odd cell, so that the reference's error estimate (the same
    tile on every second pixel, :func:`bem.contact_curve`) covers the same window."""
    cell = pixels // round(tiles ** 0.5)
    return cell - cell % 2


def _wm(s, n: int, seed: int, slope_grid: int) -> np.ndarray:
    """The window of side L of the WM surface whose longest wavelength is ``wavelength``
    (default L): nested windows for the realizations of a size sweep."""
    return wm_surface(n, D=s.D[0], G=s.G, rms_slope=s.rms_slope,
                      L=s.L if s.wavelength is None else s.wavelength, side=s.L, gamma=s.gamma,
                      M=s.M, n_max=s.n_max, seed=seed,
                      slope_grid=slope_grid if s.rms_slope is not None else None,
                      periodic=s.periodic)


def _self_affine(s, n: int, seed: int, slope_grid: int) -> np.ndarray:
    """Generated on a grid twice as fine as ``slope_grid`` and band-limited to its Nyquist
    wavelength by default: the ``slope_grid`` sample is every other point, the fine one the
    whole grid, both of one continuous surface; the amplitude is fixed on ``slope_grid``."""
    fine = 2 * slope_grid
    spacing = s.L / slope_grid
    short_cutoff = s.short_cutoff if s.short_cutoff is not None else 2.0 * spacing
    heights = self_affine_surface(fine, hurst=s.hurst[0], rms_height=1.0, L=s.L,
                                  long_cutoff=s.long_cutoff, rolloff=s.rolloff,
                                  short_cutoff=short_cutoff,
                                  window=s.window * fine if s.window > 1 else None, seed=seed)
    if s.plateau is not None:   # a plateau-honed finish: the peaks cut flat
        heights = np.minimum(heights, np.quantile(heights, s.plateau))
    coarse = heights[::2, ::2]
    statistics = surface_statistics(coarse, spacing, periodic=s.window == 1)
    measured = statistics.rms_height if s.rms_slope is None else statistics.rms_gradient
    target = s.rms_height if s.rms_slope is None else s.rms_slope
    out = heights if n == fine else coarse
    return (out - out.mean()) * (target / measured)


def _file(s, n: int, seed: int, slope_grid: int) -> np.ndarray:
    scan = read_map(s)
    return tile(np.asarray(scan.heights), s.tiles, seed, shape=s.grid)


_MAKERS: dict[str, Callable] = {"wm": _wm, "self-affine": _self_affine, "file": _file}


def surface_heights(surface, seed: int, slope_grid: int | None = None) -> np.ndarray:
    """Heights [length] of realization ``seed`` (a tile index for a measured map) of a
    :class:`validation.scenes.scene.SurfaceSpec` with one sweep value, on its ``n x n`` grid."""
    return _MAKERS[surface.family](surface, surface.n, seed, slope_grid or surface.n)


def surface_identity(surface, seed: int, slope_grid: int | None = None) -> dict:
    """What determines the heights of a realization, for the cache keys."""
    s, grid = surface, slope_grid or surface.n
    if s.family == "wm":
        identity = dict(family=s.family, D=s.D[0], rms_slope=s.rms_slope, G=s.G,
                        gamma=s.gamma, M=s.M, n_max=s.n_max, L=s.L, n=s.n, seed=seed,
                        slope_grid=grid)
        if s.wavelength is not None and s.wavelength != s.L:  # absent: the paper's surface
            identity["wavelength"] = s.wavelength
        if s.periodic:  # absent: eq. (11) as the paper writes it
            identity["periodic"] = True
        return identity
    if s.family == "self-affine":
        identity = dict(family=s.family, hurst=s.hurst[0], rms_slope=s.rms_slope,
                        rms_height=s.rms_height, long_cutoff=s.long_cutoff, rolloff=s.rolloff,
                        short_cutoff=s.short_cutoff, window=s.window, L=s.L, n=s.n, seed=seed,
                        slope_grid=grid)
        if s.plateau is not None:  # absent for Gaussian surfaces: their cache keys stay
            identity["plateau"] = s.plateau
        return identity
    identity = dict(family=s.family, sha256=file_digest(s.path), physical_size=s.physical_size,
                    file_unit=s.file_unit, unit=s.unit, detrend=s.detrend, tiles=s.tiles,
                    tile=seed, n=s.n)
    # absent by default, so that the cache keys of cropped maps on square pixels stay
    identity.update({key: getattr(s, key) for key, default in (("resample", "none"),
                     ("square", "crop")) if getattr(s, key) != default})
    if s.read_options:
        identity["read_options"] = dict(s.read_options)
    if s.short_cutoff is not None:  # in the scene's unit: "20 nm" and 20 (unit nm) are one key
        identity["short_cutoff"] = s.short_cutoff_length
    if s.square == "keep":
        identity["shape"] = list(s.grid)
    return identity

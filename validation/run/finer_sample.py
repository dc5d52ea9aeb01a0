"""The finer sample of a scene's surface: the same window on ``factor`` times its grid, where a
finer boundary-element reference is solved (:mod:`validation.run.refine`, docs/theory.md,
"Finer reference where the band decides").

The finer sample exists exactly for generated surfaces:

* a WM surface is eq. (11) (its periodic form, eq. T52, with ``periodic``) evaluated at the
  ``2 n`` points (its amplitude fixed on the scene's grid, ``slope_grid = n``), so every
  second point is the scene's sample;
* a self-affine surface is band-limited to the scene grid's Nyquist wavelength: its ``2 n``
  sample is the generator's own fine grid, and finer ones are its trigonometric interpolation
  (the same spectrum and phases, zero above the cut-off);
* a measured map (a tile of it) has no finer sample: its ``factor n`` grid is the trigonometric
  interpolation of the map's even (mirror) extension (:func:`interpolated_scan`), band-limited to
  the scan's own Nyquist wavelength, so the finer solve measures the solver's discretisation
  error on the surface as sampled and adds no roughness the instrument did not record.

Each finer sample is shifted and scaled so that every ``factor``-th point reproduces the scene's
heights (checked), so the mean plane, and with it the separation, is the same.
"""

from __future__ import annotations

import numpy as np

from validation.surfaces.families import surface_heights
from validation.surfaces.self_affine import self_affine_surface
from validation.surfaces.wm import wm_surface

__all__ = ["interpolated_scan", "refined_heights"]


def _self_affine_periodic(s, seed: int) -> tuple[np.ndarray, int]:
    """The periodic surface the self-affine generator cuts its window from, on the grid of
    ``2 n`` points per window side (validation.surfaces.families), up to scale and offset."""
    fine = 2 * s.n
    spacing = s.L / s.n
    short_cutoff = s.short_cutoff if s.short_cutoff is not None else 2.0 * spacing
    field = self_affine_surface(s.window * fine, hurst=s.hurst[0], rms_height=1.0,
                                L=s.window * s.L, long_cutoff=s.long_cutoff or s.L,
                                rolloff=s.rolloff, short_cutoff=short_cutoff, seed=seed)
    return field, fine


def _interpolate(field: np.ndarray, factor: int) -> np.ndarray:
    """Trigonometric interpolation of a periodic field with no power at or above half its
    Nyquist wavevector onto a grid ``factor`` times finer (zero-padded spectrum)."""
    size = field.shape[0]
    half = size // 2
    spectrum = np.fft.rfft2(field)
    padded = np.zeros((factor * size, factor * size // 2 + 1), dtype=complex)
    padded[:half, :half + 1] = spectrum[:half, :half + 1]
    padded[-half:, :half + 1] = spectrum[-half:, :half + 1]
    return np.fft.irfft2(padded, s=(factor * size, factor * size)) * factor**2


def interpolated_scan(heights: np.ndarray, factor: int) -> np.ndarray:
    """A measured height map on a grid ``factor`` times finer along both axes, through every
    original sample (``out[::factor, ::factor] == heights``).

    The map's even extension (the map and its mirror images, period twice its size) is
    continuous across the scan's edges, so its trigonometric interpolation (zero-padded
    spectrum, the Nyquist term split evenly: :func:`scipy.signal.resample`) neither rings at
    the edges nor adds any wavelength shorter than two pixels of the scan.
    """
    from scipy import signal   # where used (start-up of a warm report)

    rows, columns = heights.shape
    extended = np.concatenate((heights, heights[::-1]), axis=0)
    extended = np.concatenate((extended, extended[:, ::-1]), axis=1)
    fine = signal.resample(extended, factor * 2 * rows, axis=0)
    fine = signal.resample(fine, factor * 2 * columns, axis=1)
    return fine[:factor * rows, :factor * columns]


def refined_heights(surface, seed: int, factor: int) -> np.ndarray:
    """Heights [length] of realization ``seed`` on ``factor * n`` points per side of the same
    window, with ``heights[::factor, ::factor]`` equal to the scene's sample.

    Parameters
    ----------
    surface : validation.scenes.scene.SurfaceSpec
        A WM or self-affine surface with one sweep value, or a measured map (one tile of it).
    seed : int
        Realization seed.
    factor : int
        Refinement factor, a power of two >= 2.

    Raises
    ------
    ValueError
        For a factor that is not a power of two >= 2.
    """
    if isinstance(factor, bool) or not isinstance(factor, int) or factor < 2 \
            or factor & (factor - 1):
        raise ValueError(f"factor must be a power of two >= 2, got {factor!r}")
    s, n = surface, surface.n
    base = surface_heights(s, seed)
    if s.family == "wm":
        # the window of side L of the surface whose longest wavelength is ``wavelength``
        fine = wm_surface(factor * n, D=s.D[0], G=s.G, rms_slope=s.rms_slope,
                          L=s.L if s.wavelength is None else s.wavelength, side=s.L,
                          gamma=s.gamma, M=s.M, n_max=s.n_max, seed=seed,
                          slope_grid=n if s.rms_slope is not None else None,
                          periodic=s.periodic)
    elif s.family == "self-affine":
        field, grid = _self_affine_periodic(s, seed)
        if factor > 2:
            field, grid = _interpolate(field, factor // 2), grid * (factor // 2)
        fine = field[:grid, :grid]
    elif s.family == "file":
        fine = interpolated_scan(base, factor)
    else:
        raise ValueError(f"a {s.family} surface cannot be refined (no finer sample exists)")
    sample = fine[::factor, ::factor]
    scale = float(np.std(base) / np.std(sample))
    fine = (fine - sample.mean()) * scale + base.mean()
    mismatch = float(np.max(np.abs(fine[::factor, ::factor] - base)))
    if not mismatch <= 1e-8 * float(np.std(base)):
        raise RuntimeError(f"the refined sample does not reproduce the scene grid (off by "
                           f"{mismatch:.3g}); the surface generator has changed")
    return fine

"""Descriptors of a rough surface read off its height map before any contact solve: what decides
which contact theory holds on it (docs/theory.md, "12.1 Descriptors").

Spectral moments and Nayak's bandwidth alpha by central finite differences (the moments every
model of this project uses, :func:`validation.surface_statistics`); the Hurst exponent from the
slope of the radially averaged power spectrum over its self-affine range, found by a hinge fit
(flat below the rolloff wavevector, a power law above it; the empty bins between the lines of a
line spectrum, a WM surface's, left out); the magnification, the rolloff
wavelength (or the longest resolved one, where the spectrum shows no rolloff) over the shortest
resolved wavelength (the short cutoff, where the spectrum falls to nothing, or the Nyquist
wavelength); and the shape of the height distribution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from asperity.spectral.spectrum import power_spectrum_2d
from bem.common import checks
from validation.surfaces.statistics import surface_statistics

__all__ = ["SurfaceDescriptors", "surface_descriptors"]

#: Logarithmic bins of the radially averaged spectrum.
SPECTRUM_BINS = 40
#: A known short cutoff's wavevector times this ends the fitted range (the bins just below a
#: sharp cutoff take power from beyond it through the window).
CUTOFF_MARGIN = 0.8
#: Bins whose power is below this share of the spectrum's largest carry none (rounding: a
#: spectrum falling as q^-3.8 spans 1e8 over a magnification of 128).
EMPTY_POWER = 1e-20
#: A bin with less than this share of the largest power at shorter wavelengths lies between the
#: lines of a line spectrum (a WM surface): it carries no power and no slope. A spectrum that
#: falls with q never has such a bin (a bin's mean over its modes is not a millionth of the
#: next bin's).
HOLE = 1e-6


@dataclass(frozen=True)
class SurfaceDescriptors:
    """What a height map says about the contact it will make (:func:`surface_descriptors`).

    Attributes
    ----------
    m0 : float
        Nayak's zeroth profile moment, the height variance [length^2].
    m2 : float
        Second profile moment, the mean squared profile slope [-].
    m4 : float
        Fourth profile moment, the mean squared profile curvature [1/length^2].
    nayak : float
        Nayak's bandwidth alpha = m0 m4 / m2^2 [-] (1.5 for a single wave and larger for
        broader spectra).
    rms_height : float
        Sq [length].
    rms_slope : float
        ``h'_rms = sqrt(<|grad h|^2>)`` [-].
    hurst : float
        Hurst exponent H from the power spectrum's slope, C(q) ~ q^-2(1+H) [-]; NaN where
        fewer than five bins of the spectrum carry power (a few waves have no slope).
    hurst_error : float
        Standard error of ``hurst`` from the fit [-].
    magnification : float
        Rolloff (or longest resolved) over shortest resolved wavelength [-].
    rolloff_wavelength : float
        Where the self-affine range starts: the rolloff wavelength, or the longest resolved
        one (the scan's side) where the spectrum shows no rolloff [length].
    short_wavelength : float
        Where it ends: the short cutoff, or the Nyquist wavelength 2 dx [length].
    skewness : float
        Of the heights [-] (0 for Gaussian heights; negative for a plateau-honed finish).
    kurtosis : float
        Of the heights, not in excess [-] (3 for Gaussian heights).
    peak : float
        Highest point above the mean plane in units of Sq [-].
    spacing : float
        Pixel size dx [length].
    shape : tuple of int
        (rows, columns) of the map.
    """

    m0: float
    m2: float
    m4: float
    nayak: float
    rms_height: float
    rms_slope: float
    hurst: float
    hurst_error: float
    magnification: float
    rolloff_wavelength: float
    short_wavelength: float
    skewness: float
    kurtosis: float
    peak: float
    spacing: float
    shape: tuple[int, int]


def _radial_spectrum(heights: np.ndarray, spacing: float, periodic: bool
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Radially averaged C(q) in logarithmic bins from 2 pi / (longer side) to Nyquist:
    (mean |q| [1/length], mean C [length^4], modes) of each non-empty bin."""
    q_x, q_y, psd = power_spectrum_2d(heights, spacing, window="none" if periodic else "hann")
    q = np.hypot(q_y, q_x).ravel()
    q_low = 2.0 * np.pi / (max(heights.shape) * spacing)
    edges = np.geomspace(q_low * (1 - 1e-9), np.pi / spacing * (1 + 1e-9), SPECTRUM_BINS + 1)
    index = np.digitize(q, edges) - 1
    inside = (index >= 0) & (index < SPECTRUM_BINS)
    count = np.bincount(index[inside], minlength=SPECTRUM_BINS)
    q_sum = np.bincount(index[inside], weights=q[inside], minlength=SPECTRUM_BINS)
    c_sum = np.bincount(index[inside], weights=psd.ravel()[inside], minlength=SPECTRUM_BINS)
    filled = count > 0
    return q_sum[filled] / count[filled], c_sum[filled] / count[filled], count[filled]


def _hinge_fit(log_q: np.ndarray, log_c: np.ndarray, weight: np.ndarray
               ) -> tuple[int, float, float]:
    """(first bin of the power law, its slope, the slope's standard error): log C flat up to a
    breakpoint and linear in log q after it, the breakpoint chosen among the bins by the least
    weighted squared residual."""
    best = (math.inf, 0, 0.0, math.inf)
    for start in range(0, len(log_q) - 3):
        ramp = np.maximum(log_q - log_q[start], 0.0)
        design = np.column_stack([np.ones_like(ramp), ramp]) * weight[:, None]
        coefficients, *_ = np.linalg.lstsq(design, log_c * weight, rcond=None)
        residual = float(np.sum((design @ coefficients - log_c * weight) ** 2))
        if residual < best[0]:
            best = (residual, start, float(coefficients[1]), residual)
    _, start, _, _ = best
    # the slope and its standard error from the power-law range alone
    x, y, w = log_q[start:], log_c[start:], weight[start:]
    design = np.column_stack([np.ones_like(x), x]) * w[:, None]
    coefficients, *_ = np.linalg.lstsq(design, y * w, rcond=None)
    dof = max(len(x) - 2, 1)
    variance = float(np.sum((design @ coefficients - y * w) ** 2)) / dof
    covariance = variance * np.linalg.inv(design.T @ design)
    return start, float(coefficients[1]), math.sqrt(float(covariance[1, 1]))


def surface_descriptors(heights, spacing: float, *, periodic: bool = False,
                        short_cutoff: float | None = None) -> SurfaceDescriptors:
    """The descriptors of a height map (:class:`SurfaceDescriptors`), in a few FFTs.

    Parameters
    ----------
    heights : array_like
        Height map [length], 2-D, at least 8 x 8, finite; its mean plane is not removed here
        (its mean is).
    spacing : float
        Pixel size dx [length], > 0.
    periodic : bool
        The map is one period of a periodic surface: derivatives wrap around and the spectrum
        takes no window; otherwise a Hann window keeps the edges' jump out of the spectrum.
    short_cutoff : float, optional
        A short-wavelength cutoff [length] the map was low-pass filtered at
        (:func:`validation.short_wavelength_cutoff`): the shortest resolved wavelength, and the
        end of the range the Hurst exponent is fitted over (the window's leakage beyond a sharp
        cutoff is no power law of the surface).

    Returns
    -------
    SurfaceDescriptors

    Raises
    ------
    ValueError, TypeError
        Naming ``heights`` or ``spacing`` (a flat map has no descriptors).
    """
    z = checks.height_map("heights", heights)
    if min(z.shape) < 8:
        raise ValueError(f"heights must be at least 8 x 8 points, got {z.shape[0]} x {z.shape[1]}")
    statistics = surface_statistics(z, spacing, periodic=periodic)
    spacing = float(spacing)
    z = z - z.mean()
    sq = statistics.rms_height
    q, c, modes = _radial_spectrum(z, spacing, periodic)
    shorter = np.append(np.maximum.accumulate(c[::-1])[::-1][1:], 0.0)
    kept = c >= HOLE * shorter       # the bins between a line spectrum's lines left out
    q, c, modes = q[kept], c[kept], modes[kept]
    # the spectrum's range: the bins whose power is something next to its largest
    powered = np.flatnonzero(c > EMPTY_POWER * c.max())
    first, end = int(powered[0]), int(powered[-1]) + 1
    if short_cutoff is not None:
        cutoff_q = 2.0 * np.pi / checks.positive("short_cutoff", short_cutoff)
        end = min(end, int(np.searchsorted(q, CUTOFF_MARGIN * cutoff_q)))
    if end - first >= 5:
        start, slope, slope_error = _hinge_fit(np.log(q[first:end]), np.log(c[first:end]),
                                               np.sqrt(modes[first:end].astype(float)))
        start += first
        hurst, hurst_error = -slope / 2.0 - 1.0, slope_error / 2.0
    else:   # a few waves (a sine): no spectral slope to read
        start, hurst, hurst_error = first, math.nan, math.nan
    longest = 2.0 * np.pi / (max(z.shape) * spacing)
    rolloff_q = longest if start == 0 else float(q[start])
    short_q = (math.pi / spacing if end == len(q) else float(q[end - 1])) \
        if short_cutoff is None else min(math.pi / spacing, cutoff_q)
    deviation = z / sq
    return SurfaceDescriptors(
        m0=statistics.m0, m2=statistics.m2, m4=statistics.m4, nayak=statistics.nayak,
        rms_height=sq, rms_slope=statistics.rms_gradient,
        hurst=hurst, hurst_error=hurst_error,
        magnification=short_q / rolloff_q, rolloff_wavelength=2.0 * np.pi / rolloff_q,
        short_wavelength=2.0 * np.pi / short_q,
        skewness=float(np.mean(deviation ** 3)), kurtosis=float(np.mean(deviation ** 4)),
        peak=float(deviation.max()), spacing=spacing, shape=tuple(int(s) for s in z.shape))

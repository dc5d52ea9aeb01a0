"""Self-affine Gaussian random surfaces by Fourier filtering, and their power spectrum.

Power-spectrum convention, for a surface of mean zero,

    C(q) = (2 pi)^-2 \\int <h(0) h(x)> exp(-i q.x) d^2x,      so that  h_rms^2 = \\int C(q) d^2q.

On a periodic L x L grid of n x n points (spacing h = L/n) with wavevectors q = 2 pi (k, l) / L
and ``H(q) = FFT(h)`` (numpy's unnormalised forward transform), the estimate is
``C(q) = |H(q)|^2 L^2 / (2 pi n^2)^2`` and Parseval reads
``mean(h^2) = sum_q C(q) (2 pi / L)^2``.

The generated spectrum is isotropic (Persson; Jacobs, Junge & Pastewka 2017)::

    C(q) = C0 (q_r)^-2(1+H)   for q_L <= q < q_r    (flat "rolloff" region)
    C(q) = C0 q^-2(1+H)       for q_r <= q <= q_s   (self-affine region)
    C(q) = 0                  otherwise (and at q = 0: zero mean)

with q = 2 pi / wavelength; the cut-offs are given as *wavelengths* in the unit of L.
"""

from __future__ import annotations

import math

import numpy as np

from asperity.spectral.spectrum import power_spectrum_2d
from bem.common import checks
from bem.common.checks import integer, positive, real_number
from validation.surfaces.statistics import surface_statistics

__all__ = [
    "power_spectrum",
    "radial_power_spectrum",
    "self_affine_spectrum",
    "self_affine_surface",
    "spectral_rms_slope",
]


def self_affine_spectrum(q: np.ndarray, *, hurst: float, long_cutoff: float, rolloff: float,
                         short_cutoff: float) -> np.ndarray:
    """Unnormalised isotropic spectrum C(q)/C0 of the module docstring [length^(2+2H)].

    ``q`` [1/length] is a wavevector magnitude (any shape); the cut-offs are wavelengths
    (``q_L = 2 pi / long_cutoff``, ``q_r = 2 pi / rolloff``, ``q_s = 2 pi / short_cutoff``).
    """
    q = np.asarray(q, dtype=float)
    q_long, q_roll, q_short = (2.0 * np.pi / w for w in (long_cutoff, rolloff, short_cutoff))
    exponent = -2.0 * (1.0 + hurst)
    safe = np.maximum(q, q_roll)
    spectrum = safe**exponent
    return np.where((q >= q_long * (1 - 1e-12)) & (q <= q_short * (1 + 1e-12)), spectrum, 0.0)


def power_spectrum(heights: np.ndarray, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """2-D power spectrum of a height map taken as one period of a periodic surface.

    Returns ``(q, C)``: wavevector magnitudes [1/length] and C(q) [length^4] on the FFT grid
    (shape of ``heights``), in the convention of the module docstring, so that
    ``sum(C) * (2 pi / L)^2 == mean((h - mean h)^2)`` (Parseval) for an ``n_y x n_x`` map
    with ``(2 pi / L)^2`` meaning ``(2 pi)^2 / (L_x L_y)``. No window function is applied:
    for a non-periodic map the edges leak power to high q. The periodogram of
    :func:`asperity.spectral.spectrum.power_spectrum_2d` (``window="none"``), with ``|q|`` on its grid.
    """
    q_x, q_y, spectrum = power_spectrum_2d(heights, spacing, window="none")
    return np.hypot(q_y, q_x), spectrum


def radial_power_spectrum(heights: np.ndarray, spacing: float, *, bins: int = 32
                          ) -> tuple[np.ndarray, np.ndarray]:
    """Radially averaged C(q) of :func:`power_spectrum` in logarithmic bins.

    Bins span ``2 pi / L`` (the lowest wavevector) to ``pi / spacing`` (Nyquist); empty bins
    are dropped. Returns ``(q, C)``: the mean ``|q|`` of the modes in each bin [1/length] and the
    mean C over those modes [length^4].
    """
    bins = integer("bins", bins, minimum=1)
    q, spectrum = power_spectrum(heights, spacing)
    q_low = 2.0 * np.pi / (max(q.shape) * spacing)     # q has the shape of the heights
    edges = np.geomspace(q_low * (1 - 1e-9), np.pi / spacing * (1 + 1e-9), bins + 1)
    index = np.digitize(q.ravel(), edges) - 1
    inside = (index >= 0) & (index < bins)
    count = np.bincount(index[inside], minlength=bins)
    q_sum = np.bincount(index[inside], weights=q.ravel()[inside], minlength=bins)
    c_sum = np.bincount(index[inside], weights=spectrum.ravel()[inside], minlength=bins)
    filled = count > 0
    return q_sum[filled] / count[filled], c_sum[filled] / count[filled]


def self_affine_surface(
    n: int,
    *,
    hurst: float,
    rms_height: float | None = None,
    rms_slope: float | None = None,
    long_cutoff: float | None = None,
    rolloff: float | None = None,
    short_cutoff: float | None = None,
    L: float = 1.0,
    window: int | None = None,
    seed: int | np.random.Generator | None = None,
) -> np.ndarray:
    """Gaussian random self-affine surface by Fourier filtering of white noise.

    Gaussian white noise (``numpy.random.default_rng(seed).standard_normal``) on the periodic
    grid is transformed, multiplied by ``sqrt(C(q))`` of :func:`self_affine_spectrum` and
    transformed back: every mode gets a uniformly random phase and a Rayleigh-distributed
    amplitude, the result is real by construction, and its expected power spectrum is
    ``C(q)`` of the module docstring. The amplitude C0 is then fixed so that the *returned*
    heights have exactly the requested rms height or rms slope.

    Parameters
    ----------
    n : int
        Grid points per side (>= 4). Heights sit at ``x_i = i L / n``, ``y_j = j L / n`` and
        the array is indexed ``heights[j, i]`` (row = y, column = x); spacing ``h = L / n``.
    hurst : float
        Hurst exponent H, 0 < H <= 1; C(q) ~ q^(-2(1+H)) in the self-affine region.
    rms_height, rms_slope : float
        Exactly one: the rms height [length] or the rms gradient ``sqrt(<|grad h|^2>)`` [-]
        of the returned heights, as measured by :func:`validation.surface_statistics`
        (central differences; wrap-around for the periodic surface, interior points for a
        window), the project's one definition of both. The spectral slope
        ``sqrt(\\int q^2 C d^2q)`` is larger when ``short_cutoff`` is near ``2 h``, because
        central differences attenuate a mode of wavevector q by ``sin(q h) / (q h)``.
    long_cutoff : float, optional
        Longest wavelength [length]: C = 0 for q < 2 pi / long_cutoff. Default ``L``; at most
        the period (``L``, or ``window * L / n`` with ``window``).
    rolloff : float, optional
        Rolloff wavelength [length], ``short_cutoff < rolloff <= long_cutoff``: C is flat for
        wavelengths between ``rolloff`` and ``long_cutoff``. Default ``long_cutoff`` (no
        flat region).
    short_cutoff : float, optional
        Shortest wavelength [length], at least the Nyquist wavelength ``2 h``. Default ``2 h``.
    L : float
        Side of the returned square [length], > 0.
    window : int, optional
        Non-periodic window: the surface is generated periodic on a ``window x window``
        grid (``window > n``) of the same spacing, period ``window * L / n``, and its
        ``n x n`` block ``[0:n, 0:n]`` is returned. The window's edges do not match, as on a
        measured map; the BEM of this project solves such non-periodic windows. Without it
        (default) the returned surface is exactly periodic with period L.
    seed : int or numpy.random.Generator, optional
        Seed of ``numpy.random.default_rng``; equal seeds and arguments give equal surfaces.

    Returns
    -------
    numpy.ndarray
        Heights [length], shape (n, n), mean zero over the returned array.

    Raises
    ------
    ValueError
        Naming the parameter, for values outside the ranges above, both or neither of
        ``rms_height``/``rms_slope``, or cut-offs in the wrong order.
    """
    n = integer("n", n, minimum=4)
    grid = n if window is None else integer("window", window, minimum=n + 1)
    hurst = real_number("hurst", hurst, minimum=0.0, exclusive=True)
    if hurst > 1.0:
        raise ValueError(f"hurst must lie in (0, 1], got {hurst!r}")
    L = checks.supported_magnitude("L", positive("L", L))
    spacing = L / n
    period = grid * spacing
    if (rms_height is None) == (rms_slope is None):
        raise ValueError("give exactly one of rms_height and rms_slope")
    target = positive("rms_height" if rms_slope is None else "rms_slope",
                      rms_slope if rms_height is None else rms_height)
    long_cutoff = L if long_cutoff is None else positive("long_cutoff", long_cutoff)
    rolloff = long_cutoff if rolloff is None else positive("rolloff", rolloff)
    short_cutoff = 2.0 * spacing if short_cutoff is None else positive("short_cutoff", short_cutoff)
    if long_cutoff > period * (1 + 1e-12):
        raise ValueError(f"long_cutoff must be <= the period {period:g}, got {long_cutoff!r}")
    if rolloff > long_cutoff * (1 + 1e-12):
        raise ValueError(f"rolloff must be <= long_cutoff = {long_cutoff:g}, got {rolloff!r}")
    if short_cutoff < 2.0 * spacing * (1 - 1e-12):
        raise ValueError(f"short_cutoff must be >= the Nyquist wavelength 2 L / n = "
                         f"{2 * spacing:g}, got {short_cutoff!r}")
    if short_cutoff >= rolloff:
        raise ValueError(f"short_cutoff must be < rolloff = {rolloff:g}, got {short_cutoff!r}")

    rng = checks.random_generator("seed", seed)
    # synthesised in units of L (every length / L), then scaled: slopes do not change when
    # x, y and z are scaled together, and no intermediate leaves the supported magnitudes
    unit = spacing / L
    noise = np.fft.rfft2(rng.standard_normal((grid, grid)))
    q_y = 2.0 * np.pi * np.fft.fftfreq(grid, d=unit)
    q_x = 2.0 * np.pi * np.fft.rfftfreq(grid, d=unit)
    q = np.hypot(q_y[:, None], q_x[None, :])
    noise *= np.sqrt(self_affine_spectrum(q, hurst=hurst, long_cutoff=long_cutoff / L,
                                          rolloff=rolloff / L, short_cutoff=short_cutoff / L))
    heights = np.fft.irfft2(noise, s=(grid, grid))[:n, :n]
    heights -= heights.mean()
    statistics = surface_statistics(heights, unit, periodic=window is None)
    measured = statistics.rms_height if rms_slope is None else statistics.rms_gradient
    if not measured > 0.0:
        raise ValueError("the surface is flat on this grid: widen the band between "
                         "short_cutoff and long_cutoff")
    heights *= (target / measured) * (L if rms_height is None else 1.0)
    checks.supported_magnitude("max |heights| (set by L and rms_height or rms_slope)",
                               float(np.max(np.abs(heights))))
    return heights


def spectral_rms_slope(heights: np.ndarray, spacing: float) -> float:
    """rms central-difference gradient of a periodic map from its spectrum [-].

    ``<z_x^2 + z_y^2> = sum_q (sin^2(q_x h) + sin^2(q_y h)) / h^2 C(q) (2 pi / L)^2``: the
    spectral form of what :func:`validation.surface_statistics` measures with
    ``periodic=True``.
    """
    heights = np.asarray(heights, dtype=float)
    rows, columns = heights.shape
    _, spectrum = power_spectrum(heights, spacing)
    q_y = 2.0 * np.pi * np.fft.fftfreq(rows, d=spacing)
    q_x = 2.0 * np.pi * np.fft.fftfreq(columns, d=spacing)
    transfer = (np.sin(q_y * spacing)[:, None] ** 2 + np.sin(q_x * spacing)[None, :] ** 2)
    mode_area = (2.0 * np.pi) ** 2 / (rows * columns * spacing**2)
    return math.sqrt(float(np.sum(transfer / spacing**2 * spectrum)) * mode_area)

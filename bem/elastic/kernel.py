"""The kernel of the half-space operator (:class:`bem.elastic.halfspace.HalfSpace`): Love's
displacement under uniform pressure on a pixel, and the spectrum the operator multiplies by
(docs/theory.md, "The reference"; the conventions in :mod:`bem.elastic.halfspace`).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft

from bem.common.checks import positive as _positive

__all__ = ["love_pixel_displacement", "love_quadrant", "kernel_spectrum"]


def _love_f(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """``f(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|)``, each term 0 where its denominator is 0."""
    abs_x, abs_y = np.abs(X), np.abs(Y)
    ratio_yx = np.divide(Y, abs_x, out=np.zeros_like(abs_x), where=abs_x > 0)
    ratio_xy = np.divide(X, abs_y, out=np.zeros_like(abs_y), where=abs_y > 0)
    return X * np.arcsinh(ratio_yx) + Y * np.arcsinh(ratio_xy)


def love_pixel_displacement(x, y, *, half_width_x: float, half_width_y: float | None = None,
                            pressure: float = 1.0, e_star: float = 1.0) -> np.ndarray:
    """Surface displacement of a half-space under uniform pressure on a rectangle (Love 1929).

    Uniform pressure ``p`` on ``|x'| <= a, |y'| <= b`` lowers the surface at ``(x, y)`` by::

        u(x, y) = p / (pi E*) [f(x+a, y+b) - f(x+a, y-b) - f(x-a, y+b) + f(x-a, y-b)]
        f(X, Y) = X asinh(Y/|X|) + Y asinh(X/|Y|)      (each term 0 where its denominator is 0)

    (docs/theory.md, eq. T23). This is the integral of the point-force Green's function
    ``P / (pi E* r)`` over the rectangle. The asinh form is used because the textbook log form
    ``X ln(Y + r) + Y ln(X + r)`` evaluates ``0 * log(0)`` (NaN) on some grid points.

    Parameters
    ----------
    x, y : array_like
        Field point coordinates [length], relative to the rectangle's centre; broadcast together.
    half_width_x, half_width_y : float
        Half-widths a and b of the loaded rectangle [length]; ``half_width_y`` defaults to
        ``half_width_x`` (a square pixel).
    pressure : float
        Uniform pressure p [pressure], positive in compression.
    e_star : float
        Composite modulus E* [pressure].

    Returns
    -------
    numpy.ndarray
        Displacement u [length] into the body (positive under compression), shape of the
        broadcast ``x, y``. Unit square (a = b = 1/2), p = E* = 1: 1.1221997 at the centre,
        0.5610999 at a corner.
    """
    a = _positive("half_width_x", half_width_x)
    b = a if half_width_y is None else _positive("half_width_y", half_width_y)
    e_star = _positive("e_star", e_star)
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValueError("x and y must be finite")
    total = (_love_f(x + a, y + b) - _love_f(x + a, y - b)
             - _love_f(x - a, y + b) + _love_f(x - a, y - b))
    return float(pressure) / (math.pi * e_star) * total


def love_quadrant(rows: int, columns: int, spacing: float, e_star: float) -> np.ndarray:
    """Love's pixel displacement at offsets ``(j h, i h)``, j < rows, i < columns, evaluated
    in blocks of rows (bounded temporaries)."""
    h = spacing
    quadrant = np.empty((rows, columns))
    offset_x = np.arange(columns) * h
    block = max(1, (1 << 12) // columns)  # temporaries of 32 kB
    for start in range(0, rows, block):
        stop = min(rows, start + block)
        quadrant[start:stop] = love_pixel_displacement(
            offset_x[None, :], np.arange(start, stop)[:, None] * h, half_width_x=0.5 * h,
            e_star=e_star)
    return quadrant


def kernel_spectrum(shape: tuple[int, int], spacing: float, e_star: float, *, periodic: bool,
                    mirror: bool) -> np.ndarray:
    """``K_hat`` of a grid in the unnormalised DFT convention of :mod:`bem.elastic.halfspace`:
    the rfft spectrum of the convolution grid (2N x 2N non-periodic, N x N periodic), or the
    cosine modes of a mirror quadrant."""
    ny, nx = shape
    h = spacing
    my, mx = (ny, nx) if periodic else (2 * ny, 2 * nx)
    if mirror:   # the extension's modes: q = pi k / (n h)
        qy = math.pi * np.arange(ny) / (ny * h)
        qx = math.pi * np.arange(nx) / (nx * h)
        q = np.hypot(qy[:, None], qx[None, :])
        return np.divide(2.0 / e_star, q, out=np.zeros_like(q), where=q > 0)
    if periodic:
        qy = 2.0 * math.pi * np.fft.fftfreq(my, d=h)
        qx = 2.0 * math.pi * np.fft.rfftfreq(mx, d=h)
        q = np.hypot(qy[:, None], qx[None, :])
        spectrum = np.divide(2.0 / e_star, q, out=np.zeros_like(q), where=q > 0)
        return spectrum
    # G is even in x and y: on the 2N x 2N wrap-around grid (offsets 0, 1, ..., N-1, -N,
    # ..., -1; the -N entry is never used by the first N x N block of the product, and its
    # sign is immaterial) its DFT is the type-I DCT of the quadrant of offsets 0..N, which
    # needs a (N+1) x (N+1) array instead of 2N x 2N ones.
    quadrant = love_quadrant(ny + 1, nx + 1, spacing, e_star)
    scipy.fft.dct(quadrant, type=1, axis=0, overwrite_x=True, workers=1)
    scipy.fft.dct(quadrant, type=1, axis=1, overwrite_x=True, workers=1)
    # rows of the rfft spectrum: k = 0..N from the DCT, k = N+1..2N-1 mirrored (2N - k)
    spectrum = np.empty((my, nx + 1))
    spectrum[: ny + 1] = quadrant
    spectrum[ny + 1:] = quadrant[ny - 1: 0: -1]
    return spectrum

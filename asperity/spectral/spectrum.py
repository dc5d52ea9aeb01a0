"""Isotropic power spectral density (PSD) of a rough surface, for Persson's theory.

Convention (docs/theory.md, eq. P1), used throughout the project's Persson code:

    C(q) = (2 pi)^-2 * integral d^2x <h(x) h(0)> exp(-i q.x)      [length^4],

so that ``h_rms^2 = integral d^2q C = 2 pi integral q C(q) dq`` and
``h'_rms^2 = integral d^2q q^2 C = 2 pi integral q^3 C(q) dq`` (rms gradient, both directions).

An isotropic spectrum is stored as samples ``(q_k, C_k)`` joined by straight lines in log-log
axes: a piecewise power law, ``C(q) = C_k (q/q_k)^a_k`` on ``[q_k, q_(k+1)]``. Its moments
``integral q^n C dq`` are then closed forms, and so is the inverse of the cumulative fourth
moment that Persson's integrals use as integration variable. A self-affine spectrum
``C ~ q^-2(1+H)`` is represented exactly by two samples.

From a height map (:func:`radial_power_spectrum`): subtract the mean height, multiply by a
separable Hann window (default; WM surfaces are not periodic, and the jump at the edges of an
unwindowed non-periodic map leaks power ~ q^-4 that dominates the slopes) normalised so that
``mean(window^2) = 1``, take the 2-D periodogram
``C(q) = spacing^2 |DFT(h w)|^2 / ((2 pi)^2 N_x N_y)`` and average it over rings of width
``2 pi / L`` centred on multiples of ``2 pi / L`` up to the Nyquist wavevector ``pi/spacing``.
``window="mirror"`` instead takes the periodogram of the map's even extension (2N x 2N: no
jump, only slope kinks at the mirror lines). With ``window="none"`` (periodic maps) or
``"mirror"`` the 2-D periodogram obeys Parseval exactly: ``sum C dq_x dq_y = mean(h^2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from bem.common.checks import (choice, frozen_array, height_map, points, positive, real_array,
                        real_number, supported_magnitude)

__all__ = ["WINDOWS", "IsotropicSpectrum", "power_spectrum_2d", "radial_power_spectrum"]

#: Windows understood by :func:`radial_power_spectrum`.
WINDOWS = ("hann", "mirror", "none")


def _expm1_over(z: np.ndarray) -> np.ndarray:
    """expm1(z)/z, 1 at z = 0."""
    z = np.asarray(z, dtype=float)
    small = np.abs(z) < 1e-8
    safe = np.where(small, 1.0, z)
    return np.where(small, 1.0 + 0.5 * z, np.expm1(safe) / safe)


def _log1p_over(z: np.ndarray) -> np.ndarray:
    """log1p(z)/z, 1 at z = 0."""
    z = np.asarray(z, dtype=float)
    small = np.abs(z) < 1e-8
    safe = np.where(small, 1.0, z)
    return np.where(small, 1.0 - 0.5 * z, np.log1p(safe) / safe)


@dataclass(frozen=True, eq=False)
class IsotropicSpectrum:
    """Piecewise power-law isotropic PSD C(q) through samples (convention eq. P1).

    Parameters
    ----------
    wavevector : array_like
        Strictly increasing sample wavevectors q_k > 0 [1/length]; the first is q_L, the
        last q_1 (the cut-offs of Persson's integrals).
    psd : array_like
        C(q_k) > 0 [length^4].
    """

    wavevector: np.ndarray
    psd: np.ndarray

    def __post_init__(self) -> None:
        q = real_array("wavevector", self.wavevector, finite=False)
        c = real_array("psd", self.psd, finite=False)
        if q.ndim != 1 or q.size < 2 or c.shape != q.shape:
            raise ValueError(f"wavevector and psd must be 1-D of one length >= 2, got shapes "
                             f"{q.shape} and {c.shape}")
        if not (np.all(np.isfinite(q)) and np.all(q > 0) and np.all(np.diff(q) > 0)):
            raise ValueError("wavevector must be finite, > 0 and strictly increasing")
        if not (np.all(np.isfinite(c)) and np.all(c > 0)):
            raise ValueError("psd must be finite and > 0")
        object.__setattr__(self, "wavevector", frozen_array(q))
        object.__setattr__(self, "psd", frozen_array(c))

    # pieces ---------------------------------------------------------------------------------
    @property
    def exponents(self) -> np.ndarray:
        """Power-law exponent a_k of each piece, C = C_k (q/q_k)^a_k."""
        q, c = self.wavevector, self.psd
        return np.diff(np.log(c)) / np.diff(np.log(q))

    def _piece_moments(self, order: int) -> np.ndarray:
        """integral_{q_k}^{q_(k+1)} q^order C dq for each piece (closed form)."""
        q, c = self.wavevector, self.psd
        span = np.diff(np.log(q))
        b = self.exponents + order + 1
        return c[:-1] * q[:-1] ** (order + 1) * span * _expm1_over(b * span)

    def moment(self, order: int) -> float:
        """integral_{q_L}^{q_1} q^order C(q) dq [length^(3 - order)]."""
        return float(np.sum(self._piece_moments(real_number("order", order))))

    def cumulative_moment(self, order: int, wavevector: ArrayLike) -> np.ndarray:
        """integral_{q_L}^q q'^order C(q') dq' at each q (clipped to [q_L, q_1]), closed form
        on each piece [length^(3 - order)]; ``wavevector`` may hold +inf (clipped to q_1)."""
        q_all, c_all = self.wavevector, self.psd
        order = real_number("order", order)
        q = np.clip(points("wavevector", wavevector, allow_infinity=True), q_all[0], q_all[-1])
        below = np.concatenate(([0.0], np.cumsum(self._piece_moments(order))))
        piece = np.clip(np.searchsorted(q_all, q, side="right") - 1, 0, q_all.size - 2)
        q_k = q_all[piece]
        span = np.log(q / q_k)
        b = self.exponents[piece] + order + 1
        return below[piece] + c_all[piece] * q_k ** (order + 1) * span * _expm1_over(b * span)

    def cumulative_fourth_moment(self) -> np.ndarray:
        """m(q_k) = integral_{q_L}^{q_k} q^3 C dq at every sample (m(q_L) = 0) [length^0]."""
        return np.concatenate(([0.0], np.cumsum(self._piece_moments(3))))

    def wavevector_at_fourth_moment(self, m: ArrayLike) -> np.ndarray:
        """The inverse of m(q) = integral_{q_L}^q q'^3 C dq' (closed form on each piece).

        ``m`` (real, +inf allowed, no NaN) is clipped to ``[0, m(q_1)]``; returns q
        [1/length], same shape.
        """
        cumulative = self.cumulative_fourth_moment()
        m = np.clip(points("m", m, allow_infinity=True), 0.0, cumulative[-1])
        piece = np.clip(np.searchsorted(cumulative, m, side="right") - 1, 0,
                        self.wavevector.size - 2)
        q_k, c_k = self.wavevector[piece], self.psd[piece]
        b = self.exponents[piece] + 4.0
        y = (m - cumulative[piece]) / (c_k * q_k**4)
        return q_k * np.exp(y * _log1p_over(b * y))

    # statistics -------------------------------------------------------------------------------
    @property
    def rms_height(self) -> float:
        """h_rms = (2 pi integral q C dq)^(1/2) [length] (eq. P2)."""
        return math.sqrt(2.0 * math.pi * self.moment(1))

    @property
    def rms_gradient(self) -> float:
        """h'_rms = (2 pi integral q^3 C dq)^(1/2) [-] (eq. P2)."""
        return math.sqrt(2.0 * math.pi * self.moment(3))

    def __call__(self, q: ArrayLike) -> np.ndarray:
        """C(q) by log-log interpolation [length^4]; q outside [q_L, q_1] gives 0."""
        q = np.asarray(q, dtype=float)
        inside = (q >= self.wavevector[0]) & (q <= self.wavevector[-1])
        safe = np.where(inside, q, self.wavevector[0])
        value = np.exp(np.interp(np.log(safe), np.log(self.wavevector), np.log(self.psd)))
        return np.where(inside, value, 0.0)


def power_spectrum_2d(heights: ArrayLike, spacing: float, *, window: str = "hann"
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """2-D periodogram of a height map in the convention of eq. (P1).

    Returns ``(q_x, q_y, psd)``: wavevector components [1/length] broadcastable against the
    ``psd`` array [length^4] (numpy FFT order). The mean height is removed first; the window
    is normalised to ``mean(window^2) = 1``. ``window="mirror"`` takes the periodogram of the
    2N_y x 2N_x even extension of the map (no edge jump; wavevectors of the doubled map). With
    ``"none"`` or ``"mirror"``, ``psd.sum() * dq_x * dq_y == mean((h - mean h)^2)`` exactly
    (Parseval).
    """
    h = height_map("heights", heights, minimum=4)
    spacing = supported_magnitude("spacing", positive("spacing", spacing))
    supported_magnitude("max |heights|", float(np.max(np.abs(h))))
    choice("window", window, WINDOWS)
    ny, nx = h.shape
    z = h - h.mean()
    if window == "mirror":
        z = np.block([[z, z[:, ::-1]], [z[::-1, :], z[::-1, ::-1]]])
        ny, nx = z.shape
    elif window == "hann":
        wy, wx = np.hanning(ny + 2)[1:-1], np.hanning(nx + 2)[1:-1]   # no zero end points
        w = np.outer(wy, wx)
        z = z * w / math.sqrt(float(np.mean(w * w)))
    spectrum = np.abs(np.fft.fft2(z)) ** 2 * spacing**2 / ((2.0 * math.pi) ** 2 * nx * ny)
    q_x = 2.0 * math.pi * np.fft.fftfreq(nx, d=spacing)[np.newaxis, :]
    q_y = 2.0 * math.pi * np.fft.fftfreq(ny, d=spacing)[:, np.newaxis]
    return q_x, q_y, spectrum


def radial_power_spectrum(heights: ArrayLike, spacing: float, *, window: str = "hann"
                          ) -> IsotropicSpectrum:
    """Radially averaged PSD of a height map (module docstring; eq. P1).

    Rings of width ``dq = 2 pi / L`` (L the longer side) centred on ``k dq``, k = 1, 2, ...,
    up to the Nyquist wavevector ``pi / spacing``; each ring's value is the mean periodogram
    over its wavevectors, placed at their mean ``|q|``, scaled so that the ring's power equals
    ``2 pi q dq C`` (the lattice count of a ring differs from its area). Empty rings are
    skipped.
    """
    q_x, q_y, spectrum = power_spectrum_2d(heights, spacing, window=window)
    modulus = np.hypot(q_x, q_y).ravel()
    length = max(spectrum.shape) * spacing
    step = 2.0 * math.pi / length
    ring = np.rint(modulus / step).astype(int)
    rings = math.floor(math.pi / spacing / step)
    keep = (ring >= 1) & (ring <= rings)
    count = np.bincount(ring[keep], minlength=rings + 1)[1:]
    total = np.bincount(ring[keep], weights=spectrum.ravel()[keep], minlength=rings + 1)[1:]
    where = np.bincount(ring[keep], weights=modulus[keep], minlength=rings + 1)[1:]
    filled = (count > 0) & (total > 0)
    if np.count_nonzero(filled) < 2:
        raise ValueError("heights: fewer than two non-empty rings in the spectrum")
    # Each ring's value is its power spread evenly over the ring's area 2 pi q dq (the lattice
    # puts 8 wavevectors in the first ring, whose area is 2 pi dq^2 in units of dq^2).
    q = where[filled] / count[filled]
    c = total[filled] * (2.0 * math.pi / (spectrum.shape[0] * spacing)) * (
        2.0 * math.pi / (spectrum.shape[1] * spacing)) / (2.0 * math.pi * q * step)
    # The rings span [dq/2, (n + 1/2) dq]: extend the spectrum to those edges, flat below the
    # first ring (no power is invented at unresolved wavelengths) and along the last piece's
    # power law above the last, so 2 pi integral q C dq counts every ring once (Parseval up
    # to the ring discretisation; docs/theory.md).
    top = (ring[keep].max() + 0.5) * step
    slope = math.log(c[-1] / c[-2]) / math.log(q[-1] / q[-2])
    return IsotropicSpectrum(np.concatenate(([0.5 * step], q, [top])),
                             np.concatenate(([c[0]], c, [c[-1] * (top / q[-1]) ** slope])))

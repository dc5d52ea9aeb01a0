"""Nayak's summit statistics from the spectral moments (asperity.spectral.spectral_summits).

Checked against the closed forms, against direct numerical integration of Nayak's summit
density (independent of the constants written in the code), against the finite-difference
moments of validation.surface_statistics, and against summits counted on large synthetic
Gaussian surfaces.
"""

import math

import numpy as np
import pytest
from scipy import stats

from asperity import (GreenwoodWilliamson, ImprovedGreenwoodWilliamson, IsotropicSpectrum,
                      SpectralMoments, find_summits, spectral_moments, spectral_summits)
from asperity.spectral.spectral_summits import SUMMIT_VARIANCE_CONSTANT
from validation.surfaces.self_affine import self_affine_surface
from validation.surfaces.statistics import surface_statistics
from validation.surfaces.wm import wm_surface


@pytest.mark.parametrize("m0, m2, m4", [(1.0, 1.0, 10.0), (2e-12, 3e-4, 7e4), (1.0, 1.0, 1.5)])
def test_closed_forms(m0, m2, m4):
    s = spectral_summits(m0, m2, m4)
    alpha = m0 * m4 / m2**2
    assert s.alpha == pytest.approx(alpha, rel=1e-15)
    assert s.density == pytest.approx(m4 / (6 * math.pi * math.sqrt(3) * m2), rel=1e-15)
    assert s.radius == pytest.approx(0.375 * math.sqrt(math.pi / m4), rel=1e-15)
    assert s.mean == pytest.approx(4 * math.sqrt(m0 / (math.pi * alpha)), rel=1e-15)
    # McCool's rounded constant 0.8968 against the exact 16/pi - 3 sqrt(3) + 1
    assert s.sigma == pytest.approx(math.sqrt(1 - 0.8968 / alpha) * math.sqrt(m0), rel=1e-5)
    assert SUMMIT_VARIANCE_CONSTANT == pytest.approx(0.896806, abs=1e-6)


def _nayak_expectations(m0, m2, m4):
    """Summit density, mean height, height variance and mean curvature by integrating Nayak's
    summit density n(z, a, r) over heights (Gaussian given a, in closed form) and over the
    mean curvature a and half-difference r = a t of the principal curvatures (Gauss-Legendre,
    400 x 400 nodes: the integrand is smooth)."""
    s = m4 / 3.0
    slope = m2 / (2 * s)                         # E[z | a] = slope * a
    variance = m0 - m2**2 / (2 * s)              # Var[z | a]
    nodes, weights = np.polynomial.legendre.leggauss(400)
    top = 14 * math.sqrt(2 * s)
    a, wa = top * (nodes + 1) / 2, top * weights / 2
    t, wt = (nodes + 1) / 2, weights / 2
    a, t = a[:, None], t[None, :]
    r = a * t
    density = ((a * a - r * r) / (2 * math.pi * m2) * stats.norm.pdf(a, 0, math.sqrt(2 * s))
               * r / s * np.exp(-r * r / (2 * s)) * a)           # dr = a dt
    weight = wa[:, None] * wt[None, :] * density

    def expect(values):
        return float(np.sum(weight * values))

    count = expect(1.0)
    mean = expect(slope * a) / count
    square = expect((slope * a) ** 2 + variance) / count
    curvature = expect(a) / count
    return count, mean, square - mean**2, curvature


@pytest.mark.parametrize("alpha", [1.6, 3.0, 40.0])
def test_statistics_integrate_nayaks_summit_density(alpha):
    m0, m2 = 2.0, 0.5
    m4 = alpha * m2**2 / m0
    count, mean, variance, curvature = _nayak_expectations(m0, m2, m4)
    s = spectral_summits(m0, m2, m4)
    assert s.density == pytest.approx(count, rel=1e-11)
    assert s.mean == pytest.approx(mean, rel=1e-11)
    assert s.sigma**2 == pytest.approx(variance, rel=1e-10)
    assert 1 / s.radius == pytest.approx(curvature, rel=1e-11)


def test_gw_from_the_spectrum_uses_the_summit_statistics():
    s = spectral_summits(1e-6, 4e-3, 60.0)
    gw = s.greenwood_williamson(2.0, e_star=3.0)
    assert isinstance(gw, GreenwoodWilliamson)
    assert (gw.density, gw.radius, gw.sigma, gw.mean, gw.area, gw.e_star) == (
        s.density, s.radius, s.sigma, s.mean, 2.0, 3.0)
    improved = s.improved_greenwood_williamson(2.0, 0.95, e_star=3.0)
    assert isinstance(improved, ImprovedGreenwoodWilliamson) and improved.m == 0.95
    assert improved.sigma == s.sigma and improved.mean == s.mean


def test_moments_of_a_plane_wave_by_finite_differences():
    # z = cos(q x) on a periodic grid: central differences attenuate m2 by (sin(qh)/(qh))^2 and
    # m4 by (sin(qh/2)/(qh/2))^4; the y direction sees no slope, so the average halves them.
    n, spacing = 64, 0.1
    q = 2 * math.pi * 5 / (n * spacing)
    x = np.arange(n) * spacing
    z = np.tile(np.cos(q * x), (n, 1))
    moments = spectral_moments(z, spacing, periodic=True)
    assert moments.m0 == pytest.approx(0.5, rel=1e-13)
    assert moments.m2 == pytest.approx(0.25 * (math.sin(q * spacing) / spacing) ** 2, rel=1e-12)
    assert moments.m4 == pytest.approx(4 * math.sin(q * spacing / 2) ** 4 / spacing**4,
                                       rel=1e-12)
    assert moments.rms_gradient == pytest.approx(math.sqrt(2 * moments.m2))


@pytest.mark.parametrize("periodic", [False, True])
def test_the_one_definition_of_the_moments(periodic):
    heights = wm_surface(64, D=2.4, rms_slope=0.2, seed=5)
    moments = spectral_moments(heights, 1 / 64, periodic=periodic)
    statistics = surface_statistics(heights, 1 / 64, periodic=periodic)
    for name in ("m0", "m2", "m4"):
        assert getattr(moments, name) == pytest.approx(getattr(statistics, name), rel=1e-12)
    assert moments.alpha == pytest.approx(statistics.nayak, rel=1e-12)
    assert moments.rms_gradient == pytest.approx(statistics.rms_gradient, rel=1e-12)


def test_moments_of_a_power_law_spectrum():
    # C = c q^-3 on [1, 10]: integral q^k C dq = c (10^(k-2) - 1)/(k - 2) (k != 2)
    c = 2.0
    spectrum = IsotropicSpectrum([1.0, 10.0], [c, c * 10.0**-3])
    moments = SpectralMoments.from_spectrum(spectrum)
    band = lambda k: c * (10.0 ** (k - 2) - 1) / (k - 2)  # noqa: E731
    assert moments.m0 == pytest.approx(2 * math.pi * band(1), rel=1e-13)
    assert moments.m2 == pytest.approx(math.pi * band(3), rel=1e-13)
    assert moments.m4 == pytest.approx(0.75 * math.pi * band(5), rel=1e-13)
    assert moments.rms_gradient == pytest.approx(spectrum.rms_gradient, rel=1e-13)
    assert moments.rms_height == pytest.approx(spectrum.rms_height, rel=1e-13)
    with pytest.raises(TypeError, match="spectrum"):
        SpectralMoments.from_spectrum([1.0, 2.0])


def _continuous_moments(heights, length):
    """Profile moments of the trigonometric polynomial a periodic map samples (no mode at the
    Nyquist wavevector): sums over its Fourier modes."""
    n = heights.shape[0]
    power = np.abs(np.fft.fft2(heights - heights.mean()) / heights.size) ** 2
    q = 2 * math.pi * np.fft.fftfreq(n, d=length / n)
    qx2, qy2 = (q**2)[None, :], (q**2)[:, None]
    return SpectralMoments(power.sum(), 0.5 * (power * (qx2 + qy2)).sum(),
                           0.5 * (power * (qx2**2 + qy2**2)).sum())


def _block_error(mask, blocks=8):
    """Standard error of the mean density of True points, from blocks x blocks sub-maps."""
    n = mask.shape[0] // blocks
    counts = mask[:n * blocks, :n * blocks].reshape(blocks, n, blocks, n).sum(axis=(1, 3))
    return counts.std(ddof=1) / math.sqrt(counts.size) / (n * n)


@pytest.mark.slow
def test_counted_summits_approach_nayaks_density_as_the_sampling_refines():
    # A Gaussian self-affine surface (H = 0.8) with wavelengths between 16 and 128 grid steps,
    # alpha ~ 5: the 8-neighbour count on every 1st, 2nd, 4th and 8th point (16, 8, 4, 2
    # points per shortest wavelength) against Nayak's density of the continuous surface.
    n = 2048
    heights = self_affine_surface(n, hurst=0.8, rms_height=1.0, long_cutoff=128 / n,
                                  short_cutoff=16 / n, seed=11)
    nayak = _continuous_moments(heights, 1.0).summits()
    assert 4 < nayak.alpha < 7
    errors, bounds = [], []
    for step in (1, 2, 4, 8):
        summits = find_summits(heights[::step, ::step], step / n, periodic=True)
        mask = np.zeros((n // step, n // step), dtype=bool)
        mask[summits.row, summits.column] = True
        mask[summits.rejected_row, summits.rejected_column] = True
        errors.append(mask.sum() / nayak.density - 1)          # L = 1: count = density
        bounds.append(4 * _block_error(mask) * mask.size / nayak.density)
    # finest sampling: Nayak's density within four standard errors and a 1 % sampling bias
    assert abs(errors[0]) < bounds[0] + 0.01, (errors, bounds)
    # coarser sampling loses summits, more the coarser (the 8-neighbour test cannot see
    # maxima closer than a grid step); at 2 points per wavelength ~40 % are lost
    assert errors[3] < errors[2] < errors[1] < errors[0] + bounds[0]
    assert -0.55 < errors[3] < -0.3


def test_bad_input_names_the_moment():
    with pytest.raises(ValueError, match="m2"):
        spectral_summits(1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="m0"):
        spectral_summits(float("nan"), 1.0, 1.0)
    with pytest.raises(TypeError, match="m4"):
        spectral_summits(1.0, 1.0, "big")
    with pytest.raises(ValueError, match="alpha"):
        spectral_summits(1.0, 1.0, 1.4)               # alpha < 3/2: no isotropic surface
    with pytest.raises(ValueError, match="spacing"):
        spectral_moments(np.ones((8, 8)), 0.0)
    with pytest.raises(ValueError, match="flat"):
        spectral_moments(np.ones((8, 8)), 1.0)

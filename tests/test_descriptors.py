"""Surface descriptors (validation.surface_descriptors) against surfaces of known H, rolloff and
moments."""

import math

import numpy as np
import pytest

import validation
from validation.surfaces.descriptors import surface_descriptors


@pytest.mark.parametrize("hurst, rolloff", [(0.3, 0.25), (0.6, 0.1), (0.9, 1.0)])
@pytest.mark.parametrize("window", [None, 512])
def test_hurst_exponent_and_rolloff_of_a_self_affine_surface(hurst, rolloff, window):
    z = validation.self_affine_surface(256, hurst=hurst, rms_slope=0.1, rolloff=rolloff,
                                       window=window, seed=4)
    d = surface_descriptors(z, 1 / 256, periodic=window is None)
    assert d.hurst == pytest.approx(hurst, abs=max(0.04, 4 * d.hurst_error))
    assert 0 < d.hurst_error < 0.03
    if rolloff < 1:   # the rolloff found within one bin; none shown: the scan's side
        assert d.rolloff_wavelength == pytest.approx(rolloff, rel=0.25)
        assert d.magnification == pytest.approx(rolloff / (2 / 256), rel=0.25)
    elif window is None:
        assert d.rolloff_wavelength == pytest.approx(1.0)
        assert d.magnification == pytest.approx(128.0)
    assert d.short_wavelength == pytest.approx(2 / 256)
    assert d.rms_slope == pytest.approx(0.1, rel=1e-6 if window is None else 0.1)
    assert abs(d.skewness) < 0.4 and abs(d.kurtosis - 3) < 0.8


def test_short_cutoff_is_found_where_the_spectrum_ends():
    z = validation.self_affine_surface(256, hurst=0.7, rms_slope=0.1, rolloff=0.5,
                                       short_cutoff=0.05, seed=2)
    d = surface_descriptors(z, 1 / 256, periodic=True)
    assert d.short_wavelength == pytest.approx(0.05, rel=0.15)
    assert d.magnification == pytest.approx(10, rel=0.3)
    assert d.hurst == pytest.approx(0.7, abs=0.1)


@pytest.mark.parametrize("hurst", [0.4, 0.8])
def test_a_known_cutoff_ends_the_fit_where_a_windowed_spectrum_shows_none(hurst):
    """A non-periodic window low-pass filtered at 8 pixels (what the check does to a scan):
    the window's leakage beyond the cutoff is no power law of the surface; told the cutoff,
    the fit stops short of it, and the shortest wavelength is the cutoff's."""
    z = validation.self_affine_surface(256, hurst=hurst, rms_slope=0.1, window=1024, seed=5)
    filtered = validation.short_wavelength_cutoff(z, 1 / 256, 8 / 256)
    told = surface_descriptors(filtered, 1 / 256, short_cutoff=8 / 256)
    assert told.hurst == pytest.approx(hurst, abs=0.05)      # about one standard error
    # untold, the leakage beyond the cutoff is read as a spectrum far steeper than any surface's
    assert surface_descriptors(filtered, 1 / 256).hurst > 2
    assert told.short_wavelength == pytest.approx(8 / 256)
    with pytest.raises(ValueError, match="short_cutoff"):
        surface_descriptors(filtered, 1 / 256, short_cutoff=-1.0)


def test_moments_of_a_sine_are_the_finite_difference_ones():
    n, waves, amplitude = 64, 4, 3e-6
    spacing = 1e-6
    x = np.arange(n) * spacing
    k = 2 * np.pi * waves / (n * spacing)
    z = amplitude * np.sin(k * x)[None, :] * np.ones((n, 1))
    d = surface_descriptors(z, spacing, periodic=True)
    kh = k * spacing
    m0 = amplitude ** 2 / 2
    m2 = amplitude ** 2 * math.sin(kh) ** 2 / spacing ** 2 / 4     # <z_x^2> / 2
    m4 = amplitude ** 2 * (2 - 2 * math.cos(kh)) ** 2 / spacing ** 4 / 4
    assert d.m0 == pytest.approx(m0, rel=1e-9)
    assert d.m2 == pytest.approx(m2, rel=1e-9)
    assert d.m4 == pytest.approx(m4, rel=1e-9)
    assert d.nayak == pytest.approx(m0 * m4 / m2 ** 2, rel=1e-9)
    assert d.nayak == pytest.approx(2 * (2 - 2 * math.cos(kh)) ** 2 / math.sin(kh) ** 4)  # -> 2
    assert d.rms_height == pytest.approx(math.sqrt(m0), rel=1e-9)
    assert d.peak == pytest.approx(math.sqrt(2), rel=1e-9)
    assert d.skewness == pytest.approx(0, abs=1e-9)
    assert d.kurtosis == pytest.approx(1.5, rel=1e-9)   # <sin^4> / <sin^2>^2
    assert d.shape == (n, n) and d.spacing == spacing
    assert math.isnan(d.hurst)   # one wave has no spectral slope
    assert d.short_wavelength == pytest.approx(n * spacing / waves, rel=0.1)


def test_a_plateau_shows_in_the_height_distribution():
    z = validation.self_affine_surface(128, hurst=0.8, rms_slope=0.1, seed=1)
    honed = np.minimum(z, np.quantile(z, 0.7))
    gaussian, plateau = (surface_descriptors(h, 1 / 128, periodic=True) for h in (z, honed))
    assert plateau.skewness < gaussian.skewness - 0.5
    assert plateau.peak < 0.8 * gaussian.peak


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="heights"):
        surface_descriptors(np.ones((4, 4)), 1.0)
    with pytest.raises(ValueError, match="heights"):
        surface_descriptors(np.ones((16, 16)), 1.0)
    with pytest.raises((ValueError, TypeError), match="spacing"):
        surface_descriptors(np.random.default_rng(0).standard_normal((16, 16)), -1.0)


def test_a_line_spectrum_has_a_slope_and_its_band():
    """A periodic WM surface's spectrum is a set of lines with empty bins between them: the
    Hurst exponent is read over the lines (it falls with D) and the magnification is the
    lines' span gamma^n_max; with the empty bins in the fit it was meaningless (|H| of tens)."""
    from validation import wm_surface

    readings = {}
    for dimension in (2.2, 2.5):
        z = wm_surface(256, D=dimension, rms_slope=0.1, n_max=10, periodic=True, seed=1)
        readings[dimension] = surface_descriptors(z, 1 / 256, periodic=True)
    for d in readings.values():
        assert d.hurst_error < 0.2 and -0.2 < d.hurst < 1.0
        assert 0.6 * 1.5 ** 10 < d.magnification < 1.1 * 1.5 ** 10
    assert readings[2.2].hurst - readings[2.5].hurst > 0.2

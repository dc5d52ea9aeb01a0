"""Self-affine random surfaces: spectrum, normalisation, reproducibility, windows, bad input."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import validation
from validation.surfaces.self_affine import (
    power_spectrum,
    radial_power_spectrum,
    self_affine_spectrum,
    self_affine_surface,
    spectral_rms_slope,
)

N = 256


@pytest.mark.parametrize("hurst", [0.3, 0.8])
def test_radial_psd_slope_is_minus_two_one_plus_hurst(hurst):
    rolloff, short_cutoff = 0.25, 4.0 / N
    spectra = []
    for seed in range(8):
        heights = self_affine_surface(N, hurst=hurst, rms_height=1.0, rolloff=rolloff,
                                      short_cutoff=short_cutoff, seed=seed)
        q, spectrum = radial_power_spectrum(heights, 1.0 / N, bins=24)
        spectra.append(spectrum)
    mean = np.mean(spectra, axis=0)
    band = (q > 1.1 * 2 * np.pi / rolloff) & (q < 2 * np.pi / short_cutoff / 1.1)
    assert band.sum() >= 8
    slope = np.polyfit(np.log(q[band]), np.log(mean[band]), 1)[0]
    assert slope == pytest.approx(-2.0 * (1.0 + hurst), abs=0.05)


def test_spectrum_level_flat_rolloff_and_cutoffs():
    """Seed-averaged C(q) matches the analytic spectrum normalised to the rms height; no power
    outside [q_L, q_s]."""
    long_cutoff, rolloff, short_cutoff, hurst = 0.5, 0.125, 8.0 / N, 0.7
    kw = dict(hurst=hurst, long_cutoff=long_cutoff, rolloff=rolloff, short_cutoff=short_cutoff)
    q, analytic = power_spectrum(np.zeros((N, N)), 1.0 / N)
    analytic = self_affine_spectrum(q, **kw)
    analytic /= analytic.sum() * (2 * np.pi) ** 2          # rms height 1 (Parseval, L = 1)
    spectra = [power_spectrum(self_affine_surface(N, rms_height=1.0, seed=s, **kw), 1.0 / N)[1]
               for s in range(8)]
    mean = np.mean(spectra, axis=0)
    outside = analytic == 0.0
    assert np.all(mean[outside] < 1e-20 * mean.max())
    for low, high in [(2 * np.pi / long_cutoff, 2 * np.pi / rolloff),    # flat region
                      (2 * np.pi / rolloff, 2 * np.pi / short_cutoff)]:  # self-affine region
        band = (q >= low) & (q < high)
        assert mean[band].sum() == pytest.approx(analytic[band].sum(), rel=0.1)
    flat = (q >= 2 * np.pi / long_cutoff) & (q < 2 * np.pi / rolloff)
    assert np.ptp(analytic[flat]) == 0.0


def test_parseval_and_spectral_slope_agree_with_surface_statistics():
    heights = self_affine_surface(64, hurst=0.5, rms_slope=0.2, L=3.0, seed=4)
    spacing = 3.0 / 64
    q, spectrum = power_spectrum(heights, spacing)
    assert spectrum.sum() * (2 * np.pi / 3.0) ** 2 == pytest.approx(np.mean(heights**2), rel=1e-12)
    stats = validation.surface_statistics(heights, spacing, periodic=True)
    assert spectral_rms_slope(heights, spacing) == pytest.approx(stats.rms_gradient, rel=1e-12)


@pytest.mark.parametrize("window", [None, 96])
def test_rms_height_and_slope_as_requested(window):
    periodic = window is None
    for seed in range(3):
        heights = self_affine_surface(64, hurst=0.6, rms_slope=0.1, L=2.0, window=window, seed=seed)
        stats = validation.surface_statistics(heights, 2.0 / 64, periodic=periodic)
        assert stats.rms_gradient == pytest.approx(0.1, rel=0.01)
        heights = self_affine_surface(64, hurst=0.6, rms_height=0.3, L=2.0, window=window, seed=seed)
        assert np.sqrt(np.mean(heights**2)) == pytest.approx(0.3, rel=0.01)
        assert abs(heights.mean()) < 1e-12


def test_reproducible_by_seed_and_real():
    kw = dict(hurst=0.8, rms_slope=0.1, rolloff=0.5)
    first = self_affine_surface(32, seed=7, **kw)
    assert first.dtype == np.float64 and first.shape == (32, 32)
    np.testing.assert_array_equal(first, self_affine_surface(32, seed=7, **kw))
    np.testing.assert_array_equal(first, self_affine_surface(32, seed=np.random.default_rng(7), **kw))
    assert not np.allclose(first, self_affine_surface(32, seed=8, **kw))


def test_periodic_by_construction_window_is_not():
    """The periodic surface continues smoothly across its edge; a window's edges do not match.
    A window is the top-left block of the periodic parent (up to the amplitude)."""
    kw = dict(hurst=0.8, rms_height=1.0, short_cutoff=8.0 / 64, seed=3)
    periodic = self_affine_surface(64, **kw)
    jump_inside = np.abs(np.diff(periodic, axis=1)).mean()
    assert np.abs(periodic[:, 0] - periodic[:, -1]).mean() < 2 * jump_inside
    window = self_affine_surface(64, window=256, long_cutoff=1.0, **kw)
    parent = self_affine_surface(256, L=4.0, long_cutoff=1.0, **kw)[:64, :64]
    ratio = window / (parent - parent.mean())
    np.testing.assert_allclose(ratio, ratio[0, 0], rtol=1e-9)
    assert np.abs(window[:, 0] - window[:, -1]).mean() > 5 * np.abs(np.diff(window, axis=1)).mean()


@given(hurst=st.floats(0.05, 1.0), n=st.integers(8, 40), seed=st.integers(0, 2**32 - 1))
def test_property_finite_zero_mean_requested_slope(hurst, n, seed):
    heights = self_affine_surface(n, hurst=hurst, rms_slope=0.3, seed=seed)
    assert np.all(np.isfinite(heights))
    assert abs(heights.mean()) < 1e-12
    stats = validation.surface_statistics(heights, 1.0 / n, periodic=True)
    assert math.isclose(stats.rms_gradient, 0.3, rel_tol=1e-9)


@pytest.mark.parametrize("kwargs, name", [
    (dict(n=3), "n"),
    (dict(n=32.0), "n"),
    (dict(hurst=0.0), "hurst"),
    (dict(hurst=1.5), "hurst"),
    (dict(hurst=float("nan")), "hurst"),
    (dict(rms_height=1.0), "exactly one"),
    (dict(rms_slope=None), "exactly one"),
    (dict(rms_slope=-0.1), "rms_slope"),
    (dict(L=0.0), "L"),
    (dict(long_cutoff=2.0), "long_cutoff"),
    (dict(rolloff=0.5, long_cutoff=0.25), "rolloff"),
    (dict(short_cutoff=1.0 / 32), "short_cutoff"),
    (dict(short_cutoff=0.5, rolloff=0.5), "short_cutoff"),
    (dict(window=32), "window"),
    (dict(window=True), "window"),
])
def test_bad_input_names_the_parameter(kwargs, name):
    arguments = dict(n=32, hurst=0.5, rms_slope=0.1) | kwargs
    with pytest.raises(ValueError, match=name):
        self_affine_surface(**arguments)


def test_exported():
    assert validation.self_affine_surface is self_affine_surface


def test_a_plateau_cuts_the_peaks_flat_and_keeps_the_slope():
    from validation.scenes.scene import SurfaceSpec
    from validation.surfaces.families import surface_heights, surface_identity

    gaussian = SurfaceSpec(family="self-affine", hurst=(0.7,), rms_slope=0.1, window=1, n=64)
    honed = SurfaceSpec(family="self-affine", hurst=(0.7,), rms_slope=0.1, window=1, n=64,
                        plateau=0.8)
    z, flat = surface_heights(gaussian, 3), surface_heights(honed, 3)
    top = flat.max()
    # a fifth of the points (up to the subsampling) sit on the plateau, the valleys stay
    assert 0.1 < np.mean(np.isclose(flat, top, atol=1e-12 * np.ptp(flat))) < 0.3
    skew = lambda h: np.mean((h - h.mean()) ** 3) / np.std(h) ** 3  # noqa: E731
    assert skew(flat) < skew(z) - 0.3
    assert validation.surface_statistics(flat, 1 / 64, periodic=True).rms_gradient == pytest.approx(0.1)
    assert "plateau" not in surface_identity(gaussian, 3)
    assert surface_identity(honed, 3)["plateau"] == 0.8
    with pytest.raises(ValueError, match="plateau"):
        SurfaceSpec(family="self-affine", hurst=(0.7,), plateau=1.0)

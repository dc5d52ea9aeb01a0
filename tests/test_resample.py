"""Non-square pixels resampled onto square ones (validation.surfaces.resample, read_topography's
``resample``): exact on smooth maps, the spectral transfer of docs/theory.md (T33, T34), the
physical size kept, and the refusal without the option."""

from __future__ import annotations

import math

import numpy as np
import pytest

from validation.surfaces.resample import resample_square
from validation.surfaces.topography import read_topography

DX, DY = 1.0, 2.5              # µm: pixels 2.5 times longer in y, as an optical profilometer's
ROWS, COLUMNS = 40, 100        # a 100 µm x 100 µm map


def surface(y, x):
    """A smooth map with 16 samples per wavelength along y and 50 along x [µm]."""
    return np.sin(2 * np.pi * y / 40.0) + 0.5 * np.cos(2 * np.pi * x / 50.0)


def centres(count, spacing, size):
    """Pixel centres of ``count`` pixels of ``spacing`` centred on an extent ``size``."""
    return 0.5 * (size - count * spacing) + (np.arange(count) + 0.5) * spacing


@pytest.fixture
def anisotropic(tmp_path):
    heights = surface(centres(ROWS, DY, ROWS * DY)[:, None],
                      centres(COLUMNS, DX, COLUMNS * DX)[None, :])
    path = tmp_path / "scan.npy"
    np.save(path, heights)
    return path


def _read(path, **options):
    return read_topography(path, file_unit="um", height_unit="um", detrend=None,
                           physical_size=(COLUMNS * DX, ROWS * DY), **options)


def test_non_square_pixels_are_refused_without_the_option(anisotropic):
    with pytest.raises(ValueError, match="pixels are not square .* resample='finer'"):
        _read(anisotropic)
    with pytest.raises(ValueError, match="resample must be one of"):
        _read(anisotropic, resample="cubic")


def test_finer_interpolates_the_coarse_axis_to_the_spline_accuracy(anisotropic):
    top = _read(anisotropic, resample="finer")
    assert top.heights.shape == (100, 100) and top.spacing == DX
    assert top.physical_size == (100.0, 100.0)
    y = centres(100, DX, ROWS * DY)
    exact = surface(y[:, None], centres(COLUMNS, DX, COLUMNS * DX)[None, :])
    # cubic spline error <= (5/384) (2 pi / 40)^4 dy^4 = 3.1e-4 away from the ends (whose
    # not-a-knot conditions do a little worse); held flat within dy/2 of the edges
    error = np.abs(top.heights - exact)
    middle = (y >= 3 * DY) & (y <= ROWS * DY - 3 * DY)
    inside = (y >= DY / 2) & (y <= ROWS * DY - DY / 2)
    assert np.max(error[middle]) < 3.1e-4 and np.max(error[inside]) < 1e-3
    old_first_row = surface(DY / 2, centres(COLUMNS, DX, COLUMNS * DX))
    np.testing.assert_allclose(top.heights[0], old_first_row, rtol=0, atol=1e-12)  # 0.5 < 1.25


def test_coarser_takes_the_pixel_mean_along_the_fine_axis(anisotropic):
    top = _read(anisotropic, resample="coarser")
    assert top.heights.shape == (40, 40) and top.spacing == DY
    edges = np.arange(41) * DY
    k = 2 * np.pi / 50.0
    mean_x = 0.5 * (np.sin(k * edges[1:]) - np.sin(k * edges[:-1])) / (k * DY)
    exact = np.sin(2 * np.pi * centres(ROWS, DY, ROWS * DY) / 40.0)[:, None] + mean_x[None, :]
    # every new pixel lies within the old centres but the first and last (held flat there)
    np.testing.assert_allclose(top.heights[:, 1:-1], exact[:, 1:-1], atol=1e-6)


@pytest.mark.parametrize("ratio", [1.7, 2.5, 3.0])
def test_physical_size_is_kept_to_half_a_new_pixel(ratio):
    heights = np.random.default_rng(0).standard_normal((30, 70))
    for to, spacing in (("finer", 1.0), ("coarser", ratio)):
        resampled, h = resample_square(heights, ratio, 1.0, to)   # dx = ratio, dy = 1
        assert h == spacing
        assert abs(resampled.shape[1] * h - 70 * ratio) <= h / 2 + 1e-12
        assert abs(resampled.shape[0] * h - 30.0) <= h / 2 + 1e-12


def _amplitude(values, y, q):
    basis = np.stack((np.cos(q * y), np.sin(q * y)), axis=1)
    coefficients, *_ = np.linalg.lstsq(basis, values, rcond=None)
    return float(np.hypot(*coefficients))


def spline_response(w):
    """H of eq. (T33): the cardinal cubic spline's response at w = q dy."""
    return np.sinc(w / (2 * np.pi)) ** 4 * 3.0 / (2.0 + np.cos(w))


@pytest.mark.parametrize("w", [0.25 * np.pi, 0.5 * np.pi, 0.8 * np.pi])
def test_refining_transfers_amplitudes_as_eq_t33(w):
    dy, rows = 2.5, 400
    q = w / dy
    y_old = (np.arange(rows) + 0.5) * dy
    heights = np.repeat(np.cos(q * y_old + 0.3)[:, None], 4, axis=1)
    refined, h = resample_square(heights, 0.5, dy, "finer")
    y = centres(refined.shape[0], h, rows * dy)
    middle = slice(refined.shape[0] // 5, 4 * refined.shape[0] // 5)   # away from the ends
    both = np.stack((np.cos(q * y), np.sin(q * y), np.cos((2 * np.pi / dy - q) * y),
                     np.sin((2 * np.pi / dy - q) * y)), axis=1)[middle]
    c, *_ = np.linalg.lstsq(both, refined[middle, 0], rcond=None)
    assert math.hypot(c[0], c[1]) == pytest.approx(spline_response(w), abs=2e-4)
    assert math.hypot(c[2], c[3]) == pytest.approx(spline_response(2 * np.pi - w), abs=2e-4)


@pytest.mark.parametrize("qh", [0.5 * np.pi, 1.1 * np.pi])
def test_coarsening_damps_and_folds_back_as_eq_t34(qh):
    dy, h, rows = 1.0, 2.5, 1000
    q = qh / h
    y_old = (np.arange(rows) + 0.5) * dy
    heights = np.repeat(np.cos(q * y_old + 0.3)[:, None], 4, axis=1)
    coarse, spacing = resample_square(heights, h, dy, "coarser")
    assert spacing == h
    y = centres(coarse.shape[0], h, rows * dy)
    seen = q if q <= np.pi / h else 2 * np.pi / h - q          # the folded wavevector
    middle = slice(coarse.shape[0] // 5, 4 * coarse.shape[0] // 5)
    expected = np.sinc(q * h / (2 * np.pi)) * spline_response(q * dy)
    assert _amplitude(coarse[middle, 0], y[middle], seen) == pytest.approx(expected, abs=1e-3)


def test_square_pixels_are_left_alone_and_missing_points_filled_first(tmp_path):
    heights = np.random.default_rng(1).standard_normal((8, 8))
    same, h = resample_square(heights, 0.5, 0.5, "coarser")
    np.testing.assert_array_equal(same, heights) and h == 0.5
    heights = np.random.default_rng(2).standard_normal((16, 40))
    heights[4, 7] = np.nan
    np.save(tmp_path / "gap.npy", heights)
    options = dict(file_unit="um", physical_size=(40.0, 40.0), resample="finer")
    with pytest.raises(ValueError, match="missing"):
        read_topography(tmp_path / "gap.npy", **options)
    top = read_topography(tmp_path / "gap.npy", fill="interpolate", square="keep", **options)
    assert top.heights.shape == (40, 40) and np.isfinite(top.heights).all()


def test_x3p_with_pixels_longer_in_y(tmp_path):
    st = pytest.importorskip("SurfaceTopography")
    heights = surface(centres(ROWS, DY, 100.0)[:, None], centres(32, DX, 32.0)[None, :])
    instrument = st.Topography(heights.T.copy(), (32.0, 100.0), unit="µm")    # [x, y]
    if not hasattr(instrument, "to_x3p"):
        pytest.skip("this SurfaceTopography version has no x3p writer")
    instrument.to_x3p(str(tmp_path / "scan.x3p"))
    with pytest.raises(ValueError, match="pixels are not square"):
        read_topography(tmp_path / "scan.x3p")
    top = read_topography(tmp_path / "scan.x3p", resample="finer", square="keep", detrend=None,
                          height_unit="um")
    assert top.heights.shape == (100, 32) and top.spacing == pytest.approx(1.0)
    assert top.physical_size == pytest.approx((32.0, 100.0))


def test_file_scene_family_takes_the_resample_key(anisotropic):
    from validation import SceneError, parse_scene
    from validation.surfaces.families import surface_heights, surface_identity

    def scene(**surface):
        return parse_scene({"surface": {"family": "file", "path": str(anisotropic),
                                        "file_unit": "um", "unit": "um", "detrend": "none",
                                        "physical_size": [100.0, 100.0], **surface}})

    with pytest.raises(SceneError, match="surface.resample.*pixels are not square"):
        scene()
    with pytest.raises(SceneError, match="surface.resample"):
        scene(resample="bicubic")
    finer, coarser = scene(resample="finer").surface, scene(resample="coarser").surface
    assert (finer.n, finer.L, coarser.n, coarser.L) == (100, 100.0, 40, 100.0)
    assert surface_identity(finer, 0)["resample"] == "finer"
    heights = surface_heights(finer, 0)
    reread = _read(anisotropic, resample="finer").heights
    np.testing.assert_allclose(heights, reread - reread.mean(), atol=1e-12)

"""Which reader reads a file by default (validation.surfaces.formats): text first for the text
suffixes, SurfaceTopography first for the rest, then the other; and the clear error of each bad
file (corrupted, line scan, too small, all missing, no lateral size). The instrument files are
made here by SurfaceTopography's own writers (netCDF, x3p), so no binary data is committed."""

import sys

import numpy as np
import pytest

from validation.surfaces.topography import MIN_SIDE, read_topography, write_gwyddion_ascii


def noise(rows=40, columns=48, seed=0):
    return np.random.default_rng(seed).standard_normal((rows, columns))


@pytest.fixture
def st():
    return pytest.importorskip("SurfaceTopography")


def instrument_file(st, path, heights, size, unit="nm"):
    """``heights[j, i]`` written by SurfaceTopography (arrays [x, y]) in the format of the
    suffix: ``.x3p`` (ISO 25178-72), anything else netCDF."""
    topography = st.Topography(np.ma.asarray(heights).T.copy(), size, unit=unit)
    if path.suffix == ".x3p":
        if not hasattr(topography, "to_x3p"):
            pytest.skip("this SurfaceTopography version has no x3p writer")
        topography.to_x3p(str(path))
    else:
        topography.to_netcdf(str(path))
    return path


def test_binary_dat_is_read_by_surfacetopography_after_the_text_reader(st, tmp_path):
    """A .dat suffix is a text matrix's, but an instrument's too (Zygo MetroPro): a binary .dat
    goes on to SurfaceTopography by default, as with reader="surfacetopography"."""
    heights = noise()
    path = instrument_file(st, tmp_path / "scan.dat", heights, (24.0, 20.0))
    top = read_topography(path, square="keep", detrend=None, height_unit="nm")
    assert "SurfaceTopography" in top.source and top.heights.shape == (40, 48)
    np.testing.assert_allclose(top.heights, heights, rtol=1e-12)
    assert top.spacing == pytest.approx(0.5)
    forced = read_topography(path, square="keep", detrend=None, height_unit="nm",
                             reader="surfacetopography")
    np.testing.assert_array_equal(forced.heights, top.heights)
    with pytest.raises(ValueError, match="as text: a binary file"):
        read_topography(path, reader="builtin")


def test_x3p_is_read_by_default(st, tmp_path):
    heights = noise(36, 36, seed=1)
    path = instrument_file(st, tmp_path / "scan.x3p", heights, (3.6, 3.6), unit="µm")
    top = read_topography(path, detrend=None, height_unit="um")
    np.testing.assert_allclose(top.heights, heights, rtol=1e-6, atol=1e-6)
    assert top.spacing == pytest.approx(0.1) and "x3p" in top.source


def test_point_lists_go_to_surfacetopography(st, tmp_path):
    """Three columns x y z of a grid: a point list, read as the map it samples (not as a
    1024 x 3 matrix); two columns x, z: a profile, refused as a line scan."""
    heights = noise(32, 32, seed=2)
    y, x = np.indices(heights.shape)
    np.savetxt(tmp_path / "points.txt", np.c_[0.5 * x.ravel(), 0.5 * y.ravel(), heights.ravel()])
    top = read_topography(tmp_path / "points.txt", file_unit="nm", height_unit="nm",
                          detrend=None)
    assert top.heights.shape == (32, 32) and top.spacing == pytest.approx(0.5)
    np.testing.assert_allclose(np.sort(top.heights.ravel()), np.sort(heights.ravel()))
    np.savetxt(tmp_path / "profile.csv", np.c_[0.1 * np.arange(100), noise(100, 1)[:, 0]],
               delimiter=",")
    with pytest.raises(ValueError, match="line scan"):
        read_topography(tmp_path / "profile.csv", file_unit="nm")


@pytest.mark.parametrize("suffix", [".dat", ".x3p", ".nc"])
def test_truncated_file_names_both_attempts_and_the_formats_reason(st, tmp_path, suffix):
    path = instrument_file(st, tmp_path / f"scan{suffix}", noise(), (24.0, 20.0))
    data = path.read_bytes()
    path.write_bytes(data[:len(data) // 2])
    with pytest.raises(ValueError, match="cannot read it as a height map") as raised:
        read_topography(path)
    message = str(raised.value)
    assert "as text: a binary file" in message and "with SurfaceTopography:" in message
    assert len(message) < 1000                  # the readers' reasons quoted, not their dumps


def test_without_the_extra_text_is_still_read_and_binary_says_how_to_install(tmp_path,
                                                                             monkeypatch):
    monkeypatch.setitem(sys.modules, "SurfaceTopography", None)
    np.savetxt(tmp_path / "scan.hgt", noise(32, 32))          # a text matrix, unknown suffix
    top = read_topography(tmp_path / "scan.hgt", file_unit="nm", physical_size="32 nm")
    assert top.heights.shape == (32, 32) and "text" in top.source
    (tmp_path / "scan.ibw").write_bytes(bytes(range(256)) * 4)
    # what to install first, then what the built-in reader found
    with pytest.raises(ImportError, match=r"needs the optional extra: pip install "
                                          r"'asperity-validation\[topography\]'.*as text: a "
                                          r"binary file"):
        read_topography(tmp_path / "scan.ibw")


def test_small_empty_and_sizeless_maps_are_refused(tmp_path):
    path = write_gwyddion_ascii(tmp_path / "small.txt", noise(MIN_SIDE - 1, 64), 1e-9)
    with pytest.raises(ValueError, match=r"a map of 31 x 64 points.*at least 32 x 32"):
        read_topography(path)
    with pytest.raises(ValueError, match=r"a map of 31 x 64 points"):
        read_topography(path, square="keep")
    np.save(tmp_path / "coarse.npy", noise(40, 40))      # dy = 1.5 dx: x coarsened to 27 pixels
    with pytest.raises(ValueError, match=r"a map of 40 x 27 points"):
        read_topography(tmp_path / "coarse.npy", file_unit="nm", physical_size=(40.0, 60.0),
                        resample="coarser", square="keep")
    np.save(tmp_path / "empty.npy", np.full((32, 32), np.nan))
    with pytest.raises(ValueError, match="no valid height"):
        read_topography(tmp_path / "empty.npy", file_unit="nm", physical_size=1.0, fill="mean")
    np.save(tmp_path / "bare.npy", noise(32, 32))
    with pytest.raises(ValueError, match="does not state its physical size: pass physical_size"):
        read_topography(tmp_path / "bare.npy", file_unit="nm")


def test_masked_points_of_an_instrument_file_are_filled_as_asked(st, tmp_path):
    """A Wyko-like map with gaps (masked in SurfaceTopography): refused without fill, filled
    by the mean or by interpolation inside the gaps; a plane is interpolated exactly."""
    y, x = np.indices((40, 40), dtype=float)
    heights = np.ma.masked_array(0.3 + 0.02 * x - 0.05 * y, mask=np.zeros((40, 40), bool))
    heights.mask[10:14, 5:9] = heights.mask[30, 30] = True
    path = instrument_file(st, tmp_path / "gaps.nc", heights, (40.0, 40.0))
    with pytest.raises(ValueError, match="17 of 1600 points are missing"):
        read_topography(path)
    filled = read_topography(path, fill="interpolate", detrend=None, height_unit="nm")
    np.testing.assert_allclose(filled.heights, heights.data, atol=1e-12)
    mean = read_topography(path, fill="mean", detrend=None, height_unit="nm")
    assert mean.heights[11, 6] == pytest.approx(heights.mean())


def test_gaps_whose_valid_border_spans_no_triangle_take_the_nearest_value(tmp_path):
    heights = np.full((32, 32), np.nan)
    heights[0] = np.arange(32.0)                    # the only valid row: collinear points
    np.save(tmp_path / "row.npy", heights)
    top = read_topography(tmp_path / "row.npy", file_unit="m", physical_size=32.0,
                          fill="interpolate", detrend=None)
    np.testing.assert_array_equal(top.heights, np.broadcast_to(np.arange(32.0), (32, 32)))

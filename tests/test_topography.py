"""Measured topographies: built-in readers, units, detrending, missing data, the optional
SurfaceTopography reader."""

import dataclasses
import importlib.util
import pathlib
import sys

import numpy as np
import pytest

import validation
from validation.surfaces.self_affine import self_affine_surface
from validation.surfaces.topography import LENGTH_UNITS, read_topography, write_gwyddion_ascii


def rough(rows=24, columns=24, seed=0):
    """A non-trivial map without plane: a self-affine surface (cropped when rectangular)."""
    heights = self_affine_surface(max(rows, columns), hurst=0.8, rms_height=1.0, seed=seed)
    heights = heights[:rows, :columns]
    return heights - heights.mean()


def plane(rows, columns, a=0.3, b=-0.02, c=0.05):
    y, x = np.indices((rows, columns), dtype=float)
    return a + b * x + c * y


def test_gwyddion_ascii_units_spacing_and_plane(tmp_path):
    heights = rough(32, 32) + plane(32, 32)          # numbers in µm
    path = write_gwyddion_ascii(tmp_path / "map.txt", heights, 0.25, unit="µm")
    top = read_topography(path)
    assert top.unit == "m" and top.spacing == pytest.approx(0.25e-6)
    assert top.physical_size == pytest.approx((8e-6, 8e-6))
    residual = heights - plane(32, 32)
    y, x = np.indices(residual.shape, dtype=float)
    basis = np.stack((np.ones(x.size), x.ravel(), y.ravel()), axis=1)
    fitted = basis @ np.linalg.lstsq(basis, residual.ravel(), rcond=None)[0]
    expected = (residual.ravel() - fitted).reshape(residual.shape) * 1e-6
    np.testing.assert_allclose(top.heights, expected, rtol=0, atol=1e-12)   # 7 digits of ~1 µm
    in_nm = read_topography(path, height_unit="nm")
    np.testing.assert_allclose(in_nm.heights, top.heights * 1e9, rtol=1e-12, atol=1e-9)
    assert in_nm.spacing == pytest.approx(250.0) and "Gwyddion" in in_nm.source


def test_gwyddion_header_with_si_values_and_micrometre_size(tmp_path):
    """Gwyddion's own export: Width in µm, values in m, tab separated."""
    values = np.arange(32 * 48).reshape(32, 48) * 1e-9              # m
    text = ("# Channel: Topography\n# Width: 48.000 µm\n# Height: 32.000 µm\n# Value units: m\n"
            + "".join("\t".join(f"{v:g}" for v in row) + "\n" for row in values))
    path = tmp_path / "gwy.txt"
    path.write_text(text, encoding="utf-8")
    top = read_topography(path, detrend=None, square="keep", height_unit="um")
    assert top.heights.shape == (32, 48) and top.spacing == pytest.approx(1.0)
    np.testing.assert_allclose(top.heights, values * 1e6)


def test_csv_with_comment_header_needs_unit_and_size(tmp_path):
    heights = rough(32, 32)
    path = tmp_path / "map.csv"
    np.savetxt(path, heights, delimiter=",", header="exported by hand\nanother line")
    with pytest.raises(ValueError, match="file_unit"):
        read_topography(path, physical_size=6.0)
    with pytest.raises(ValueError, match="physical_size"):
        read_topography(path, file_unit="nm")
    top = read_topography(path, file_unit="nm", physical_size="16 um", detrend="mean",
                          height_unit="um")
    assert top.spacing == pytest.approx(0.5)
    np.testing.assert_allclose(top.heights, (heights - heights.mean()) * 1e-3, atol=1e-15)
    same = read_topography(path, file_unit="nm", physical_size=16e-6, detrend="mean")
    np.testing.assert_allclose(same.heights, top.heights * 1e-6, atol=1e-20)


def test_decimal_comma_and_comma_space_separated(tmp_path):
    values = np.tile([1.5, 2.5, 3.5, -45.0], (32, 8))                 # 32 x 32, nm
    rows = ["\t".join(f"{v:g}".replace(".", ",") for v in row) for row in values]
    rows[1] = rows[1].replace("-45", "-4,5e1")
    (tmp_path / "de.txt").write_text("# Width: 32,000 mm\n# Height: 32 mm\n# Value units: nm\n"
                                     + "\n".join(rows) + "\n", encoding="utf-8")
    top = read_topography(tmp_path / "de.txt", detrend=None, square="keep", height_unit="nm")
    np.testing.assert_allclose(top.heights, values)
    assert top.spacing == pytest.approx(1e6)
    (tmp_path / "en.csv").write_text("".join(", ".join(f"{v:g}" for v in row) + "\n"
                                             for row in values), encoding="utf-8")
    top = read_topography(tmp_path / "en.csv", detrend=None, file_unit="nm", physical_size=2.0,
                          height_unit="nm")
    np.testing.assert_allclose(top.heights, values)


def test_npy_non_square_is_cropped_to_centred_square_or_kept(tmp_path):
    heights = rough(32, 48)
    path = tmp_path / "map.npy"
    np.save(path, heights)
    top = read_topography(path, file_unit="m", physical_size=(48.0, 32.0), detrend=None)
    np.testing.assert_array_equal(top.heights, heights[:, 8:40])
    assert top.physical_size == (32.0, 32.0) and top.spacing == 1.0
    kept = read_topography(path, file_unit="m", physical_size=(48.0, 32.0), detrend=None,
                           square="keep")
    assert kept.heights.shape == (32, 48) and kept.physical_size == (48.0, 32.0)
    with pytest.raises(ValueError, match="not square"):
        read_topography(path, file_unit="m", physical_size=(48.0, 48.0))


def test_result_is_frozen_and_read_only(tmp_path):
    path = write_gwyddion_ascii(tmp_path / "map.txt", rough(32, 32), 1.0)
    top = read_topography(path)
    assert isinstance(top, validation.Topography)
    with pytest.raises(dataclasses.FrozenInstanceError):
        top.spacing = 2.0
    with pytest.raises(ValueError):
        top.heights[0, 0] = 1.0


@pytest.mark.parametrize("shape", [(1, 16), (16, 1)])
def test_line_scan_is_an_error(tmp_path, shape):
    path = write_gwyddion_ascii(tmp_path / "line.txt", np.ones(shape), 1.0)
    with pytest.raises(ValueError, match="line scan"):
        read_topography(path)
    np.save(tmp_path / "line.npy", np.ones(16))
    with pytest.raises(ValueError, match="line scan"):
        read_topography(tmp_path / "line.npy", file_unit="m", physical_size=1.0)


def test_missing_data_error_or_explicit_fill(tmp_path):
    heights = plane(32, 32)
    heights[3:5, 6] = np.nan
    heights[20:26, 10:17] = np.nan                            # a larger gap
    heights[0, 0] = np.nan                                    # on the hull: nearest value
    path = write_gwyddion_ascii(tmp_path / "holes.txt", heights, 1.0)
    with pytest.raises(ValueError, match="45 of 1024 points are missing"):
        read_topography(path)
    filled = read_topography(path, fill="interpolate", detrend=None)
    inside = np.ones_like(heights, dtype=bool)
    inside[0, 0] = False
    np.testing.assert_allclose(filled.heights[inside], plane(32, 32)[inside], atol=1e-12)
    nearest = (plane(32, 32)[0, 1], plane(32, 32)[1, 0])                # equally near
    assert min(abs(filled.heights[0, 0] - value) for value in nearest) < 1e-12
    mean = read_topography(path, fill="mean", detrend="plane")
    assert np.all(np.isfinite(mean.heights))
    assert filled.filled == mean.filled == 45     # said, so that a report can say it
    assert read_topography(write_gwyddion_ascii(tmp_path / "whole.txt", plane(32, 32), 1.0),
                           fill="mean").filled == 0
    np.testing.assert_allclose(mean.heights, 0.0, atol=1e-12)    # plane fitted on valid points
    np.save(tmp_path / "empty.npy", np.full((32, 32), np.nan))
    with pytest.raises(ValueError, match="no valid height"):
        read_topography(tmp_path / "empty.npy", file_unit="m", physical_size=1.0, fill="mean")


@pytest.mark.parametrize("kwargs, name", [
    ({"detrend": "quadratic"}, "detrend"),
    ({"fill": "zero"}, "fill"),
    ({"square": "pad"}, "square"),
    ({"reader": "gwyddion"}, "reader"),
    ({"height_unit": "inch"}, "height_unit"),
    ({"physical_size": -1.0}, "physical_size"),
    ({"physical_size": "10 furlong"}, "physical_size"),
    ({"physical_size": (1.0, 2.0, 3.0)}, "physical_size"),
])
def test_bad_options_name_the_parameter(tmp_path, kwargs, name):
    np.save(tmp_path / "map.npy", rough(4, 4))
    arguments = {"file_unit": "m", "physical_size": 1.0} | kwargs
    with pytest.raises(ValueError, match=name):
        read_topography(tmp_path / "map.npy", **arguments)


def test_bad_files(tmp_path):
    with pytest.raises(ValueError, match="path"):
        read_topography(tmp_path / "absent.txt")
    (tmp_path / "words.txt").write_text("a b c\nd e f\n")
    with pytest.raises(ValueError, match="first line is not numbers"):
        read_topography(tmp_path / "words.txt", file_unit="m", physical_size=1.0)
    # a spreadsheet's column names: named as a header row (was "could not convert 'c0.c1...'")
    names = ",".join(f"c{k}" for k in range(32))
    values = "\n".join(",".join(f"{v:.3f}" for v in row) for row in rough(32, 32))
    (tmp_path / "table.csv").write_text(names + "\n" + values)
    with pytest.raises(ValueError, match=r"first line is not numbers \('c0,c1,c2,.*header row"):
        read_topography(tmp_path / "table.csv", file_unit="m", physical_size=1.0)
    (tmp_path / "table.csv").write_text("# " + names + "\n" + values)   # as the message says
    assert read_topography(tmp_path / "table.csv", file_unit="m",
                           physical_size=1.0).heights.shape == (32, 32)
    (tmp_path / "empty.txt").write_text("")
    with pytest.raises(ValueError, match="empty file"):
        read_topography(tmp_path / "empty.txt", file_unit="m", physical_size=1.0)
    np.save(tmp_path / "complex.npy", np.ones((4, 4), dtype=complex))
    with pytest.raises(ValueError, match="real numbers"):
        read_topography(tmp_path / "complex.npy", file_unit="m", physical_size=1.0)
    path = write_gwyddion_ascii(tmp_path / "map.txt", rough(4, 4), 1.0)
    with pytest.raises(ValueError, match="states its physical size"):
        read_topography(path, physical_size=4.0)
    write_gwyddion_ascii(tmp_path / "odd.txt", rough(32, 32), 1.0)
    (tmp_path / "odd.txt").write_text((tmp_path / "odd.txt").read_text(encoding="utf-8")
                                      .replace("Value units: m", "Value units: furlong"),
                                      encoding="utf-8")
    with pytest.raises(ValueError, match="furlong"):
        read_topography(tmp_path / "odd.txt")


def test_instrument_format_without_the_extra_says_how_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "SurfaceTopography", None)
    (tmp_path / "scan.ibw").write_bytes(b"\x00" * 16)
    with pytest.raises(ImportError, match=r"\[topography\]"):
        read_topography(tmp_path / "scan.ibw")


EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "example_topography.txt"


def test_example_file_is_what_the_script_writes(tmp_path):
    """The committed example scan: 10 µm square, 128 x 128, rms slope 0.1 after the tilt is
    removed, and the script that makes it reproduces it."""
    spec = importlib.util.spec_from_file_location(
        "make_example_topography", EXAMPLE.with_name("make_example_topography.py"))
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    script.main(tmp_path / "again.txt")
    committed = read_topography(EXAMPLE, height_unit="um")
    again = read_topography(tmp_path / "again.txt", height_unit="um")
    assert committed.heights.shape == (128, 128) and committed.physical_size == (10.0, 10.0)
    np.testing.assert_allclose(again.heights, committed.heights, rtol=0, atol=1e-6)
    slope = validation.surface_statistics(committed.heights, committed.spacing).rms_gradient
    assert slope == pytest.approx(0.1, rel=0.01)
    assert EXAMPLE.stat().st_size < 300_000


def test_writer_size_unit_differs_from_value_unit(tmp_path):
    path = write_gwyddion_ascii(tmp_path / "a.txt", np.ones((32, 32)) * 2e-9, 1e-6,
                                size_unit="µm")
    assert "# Width: 32 µm" in path.read_text(encoding="utf-8")
    top = read_topography(path, detrend=None, height_unit="nm")
    assert top.spacing == pytest.approx(1000.0)
    np.testing.assert_allclose(top.heights, 2.0)


def test_unit_table():
    assert LENGTH_UNITS["µm"] == LENGTH_UNITS["um"] == LENGTH_UNITS["\u03bcm"] == 1e-6
    assert LENGTH_UNITS["\u00c5"] == LENGTH_UNITS["\u212b"] == 1e-10


class TestSurfaceTopographyReader:
    """The optional extra: an instrument file read through SurfaceTopography's reader."""

    @pytest.fixture(autouse=True)
    def _extra(self):
        self.st = pytest.importorskip("SurfaceTopography")

    def test_x3p_transposed_to_row_y_and_converted(self, tmp_path):
        heights = rough(40, 56)                               # heights[j, i]: 40 rows (y), 56 x
        instrument = self.st.Topography(heights.T.copy(), (28.0, 20.0), unit="µm")  # [x, y]
        if not hasattr(instrument, "to_x3p"):
            pytest.skip("this SurfaceTopography version has no x3p writer")
        instrument.to_x3p(str(tmp_path / "scan.x3p"))
        top = read_topography(tmp_path / "scan.x3p", square="keep", detrend=None,
                              height_unit="nm")
        assert top.heights.shape == (40, 56) and top.spacing == pytest.approx(500.0)
        np.testing.assert_allclose(top.heights, heights * 1e3, rtol=1e-6, atol=1e-6)
        assert "SurfaceTopography" in top.source

    def test_netcdf_and_forced_reader(self, tmp_path):
        heights = rough(32, 32)
        self.st.Topography(heights.T.copy(), (16.0, 16.0), unit="nm").to_netcdf(
            str(tmp_path / "a.nc"))
        top = read_topography(tmp_path / "a.nc", detrend=None)
        np.testing.assert_allclose(top.heights, heights * 1e-9, rtol=1e-12)
        assert top.spacing == pytest.approx(0.5e-9)

    def test_masked_points_are_missing_data_and_size_from_the_caller(self, tmp_path):
        heights = np.ma.masked_array(rough(32, 32), mask=np.zeros((32, 32), dtype=bool))
        heights.mask[2, 3] = True
        self.st.Topography(heights.T.copy(), (16.0, 16.0), unit="nm").to_netcdf(
            str(tmp_path / "m.nc"))
        with pytest.raises(ValueError, match="1 of 1024 points are missing"):
            read_topography(tmp_path / "m.nc")
        assert np.isfinite(read_topography(tmp_path / "m.nc", fill="mean").heights).all()
        np.save(tmp_path / "bare.npy", rough(32, 32))        # states neither size nor unit
        with pytest.raises(ValueError, match="physical_size"):
            read_topography(tmp_path / "bare.npy", reader="surfacetopography", file_unit="nm")
        top = read_topography(tmp_path / "bare.npy", reader="surfacetopography", file_unit="nm",
                              physical_size="16 um", detrend=None, height_unit="nm")
        assert top.spacing == pytest.approx(500.0)
        np.testing.assert_allclose(top.heights, rough(32, 32).T, rtol=1e-12)  # its [x, y] order

    def test_builtin_gwyddion_parser_agrees_with_surfacetopography(self):
        ours = read_topography(EXAMPLE, reader="builtin")
        theirs = read_topography(EXAMPLE, reader="surfacetopography")
        assert ours.spacing == pytest.approx(theirs.spacing, rel=1e-12)
        np.testing.assert_allclose(ours.heights, theirs.heights, rtol=0, atol=1e-15)

    def test_unreadable_file_is_a_value_error(self, tmp_path):
        (tmp_path / "noise.ibw").write_bytes(bytes(range(256)) * 4)
        with pytest.raises(ValueError, match="cannot read"):
            read_topography(tmp_path / "noise.ibw")

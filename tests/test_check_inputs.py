"""A new user's first inputs to the check: rectangular scans as they are, sizes with a width and
a height, arrays refused saying what they are (never naming the cache), numbers as text without
their unit, and units that are implausible for the scan caught before any solve."""

from __future__ import annotations

import math
import tempfile
import tomllib
import warnings

import numpy as np
import pytest

import validation
from validation.check.glance import CLOSED, closed_pressures, glance_lines
from validation.check.library import check_scenes, make_request
from validation.check.physical import PhysicalTable
from validation.check.plausible import PlausibilityWarning, contact_estimate
from validation.check.units import parse_size
from validation.cli import _joined_values, main
from validation.scenes.reader import parse_scene

NM = 1e-9


def _surface(rows: int, columns: int, *, rms_slope: float = 0.2, seed: int = 3) -> np.ndarray:
    """A self-affine map of rms slope ``rms_slope`` in units of its pixel (heights [pixels])."""
    side = max(rows, columns)
    heights = validation.self_affine_surface(side, hurst=0.8, rms_slope=rms_slope, L=float(side),
                                             window=2 * side, seed=seed)
    return np.ascontiguousarray(heights[:rows, :columns])


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return str(tmp_path_factory.mktemp("cache"))


@pytest.mark.parametrize("text, width, height", [
    ("10um", 10e-6, 10e-6), ("10 um", 10e-6, 10e-6), ("1,5 nm", 1.5e-9, 1.5e-9),
    ("10um x 7.8125um", 10e-6, 7.8125e-6), ("10um,7.8125um", 10e-6, 7.8125e-6),
    ("10umx5um", 10e-6, 5e-6), ("10 x 7.8 um", 10e-6, 7.8e-6), ("10um 5um", 10e-6, 5e-6),
    ("10um\u00d75um", 10e-6, 5e-6), (("1um", "2um"), 1e-6, 2e-6), (1e-5, 1e-5, 1e-5),
    ((1e-5, 2e-6), 1e-5, 2e-6)])
def test_a_size_is_a_side_or_a_width_and_a_height(text, width, height):
    assert parse_size("physical_size", text) == pytest.approx((width, height), rel=1e-12)


@pytest.mark.parametrize("text, words", [
    ("10", "needs a unit, e.g. '10nm', '10um' or '10mm'"),
    ("10 x 5", "needs a unit"), ("abc", "physical_size"), ("1um x 2um x 3um", "width and height"),
    (("1um",), "(width, height)")])
def test_a_size_without_its_unit_or_with_three_sides_is_refused(text, words):
    with pytest.raises(ValueError, match="physical_size") as error:
        parse_size("physical_size", text)
    assert words in str(error.value)


def test_a_rectangular_array_is_checked_as_it_is(cache):
    heights = _surface(64, 96) * 39 * NM
    result = validation.check_scan(heights, spacing="39nm", e_star="115GPa",
                                   pressures=("100MPa", "2GPa", 2), cache=cache)
    surface = result.runs[0].scene.surface
    assert surface.grid == (64, 96) and surface.spacing == pytest.approx(39.0, rel=1e-9)
    assert len(result.request.physical_size) == 2          # (width, height)
    area = result.table("area")
    assert area.reference.shape == (2,) and np.all((area.reference > 0) & (area.reference < 1))
    assert "64 x 96 pixels" in result.markdown()


def test_the_issues_200_by_256_array_keeps_its_square_pixels(cache):
    heights = _surface(200, 256) * 39 * NM
    request = make_request(heights, spacing="39nm", e_star="115GPa",
                           pressures=("10MPa", "1GPa", 4), cache_dir=cache)
    scan = request.read("m")
    assert scan.heights.shape == (200, 256) and scan.spacing == pytest.approx(39e-9)
    (scene,), _ = check_scenes(request)
    assert scene.surface.grid == (200, 256) and scene.surface.square == "keep"


@pytest.mark.parametrize("size", [["10um", "5um"], ["10umx5um"], ["10um,5um"], ["10um x 5um"]])
def test_a_text_map_of_256_by_128_takes_its_width_and_height_on_the_command_line(tmp_path, size):
    heights = _surface(128, 256) * 30                      # nm; 256 columns (x), 128 rows (y)
    np.savetxt(tmp_path / "map.txt", heights)
    argv = ["check", str(tmp_path / "map.txt"), "--physical-size", *size, "--file-unit", "nm"]
    from validation.check.command import check_request
    from validation.cli import build_parser

    request = check_request(build_parser().parse_args(_joined_values(argv)))
    scan = request.read("m")
    assert scan.heights.shape == (128, 256)
    assert scan.physical_size == pytest.approx((10e-6, 5e-6)) and scan.spacing == pytest.approx(
        10e-6 / 256)
    (scene,), text = check_scenes(request)
    assert scene.surface.grid == (128, 256)
    assert parse_scene(tomllib.loads(text)).surface.grid == (128, 256)


def test_a_second_size_value_is_never_a_files_name(tmp_path):
    (tmp_path / "5um").write_text("")
    argv = ["check", "a.txt", "--physical-size", "10um", str(tmp_path / "5um")]
    assert _joined_values(argv) == argv
    assert _joined_values(["check", "--physical-size", "10um", "5um", "a.txt"])[1:] == [
        "--physical-size=10um x 5um", "a.txt"]


def test_a_rectangular_file_whose_pixels_are_not_square_says_how_to_resample(tmp_path, capsys):
    np.savetxt(tmp_path / "map.txt", _surface(128, 256) * 30)
    assert main(["check", str(tmp_path / "map.txt"), "--physical-size", "10um", "--file-unit",
                 "nm", "--out", str(tmp_path / "o"), "--no-cache"]) == 2
    err = capsys.readouterr().err
    assert "pixels are not square" in err and "--resample" in err


def _refused(scan, **options) -> str:
    options = {"spacing": "3nm"} | options
    with pytest.raises((ValueError, TypeError)) as error:
        validation.check_scan(scan, cache=False, **options)
    message = str(error.value)
    assert tempfile.gettempdir() not in message and "scan-" not in message, (
        f"the message names a file the user never wrote: {message}")
    return message


def test_odd_arrays_are_refused_saying_what_they_are():
    heights = _surface(64, 64) * 3 * NM
    high = heights > np.quantile(heights, 0.99)
    assert "complex" in _refused(heights.astype(complex))
    assert "fill='mean'" in _refused(np.where(high, np.nan, heights))
    assert "infinite" in _refused(np.where(high, np.inf, heights))
    assert "8 x 8" in _refused(heights[:8, :8]) and "32 x 32" in _refused(heights[:8, :8])
    assert "no valid height" in _refused(np.full((64, 64), np.nan), fill="mean")
    assert "2-D" in _refused(heights[0])
    assert "physical_size is for a file" in _refused(heights, physical_size="1um")
    # missing points filled when asked: the array is checked
    request = make_request(np.where(high, np.nan, heights), spacing="3nm", fill="mean",
                           cache_dir=None)
    assert request.read("m").filled == int(high.sum())


@pytest.mark.parametrize("options, words", [
    (dict(spacing="10"), "spacing needs a unit, e.g. '10nm', '10um' or '10mm', got '10'"),
    (dict(e_star="115"), "e_star needs a unit, e.g. '115MPa' or '115GPa'"),
    (dict(short_cutoff="20"), "'20px'"),
    (dict(nominal_size="10"), "nominal_size needs a unit")])
def test_a_number_as_text_without_its_unit_is_refused_with_the_units_it_could_mean(options,
                                                                                  words):
    assert words in _refused(_surface(64, 64) * 3 * NM, **options)


def test_heights_in_nanometres_read_as_metres_are_refused_naming_the_mistake():
    message = _refused(_surface(64, 64) * 3)                # nm meant, metres read
    assert "heights in nm read as metres" in message and "rms slope" in message
    assert "file_unit" in message


def test_a_scan_wider_than_a_metre_or_finer_than_an_atom_is_refused():
    heights = _surface(64, 64)
    assert "wide" in _refused(heights * 0.1, spacing="0.1m")
    assert "finer than an atom" in _refused(heights * 1e-12, spacing=1e-12)


def test_e_star_in_the_wrong_unit_is_refused_where_every_pressure_is_closed_or_open():
    heights = _surface(64, 64, rms_slope=0.02) * 3 * NM
    closed = _refused(heights, e_star="115MPa", pressures=("20MPa", "100MPa", 3))
    assert "full contact at 20 MPa" in closed and "115 GPa" in closed
    open_ = _refused(heights, e_star="115GPa", pressures=("1kPa", "10kPa", 3))
    assert "no contact at 10 kPa" in open_ and "115 MPa" in open_


@pytest.mark.filterwarnings("ignore:.*full contact of a periodic surface")
def test_a_range_that_reaches_full_contact_is_warned_about(capsys, tmp_path):
    heights = _surface(64, 64) * 3 * NM                     # rms slope 0.2
    with pytest.warns(PlausibilityWarning, match="contact is closed") as caught:
        make_request(heights, spacing="3nm", e_star="115MPa", pressures=("1MPa", "100MPa", 3),
                     cache_dir=str(tmp_path))
    assert "115 GPa" in str(caught[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error")                      # a plausible range: no warning
        make_request(heights, spacing="3nm", e_star="115GPa", pressures=("10MPa", "1GPa", 3),
                     cache_dir=str(tmp_path))
    np.save(tmp_path / "scan.npy", heights / NM)
    main(["check", str(tmp_path / "scan.npy"), "--physical-size", f"{64 * 3}nm", "--file-unit",
          "nm", "--e-star", "115MPa", "--pressure", "1MPa:100MPa:2", "--out",
          str(tmp_path / "o"), "--cache", str(tmp_path / "c"), "--quiet"])
    assert "warning: scan.npy: from about" in capsys.readouterr().err


def test_a_steep_map_is_warned_about_and_a_cutoff_suggested(tmp_path):
    with pytest.warns(PlausibilityWarning, match="--short-cutoff 8px"):
        make_request(_surface(64, 64, rms_slope=2.0) * 3 * NM, spacing="3nm",
                     cache_dir=str(tmp_path))


def test_persson_estimate_is_erf_of_root_two_p_over_e_star_slope():
    slope = 0.1
    assert float(contact_estimate(0.0, slope)) == 0.0
    assert float(contact_estimate(1e-4, slope)) == pytest.approx(
        math.sqrt(8 / math.pi) * 1e-4 / slope, rel=1e-5)           # kappa = sqrt(8/pi)
    assert float(contact_estimate(slope, slope)) == pytest.approx(math.erf(math.sqrt(2)))


def _table(field: str, reference, verdicts) -> PhysicalTable:
    load = np.array([1e-4, 1e-3, 1e-2])
    return PhysicalTable(field, field, "", load, load * 1e9, np.asarray(reference, float),
                         np.full(3, 0.01), {"persson": np.ones(3)},
                         {"persson": np.array(verdicts)}, 0.2)


def test_the_glance_says_where_the_reference_is_in_full_contact():
    tables = [_table("area", [0.3, 0.995, 1.0], ["holds"] * 3),
              _table("separation", [3.0, 1.0, 0.1], ["holds"] * 3)]
    assert closed_pressures(tables).tolist() == [False, True, True]
    lines = "\n".join(glance_lines(tables))
    assert "holds everywhere" not in lines
    assert "**Full contact** at 1 MPa to 10 MPa" in lines and f"{100 * CLOSED:g} %" in lines
    assert "Persson holds at every pressure, 2 of them in full contact (1 MPa to 10 MPa)" in lines
    open_ = "\n".join(glance_lines([_table("area", [0.01, 0.1, 0.3], ["holds"] * 3)]))
    assert "Persson holds everywhere." in open_ and "Full contact" not in open_


@pytest.mark.parametrize("value, digits, text", [
    (1567.0, 3, "1570"), (0.00123, 3, "0.00123"), (12.34, 3, "12.3"), (0.5, 3, "0.5"),
    (999.7, 3, "1000"), (999.7, 4, "999.7"), (2.0, 3, "2"), (123456.0, 3, "123000"),
    (1e7, 3, "1e+07"), (1.5e-5, 3, "1.5e-05"), (-1567.2, 3, "-1570"), (0.0, 3, "0")])
def test_numbers_are_written_without_an_exponent_where_a_reader_writes_none(value, digits, text):
    from validation.surfaces.units import readable

    assert readable(value, digits) == text


def test_the_guide_states_the_plausibility_limits_the_program_uses():
    import pathlib

    from validation.check import plausible

    text = (pathlib.Path(__file__).resolve().parents[1] / "docs" / "guide"
            / "your-surface.md").read_text(encoding="utf-8")
    paragraph = text[text.index("**Units checked before any solve.**"):]
    paragraph = paragraph[:paragraph.index("\n\n")]
    assert f"rms slope above {plausible.STEEP:g}" in paragraph
    assert f"Sq above {plausible.TALL * 1e3:g} mm" in paragraph
    assert f"wider\nthan {plausible.WIDE:g} m" in paragraph or \
        f"wider than {plausible.WIDE:g} m" in paragraph
    assert f"finer than {plausible.FINE * 1e9:g} nm" in paragraph
    assert f"at least {100 * plausible.FULL:g} %" in paragraph
    assert f"at least {100 * CLOSED:g} %" in paragraph.replace("\n", " ")

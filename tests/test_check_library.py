"""The check as a library call: validation.check_scan and its CheckResult give the command's
numbers, read in a notebook without writing anything, pickle, and write the same report that
``python -m validation report check.toml`` writes again."""

from __future__ import annotations

import csv
import pickle

import numpy as np
import pytest

import validation
from validation import check_scan
from validation.cli import main

SPACING = 2e-9   # m


@pytest.fixture(scope="module")
def heights():
    return validation.self_affine_surface(64, hurst=0.8, rms_slope=0.3, L=64.0, window=128,
                                          seed=5) * SPACING


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("cache")


@pytest.fixture(scope="module")
def result(heights, cache):
    return check_scan(heights, spacing=SPACING, e_star="115GPa",
                      pressures=("20MPa", "2GPa", 3), cache=cache)


def _rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def test_the_library_call_gives_the_commands_numbers(result, heights, cache, tmp_path):
    np.save(tmp_path / "scan.npy", heights)
    out = tmp_path / "command"
    assert main(["check", str(tmp_path / "scan.npy"), "--physical-size",
                 f"{64 * SPACING}m", "--file-unit", "m", "--e-star", "115GPa", "--pressure",
                 "20MPa:2GPa:3", "--out", str(out), "--cache", str(cache), "--quiet"]) == 0
    written = _rows(out / "physical.csv")
    assert len(written) == sum(len(t.rows()) for t in result.tables) > 0
    for row, expected in zip(written, (r for t in result.tables for r in t.rows())):
        assert row["model"] == expected["model"] and row["field"] == expected["field"]
        assert float(row["value"]) == pytest.approx(expected["value"], rel=1e-9)
        assert row["verdict"] == (expected["verdict"] or "")


def test_a_table_reads_one_field_and_names_the_others_when_asked_for_one_it_lacks(result):
    area = result.table("area")
    assert area.field == "area" and area.pressure is not None
    assert area.pressure == pytest.approx([2e7, 2e8, 2e9])
    assert str(area) == area._repr_markdown_() == area.markdown()
    assert area.markdown() in "\n".join(result.sections)   # the report shows the same table
    assert set(area.models) >= {"gw", "persson"} and set(area.verdicts) == set(area.models)
    with pytest.raises(ValueError, match=r"field must be one the check compared \('area'"):
        result.table("volume")
    assert "At a glance" in result.glance() and result.glance() in result.markdown()


def test_the_stiffness_has_one_name_and_is_found_by_the_other(result, tmp_path):
    """The check says "stiffness" in its report, its tables, physical.csv and errors.csv; the
    ensemble reports' "conductance" finds the same table."""
    assert "stiffness" in result.fields and "conductance" not in result.fields
    assert result.table("conductance") is result.table("stiffness")
    assert result.table("stiffness").unit == "N/m³"
    result.write_report(tmp_path / "out")
    assert {row["field"] for row in _rows(tmp_path / "out" / "physical.csv")} >= {"stiffness"}
    quantities = {row["quantity"] for row in _rows(tmp_path / "out" / "errors.csv")}
    assert "stiffness" in quantities and "conductance" not in quantities


def test_the_result_pickles_and_converts_to_data_frames(result):
    again = pickle.loads(pickle.dumps(result))
    assert again.fields == result.fields
    for a, b in zip(again.tables, result.tables):
        np.testing.assert_array_equal(a.reference, b.reference)
    pandas = pytest.importorskip("pandas")
    frame = result.to_frame()
    assert isinstance(frame, pandas.DataFrame)
    assert len(frame) == sum(len(t.rows()) for t in result.tables)
    wide = result.table("area").to_frame()
    np.testing.assert_array_equal(wide["reference"], result.table("area").reference)
    assert list(wide["gw verdict"]) == list(result.table("area").verdicts["gw"])


def test_the_figure_has_one_panel_per_table(result):
    figure = result.plot()
    assert sum(ax.get_visible() for ax in figure.axes) == len(result.tables)


@pytest.mark.parametrize("count", [1, 3, None])
def test_the_figures_labels_and_legend_lie_inside_it(result, count):
    """Fixed margins: every tick label, axis label and the legend inside the figure, whatever
    the number of panels (one column: the legend in two columns)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from validation.check.figure import physical_figure

    figure = physical_figure(list(result.tables)[:count])
    renderer = FigureCanvasAgg(figure).get_renderer()
    inside = figure.bbox.padded(1.0)
    boxes = [ax.get_tightbbox(renderer) for ax in figure.axes if ax.get_visible()]
    boxes += [legend.get_window_extent(renderer) for legend in figure.legends]
    assert boxes and all(inside.x0 <= b.x0 and b.x1 <= inside.x1 and inside.y0 <= b.y0
                         and b.y1 <= inside.y1 for b in boxes)
    panels = sorted((ax.get_tightbbox(renderer) for ax in figure.axes if ax.get_visible()),
                    key=lambda b: (b.y0, b.x0))
    legend = figure.legends[0].get_window_extent(renderer)
    assert legend.y1 <= min(b.y0 for b in panels)   # below every panel, overlapping none


def test_the_checks_figure_is_drawn_with_the_reports_and_read_back_from_the_cache(
        result, tmp_path, monkeypatch):
    from validation.report import figures

    cache = tmp_path / "cache"
    result.write_report(tmp_path / "one", cache_dir=cache)
    drawn, png = [], figures.png

    def counted(fig, **options):
        drawn.append(fig)
        return png(fig, **options)
    monkeypatch.setattr(figures, "png", counted)
    result.write_report(tmp_path / "two", cache_dir=cache)
    assert drawn == []   # every figure, the check's own too, from the cache
    pictures = sorted(path.name for path in (tmp_path / "one").glob("*.png"))
    assert "check-physical.png" in pictures and len(pictures) > 1
    assert pictures == sorted(path.name for path in (tmp_path / "two").glob("*.png"))
    for name in pictures:
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes()
    result.write_report(tmp_path / "three")   # no cache: drawn again, the same picture
    assert len(drawn) == len(pictures)
    assert (tmp_path / "three" / "check-physical.png").read_bytes() == \
        (tmp_path / "one" / "check-physical.png").read_bytes()


def test_the_written_report_is_written_again_from_its_scene(result, cache, tmp_path):
    first = result.write_report(tmp_path / "one")
    assert (tmp_path / "one" / "scan.npy").is_file()
    assert main(["report", str(tmp_path / "one" / "check.toml"), "--out", str(tmp_path / "two"),
                 "--cache", str(cache), "--quiet"]) == 0
    assert _rows(tmp_path / "one" / "physical.csv") == _rows(tmp_path / "two" / "physical.csv")
    text = [(tmp_path / name / "report.md").read_text(encoding="utf-8") for name in ("one", "two")]
    start = [t.index("## Your surface") for t in text]
    assert text[0][start[0]:] == text[1][start[1]:]   # all but the header (command, time)
    assert "E* = 115 GPa" in text[1] and first.name == "report.md"
    assert "Sq (rms height) = " in text[0] and "σ (rms of the summit heights)" in text[0]
    # the check's answer stands for the summary; the paper's findings speak of populations
    assert "## Summary" not in text[0] and "## Findings" not in text[0]
    assert text[0].count("## At a glance") + text[0].count("**At a glance**") == 1


def test_a_topography_is_checked_as_its_heights(result, heights, cache):
    scan = validation.Topography(heights / 1e-9, SPACING / 1e-9, (64 * SPACING / 1e-9,) * 2, "nm",
                                 "an array")
    again = check_scan(scan, e_star=115e9, pressures=(2e7, 2e9, 3), cache=cache)
    np.testing.assert_allclose(again.table("area").reference, result.table("area").reference,
                               rtol=1e-9)


@pytest.mark.parametrize("options, error, words", [
    (dict(), ValueError, "needs its spacing"),
    (dict(spacing=SPACING, e_star="115"), ValueError, "e_star needs a unit"),
    (dict(spacing=SPACING, pressures=(1e6,)), TypeError, "pressures must be"),
    (dict(spacing=SPACING, pressures="1MPa:100MPa"), ValueError, "needs e_star"),
    (dict(spacing=SPACING, models=["nope"]), ValueError, "models must name"),
    (dict(spacing=-1.0), ValueError, "spacing must be a finite real number > 0"),
    (dict(spacing=SPACING, tiles=3), ValueError, "tiles must be a square number"),
])
def test_bad_arguments_are_refused_naming_the_keyword(heights, options, error, words):
    with pytest.raises(error, match=words):
        check_scan(heights, cache=False, **options)


def test_what_is_not_a_scan_is_refused():
    with pytest.raises(TypeError, match="scan must be a file path, a Topography or a 2-D"):
        check_scan(42, cache=False)
    with pytest.raises(ValueError, match="2-D map of heights"):
        check_scan(np.zeros(8), spacing=1e-9, cache=False)
    with pytest.raises(ValueError, match="names no file"):
        check_scan("no-such-scan.di", cache=False)


def test_the_errors_of_one_surface_leave_the_interval_empty(result, tmp_path):
    result.write_report(tmp_path / "report")
    rows = _rows(tmp_path / "report" / "errors.csv")
    assert rows and all(r["realizations"] == "1" for r in rows)
    assert all(r["ci95_low"] == r["ci95_high"] == r["std_error"] == "" for r in rows)
    assert all(r["mean_error"] != "" for r in rows if r["model"] == "gw")

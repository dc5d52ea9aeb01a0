"""One scan, one answer: what the check says where the reference cannot judge, how it reads
odd input, and the command line's values with a leading minus (each refused naming what is
wrong)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from validation.check.glance import glance_lines
from validation.check.physical import PhysicalTable
from validation.check.resolution import Resolution, resolution, resolution_lines, unjudged
from validation.cli import _joined_values, main


def _table(field: str, verdicts) -> PhysicalTable:
    load = np.array([1e-5, 1e-4, 1e-3])
    return PhysicalTable(field, field, "", load, load * 1e11, np.ones(3), np.full(3, 0.1),
                         {"gw": np.ones(3), "persson": np.ones(3)},
                         {"gw": np.array(verdicts), "persson": np.array(["fails"] * 3)}, 0.2)


def test_the_glance_names_no_theory_for_a_field_the_reference_cannot_judge():
    tables = [_table("area", ["holds", "fails", "fails"]),
              _table("separation", ["holds", "holds", "fails"])]
    plain = glance_lines(tables)
    assert any("original GW holds at 1 of 3" in line for line in plain)
    rows = [Resolution("area", 0.38, 0.49, 0.05, 3)]
    said = glance_lines(tables, unjudged(rows, spacing=1.0, unit="nm", short_cutoff=None))
    area = next(line for line in said if line.startswith("- Area"))
    assert "not judged at this resolution" in area and "holds" not in area
    assert "median 38 %" in area and "--short-cutoff 8px" in area and "8 nm" in area
    assert any("original GW holds at 2 of 3" in line for line in said)   # the others still are
    # with a cutoff applied, the remedy is a longer one
    again = unjudged(rows, spacing=1.0, unit="nm", short_cutoff="8e-09 m")
    assert "longer" in again["area"] and "--short-cutoff 16px" in again["area"]
    assert unjudged([Resolution("area", 0.01, 0.02, 0.01, 0)], spacing=1.0, unit="nm",
                    short_cutoff=None) == {}


def test_the_resolution_leaves_out_the_reference_methods_own_error():
    class Entry:   # the comparison's entry of one model: its reference field and band
        def __init__(self, field, band):
            self.reference_field, self.band = field, band

    class Comparison:
        def __init__(self, bands):
            self.models = {(f, "x"): Entry(f, np.asarray(b)) for f, b in bands.items()}

    sampled = Comparison({"separation": [0.09, 0.095], "area": [0.3, 0.4]})
    final = Comparison({"separation": [0.086, 0.086], "area": [0.1, 0.1]})
    method = {"separation": np.array([0.085, 0.085]), "area": np.array([0.07, 0.07])}
    rows = {r.field: r for r in resolution(sampled, final, method=method)}
    assert rows["separation"].half_grid_median == pytest.approx(0.0075)
    assert rows["separation"].converged and not rows["area"].converged
    assert rows["area"].final_median == pytest.approx(0.03)
    plain = {r.field: r for r in resolution(sampled, final)}
    assert not plain["separation"].converged   # the method's bound alone is not resolution


def test_the_resolution_names_the_scale_that_sets_the_area():
    rows = [Resolution("area", 0.3, 0.4, 0.05, 3)]
    pixel = "\n".join(resolution_lines(rows, spacing=0.977, unit="nm", short_cutoff=None))
    assert "scale of the pixel (0.977 nm)" in pixel
    cut = "\n".join(resolution_lines(rows, spacing=0.977, unit="nm", short_cutoff="7.816e-09 m"))
    assert "scale of the cutoff (7.82 nm)" in cut and "scale of the pixel" not in cut


def test_values_with_a_leading_minus_reach_their_options_check(tmp_path, capsys):
    assert _joined_values(["check", "s", "--e-star", "-115GPa", "--out", "o"]) == [
        "check", "s", "--e-star=-115GPa", "--out", "o"]
    assert _joined_values(["--quiet", "--e-star", "--out"]) == ["--quiet", "--e-star", "--out"]
    scan = tmp_path / "scan.npy"
    np.save(scan, np.random.default_rng(0).standard_normal((64, 64)))
    base = ["check", str(scan), "--physical-size", "1um", "--file-unit", "nm", "--out",
            str(tmp_path / "o")]
    for option, value, words in (("--e-star", "-115GPa", "--e-star must be a positive"),
                                 ("--short-cutoff", "-5nm", "--short-cutoff must be"),
                                 ("--tiles", "-4", "--tiles must be a square number")):
        assert main(base + [option, value]) == 2
        assert words in capsys.readouterr().err


@pytest.mark.parametrize("options, words", [
    (["--e-star", "115GPa", "--pressure", "1MPa:100MPa:100000"], "COUNT must be at most 100"),
    (["--tiles", "16"], "--tiles 16 cuts the 64 x 64-pixel scan into tiles of 16 pixels"),
])
def test_counts_no_one_means_are_refused_naming_the_option(tmp_path, capsys, options, words):
    scan = tmp_path / "scan.npy"
    np.save(scan, np.random.default_rng(0).standard_normal((64, 64)))
    assert main(["check", str(scan), "--physical-size", "1um", "--file-unit", "nm", "--out",
                 str(tmp_path / "o")] + options) == 2
    assert words in capsys.readouterr().err


def test_a_plane_and_a_tiny_matrix_are_refused_saying_what_they_are(tmp_path, capsys):
    np.save(tmp_path / "plane.npy", np.arange(4096).reshape(64, 64))
    assert main(["check", str(tmp_path / "plane.npy"), "--physical-size", "1um", "--file-unit",
                 "nm", "--e-star", "1GPa", "--pressure", "1MPa:10MPa:2", "--out",
                 str(tmp_path / "o")]) == 2
    assert "flat after removing its mean plane" in capsys.readouterr().err
    np.savetxt(tmp_path / "m.txt", np.array([[1.0, 2.0], [3.0, 4.0]]))
    assert main(["check", str(tmp_path / "m.txt"), "--physical-size", "1um", "--file-unit", "nm",
                 "--out", str(tmp_path / "o2")]) == 2
    err = capsys.readouterr().err
    assert "not a height map" in err and "at least 32 x 32" in err


def test_a_format_that_needs_the_extra_says_so_first(tmp_path, monkeypatch):
    from validation.surfaces import formats

    (tmp_path / "scan.mi").write_text("fileType      Image\nxPixels 256\n", encoding="utf-8")
    monkeypatch.setitem(sys.modules, "SurfaceTopography", None)   # as if not installed
    with pytest.raises(ImportError) as error:
        formats.load_map(tmp_path / "scan.mi")
    message = str(error.value)
    assert message.startswith(f"{tmp_path / 'scan.mi'}: reading '.mi' files needs the optional "
                              f"extra: pip install")
    assert message.index("optional extra") < message.index("first line is not numbers")


def test_no_surface_interval_of_a_relative_error_reaches_below_minus_one():
    from validation.judge.headline import headline_numbers
    from validation.judge.tolerance import surface_interval

    mean, std, count = np.array([-0.4, 0.1]), np.array([0.5, 0.01]), np.array([8, 8])
    free = surface_interval(mean, std, count)
    bounded = surface_interval(mean, std, count, floor=-1.0)
    assert free.low[0] < -1.0 and bounded.low[0] == -1.0
    assert bounded.low[1] == free.low[1] and np.array_equal(bounded.high, free.high)
    errors = np.column_stack([np.linspace(-0.95, 0.3, 8), np.linspace(-0.95, 0.3, 8)])
    cells = headline_numbers(errors, np.zeros(2), (0.05, 0.2), floor=np.array([-1.0, -np.inf]))
    assert cells["surface_low"][0] == -1.0 and cells["surface_low"][1] < -1.0
    assert np.array_equal(cells["surface_verdicts"][:, 0], cells["surface_verdicts"][:, 1])


def test_surprising_values_are_explained_under_their_table():
    from validation.check.physical import table_lines

    load = np.array([1e-5, 1e-4])
    separation = PhysicalTable("separation", "Separation d", "nm", load, None,
                               np.array([2.0, -0.5]), np.array([0.1, 0.1]), {"gw": np.ones(2)},
                               {"gw": np.array(["holds", "fails"])}, 0.2)
    assert "A negative separation" in "\n".join(table_lines(separation))
    leakage = PhysicalTable("leakage", "h_eff", "nm", load, None, np.array([3.0, 0.0]),
                            np.array([0.1, 0.0]), {"gw": np.ones(2)},
                            {"gw": np.array(["holds", "fails"])}, 0.2)
    assert "h_eff = 0" in "\n".join(table_lines(leakage))
    area = PhysicalTable("area", "A/A0", "", load, None, np.array([1e-4, 1e-2]),
                         np.array([2e-4, 1e-3]), {"gw": np.ones(2)},
                         {"gw": np.array(["undecided", "fails"])}, 0.2)
    text = "\n".join(table_lines(area))
    assert "At 1 pressure(s) the reference's band is wider than its value" in text
    assert "negative" not in text and "h_eff = 0" not in text


def test_the_sink_is_written_in_the_unit_that_reads_best():
    from validation.check.frames import frame_lines

    load = np.array([1e-4, 1e-3])
    table = PhysicalTable("area", "A/A0", "", load, None, np.ones(2), np.zeros(2), {}, {}, 0.2)
    text = frame_lines([table], sigma=5.0, unit="nm", e_star=115e9, nominal_size=2e7)  # 20 mm
    assert "m p L/E* = 18.9 um = 3,786 σ" in text[0]


def test_a_table_the_reference_cannot_judge_shows_its_values_without_marks():
    from validation.check.physical import table_lines

    table = _table("area", ["holds", "fails", "undecided"])
    judged = "\n".join(table_lines(table))
    assert "✔" in judged and "✘" in judged
    from dataclasses import replace

    plain = "\n".join(table_lines(replace(table, judged=False)))
    rows = [line for line in plain.splitlines() if line.startswith("| ") and "%" in line]
    assert rows and not any(mark in row for row in rows for mark in "✔✘?")
    assert "not judged at this resolution" in plain

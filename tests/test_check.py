"""``python -m validation check``: one measured scan, answered in physical units.

The known answer: a scan whose only contact at light load is one paraboloidal cap of radius R.
Hertz's solution is then exact for the discrete asperity model (a = (3 W R / 4 E*)^(1/3), area
pi a^2, stiffness S = 2 a E*), and the boundary-element reference must agree with it within its
own band and a few per cent of discretisation.
"""

import csv
import math
import re

import numpy as np
import pytest

from validation.check.units import (format_length, format_pressure, length_unit_for,
                                    parse_length, parse_pressure, parse_pressure_range)
from validation.cli import main

SIDE, PIXELS, RADIUS = 12.8, 128, 40.0      # um, pixels, um
E_STAR = 100e9                              # Pa


def rows(path):
    with open(path, newline="") as stream:
        return list(csv.DictReader(stream))


@pytest.mark.parametrize("text, value, has_unit", [
    ("115GPa", 115e9, True), ("115 GPa", 115e9, True), ("1.15e11 Pa", 1.15e11, True),
    ("3 MPa", 3e6, True), ("200 kPa", 2e5, True), ("1e-4", 1e-4, False), ("2 bar", 2e5, True),
])
def test_pressures_parse_with_and_without_prefix(text, value, has_unit):
    parsed, unit = parse_pressure("--e-star", text)
    assert parsed == pytest.approx(value, rel=1e-12) and unit is has_unit


@pytest.mark.parametrize("text, value", [("20nm", 20e-9), ("0.5 um", 0.5e-6), ("0.5µm", 0.5e-6),
                                         ("3 Å", 3e-10), ("1.5mm", 1.5e-3)])
def test_lengths_parse(text, value):
    assert parse_length("--short-cutoff", text)[0] == pytest.approx(value, rel=1e-12)


@pytest.mark.parametrize("text, match", [("115 GPascal", "unknown unit"), ("-1 GPa", "positive"),
                                         ("GPa", "pressure like"), ("0 Pa", "positive"),
                                         ("inf Pa", "pressure like")])
def test_bad_pressures_name_the_option(text, match):
    with pytest.raises(ValueError, match=f"--e-star.*{match}|{match}.*--e-star|--e-star: {match}"):
        parse_pressure("--e-star", text)


def test_pressure_ranges():
    r = parse_pressure_range("1MPa:100MPa")
    assert (r.low, r.high, r.count, r.physical) == (1e6, 1e8, 12, True)
    assert r.dimensionless(1e11) == pytest.approx((1e-5, 1e-3))
    assert parse_pressure_range("1e-5:1e-3:7").dimensionless(None) == pytest.approx((1e-5, 1e-3))
    with pytest.raises(ValueError, match="needs --e-star"):
        r.dimensionless(None)
    for bad, match in (("1MPa", "LOW:HIGH"), ("1MPa:1e-3", "both ends"), ("5MPa:1MPa", "greater"),
                       ("1MPa:2MPa:0", "COUNT"), ("1MPa:2MPa:x", "COUNT"),
                       ("1MPa:100MPa:1", "COUNT must be at least 2")):
        with pytest.raises(ValueError, match=match):
            parse_pressure_range(bad)
    with pytest.raises(ValueError, match="below E"):
        parse_pressure_range("1GPa:200GPa").dimensionless(100e9)


def test_readable_units():
    assert length_unit_for(3e-7) == "nm" and length_unit_for(3e-6) == "um"
    assert format_pressure(3.2e6) == "3.2 MPa" and format_length(2e-8) == "20 nm"
    # a value that prints as a round 1000 moves to the next prefix (1 MPa after a round trip
    # through E* is 999999.9999 Pa, and was shown as "1e+03 kPa")
    assert format_pressure(1e6 * (1 - 1e-12)) == "1 MPa"
    assert format_pressure(999.4e3) == "999 kPa" and format_pressure(999.6e3) == "1 MPa"
    assert format_length(1e-6 * (1 - 1e-12)) == "1 um" and format_length(999e-9) == "999 nm"


def test_the_remedy_for_an_unconverged_area_is_a_longer_cutoff_than_the_one_applied():
    from validation.check.resolution import Resolution, cutoff_text, resolution_lines

    area = [Resolution("area", 0.3, 0.5, 0.02, 12)]
    plain = "\n".join(resolution_lines(area, spacing=0.98, unit="nm", short_cutoff=None))
    assert "not converged" in plain and "`--short-cutoff 8px` (= 7.84 nm)" in plain
    assert "tables above" in plain
    filtered = "\n".join(resolution_lines(area, spacing=0.98, unit="nm",
                                          short_cutoff="7.84e-09 m"))
    # filtered at 8 px already: the advice is a longer cutoff (16 px), in the scan's unit
    assert "low-pass filtered at 7.84 nm (8 px)" in filtered
    assert "`--short-cutoff 16px` (= 15.7 nm)" in filtered and "8px" not in filtered
    assert cutoff_text("1.5e-05 m", 1.66, "um") == "15 um (9.04 px)"
    converged = [Resolution("area", 0.01, 0.02, 0.01, 0)]
    text = "\n".join(resolution_lines(converged, spacing=1.0, unit="nm", short_cutoff="8e-9 m"))
    assert "is converged" in text and "8 nm (8 px)" in text


def test_the_full_contact_ceiling_is_the_references_own():
    """A flat square window in full contact (a rigid punch): K L / E* from the reference."""
    import bem
    from validation.check.frames import FULL_CONTACT_STIFFNESS

    flat = bem.solve_contact(np.zeros((64, 64)), 1.0 / 64, load=1e-3, stiffness=True)
    assert flat.contact.all()
    assert flat.stiffness == pytest.approx(FULL_CONTACT_STIFFNESS, rel=5e-3)


def _stiffness_table(load, stiffness, unit="N/m³"):
    from validation.check.physical import PhysicalTable

    load = np.asarray(load, float)
    return PhysicalTable("stiffness", "K", unit, load, load * 115e9, np.asarray(stiffness),
                         0.01 * np.asarray(stiffness), {}, {}, 0.2)


def test_the_frames_paragraph_names_the_nominal_contacts_sink_and_ceiling():
    from bem.reference import UNIFORM_SQUARE_MEAN_DEFLECTION as m
    from validation.check.frames import FULL_CONTACT_STIFFNESS, frame_lines

    e_star = 115e9
    table = _stiffness_table([1e-4, 1e-3], [1e12, 1e13])
    (plain,) = frame_lines([table], sigma=2.0, unit="um", e_star=e_star, nominal_size=None)
    assert "*Interface*" in plain and "`--nominal-size`" in plain
    # a 10 mm nominal contact (side in um) at p/E* up to 1e-3: it sinks by m p L / E* = 9.46 um
    side = 1e4
    (text,) = frame_lines([table], sigma=2.0, unit="um", e_star=e_star, nominal_size=side)
    assert f"{m * 1e-3 * side:.3g} um = {m * 1e-3 * side / 2.0:.3g} σ" in text
    ceiling = FULL_CONTACT_STIFFNESS * e_star / (side * 1e-6)
    assert f"{ceiling:.3g} N/m³" in text
    assert frame_lines([], sigma=2.0, unit="um", e_star=e_star, nominal_size=None) == []


def test_at_a_glance_each_theory_has_one_strip_per_field_and_the_best_is_named():
    from validation.check.glance import glance_lines
    from validation.check.physical import PhysicalTable

    load = np.array([1e-5, 1e-4, 1e-3, 1e-2])       # p/E*: 1.15, 11.5, 115, 1150 MPa
    h, f, u = "holds", "fails", "undecided"

    def table(field, verdicts):
        return PhysicalTable(field, field, "", load, load * 115e9, load, 0 * load,
                             {m: load for m in verdicts},
                             {m: np.array(v) for m, v in verdicts.items()}, 0.2, "20 %")

    area = table("area", {"gw": [f, f, h, h], "persson": [u, h, h, f]})
    leakage = table("leakage", {"gw": [f, f, f, u], "persson": [f, f, f, f]})
    text = "\n".join(glance_lines([area, leakage]))
    assert "at the 4 pressures from 1.15 MPa to 1.15 GPa" in text
    assert "| original GW | ✘✘✔✔ | ✘✘✘? |" in text and "| Persson | ?✔✔✘ | ✘✘✘✘ |" in text
    # ties on holds go to the fewer failures; the pressures are named as ranges
    assert "- Area A/A0: Persson holds at 2 of 4 pressures (11.5 MPa to 115 MPa)." in text
    assert "- Leakage h_eff: no theory holds at any pressure (some are undecided)." in text
    everywhere = table("area", {"gw": [h, h, h, h]})
    assert "- Area A/A0: original GW holds everywhere." in glance_lines([everywhere])


def _one_cap_scan(path):
    """16 paraboloidal caps of radius RADIUS on a 4 x 4 lattice; the cap of cell (1, 1) stands
    0.1 um above the others, so at light load it is the only contact (its indentation stays
    below 0.02 um); no linear trend, so removing the mean plane leaves it on top."""
    spacing = SIDE / PIXELS
    y, x = np.mgrid[0:PIXELS, 0:PIXELS] * spacing
    caps = [(0.0 if k == 5 else -0.1)
            - ((x - (16 + 32 * (k % 4)) * spacing) ** 2
               + (y - (16 + 32 * (k // 4)) * spacing) ** 2) / (2 * RADIUS) for k in range(16)]
    np.save(path, np.max(caps, axis=0))


@pytest.fixture(scope="module")
def checked(tmp_path_factory):
    folder = tmp_path_factory.mktemp("check")
    _one_cap_scan(folder / "cap.npy")
    out = folder / "out"
    status = main(["check", str(folder / "cap.npy"), "--physical-size", f"{SIDE} um",
                   "--file-unit", "um", "--e-star", "100GPa", "--pressure", "2MPa:10MPa:3",
                   "--out", str(out), "--cache", str(folder / "cache"), "--jobs", "1",
                   "--quiet"])
    assert status == 0
    return folder, out


def _values(out, field, model):
    return {int(r["point"]): r for r in rows(out / "physical.csv")
            if r["field"] == field and r["model"] == model}


def test_one_cap_is_hertz_in_physical_units(checked):
    _, out = checked
    area_fraction = _values(out, "area", "discrete_no_interaction")
    reference = _values(out, "area", "bem")
    stiffness = _values(out, "stiffness", "discrete_no_interaction")
    nominal = (SIDE * 1e-6) ** 2                                  # m^2
    for k, pressure in enumerate(np.geomspace(2e6, 10e6, 3)):
        assert float(reference[k]["pressure_Pa"]) == pytest.approx(pressure, rel=1e-9)
        load = pressure * nominal                                 # N
        a = (3 * load * RADIUS * 1e-6 / (4 * E_STAR)) ** (1 / 3)   # m
        assert float(area_fraction[k]["value"]) == pytest.approx(math.pi * a * a / nominal,
                                                                 rel=1e-6)
        assert stiffness[k]["unit"] == "N/m³"
        assert float(stiffness[k]["value"]) == pytest.approx(2 * a * E_STAR / nominal, rel=1e-6)
        # the reference agrees with Hertz within its band and 3 % of discretisation
        bem, band = float(reference[k]["value"]), float(reference[k]["reference_band"])
        assert abs(bem - math.pi * a * a / nominal) <= band + 0.03 * bem
        # a cap of a few pixels: its area changes by tens of per cent on every second pixel,
        # so the area is not judged at this resolution, in physical.csv as in the glance
        assert area_fraction[k]["verdict"] == "not judged"
    # GW's Gaussian of summit heights puts 40 % too little area at the lightest pressure
    gw = float(_values(out, "area", "gw")[0]["value"])
    assert gw < 0.7 * float(_values(out, "area", "bem")[0]["value"])
    assert "Area A/A0: not judged at this resolution" in (out / "report.md").read_text(
        encoding="utf-8")


def test_check_report_heads_with_the_surface_and_its_resolution(checked):
    _, out = checked
    text = (out / "report.md").read_text()
    assert text.index("## Your surface: cap.npy") < text.index("## Is the reference converged")
    assert "128 x 128 pixels of 100 nm" in text and "E* = 100 GPa" in text
    assert "| 2 MPa |" in text and "(check-physical.png)" in text
    # each table's tolerance in its field's measure (the scene's largest, 0.2)
    assert "undecided within 20 %)" in text
    assert re.search(r"undecided within 0\.2 σ = [0-9.]+ nm\)", text)
    # one surface: the rules over realizations are left out of "How to read the numbers"
    assert "**One surface.**" in text and "How a verdict is reached" not in text
    assert (out / "check-physical.png").stat().st_size > 10_000
    for name in ("errors.csv", "verdicts.csv", "physical.csv", "check.toml"):
        assert (out / name).is_file()


def test_the_scene_it_writes_gives_the_same_numbers(checked):
    folder, out = checked
    again = folder / "again"
    assert main(["report", str(out / "check.toml"), "--out", str(again), "--cache",
                 str(folder / "cache"), "--jobs", "1", "--quiet"]) == 0
    first, second = rows(out / "errors.csv"), rows(again / "errors.csv")
    assert len(first) == len(second) > 0
    for a, b in zip(first, second):
        assert (a["model"], a["quantity"], a["point"]) == (b["model"], b["quantity"], b["point"])
        assert a["mean_error"] == b["mean_error"] and a["reference_band"] == b["reference_band"]


@pytest.mark.parametrize("options, match", [
    (["--pressure", "1MPa:10MPa"], "needs --e-star"),
    (["--e-star", "115"], "--e-star needs a unit"),
    (["--tiles", "3"], "--tiles must be a square"),
    (["--short-cutoff", "20"], "--short-cutoff needs a unit"),
    (["--physical-size", "10"], "--physical-size needs a unit"),
    (["--pressure", "1MPa:100MPa:1", "--e-star", "115GPa"], "COUNT must be at least 2"),
])
def test_bad_options_are_named(checked, capsys, options, match):
    folder, _ = checked
    status = main(["check", str(folder / "cap.npy"), "--physical-size", f"{SIDE} um",
                   "--file-unit", "um", "--out", str(folder / "bad"), "--no-cache"] + options)
    assert status == 2 and match in capsys.readouterr().err


def test_a_missing_scan_is_named(tmp_path, capsys):
    assert main(["check", str(tmp_path / "none.di"), "--out", str(tmp_path / "o")]) == 2
    assert "names no file" in capsys.readouterr().err


def test_a_reader_message_names_the_checks_options(tmp_path, capsys):
    """A file without its size or unit, and one with missing points: the reader's advice in the
    command line's words."""
    np.save(tmp_path / "plain.npy", np.random.default_rng(0).standard_normal((64, 64)))
    assert main(["check", str(tmp_path / "plain.npy"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--file-unit" in err and "--physical-size" in err
    holes = np.random.default_rng(1).standard_normal((64, 64))
    holes[10, 10:14] = np.nan
    np.save(tmp_path / "holes.npy", holes)
    assert main(["check", str(tmp_path / "holes.npy"), "--physical-size", "1 um", "--file-unit",
                 "nm", "--out", str(tmp_path / "o")]) == 2
    assert "(on the command line: --fill)" in capsys.readouterr().err


def test_the_report_says_how_much_of_the_scan_was_filled(tmp_path):
    from validation.check.result import _filled_text
    from validation.check.request import CheckRequest

    holes = np.random.default_rng(1).standard_normal((64, 64))
    holes[10, 10:14] = np.nan
    np.save(tmp_path / "holes.npy", holes)
    options = dict(physical_size="1 um", file_unit="nm")
    few = _filled_text(CheckRequest(tmp_path / "holes.npy", fill="mean", **options))
    assert few == "; 4 of 4096 points (0.0977 %) missing in the file and filled (fill = mean)"
    holes[:32] = np.nan
    np.save(tmp_path / "holes.npy", holes)
    many = _filled_text(CheckRequest(tmp_path / "holes.npy", fill="interpolate", **options))
    assert "2048 of 4096 points (50 %)" in many and "not measured topography" in many
    assert _filled_text(CheckRequest(tmp_path / "holes.npy", **options)) == ""

"""One surface, one answer: a scene of one realization is judged by its error and the reference
band alone, never by statistics over realizations."""

from __future__ import annotations

import csv
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from validation.judge.verdicts import (FAILS, HOLDS, REFERENCE_BAND, TOO_FEW_REALIZATIONS,
                                       UNCONVERGED, UNDECIDED, one_surface_reasons,
                                       one_surface_verdicts)


def test_known_one_surface_verdicts_and_reasons():
    # inside with room; on the bound; outside beyond the band; straddling; outside below;
    # unconverged; band not estimated; a band that alone exceeds the tolerance
    error = np.array([0.0, 0.1, 0.3, 0.25, -0.3, np.nan, 0.1, 0.0])
    band = np.array([0.05, 0.1, 0.05, 0.1, 0.05, 0.01, np.nan, 0.3])
    verdicts = one_surface_verdicts(error, band, 0.2)
    assert list(verdicts) == [HOLDS, HOLDS, FAILS, UNDECIDED, FAILS, UNDECIDED, UNDECIDED,
                              UNDECIDED]
    reasons = one_surface_reasons(error, band, 0.2)
    assert list(reasons) == ["", "", "", REFERENCE_BAND, "", UNCONVERGED, REFERENCE_BAND,
                             REFERENCE_BAND]
    assert TOO_FEW_REALIZATIONS not in reasons


def test_no_reference_accuracy_rule_for_one_surface():
    # a band of 0.1 is above a quarter of 0.2, which keeps a population's point open; one
    # surface with error 0.05 is still within: 0.05 + 0.1 <= 0.2
    assert one_surface_verdicts(0.05, 0.1, 0.2) == HOLDS
    assert one_surface_verdicts(np.float64(-0.35), 0.1, 0.2) == FAILS


def test_one_surface_verdicts_are_vectorised_and_broadcast():
    error = np.array([[0.0, 0.5], [0.19, -0.19]])
    verdicts = one_surface_verdicts(error, 0.0, 0.2)        # a scalar band: an exact reference
    assert verdicts.shape == (2, 2)
    assert verdicts.tolist() == [[HOLDS, FAILS], [HOLDS, HOLDS]]
    assert one_surface_verdicts(error, np.array([0.02, 0.4]), 0.2).tolist() == [
        [HOLDS, UNDECIDED], [UNDECIDED, UNDECIDED]]
    with pytest.raises(ValueError, match="tolerance"):
        one_surface_verdicts(error, 0.0, 0.0)


@given(st.floats(-2, 2), st.floats(0, 1), st.floats(0.01, 1), st.floats(-1, 1))
def test_a_decided_verdict_is_right_for_every_value_the_band_allows(error, band, tolerance,
                                                                     where):
    # the exact error lies somewhere in [error - band, error + band]: "holds" and "fails" must
    # be right wherever it lies, and only a band that straddles the tolerance leaves it open
    verdict = one_surface_verdicts(error, band, tolerance)
    exact = error + where * band
    if verdict == HOLDS:
        assert abs(exact) <= tolerance + 1e-12
    elif verdict == FAILS:
        assert abs(exact) > tolerance - 1e-12
    else:
        assert abs(error) - band <= tolerance < abs(error) + band
    if band == 0:
        assert verdict == (HOLDS if abs(error) <= tolerance else FAILS)


def synthetic_one(error: float, band: float):
    """One realization whose model area is off by ``error`` everywhere, the BEM's band ``band``."""
    from types import SimpleNamespace

    from bem.common.curve import ContactCurve

    load, area = np.logspace(-4, -2, 4), np.array([0.01, 0.03, 0.1, 0.2])
    reference = ContactCurve(separation=[3.0, 2.0, 1.5, 1.0], load=load, area=area,
                             mean_pressure=load, nominal_area=1.0, e_star=1.0,
                             extras={"area_error": band * area})
    model = ContactCurve(separation=[3.0, 2.0, 1.5, 1.0], load=load, area=area * (1 + error),
                         mean_pressure=load, nominal_area=1.0, e_star=1.0)
    task = SimpleNamespace(seed=0, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                           quantities=("area",), sweep_value=2.3)
    return [SimpleNamespace(task=task, curves={"bem": reference, "gw": model}, sigma=1.0)]


@pytest.mark.parametrize("error, band, verdict, reason", [
    (0.05, 0.1, HOLDS, ""),
    (0.5, 0.1, FAILS, ""),
    (0.15, 0.1, UNDECIDED, REFERENCE_BAND),
])
def test_a_comparison_of_one_realization_is_judged_by_its_band(error, band, verdict, reason):
    from validation.judge.compare import compare_realizations

    entry = compare_realizations(synthetic_one(error, band), tolerances=(0.2,)).models[
        ("gw", "area")]
    assert entry.one_surface and not entry.surface_verdicts and entry.surface is None
    assert set(entry.verdicts[0]) == {verdict}
    assert set(entry.reasons(0)) == {reason}
    assert entry.ranges[0].holds_anywhere == (verdict == HOLDS)


ONE = {
    "name": "one-scan",
    "title": "One surface",
    "surface": {"D": 2.4, "rms_slope": 0.1, "n": 32},
    "realizations": {"count": 1, "seed": 2},
    "loads": {"min": 1e-4, "max": 3e-2, "count": 6},
    "models": {"use": ["gw", "persson", "bem"]},
    "bem": {"reference_error": True},
    "tolerances": {"levels": [0.2, 1.0]},
}


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def test_a_scene_of_one_realization_gives_holds_and_fails_from_its_band(tmp_path):
    from validation.report.write import write_report
    from validation.judge.decide import run_scenes
    from validation.scenes.reader import parse_scene

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = run_scenes([parse_scene(ONE, source="test")], progress=False)
    write_report(results, tmp_path)
    verdicts = rows(tmp_path / "verdicts.csv")
    assert {r["verdict"] for r in verdicts} >= {HOLDS, FAILS}
    assert TOO_FEW_REALIZATIONS not in {r["undecided_reason"] for r in verdicts}
    assert {r["verdict_per_surface"] for r in verdicts} == {""}
    # every verdict is the one-surface rule on the error and band of errors.csv
    errors = {(r["model"], r["quantity"], r["point"]): r for r in rows(tmp_path / "errors.csv")}
    for r in verdicts:
        e = errors[r["model"], r["quantity"], r["point"]]
        band = float("nan") if e["reference_band"] == "not estimated" else float(e["reference_band"])
        expected = one_surface_verdicts(float(e["mean_error"]), band, float(r["tolerance"]))
        assert r["verdict"] == expected, r
        if r["verdict"] == UNDECIDED:
            assert r["undecided_reason"] in (REFERENCE_BAND, UNCONVERGED)
    # the headline gives the error with ± the band, and no per-surface interval
    headline = rows(tmp_path / "headline.csv")
    assert headline and {r["interval"] for r in headline} == {"reference band"}
    for r in headline:
        assert float(r["half_width"]) == pytest.approx(float(r["reference_band"]), rel=1e-8)
        assert r["surfaces90_low"] == "nan" and r["verdict_per_surface"] == ""
        assert r["verdict"] == one_surface_verdicts(float(r["mean_error"]),
                                                    float(r["reference_band"]),
                                                    float(r["tolerance"]))
    text = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert "one surface, judged by the reference band alone" in text and " ± " in text
    assert "too few realizations" not in (tmp_path / "one-scan.md").read_text(encoding="utf-8")


@pytest.mark.parametrize("error, band, refined", [
    (0.18, 0.03, True),    # a band below a quarter of the tolerance still holds this cell open
    (0.05, 0.03, False),   # decided: nothing to refine
    (0.5, 0.03, False),
])
def test_one_surface_refines_wherever_its_band_holds_a_cell(error, band, refined):
    """On one surface the refinement targets every cell the band leaves open, small bands too
    (the realizations' quarter-of-tolerance rule belongs to a mean over surfaces)."""
    from types import SimpleNamespace

    from validation.judge.decide import band_decides

    scene = SimpleNamespace(tolerances=(0.2,))
    mask, smallest, held = band_decides(scene, synthetic_one(error, band), 0.95)
    assert bool(mask.all()) is refined and bool(mask.any()) is refined
    # the band the finer solve must resolve: that of the cells it holds, none where it holds none
    np.testing.assert_allclose(smallest, band if refined else np.nan)


def test_the_finer_solve_resolves_the_band_of_the_fields_it_decides_only():
    """A separation decided with a tiny band does not set the finer solve's tolerance when only
    the area is held open (it did: a 576² map's refinement ran at tol ~1e-7)."""
    import dataclasses
    from types import SimpleNamespace

    from validation.judge.decide import band_decides

    (one,) = synthetic_one(0.18, 0.03)      # the area: open, held by its band of 3 %
    reference = one.curves["bem"]
    extras = dict(reference.extras) | {"separation_error": np.full(4, 1e-6)}
    one.curves["bem"] = dataclasses.replace(reference, extras=extras)
    one.task.quantities = ("area", "separation")
    mask, smallest, held = band_decides(SimpleNamespace(tolerances=(0.2,)), [one], 0.95)
    assert mask.all() and not held["separation"].any()
    np.testing.assert_allclose(smallest, 0.03)     # not 1e-6

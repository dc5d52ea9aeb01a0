"""The error atlas' model and prediction: a fit recovers a known error law, its interval covers
left-out points, predictions use the check's load points and say when a scan is outside."""

import json

import csv
import math

import numpy as np
import pytest

import validation
from validation.atlas.design import atlas_design, atlas_scene, design
from validation.atlas.model import fit_error_model, interval_of, verdict_of
from validation.check.library import check_scenes, make_request


def synthetic_model(tmp_path, noise=0.02):
    """A model fitted to errors that follow a known law of the descriptors and the load."""
    rng = np.random.default_rng(0)
    points = 30
    hurst, nayak = rng.uniform(0.3, 0.9, points), rng.uniform(1.0, 2.5, points)
    skew = rng.uniform(-1.0, 0.2, points)
    x = np.log10(np.geomspace(5e-4, 0.15, 12))
    rows = [(h, a, s, xx, p) for p, (h, a, s) in enumerate(zip(hurst, nayak, skew))
            for _ in range(2) for xx in x]
    covariates = np.array([r[:4] for r in rows])
    law = 0.3 * covariates[:, 0] - 0.1 * covariates[:, 1] + 0.05 * covariates[:, 3]
    error = law + noise * rng.standard_normal(law.size)
    keys = np.array(["gw/interface/area"] * law.size)
    groups = np.array([r[4] for r in rows])
    ranges = {"hurst": [0.3, 0.9], "nayak": [10.0, 300.0], "skewness": [-1.0, 0.2],
              "magnification": [4.0, 128.0], "peak": [1.0, 5.0], "load_ratio": [5e-4, 0.15]}
    model = fit_error_model(covariates, keys, error, groups,
                            meta={"atlas_commit": "0" * 40, "grid": 64, "realizations": 2,
                                  "design_points": points, "tolerance": 0.2,
                                  "range": ranges})
    path = tmp_path / "model.json"
    path.write_text(json.dumps(model), encoding="utf-8")
    return model, path, covariates, law


def test_the_fit_recovers_a_known_law_and_its_interval_its_noise(tmp_path):
    model, _, covariates, law = synthetic_model(tmp_path)
    mean, low, high = interval_of(model, "gw/interface/area", covariates)
    assert np.max(np.abs(mean - law)) < 0.02
    width = high - low        # 90 % of a normal scatter of 0.02: 2 x 1.645 x 0.02
    assert np.all((width > 0.04) & (width < 0.1))
    assert np.all(low < mean) and np.all(mean < high)


def test_verdicts_of_an_interval():
    verdicts = verdict_of(np.array([-0.1, 0.25, -0.5, -0.1]), np.array([0.1, 0.4, -0.3, 0.3]),
                          0.2)
    assert verdicts.tolist() == ["holds", "fails", "fails", "undecided"]


def test_prediction_uses_the_check_load_points_and_its_names(tmp_path):
    _, path, _, _ = synthetic_model(tmp_path)
    z = validation.self_affine_surface(128, hurst=0.6, rms_slope=0.1, rolloff=0.25, window=256,
                                       seed=1) * 1e-6
    prediction = validation.predict_errors(z, spacing="1um", e_star="100GPa", model_file=path,
                                           cache=str(tmp_path / "cache"))
    request = make_request(z, spacing="1um", e_star="100GPa", cache_dir=str(tmp_path / "c2"))
    loads = check_scenes(request)[0][0].loads.values()
    assert [r.load for r in prediction.rows] == pytest.approx(list(loads))
    assert {(r.model, r.frame, r.quantity) for r in prediction.rows} == \
        {("gw", "interface", "area")}
    assert [r.pressure for r in prediction.rows] == pytest.approx([1e11 * p for p in loads])
    assert prediction.descriptors.hurst == pytest.approx(0.6, abs=0.1)
    report = prediction.write(tmp_path / "out")
    text = report.read_text(encoding="utf-8")
    assert "(predicted)" in text and "Hurst" in text
    header = (tmp_path / "out" / "predicted.csv").read_text(encoding="utf-8").splitlines()[0]
    assert header == "model,frame,quantity,point,Load,pressure_Pa,error,low,high,tolerance,verdict"


def test_a_scan_outside_the_atlas_gets_no_verdict(tmp_path):
    _, path, _, _ = synthetic_model(tmp_path)
    rng = np.random.default_rng(2)
    z = np.cumsum(rng.standard_normal((128, 128)), axis=1) * 1e-9   # H = 0.5 along x only
    z = np.minimum(z, np.quantile(z, 0.3))                           # strongly skewed
    prediction = validation.predict_errors(z, spacing="1um", model_file=path,
                                           cache=str(tmp_path / "cache"))
    assert prediction.outside
    assert {r.verdict for r in prediction.rows} == {"outside atlas"}
    assert "outside" in prediction.markdown()
    # the model is not extrapolated: no number either, in the rows and in predicted.csv
    assert all(math.isnan(r.error) and math.isnan(r.low) and math.isnan(r.high)
               for r in prediction.rows)
    prediction.write(tmp_path / "out")
    with open(tmp_path / "out" / "predicted.csv", newline="", encoding="utf-8") as stream:
        assert {row["error"] for row in csv.DictReader(stream)} == {""}


def test_the_design_is_space_filling_and_its_scenes_periodic():
    points = design()
    assert len(points) == 60 and len(atlas_design()) == 60
    hurst = np.array([p.hurst for p in points if p.plateau is None and p.family != "wm"])
    # a Latin hypercube: one point in each of 40 strata of H
    assert np.unique(np.floor((hurst - 0.3) / 0.6 * 40)).size == 40
    honed = [p for p in points if p.plateau is not None][-1]
    scene = atlas_scene(honed, n=64)
    assert scene.surface.one_period and scene.surface.plateau == honed.plateau is not None
    with pytest.raises(ValueError, match="gaussian"):
        design(0)
    with pytest.raises(ValueError, match="wm"):
        design(wm=-1)
    # the WM points: D over [2.05, 2.95] in 12 strata, n_max 4 to 11 on the 256 grid, periodic
    wm = [p for p in points if p.family == "wm"]
    d = np.array([3 - p.hurst for p in wm])
    assert np.unique(np.floor((d - 2.05) / 0.9 * 12)).size == 12
    assert {p.n_max for p in wm} <= set(range(4, 12)) and len({p.n_max for p in wm}) >= 6
    from validation.atlas.design import ATLAS_GRID, WM_GAMMA

    scene = atlas_scene(wm[0], n=ATLAS_GRID)
    assert scene.surface.family == "wm" and scene.surface.periodic
    assert scene.surface.n_max == wm[0].n_max
    # the shortest wavelength at least 2.9 grid steps, on the atlas' grid and a coarser one
    assert ATLAS_GRID / WM_GAMMA ** max(p.n_max for p in wm) > 2.9
    finest = max(wm, key=lambda p: p.n_max)
    assert 64 / WM_GAMMA ** atlas_scene(finest, n=64).surface.n_max > 2.9


def test_the_stored_model_is_small_and_versioned():
    from validation.atlas.model import MODEL_FILE, load_error_model

    model = load_error_model()
    assert MODEL_FILE.stat().st_size < 60_000
    assert len(model["atlas_commit"]) == 40
    assert {"gw", "persson", "bgt"} <= {key.split("/")[0] for key in model["entries"]}
    assert 0.8 < model["validation"]["all"]["coverage"] <= 1.0
    # the stored model is the design's: every point, every kind, every quantity compared
    assert model["design_points"] == len(atlas_design())
    assert model["families"] == {"self-affine": 40, "plateau": 8, "wm": 12}
    assert {key.split("/")[2] for key in model["entries"]} == \
        {"area", "separation", "stiffness", "leakage"}
    # each kind of surface covered by the interval on points left out of the fit
    assert all(v["coverage"] > 0.85 for v in model["validation"]["kinds"].values())


def test_the_interval_widens_where_the_residuals_scatter_more():
    """The interval's scale: where one kind's residuals scatter ten times more, its interval is
    wider than the other's, at the same load."""
    rng = np.random.default_rng(3)
    rows = 4000
    covariates = np.column_stack([rng.uniform(0.3, 0.9, rows), rng.uniform(1, 2.5, rows),
                                  rng.uniform(-1, 0.2, rows), rng.uniform(-3.3, -0.8, rows)])
    wide = covariates[:, 2] < -0.4
    error = 0.01 * rng.standard_normal(rows) * np.where(wide, 10.0, 1.0)
    groups = np.arange(rows) // 8
    model = fit_error_model(covariates, np.array(["gw/interface/area"] * rows), error, groups,
                            kinds=np.where(wide, "honed", "gaussian"))
    probe = np.array([[0.6, 1.7, -0.9, -2.0], [0.6, 1.7, 0.1, -2.0]])
    _, low, high = interval_of(model, "gw/interface/area", probe)
    assert (high - low)[0] > 4 * (high - low)[1]
    assert 0.01 < (high - low)[1] < 0.06       # about 2 x 1.645 x 0.01


def _rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def test_the_check_prints_the_prediction_first_and_sets_it_against_the_solve(tmp_path, capsys):
    import re

    from validation.cli import main

    z = validation.self_affine_surface(128, hurst=0.7, rms_slope=0.1, rolloff=0.25, seed=4)
    np.save(tmp_path / "scan.npy", z * 1e-6)
    out = tmp_path / "out"
    assert main(["check", str(tmp_path / "scan.npy"), "--physical-size", "128um",
                 "--file-unit", "m", "--out", str(out), "--cache", str(tmp_path / "cache"),
                 "--jobs", "1"]) == 0
    printed = capsys.readouterr().out
    assert printed.index("predicted by the error atlas") < printed.index("report written")
    assert "  original GW" in printed and "before the solve" in printed
    # the coverage recounted from the files: the solved errors (errors.csv) of the fields the
    # check judged (physical.csv) against the predicted intervals (predicted.csv)
    judged = {(r["model"], r["field"]) for r in _rows(out / "physical.csv")
              if r["verdict"] not in ("", "not judged")}
    solved = {(r["model"], r["quantity"], r["point"]): float(r["mean_error"])
              for r in _rows(out / "errors.csv") if r["frame"] == "interface"
              and (r["model"], r["reference_field"]) in judged}
    cells = inside = 0
    for r in _rows(out / "predicted.csv"):
        key = (r["model"], r["quantity"], r["point"])
        if r["verdict"] != "outside atlas" and key in solved and math.isfinite(solved[key]):
            cells += 1
            inside += float(r["low"]) <= solved[key] <= float(r["high"])
    assert cells > 50
    sentence = re.search(r"interval at (\d+) of (\d+) cells", printed)
    assert sentence and (int(sentence[1]), int(sentence[2])) == (inside, cells)
    assert sentence[0] in (out / "prediction.md").read_text(encoding="utf-8")
    # the verdicts recounted: the check's (physical.csv) against the predicted ones where both
    # decide
    decided = {(r["model"], r["field"], r["point"]): r["verdict"]
               for r in _rows(out / "physical.csv") if r["verdict"] in ("holds", "fails")}
    field = {"separation": "separation", "area": "area", "stiffness": "stiffness"}
    both = agree = 0
    for r in _rows(out / "predicted.csv"):
        name = "mean_gap" if (r["model"], r["quantity"]) == ("persson", "separation") \
            else field.get(r["quantity"], r["quantity"])
        solved = decided.get((r["model"], name, r["point"]))
        if solved and r["verdict"] in ("holds", "fails"):
            both += 1
            agree += solved == r["verdict"]
    counted = re.search(r"agree at (\d+) of the (\d+) cells", printed)
    assert (int(counted[1]), int(counted[2])) == (agree, both) if counted else both == 0


def test_a_prediction_that_cannot_be_made_never_stops_the_check(monkeypatch, capsys):
    import validation.atlas.predict as predict
    from validation.atlas.command import prediction_before

    def broken(request):
        raise KeyError("entries")

    monkeypatch.setattr(predict, "predict_request", broken)
    assert prediction_before(object(), quiet=False) is None
    assert "no prediction before the solve (KeyError" in capsys.readouterr().err


def test_the_atlas_map_reads_the_fitted_law_and_the_report_shows_it(tmp_path):
    from validation.atlas.report import error_atlas_figure, report_section, verdict_map

    model, _, _, _ = synthetic_model(tmp_path)
    # the law 0.3 H - 0.1 log10 alpha + 0.05 log10 p/(E* h'), at alpha = sqrt(10 x 300):
    # -0.25 at H 0.3 and the lightest load (fails beyond 0.2 with a 0.03 interval), +0.06 at
    # H 0.9 and the heaviest (holds)
    hurst, ratio = np.array([0.3, 0.6, 0.9]), np.array([5e-4, 0.15])
    verdicts = verdict_map(model, "gw/interface/area", hurst, ratio)
    assert verdicts.shape == (2, 3)             # rows: loads, columns: H
    assert verdicts[0, 0] == "fails" and verdicts[1, 2] == "holds"
    model["design_hurst"] = [0.4, 0.6]
    figure = error_atlas_figure(model)
    assert len(figure.axes) == 1
    lines, jobs = report_section(model)
    assert "30 design points, with 2 periodic 64² realizations each" in lines[1]
    model["families"] = {"self-affine": 20, "wm": 10}
    assert "30 design points: 20 Gaussian self-affine and 10 WM, with" in \
        report_section(model)[0][1]
    assert "](error-atlas.png)" in lines[-2] and jobs[0][0] == "error-atlas.png"


def test_a_scan_too_finely_resolved_is_told_the_cutoff_that_brings_it_inside(tmp_path):
    import re

    _, path, _, _ = synthetic_model(tmp_path)
    # a window of a wider surface: its rolloff beyond the scan, the magnification 181
    z = validation.self_affine_surface(512, hurst=0.7, rms_slope=0.1, window=1024,
                                       seed=3) * 1e-6
    prediction = validation.predict_errors(z, spacing="1um", model_file=path, cache=False)
    (sentence,) = [s for s in prediction.outside if s.startswith("magnification")]
    hint = re.search(r"--short-cutoff (\d+)px, brings it to ([\d.]+)\)", sentence)
    assert hint and float(hint[2]) <= 128
    again = validation.predict_errors(z, spacing="1um", model_file=path, cache=False,
                                      short_cutoff=f"{hint[1]}px")
    assert again.descriptors.magnification == pytest.approx(float(hint[2]), rel=0.02)
    assert not any(s.startswith("magnification") for s in again.outside)


def test_a_prediction_that_cannot_be_set_against_the_solve_leaves_the_check_whole(
        tmp_path, monkeypatch, capsys):
    import validation.atlas.predict as predict
    from validation.cli import main

    def broken(prediction, result):
        raise ValueError("different load points")

    monkeypatch.setattr(predict, "against_check", broken)
    z = validation.self_affine_surface(64, hurst=0.7, rms_slope=0.1, rolloff=0.25, seed=5)
    np.save(tmp_path / "scan.npy", z * 1e-6)
    out = tmp_path / "out"
    assert main(["check", str(tmp_path / "scan.npy"), "--physical-size", "64um",
                 "--file-unit", "m", "--out", str(out), "--no-cache", "--jobs", "1",
                 "--quiet"]) == 0
    assert "not set against the solve (ValueError: different load points)" in \
        capsys.readouterr().err
    assert (out / "report.md").is_file() and not (out / "prediction.md").exists()


def test_the_prediction_and_a_check_of_other_loads_are_not_compared(tmp_path):
    from validation.atlas.predict import against_check, predict_request

    z = validation.self_affine_surface(64, hurst=0.7, rms_slope=0.1, rolloff=0.25, seed=6)
    request = make_request(z * 1e-6, spacing="1um", cache_dir=str(tmp_path / "c"))
    prediction = predict_request(request)
    result = validation.check_scan(z * 1e-6, spacing="1um", pressures="1e-5:1e-3:12",
                                   cache=str(tmp_path / "c"))
    with pytest.raises(ValueError, match="different load points"):
        against_check(prediction, result)

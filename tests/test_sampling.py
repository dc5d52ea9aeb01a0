"""The same surface at several sampling intervals: the subsampled map, the scene key, the
runner's variants and finding (h) on synthetic results whose verdict is known."""

from types import SimpleNamespace

import numpy as np
import pytest

import asperity
from bem.common.curve import ContactCurve
from validation.judge.findings import CONTRADICTED, RANGED, REPRODUCED, UNDECIDED
from validation.judge.sampling import (KEY, sampling_finding, sampling_study,
                                       sampling_verdict)
from validation import run_scenes
from validation.run.sampling import Sampled, SummitStatistics, subsample
from validation.scenes.reader import load_scene, parse_scene
from validation.scenes.scene import SceneError
from validation.surfaces.families import surface_heights
from validation.surfaces.wm import wm_surface

# --------------------------------------------------------------------------------------------
# the subsampled map


@pytest.mark.parametrize("D, factor", [(2.05, 2), (2.5, 4), (2.95, 2)])
def test_subsampled_wm_is_the_coarse_generation_up_to_a_constant(D, factor):
    n = 128
    fine = wm_surface(n, D=D, rms_slope=0.1, seed=3)
    coarse = wm_surface(n // factor, D=D, rms_slope=0.1, seed=3, slope_grid=n)
    sampled = subsample(fine, factor)
    # eq. (11) at the same points x = i k L/n, the amplitude fixed on the same grid: only the
    # mean removal differs, and the subsampled map keeps the fine map's mean plane
    np.testing.assert_allclose(sampled - coarse, sampled.mean(), rtol=0,
                               atol=1e-12 * np.ptp(fine))
    assert abs(sampled.mean()) > 1e-6 * np.ptp(fine)   # a constant that is really there


def test_subsample_keeps_the_heights_and_their_plane():
    heights = np.arange(36.0).reshape(6, 6)
    np.testing.assert_array_equal(subsample(heights, 2), heights[::2, ::2])
    np.testing.assert_array_equal(subsample(heights, 1), heights)


# --------------------------------------------------------------------------------------------
# the scene key

GOOD = {"name": "s", "surface": {"D": 2.3, "rms_slope": 0.1, "n": 64}}


def scene(**tables):
    return parse_scene({**GOOD, **tables}, source="test.toml")


def test_sampling_key_parses_sorted_and_defaults_to_the_grid_alone():
    assert scene().sampling == (1,)
    assert scene(sampling={"factors": [4, 1, 2]}).sampling == (1, 2, 4)
    for name in ("paper-wm-d205", "paper-wm-d295", "self-affine"):
        built = load_scene(name)
        assert built.sampling == (1, 2, 4) == built.quick_version().sampling


@pytest.mark.parametrize("tables, detail", [
    (dict(sampling={"factors": [1, 2.5]}), "integers >= 1"),
    (dict(sampling={"factors": [1, True]}), "integers >= 1"),
    (dict(sampling={"factors": [0, 1]}), "integers >= 1"),
    (dict(sampling={"factors": 2}), "non-empty list"),
    (dict(sampling={"factors": []}), "non-empty list"),
    (dict(sampling={"factors": [1, 2, 2]}), "twice"),
    (dict(sampling={"factors": [2, 4]}), "must list 1"),
    (dict(sampling={"factors": [1, 3]}), "must divide the 64 x 64 grid"),
    (dict(sampling={"factors": [1, 8]}), "at least 16 points per side"),
    (dict(sampling={"factors": [1, 2]}, models={"use": ["persson", "bem"]}),
     "model fitted to summits"),
    (dict(sampling={"factor": [1, 2]}), "not a known key of [sampling]"),
])
def test_bad_sampling_values_name_the_key(tables, detail):
    with pytest.raises(SceneError) as info:
        scene(**tables)
    message = str(info.value)
    assert "test.toml" in message and "sampling" in message and detail in message


def test_sampling_does_not_belong_in_a_theory_scene():
    with pytest.raises(SceneError, match="'sampling' does not belong in a theory scene"):
        parse_scene({"kind": "theory", "theory": {"C": [5.0]}, "sampling": {"factors": [1, 2]}})


# --------------------------------------------------------------------------------------------
# the runner

TINY = {"name": "tiny", "surface": {"D": 2.3, "rms_slope": 0.1, "n": 32},
        "realizations": {"count": 2, "seed": 7}, "loads": {"min": 1e-4, "max": 1e-2, "count": 4},
        "bem": {"reference_error": False}, "quantities": {"use": ["area", "load", "separation"]},
        "models": {"use": ["gw", "discrete", "persson", "bem"]}, "sampling": {"factors": [1, 2]}}


def test_variants_are_the_models_on_the_subsampled_map_at_the_bem_loads(tmp_path):
    (result,) = run_scenes([parse_scene(TINY)], cache_dir=str(tmp_path), progress=False)
    for r in result.realizations[2.3]:
        assert [s.factor for s in r.sampled] == [1, 2]
        finest, coarse = r.sampled
        assert set(coarse.curves) == {"gw", "discrete"}            # Persson is not summit-fitted
        assert finest.curves["gw"] is r.curves["gw"]
        heights = surface_heights(r.task.surface, r.task.seed)
        found = asperity.find_summits(heights[::2, ::2], 2 * r.task.surface.spacing)
        assert coarse.summits == SummitStatistics.of(found)
        assert finest.summits.sigma == pytest.approx(r.sigma)
        gw = found.greenwood_williamson(1.0).at_load(r.curves["bem"].load)
        np.testing.assert_allclose(coarse.curves["gw"].area, gw.area, rtol=1e-12)
        np.testing.assert_allclose(coarse.curves["discrete"].load, r.curves["bem"].load,
                                   rtol=1e-6)
    log = [e for r in result.realizations[2.3] for e in r.computed]
    assert sum(e.startswith("bem ") for e in log) == 2                 # one BEM per realization
    assert sum(e.startswith("summits@2h ") for e in log) == 2
    # a second run reads summits and every model's paths back (GW at 2h too): no surface, no
    # solver, no model
    (again,) = run_scenes([parse_scene(TINY)], cache_dir=str(tmp_path), progress=False)
    assert [e for r in again.realizations[2.3] for e in r.computed] == []
    np.testing.assert_array_equal(again.realizations[2.3][1].sampled[1].curves["gw"].area,
                                  result.realizations[2.3][1].sampled[1].curves["gw"].area)
    np.testing.assert_array_equal(again.realizations[2.3][1].sampled[1].curves["discrete"].area,
                                  result.realizations[2.3][1].sampled[1].curves["discrete"].area)


def test_report_shows_the_finding_and_how_the_ranges_move(tmp_path):
    import csv

    from validation.report.write import write_report

    (result,) = run_scenes([parse_scene(TINY)], progress=False)
    write_report([result], tmp_path)
    text = (tmp_path / "tiny.md").read_text(encoding="utf-8")    # the scene's page
    assert "| (h) the asperity models' answers depend on the sampling interval | D = 2.3 |" in text
    assert "## The sampling interval" in text and "| 2h | 16 × 16 |" in text
    assert "| original GW | area |" in text and "median shift 2h − h" in text
    with open(tmp_path / "sampling-validity.csv", newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    # 2 samplings x 2 models x 2 quantities x 2 tolerances
    assert len(rows) == 16 and {r["factor"] for r in rows} == {"1", "2"}
    with open(tmp_path / "sampling-summits.csv", newline="", encoding="utf-8") as stream:
        summits = list(csv.DictReader(stream))
    assert len(summits) == 4 and all(float(r["density_ratio"]) == 1.0
                                     for r in summits if r["factor"] == "1")


def test_a_measured_map_is_subsampled_the_same_way(tmp_path):
    from validation.surfaces.self_affine import self_affine_surface
    from validation.surfaces.topography import write_gwyddion_ascii

    heights = self_affine_surface(64, hurst=0.8, rms_slope=0.1, L=8.0, window=128, seed=5)
    write_gwyddion_ascii(tmp_path / "scan.txt", heights * 1e-6, 8e-6 / 64, unit="m",
                         size_unit="µm")
    data = {"name": "measured", "surface": {"family": "file", "path": str(tmp_path / "scan.txt"),
                                            "unit": "um", "tiles": 4},
            "loads": {"min": 1e-4, "max": 1e-2, "count": 3}, "bem": {"reference_error": False},
            "models": {"use": ["gw", "bem"]}, "quantities": {"use": ["area", "load", "separation"]},
            "sampling": {"factors": [1, 2]}}
    (result,) = run_scenes([parse_scene(data)], progress=False)
    for r in result.realizations[0.0]:
        tile = surface_heights(r.task.surface, r.task.seed)
        found = asperity.find_summits(tile[::2, ::2], 2 * r.task.surface.spacing)
        assert r.sampled[1].summits == SummitStatistics.of(found)
        assert r.sampled[1].summits.count < r.sampled[0].summits.count


# --------------------------------------------------------------------------------------------
# finding (h) on synthetic results

LOAD = np.logspace(-5, -2, 8)
REALIZATIONS = 10
NOISE = np.random.default_rng(1).standard_normal((REALIZATIONS, 8))


def curve(area=1.0, separation=0.0, index=0, scatter=0.0):
    wobble = 1.0 + scatter * NOISE[index]
    return ContactCurve(separation=np.linspace(3.0, 0.5, 8) + separation, load=LOAD,
                        area=0.3 * LOAD * area * wobble, mean_pressure=LOAD, nominal_area=1.0,
                        e_star=1.0)


def synthetic(coarse_area=1.0, coarse_separation=0.0, scatter=0.0):
    """Realizations whose "gw" at 2h has its area scaled and its separation shifted (σ = 1)
    from the one at h; the BEM is the curve at h with a 10 % offset."""
    out = []
    summits = SummitStatistics(100, 100.0, 0.1, 1.0, 0.5)
    for index in range(REALIZATIONS):
        fine = curve(index=index)
        coarse = curve(coarse_area, coarse_separation, index=index, scatter=scatter)
        task = SimpleNamespace(seed=index, quantities=("area", "separation"),
                               surface=SimpleNamespace(L=1.0, sweep_name="D", grid=(64, 64)),
                               sweep_value=2.3)
        sampled = (Sampled(1, summits, {"gw": fine}),
                   Sampled(2, SummitStatistics(50, 50.0, 0.2, 0.9, 0.6), {"gw": coarse}))
        out.append(SimpleNamespace(task=task, curves={"bem": curve(area=1.1), "gw": fine},
                                   sigma=1.0, sampled=sampled))
    return out


def test_sampling_verdict_rule():
    yes, no = np.ones((1, 4), bool), np.zeros((1, 4), bool)
    half = np.array([[1, 1, 0, 0]], bool)
    assert sampling_verdict(np.vstack([no, yes]), np.vstack([yes, no])) == REPRODUCED
    assert sampling_verdict(np.vstack([no, no]), np.vstack([yes, yes])) == CONTRADICTED
    # a point supports where some row moves: half of the points suffice, none against
    assert sampling_verdict(np.vstack([half, no]), np.vstack([no, yes])) == REPRODUCED
    # moves at the light half, stays at the heavy half: reproduced over that range only
    assert sampling_verdict(half, ~half) == RANGED
    assert sampling_verdict(no, no) == UNDECIDED                    # no point decides
    with pytest.raises(ValueError, match="one shape"):
        sampling_verdict(yes, np.ones((2, 4), bool))


def test_finding_reproduced_where_coarser_sampling_moves_the_answer():
    study = sampling_study(synthetic(coarse_area=1.3, scatter=0.01), (0.05, 0.2))
    finding = sampling_finding(study)
    assert finding.key == KEY and finding.verdict == REPRODUCED
    assert "moves from 2h on: original GW area" in finding.evidence
    assert "area +27 % (8/0)" in finding.evidence      # (1.3 - 1) / 1.1, 8 of 8 outside
    assert study.summits[2]["density"][0] == pytest.approx(0.5)
    entry = study.comparisons[2].models[("gw", "area")]
    np.testing.assert_allclose(entry.summary.mean, 1.3 / 1.1 * (1 + 0.01 * NOISE.mean(axis=0)) - 1,
                               rtol=1e-12)


def test_finding_contradicted_where_no_sampling_moves_it():
    finding = sampling_finding(sampling_study(synthetic(coarse_area=1.01, coarse_separation=0.01,
                                                        scatter=0.001), (0.05, 0.2)))
    assert finding.verdict == CONTRADICTED and "moves from" not in finding.evidence


def test_finding_undecided_where_the_shift_is_within_its_scatter():
    # a mean shift of 5 % (the tolerance) with a 10 % scatter: every interval straddles a bound
    finding = sampling_finding(sampling_study(synthetic(coarse_area=1.055, scatter=0.1),
                                              (0.05, 0.2)))
    assert finding.verdict == UNDECIDED


def test_finding_not_tested_without_a_coarser_sampling():
    data = synthetic()
    for r in data:
        r.sampled = ()
    assert sampling_study(data, (0.05, 0.2)) is None
    finding = sampling_finding(None)
    assert finding.verdict == UNDECIDED and finding.evidence.startswith("not tested")

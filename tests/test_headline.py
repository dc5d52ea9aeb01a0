"""The headline (each model's error at fixed contact-area fractions), its table and CSV, the
atlas figure, the generated summary and the report's layout: checked against independent
computations on constructed curves, and on a small run of the default scenes."""

from __future__ import annotations

import csv
import dataclasses
import math
import pathlib
import re
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats

from bem.common.curve import ContactCurve
from validation.judge.compare import compare_realizations
from validation.judge.headline import (HEADLINE_FRACTIONS, REGIMES, along_path, crossing,
                                       headline, reached_fractions, regime_of)
from validation.judge.tolerance import two_sided_factor
from validation.judge.verdicts import FAILS, HOLDS, UNDECIDED


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


# ------------------------------------------------------------------------------------------
# constructed curves: errors linear in log10(area fraction), so that the headline's
# interpolation in ln(area fraction) is exact and the numbers are known in closed form

LOADS = np.logspace(-6, -1, 11)
OFFSETS = np.array([0.02, -0.03, 0.05, 0.0, -0.01, 0.04])     # c_r of e_r(a) = c_r + s log10 a
SLOPE = 0.15
BAND = 0.02


def paths() -> np.ndarray:
    """Each realization's BEM area fraction a_r = k_r Load^0.8 (capped below 1)."""
    k = np.linspace(8.0, 14.0, OFFSETS.size)[:, None]
    return np.minimum(k * LOADS[None, :] ** 0.8, 0.9)


def constructed(offsets=OFFSETS):
    area = paths()[: len(offsets)]
    out = []
    for seed, (offset, a) in enumerate(zip(offsets, area)):
        error = offset + SLOPE * np.log10(a)
        reference = ContactCurve(separation=np.linspace(3, 0.5, LOADS.size), load=LOADS, area=a,
                                 mean_pressure=LOADS, nominal_area=1.0, e_star=1.0,
                                 extras={"area_error": BAND * a})
        model = ContactCurve(separation=np.linspace(3, 0.5, LOADS.size), load=LOADS,
                             area=a * (1 + error), mean_pressure=LOADS, nominal_area=1.0,
                             e_star=1.0)
        task = SimpleNamespace(seed=seed, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                               quantities=("area",), sweep_value=2.3)
        out.append(SimpleNamespace(task=task, curves={"bem": reference, "gw": model}, sigma=1.0))
    return out


def test_crossing_interpolates_in_log_area_fraction():
    area = np.array([[0.0, 5e-4, 2e-3, 2e-2, 0.2], [8e-4, 1e-3, 1e-2, 0.1, 0.5]])
    before, after, weight, reached = crossing(area, 1e-3)
    assert reached.all() and list(before) == [1, 1] and list(after) == [2, 1]
    assert weight[0] == pytest.approx(np.log(2) / np.log(4)) and weight[1] == 0.0
    values = np.log(area + 1e-300)
    np.testing.assert_allclose(along_path(values, before, after, weight), np.log(1e-3))
    # 0.3 is beyond the first path; 5e-4 lies between a point without contact and one with
    assert list(crossing(area, 0.3)[3]) == [False, True]
    assert list(crossing(np.array([[0.0, 2e-3]]), 1e-3)[3]) == [False]
    with pytest.raises(ValueError, match="area fraction"):
        crossing(area, 0.0)
    assert [regime_of(f) for f in HEADLINE_FRACTIONS] == ["light", "light", "intermediate",
                                                          "heavy"]
    assert {f for _, held in REGIMES for f in held} == set(HEADLINE_FRACTIONS)


def test_headline_numbers_match_an_independent_computation():
    comparison = compare_realizations(constructed(), tolerances=(0.05, 0.2))
    area = paths()
    # every path spans 0.1 % to 30 % here
    assert reached_fractions(comparison) == HEADLINE_FRACTIONS
    cells = {c.fraction: c for c in headline(comparison)}
    assert set(cells) == set(HEADLINE_FRACTIONS)
    for fraction, cell in cells.items():
        errors = OFFSETS + SLOPE * np.log10(fraction)          # exact: linear in log a
        n = errors.size
        mean, sem, std = errors.mean(), stats.sem(errors), errors.std(ddof=1)
        low, high = stats.t.interval(0.95, n - 1, loc=mean, scale=sem)
        assert (cell.model, cell.quantity, cell.reference_field) == ("gw", "area", "area")
        assert cell.realizations == n and not cell.one_surface
        assert cell.mean == pytest.approx(mean, abs=1e-12)
        assert (cell.low, cell.high) == pytest.approx((low, high), abs=1e-12)
        assert cell.half_width == pytest.approx((high - low) / 2, abs=1e-12)
        k2 = two_sided_factor(n)
        assert (cell.surface_low, cell.surface_high) == pytest.approx(
            (mean - k2 * std, mean + k2 * std), abs=1e-12)
        assert cell.band == pytest.approx(BAND, rel=1e-12)
        # the Load at the fraction: a_r = k_r Load^0.8 inverted, realization by realization
        # (below the cap at 0.9 every pair of neighbours lies on the power law)
        k = area[:, 1] / LOADS[1] ** 0.8
        assert cell.load == pytest.approx(np.mean((fraction / k) ** (1 / 0.8)), rel=1e-9)
        # the verdicts by the rule, computed here from the interval and the band
        for tolerance, verdict, per_surface in zip(cell.tolerances, cell.verdicts,
                                                   cell.surface_verdicts):
            wide = (low - BAND, high + BAND)
            expected = (HOLDS if -tolerance <= wide[0] and wide[1] <= tolerance
                        and BAND <= tolerance / 4 else
                        FAILS if wide[0] > tolerance or wide[1] < -tolerance else UNDECIDED)
            assert verdict == expected, (fraction, tolerance)
            assert per_surface in (HOLDS, FAILS, UNDECIDED)
    # the constructed errors are chosen so that the headline says both
    assert {c.verdicts[1] for c in cells.values()} >= {HOLDS, FAILS}


def test_a_fraction_not_reached_by_every_realization_is_left_out():
    results = constructed()
    short = results[0].curves["bem"]
    cut = dataclasses.replace(short, area=np.minimum(short.area, 0.2))
    results[0] = SimpleNamespace(task=results[0].task, sigma=1.0,
                                 curves={"bem": cut, "gw": results[0].curves["gw"]})
    comparison = compare_realizations(results, tolerances=(0.2,))
    assert reached_fractions(comparison) == (0.001, 0.01, 0.1)
    assert {c.fraction for c in headline(comparison)} == {0.001, 0.01, 0.1}


def test_a_realization_without_an_error_at_the_fraction_prevents_holds():
    # one realization unconverged everywhere: left out of the mean, and nothing holds
    results = constructed(np.zeros(4))
    model = results[0].curves["gw"]
    results[0].curves["gw"] = dataclasses.replace(
        model, extras={"converged": np.zeros(LOADS.size, bool)})
    cells = headline(compare_realizations(results, tolerances=(10.0,)))
    assert all(c.realizations == 3 for c in cells)
    assert all(c.verdicts[0] != HOLDS for c in cells)


# ------------------------------------------------------------------------------------------
# the default scenes, small: 64 x 64 grids, 2 realizations, 5 loads (the report's layout and
# its summary do not depend on the grid); the figures are queued, not drawn


@pytest.fixture(scope="module")
def default_report(tmp_path_factory):
    from validation.cli import DEFAULT_SCENES, FULL_ONLY_SCENES
    from validation.report import write
    from validation.judge.decide import run_scenes
    from validation.scenes.reader import load_scene

    scenes = []
    for name in DEFAULT_SCENES:
        if name in FULL_ONLY_SCENES:
            continue
        scene = load_scene(name).quick_version()
        if scene.kind == "surface":
            scene = dataclasses.replace(
                scene, surface=dataclasses.replace(scene.surface, n=64), realizations=2,
                max_realizations=None, loads=dataclasses.replace(scene.loads, count=5),
                bem=dataclasses.replace(scene.bem, max_grid=None))
        scenes.append(scene)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = run_scenes(scenes, progress=False)
    folder = tmp_path_factory.mktemp("default")
    jobs = []
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(write._Figures, "render",
                      lambda self, executor=None, cache_dir=None: jobs.extend(self.jobs))
        write.write_report(results, folder, seconds=1.0, mode="quick")
    return SimpleNamespace(folder=folder, jobs={name: draw for name, draw, _ in jobs},
                           scenes=scenes, results=results)


def test_the_default_report_is_a_page_a_person_reads(default_report):
    folder = default_report.folder
    text = (folder / "report.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 300
    sections = re.findall(r"^## (.+)$", text, flags=re.M)
    assert sections[:2] == ["Summary", "Headline: each model's error at fixed contact-area "
                                       "fractions"]
    assert "Findings" in sections and "Data" in sections
    # every scene has its page, linked from report.md, and the page exists
    pages = set(re.findall(r"\]\(([^()/\s]+\.md)\)", text))
    assert pages == {f"{s.name}.md" for s in default_report.scenes}
    for page in pages:
        content = (folder / page).read_text(encoding="utf-8")
        assert content.startswith("# ") and "](report.md)" in content
    # the details live on the pages, not on the front page
    assert "Verdicts per load point" not in text
    assert "Verdicts per load point" in (folder / "paper-wm-d205.md").read_text(encoding="utf-8")
    # the atlas is the report's first figure, one per judged scene, each on report.md
    figures = re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", text)
    judged = [s.name for s in default_report.scenes if s.kind == "surface"]
    assert figures == [f"{name}-atlas.png" for name in judged]


def test_the_atlas_is_drawn_per_scene_with_a_panel_per_swept_value(default_report):
    for scene in default_report.scenes:
        if scene.kind != "surface":
            assert f"{scene.name}-atlas.png" not in default_report.jobs
            continue
        figure = default_report.jobs[f"{scene.name}-atlas.png"]()
        panels = [ax for ax in figure.axes]
        assert len(panels) == len(scene.surface.sweep_values)
        rows = [t.get_text() for t in panels[0].get_yticklabels()]
        # each row names its frame where a scene judges in both
        assert "original GW: area [interface]" in rows
        assert "Persson: mean gap ū [interface]" in rows
        assert any(row.startswith("improved GW: separation d [finite") for row in rows)
        assert figure.legends and "within 0.2" in figure.legends[0].get_title().get_text()


def test_headline_and_validity_tables_have_their_columns(default_report):
    folder = default_report.folder
    with open(folder / "headline.csv", newline="", encoding="utf-8") as stream:
        header = next(csv.reader(stream))
    assert header == ["scene", "D", "H", "L", "model", "frame", "quantity", "reference_field",
                      "area_fraction", "regime", "Load", "realizations", "mean_error", "low",
                      "high", "half_width", "interval", "surfaces90_low", "surfaces90_high",
                      "reference_band", "confidence", "tolerance", "verdict",
                      "undecided_reason", "verdict_per_surface"]
    headline_rows = rows(folder / "headline.csv")
    assert {float(r["area_fraction"]) for r in headline_rows} <= set(HEADLINE_FRACTIONS)
    assert {r["interval"] for r in headline_rows} == {"confidence interval"}
    for r in headline_rows:
        assert r["regime"] == regime_of(float(r["area_fraction"]))
        assert float(r["low"]) <= float(r["mean_error"]) <= float(r["high"])
        # the CSV keeps 10 significant digits: each value within half a unit of its 10th
        # digit, 5e-10 of itself
        high, low, half = float(r["high"]), float(r["low"]), float(r["half_width"])
        assert half == pytest.approx((high - low) / 2,
                                     abs=5e-10 * (abs(high) + abs(low) + abs(half)))
    with open(folder / "validity.csv", newline="", encoding="utf-8") as stream:
        validity = next(csv.reader(stream))
    # the range in contact-area fraction first, the load beside it
    assert validity.index("area_fraction_min") + 2 == validity.index("load_min")
    # validity ranges on the scene pages in area fraction, the Load beside (the format itself:
    # test_report_robustness.py, holds_cell)
    page = (folder / "paper-wm-d205.md").read_text(encoding="utf-8")
    assert "as the BEM's contact-area fraction over it with the Load beside it" in page


def _numbers(sentence: str) -> list[str]:
    """The numbers of a sentence (not the digits inside names such as paper-wm-d205)."""
    return re.findall(r"(?<![\w.])[+-]?\d+(?:\.\d+)?(?![\w.])", sentence)


def _summary(folder) -> str:
    text = (folder / "report.md").read_text(encoding="utf-8")
    return text[text.index("## Summary"):text.index("## Headline")]


def _decision_tables(summary: str) -> dict[str, dict[str, dict[str, str]]]:
    """frame -> quantity row name -> column heading -> cell, read from the summary."""
    from validation.report.summary import FRAME_TITLES

    tables, frame, header = {}, None, None
    for line in summary.splitlines():
        found = [f for f, title in FRAME_TITLES.items() if line.startswith(f"**{title}.**")]
        if found:
            frame, header = found[0], None
            tables[frame] = {}
        elif frame and line.startswith("| ") and header is None:
            header = line.strip("| ").split(" | ")
        elif frame and line.startswith("| "):
            cells = line.strip("| ").split(" | ")
            tables[frame][cells[0]] = dict(zip(header[1:], cells[1:]))
    return tables


def test_every_number_of_the_summary_comes_from_the_tables(default_report):
    folder = default_report.folder
    summary = _summary(folder)
    sentences = [line[2:] for line in summary.splitlines() if line.startswith("- ")]
    assert 1 <= len(sentences) <= 5
    table_rows = [line for line in summary.splitlines()
                  if line.startswith("| ") and not line.startswith("| quantity")]
    assert table_rows
    headline_rows = rows(folder / "headline.csv")
    findings = rows(folder / "findings.csv")
    families = {(r["scene"], r["D"], r["H"], r["L"]) for r in headline_rows}
    candidates = list(range(len(families) + 1))      # "holds on k of n families"
    for r in headline_rows:
        for column in ("mean_error", "low", "high", "half_width"):
            value = float(r[column])
            candidates += [value, 100 * value]
        candidates.append(100 * float(r["area_fraction"]))
        candidates += [float(r[c]) for c in ("D", "H", "L") if r[c]]
    for r in findings:
        candidates += [100 * float(r[c]) for c in ("reproduced_from", "reproduced_to") if r[c]]
    for key in {r["finding"] for r in findings}:
        verdicts = [r["verdict"] for r in findings if r["finding"] == key]
        candidates += [len(verdicts)] + [verdicts.count(v) for v in set(verdicts)]
    for tolerance in {r["tolerance"] for r in headline_rows}:   # the precision's median
        widths = sorted(float(r["half_width"]) for r in headline_rows
                        if r["tolerance"] == tolerance and math.isfinite(float(r["half_width"])))
        if widths:
            candidates.append(float(np.median(widths)))
    candidates = np.array([c for c in candidates if math.isfinite(c)])
    for sentence in sentences + table_rows:
        assert sentence.endswith((".", "|"))
        for token in _numbers(sentence):
            decimals = len(token.split(".")[1]) if "." in token else 0
            close = np.abs(candidates - float(token)) <= 0.5 * 10.0**-decimals + 1e-9
            assert close.any(), (token, sentence)


def test_the_summary_names_the_theory_the_rule_chooses(default_report):
    # the rule, computed here from headline.csv: per frame, quantity and fraction, each model
    # holds where it holds on every surface family; of those that hold the one with the
    # smallest largest |mean error|, else the smallest; its worst family's numbers
    from validation.report.summary import COLUMNS, error_text

    folder = default_report.folder
    tables = _decision_tables(_summary(folder))
    headline_rows = [r for r in rows(folder / "headline.csv") if float(r["tolerance"]) == 0.2]
    assert set(tables) == {r["frame"] for r in headline_rows} == {"interface", "finite"}
    names = {"area": "area", "separation": "separation (Persson: mean gap ū)",
             "conductance": "conductance (stiffness)"}
    checked = 0
    for frame, table in tables.items():
        assert "leakage" not in table            # the quick report has none
        for quantity, name in names.items():
            for regime, fraction in COLUMNS:
                cells = [r for r in headline_rows if r["frame"] == frame and
                         r["quantity"] == quantity and float(r["area_fraction"]) == fraction]
                heading = f"{regime}: {100 * fraction:g} %"
                reached = any(float(r["area_fraction"]) == fraction for r in headline_rows
                              if r["frame"] == frame)
                if not reached:
                    assert heading not in table[name]
                    continue
                if not cells:
                    assert table[name][heading] == "not reached"
                    continue
                by_model = {}
                for r in cells:
                    by_model.setdefault(r["model"], []).append(r)

                def largest(model):
                    sizes = [abs(float(r["mean_error"])) for r in by_model[model]]
                    return max([s for s in sizes if math.isfinite(s)], default=math.inf)

                def holds(model):
                    return all(r["verdict"] == "holds" for r in by_model[model])

                best = min(by_model, key=lambda m: (not holds(m), largest(m), m))
                worst = max(by_model[best], key=lambda r: abs(float(r["mean_error"])))
                mark = "✔" if holds(best) else "✘" if any(
                    r["verdict"] == "fails" for r in by_model[best]) else "?"
                cell = table[name][heading]
                assert error_text(float(worst["mean_error"]), quantity) in cell, cell
                assert f" {mark} " in cell, cell
                held = sum(r["verdict"] == "holds" for r in by_model[best])
                if len(by_model[best]) > 1:
                    assert f"holds on {held} of {len(by_model[best])} families" in cell
                checked += 1
    assert checked >= 6


def test_the_summary_chooses_the_theory_that_holds_on_every_family():
    from validation.report.summary import choose, decision_table

    def row(model, scene, mean, verdict, fraction=0.1, quantity="area"):
        return dict(scene=scene, D="2.2", H="", L="1", model=model, frame="finite",
                    quantity=quantity, reference_field=quantity, area_fraction=fraction,
                    mean_error=mean, low=mean - 0.01, high=mean + 0.01, verdict=verdict)

    cells = [row("a", "s1", 0.15, "holds"), row("a", "s2", -0.05, "holds"),
             row("b", "s1", 0.01, "holds"), row("b", "s2", 0.3, "fails"),
             row("c", "s1", 0.02, "undecided")]
    chosen = choose(cells)
    # the one that holds everywhere, though another is closer on one family
    assert chosen.row["model"] == "a" and chosen.verdict == "holds"
    assert chosen.row["scene"] == "s1" and (chosen.held, chosen.families) == (2, 2)
    fallback = choose(cells[2:])       # none holds everywhere: the smallest largest error
    assert fallback.row["model"] == "c" and fallback.verdict == "undecided"
    assert choose(cells[2:4]).verdict == "fails"
    table = decision_table(cells + [row("a", "s1", 0.1, "holds", fraction=0.01)], "finite")
    assert table[1] == "| quantity | light: 1 % | intermediate: 10 % |"
    assert "heavy (30 %) not reached by this run's load paths" in table[0]
    assert table[3].startswith("| area | **a** +10 % (+9.0, +11) ✔ (s1, D = 2.2) | **a** +15 %")
    assert decision_table(cells, "interface") == []


def report_pages(folder: pathlib.Path) -> dict[str, str]:
    return {p.name: p.read_text(encoding="utf-8") for p in folder.glob("*.md")}


def test_a_new_report_replaces_the_pages_of_the_previous_one(tmp_path):
    from validation.report.write import previous_report

    (tmp_path / "report.md").write_text("# old\n\n- [Old scene](old-scene.md)\n")
    (tmp_path / "old-scene.md").write_text("# Old scene\n")
    (tmp_path / "notes.md").write_text("the user's")
    owned = {p.name for p in previous_report(tmp_path)}
    assert owned == {"report.md", "old-scene.md"}


def test_a_headline_cell_without_a_known_error_says_why_not_nan():
    from validation.judge.headline import HeadlineCell
    from validation.report.front import headline_cell_text

    def cell(mean, reasons):
        return HeadlineCell("discrete", "leakage", "leakage", 0.01, 1e-4, 0, mean, mean, mean,
                            math.nan, math.nan, 0.02, (0.05, 0.2), ("undecided", "undecided"),
                            ("", ""), reasons, one_surface=True)

    assert headline_cell_text(cell(math.nan, ("unconverged", "unconverged")), 1) == \
        "not converged ?"
    assert headline_cell_text(cell(math.nan, ("reference band", "")), 0) == \
        "not known (reference band) ?"
    assert headline_cell_text(cell(-0.14, ("", "")), 1) == "-0.14 ± 0.02 ?"


def test_the_rules_over_realizations_are_read_only_where_there_are_realizations(default_report):
    from validation.report.conventions import conventions

    text = (default_report.folder / "report.md").read_text(encoding="utf-8")
    assert "**How a verdict is reached.**" in text      # scenes of several realizations

    every = "\n".join(conventions())
    one = "\n".join(conventions(populations=False))
    for paragraph in ("**How a verdict is reached.**", "**Two readings"):
        assert paragraph in every and paragraph not in one
    assert "**One surface.**" in one and "**Separation and mean gap.**" in one


def test_runs_of_a_mask_are_its_stretches_of_consecutive_points():
    from validation.judge.verdicts import true_runs

    assert true_runs(np.array([1, 1, 0, 0, 1], bool)) == [(0, 1), (4, 4)]
    assert true_runs(np.zeros(3, bool)) == [] and true_runs(np.ones(2, bool)) == [(0, 1)]
